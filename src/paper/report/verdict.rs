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
    /// The rule, checked in each member.
    pub rule: &'static str,
    /// The rule's verdict in each member.
    pub members: Vec<Verdict>,
}

impl Claim {
    /// Members with verdict `v`.
    pub fn count(&self, v: Verdict) -> usize {
        self.members.iter().filter(|&&m| m == v).count()
    }

    /// Reproduced (or not reproduced) when at least [`MEMBER_MAJORITY`] of the members say
    /// so; partly otherwise.
    pub fn verdict(&self) -> Verdict {
        let n = self.members.len() as f64;
        for v in [Verdict::Reproduced, Verdict::NotReproduced] {
            if self.count(v) as f64 >= MEMBER_MAJORITY * n {
                return v;
            }
        }
        Verdict::Partly
    }

    /// "reproduced in 16 of 16", "partly: reproduced in 9 of 16, partly in 5, not in 2".
    pub fn tally(&self) -> String {
        let n = self.members.len();
        let counts =
            [Verdict::Reproduced, Verdict::Partly, Verdict::NotReproduced].map(|v| self.count(v));
        match self.verdict() {
            Verdict::Partly => format!(
                "partly: reproduced in {} of {n}, partly in {}, not in {}",
                counts[0], counts[1], counts[2]
            ),
            v => format!("{} in {} of {n}", v.label(), self.count(v)),
        }
    }
}
