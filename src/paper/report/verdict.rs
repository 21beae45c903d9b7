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
    /// Its rule cannot be checked: a quantity it compares is undefined in the member (a
    /// ratio of wear regions the member does not have); neither a success nor a failure.
    Undefined,
}

impl Verdict {
    /// Its word in `paper.md`.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Partly => "partly",
            Verdict::NotReproduced => "not reproduced",
            Verdict::Undefined => "undefined",
        }
    }

    /// `Undefined` when `checks` is `None` or empty (nothing to check), else `Reproduced` if
    /// all of them hold, `Partly` if some do, `NotReproduced` if none does.
    pub fn of(checks: Option<&[bool]>) -> Verdict {
        let Some(checks) = checks.filter(|c| !c.is_empty()) else {
            return Verdict::Undefined;
        };
        match checks.iter().filter(|&&c| c).count() {
            0 => Verdict::NotReproduced,
            n if n == checks.len() => Verdict::Reproduced,
            _ => Verdict::Partly,
        }
    }

    /// The verdict over `n` members with `counts` of each verdict ([`Verdict::ALL`]'s order,
    /// [`Claim::verdict`]): reproduced, not reproduced or undefined when at least
    /// [`MEMBER_MAJORITY`] of the `n` say so, partly otherwise.
    pub fn of_tally(counts: [usize; 4], n: usize) -> Verdict {
        let n = n as f64;
        [
            Verdict::Reproduced,
            Verdict::NotReproduced,
            Verdict::Undefined,
        ]
        .into_iter()
        .find(|&v| counts[v as usize] as f64 >= MEMBER_MAJORITY * n)
        .unwrap_or(Verdict::Partly)
    }

    /// The verdict of `count` of `members` reproducing a result where each member either does
    /// or does not (no partly, none undefined).
    pub fn of_share(count: usize, members: usize) -> Verdict {
        Verdict::of_tally([count, 0, members - count.min(members), 0], members)
    }

    /// Every verdict, in the order the tallies list them (their discriminants' order).
    pub const ALL: [Verdict; 4] = [
        Verdict::Reproduced,
        Verdict::Partly,
        Verdict::NotReproduced,
        Verdict::Undefined,
    ];
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

    /// Reproduced, not reproduced or undefined when at least [`MEMBER_MAJORITY`] of the
    /// members say so; partly otherwise.
    pub fn verdict(&self) -> Verdict {
        Verdict::of_tally(self.counts(), self.members.len())
    }

    /// Members with each verdict, in the order of [`Verdict::ALL`].
    pub fn counts(&self) -> [usize; 4] {
        Verdict::ALL.map(|v| self.count(v))
    }

    /// "reproduced in 16 of 16", "partly: reproduced in 9 of 16, partly in 5, not in 2", with
    /// ", undefined in 4" where the rule cannot be checked in some members.
    pub fn tally(&self) -> String {
        tally(self.counts(), self.members.len())
    }
}

/// The tally of `n` members with `counts` of each verdict ([`Verdict::ALL`]'s order), as
/// [`Claim::tally`] writes it; the members where the rule is undefined are named whenever
/// there are any, so a verdict never rests on fewer members than it seems to.
pub fn tally(counts: [usize; 4], n: usize) -> String {
    let [reproduced, partly, not, undefined] = counts;
    let head = match Verdict::of_tally(counts, n) {
        Verdict::Partly => {
            format!("partly: reproduced in {reproduced} of {n}, partly in {partly}, not in {not}")
        }
        Verdict::Reproduced => format!("reproduced in {reproduced} of {n}"),
        Verdict::NotReproduced => format!("not reproduced in {not} of {n}"),
        Verdict::Undefined => format!("undefined in {undefined} of {n}"),
    };
    match (Verdict::of_tally(counts, n), undefined) {
        (Verdict::Undefined, _) | (_, 0) => head,
        _ => format!("{head}, undefined in {undefined}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_member_without_the_quantity_is_undefined_not_a_failure() {
        // checked: before the undefined verdict, nothing to check was `NotReproduced`
        assert_eq!(Verdict::of(None), Verdict::Undefined);
        assert_eq!(Verdict::of(Some(&[])), Verdict::Undefined);
        assert_eq!(Verdict::of(Some(&[false])), Verdict::NotReproduced);
        assert_eq!(Verdict::of(Some(&[true, false])), Verdict::Partly);
    }

    #[test]
    fn a_tally_names_the_members_where_the_rule_is_undefined() {
        // Fig. 11's ensemble: 6 reproduce, 2 do not, 24 lack a third region
        assert_eq!(
            tally([6, 0, 2, 24], 32),
            "partly: reproduced in 6 of 32, partly in 0, not in 2, undefined in 24"
        );
        assert_eq!(Verdict::of_tally([6, 0, 2, 24], 32), Verdict::Partly);
        assert_eq!(
            tally([30, 0, 0, 2], 32),
            "reproduced in 30 of 32, undefined in 2"
        );
        assert_eq!(tally([0, 0, 2, 30], 32), "undefined in 30 of 32");
        assert_eq!(tally([0, 0, 32, 0], 32), "not reproduced in 32 of 32");
    }
}
