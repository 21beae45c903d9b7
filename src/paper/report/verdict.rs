//! The verdict of a claim of the paper: each claim's rule is checked in every ensemble member,
//! and the verdict over the ensemble follows from how many members it holds in
//! ([`MEMBER_MAJORITY`]).

/// Verdict of a claim.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The rule holds.
    Reproduced,
    /// Some of its checks hold.
    Partly,
    /// None of its checks hold.
    NotReproduced,
}

impl Verdict {
    /// Its word in `paper.md`.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Partly => "partly",
            Verdict::NotReproduced => "not reproduced",
        }
    }

    /// `Reproduced` if all of `checks` hold, `Partly` if some do, else `NotReproduced` (also
    /// when there is nothing to check: a member without the regions a claim is about).
    pub fn of(checks: &[bool]) -> Verdict {
        match checks.iter().filter(|&&c| c).count() {
            0 => Verdict::NotReproduced,
            n if n == checks.len() => Verdict::Reproduced,
            _ => Verdict::Partly,
        }
    }

    /// The verdict over `n` members of which `reproduced` reproduce a claim and
    /// `not_reproduced` do not at all ([`Claim::verdict`]).
    pub fn of_tally(reproduced: usize, not_reproduced: usize, n: usize) -> Verdict {
        let n = n as f64;
        if reproduced as f64 >= MEMBER_MAJORITY * n {
            Verdict::Reproduced
        } else if not_reproduced as f64 >= MEMBER_MAJORITY * n {
            Verdict::NotReproduced
        } else {
            Verdict::Partly
        }
    }

    /// Every verdict, in the order the tallies list them.
    pub const ALL: [Verdict; 3] = [Verdict::Reproduced, Verdict::Partly, Verdict::NotReproduced];
}

/// Share of the members a claim's verdict must hold in to stand for the ensemble.
pub const MEMBER_MAJORITY: f64 = 0.9;

/// One claim of the paper beside what we measured.
#[derive(Clone, Debug)]
pub struct Claim {
    /// Where the paper says it.
    pub source: &'static str,
    /// What the paper says.
    pub paper: &'static str,
    /// What we measured, as ensemble statistics.
    pub measured: String,
    /// The rule, checked in each member, with the tolerances its check uses.
    pub rule: String,
    /// The rule's verdict in each member.
    pub members: Vec<Verdict>,
}

impl Claim {
    /// Members with verdict `v`.
    pub fn count(&self, v: Verdict) -> usize {
        self.members.iter().filter(|&&m| m == v).count()
    }

    /// What identifies it across runs and files: `Fig. 11: a larger clearance gives …`.
    pub fn id(&self) -> String {
        format!("{}: {}", self.source, self.paper)
    }

    /// Reproduced (or not reproduced) when at least [`MEMBER_MAJORITY`] of the members say
    /// so; partly otherwise.
    pub fn verdict(&self) -> Verdict {
        Verdict::of_tally(
            self.count(Verdict::Reproduced),
            self.count(Verdict::NotReproduced),
            self.members.len(),
        )
    }

    /// Members with each verdict, in the order of [`Verdict::ALL`].
    pub fn counts(&self) -> [usize; 3] {
        Verdict::ALL.map(|v| self.count(v))
    }

    /// "reproduced in 16 of 16", "partly: reproduced in 9 of 16, partly in 5, not in 2".
    pub fn tally(&self) -> String {
        tally(self.counts(), self.members.len())
    }
}

/// The tally of `n` members with `counts` of each verdict ([`Verdict::ALL`]'s order), as
/// [`Claim::tally`] writes it.
pub fn tally(counts: [usize; 3], n: usize) -> String {
    match Verdict::of_tally(counts[0], counts[2], n) {
        Verdict::Partly => format!(
            "partly: reproduced in {} of {n}, partly in {}, not in {}",
            counts[0], counts[1], counts[2]
        ),
        Verdict::Reproduced => format!("reproduced in {} of {n}", counts[0]),
        Verdict::NotReproduced => format!("not reproduced in {} of {n}", counts[2]),
    }
}
