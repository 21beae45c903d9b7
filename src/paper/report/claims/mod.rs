//! The claims of the paper (section 6 and the conclusions), each beside what the ensembles
//! measured and checked by a stated rule in every member: [`standard`] (section 6.1,
//! figures 3-7), [`clearance`] (section 6.2, figures 8-11), [`speed`] (section 6.3, figures
//! 12-15) and [`table3`] (section 6.4, Table 3, and conclusion 3).
//!
//! Owns: what a member of the ensembles is for the claims ([`Member`]: the i-th member of
//! every case, so the N members are N independent draws of the set of cases), the list the
//! claims are added to, and the helpers their rules share.

mod clearance;
mod speed;
mod standard;
mod table3;

use super::verdict::{Claim, Verdict};
use crate::analysis::states::States;
use crate::paper::cases::{PerCase, Runs, SteadyEnsemble, SteadyMember, WearEnsemble, WearMember};
use crate::paper::figures::staircase_shares;
use crate::paper::golden::{angle_distance, Golden};
use crate::paper::perturbation::ClaimTally;
use crate::Result;

/// One member of every ensemble the claims read: the i-th member of each case.
struct Member<'a> {
    /// Of each case's steady ensemble.
    steady: PerCase<&'a SteadyMember>,
    /// Of each case's wear ensemble.
    wear: PerCase<&'a WearMember>,
    /// Figure 7's staircase measure of its standard wear run, per severe region.
    shares: &'a [f64],
}

/// The ensembles the claims read.
struct Ensembles<'a> {
    /// The steady ensemble of each case.
    steady: PerCase<&'a SteadyEnsemble>,
    /// The wear ensemble of each case.
    wear: PerCase<&'a WearEnsemble>,
    /// Per member, figure 7's staircase measure of each severe region of the standard case.
    shares: Vec<Vec<f64>>,
    /// Members of each ensemble.
    n: usize,
}

/// The claims checked so far, and the members they are checked in.
struct Claims<'a> {
    members: Vec<Member<'a>>,
    out: Vec<Claim>,
}

impl Claims<'_> {
    /// Adds a claim: `check` gives the checks of its rule in one member, `None` where a
    /// quantity the rule compares is undefined in it (the member's verdict is then
    /// [`Verdict::Undefined`], not a failure).
    fn claim(
        &mut self,
        source: &'static str,
        paper: &'static str,
        rule: impl Into<String>,
        measured: String,
        check: &dyn Fn(&Member) -> Option<Vec<bool>>,
    ) {
        let members = self
            .members
            .iter()
            .map(|m| Verdict::of(check(m).as_deref()))
            .collect();
        self.out.push(Claim {
            source,
            paper,
            measured,
            rule: rule.into(),
            members,
        });
    }
}

/// Every claim of section 6 and the conclusions, each checked in every member.
pub fn claims(runs: &Runs, golden: &Golden) -> Result<Vec<Claim>> {
    let steady = runs.steady_cases()?;
    let wear = runs.wear_cases()?;
    let e = Ensembles {
        steady,
        wear,
        shares: staircase_shares(wear.standard),
        n: runs.ensemble.members,
    };
    let members = (0..e.n)
        .map(|i| Member {
            steady: e.steady.map(|&s| &s.members[i]),
            wear: e.wear.map(|&w| &w.members[i]),
            shares: &e.shares[i],
        })
        .collect();
    let mut claims = Claims {
        members,
        out: Vec::new(),
    };
    standard::claims(&mut claims, &e, golden);
    clearance::claims(&mut claims, &e, golden);
    speed::claims(&mut claims, &e, golden);
    table3::claims(&mut claims, &e, golden);
    Ok(claims.out)
}

/// Share of the circumference that must see contact for "the whole bearing surface sees
/// contact" (figures 4 and 12): the paper's "whole", allowing a few 1° bins a recorded
/// rotation's samples step over.
const WHOLE_SURFACE: f64 = 0.9;

/// Every claim checked in the members of `runs`, as the perturbation study records it.
pub fn claim_tallies(runs: &Runs, golden: &Golden) -> Result<Vec<ClaimTally>> {
    Ok(claims(runs, golden)?
        .iter()
        .map(|c| ClaimTally {
            id: c.id(),
            counts: Verdict::ALL
                .iter()
                .map(|&v| (v.label(), c.count(v)))
                .collect(),
            members: c.members.len(),
        })
        .collect())
}

/// Whether `v` strictly increases; `None` when a value is undefined (NaN), which is no
/// evidence either way.
fn increasing(v: &[f64]) -> Option<bool> {
    monotone(v, |a, b| b > a)
}

/// Whether `v` strictly decreases; `None` when a value is undefined (NaN).
fn decreasing(v: &[f64]) -> Option<bool> {
    monotone(v, |a, b| b < a)
}

fn monotone(v: &[f64], step: impl Fn(f64, f64) -> bool) -> Option<bool> {
    (!v.iter().any(|x| x.is_nan())).then(|| v.windows(2).all(|w| step(w[0], w[1])))
}

/// Whether any of `angles` lies within `tol` of `target` (deg).
fn within(angles: &[f64], target: f64, tol: f64) -> bool {
    angles.iter().any(|&a| angle_distance(a, target) <= tol)
}

/// mean ± sd of a quantity across several ensembles of `n` members each, joined by " / ";
/// each mean over fewer members (the quantity undefined in the others) says over how many.
fn across<E>(
    ensembles: &[&E],
    n: usize,
    states: impl Fn(&E) -> States,
    scale: f64,
    digits: usize,
) -> String {
    ensembles
        .iter()
        .map(|e| mean_sd(&states(e), n, scale, digits))
        .collect::<Vec<_>>()
        .join(" / ")
}

/// The pooled `mean ± sd` of `s` with its states where the members split
/// ([`States::mean_sd_with_states`]), over an ensemble of `n` members, followed by "(in 8 of
/// 32 members)" when the quantity is undefined in some of them, so a mean never reads as the
/// whole ensemble's or a typical member's when it is not.
fn mean_sd(s: &States, n: usize, scale: f64, digits: usize) -> String {
    with_members(s.mean_sd_with_states(scale, digits), s.pooled.n, n)
}

/// `value` followed by "(in `k` of `n` members)" when `k < n`.
fn with_members(value: String, k: usize, n: usize) -> String {
    if k < n {
        format!("{value} (in {k} of {n} members)")
    } else {
        value
    }
}

/// Angle of a member's deepest wear region (deg), NaN without regions (left out of the
/// statistics).
fn deepest_angle(m: &WearMember) -> f64 {
    m.deepest_angle().unwrap_or(f64::NAN)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_undefined_value_makes_the_order_undefined_not_false() {
        // checked: with NaN counted as false, Fig. 11's members without a third region at
        // 0.2 mm were "not reproduced"
        assert_eq!(decreasing(&[0.59, f64::NAN, 0.14]), None);
        assert_eq!(increasing(&[1.0, f64::NAN]), None);
        assert_eq!(decreasing(&[0.59, 0.23, 0.14]), Some(true));
        assert_eq!(decreasing(&[0.59, 0.23, 0.3]), Some(false));
        assert_eq!(increasing(&[1.0, 2.0, 3.0]), Some(true));
    }

    /// A claim's time in contact, contact onsets and circumference touched are of its cases'
    /// recorded rotations, and it says so, as the maxima's claims do. Failed on Fig. 4, Fig. 8's
    /// motion and both of Fig. 12's: "in contact 99.8 ± 0.5 % of the time, 0.5 ± 1.1 contact
    /// onsets per rotation, 94 ± 1 % of the circumference touched" named no window, beside
    /// the wear claims' 40 rotations.
    #[test]
    fn claims_of_the_recorded_rotations_name_them() {
        let ensemble = crate::simulation::ensemble::EnsembleSettings {
            members: 2,
            ..Default::default()
        };
        let needs = crate::paper::figures::all_needs();
        let silent = crate::io::progress::Silent;
        let runs = Runs::compute(&needs, ensemble, &|_| {}, &silent).unwrap();
        let claims = claims(&runs, &Golden::load().unwrap()).unwrap();
        let recorded = [
            "% of the time",
            "onsets per rotation",
            "circumference",
            "max penetration",
        ];
        let mut checked = 0;
        for c in claims
            .iter()
            .filter(|c| recorded.iter().any(|r| c.measured.contains(r)))
        {
            assert!(
                c.measured
                    .contains("over the recorded rotations, 3000 samples per rotation"),
                "{}: {}",
                c.source,
                c.measured
            );
            checked += 1;
        }
        assert!(checked >= 6, "{checked} claims of the recorded rotations");
    }

    #[test]
    fn a_mean_over_fewer_members_says_over_how_many() {
        let d = States::of(&[1.0, f64::NAN, 3.0]);
        assert_eq!(mean_sd(&d, 3, 1.0, 2), "2.00 ± 1.41 (in 2 of 3 members)");
        assert_eq!(mean_sd(&States::of(&[1.0, 3.0]), 2, 1.0, 1), "2.0 ± 1.4");
        // and a quantity whose members split says so, with both states
        let split = States::of(&[1.0, 1.1, 0.9, 1.0, 5.0, 5.1, 4.9, 5.0]);
        assert_eq!(
            mean_sd(&split, 8, 1.0, 1),
            "3.0 ± 2.1 (pooled over two states: low 4/8 1.0 ± 0.1, high 4/8 5.0 ± 0.1)"
        );
    }
}
