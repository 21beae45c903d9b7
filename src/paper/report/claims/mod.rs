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
use crate::analysis::statistics::Distribution;
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
    /// Adds a claim: `check` gives the checks of its rule in one member.
    fn claim(
        &mut self,
        source: &'static str,
        paper: &'static str,
        rule: impl Into<String>,
        measured: String,
        check: &dyn Fn(&Member) -> Vec<bool>,
    ) {
        let members = self
            .members
            .iter()
            .map(|m| Verdict::of(&check(m)))
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

fn increasing(v: &[f64]) -> bool {
    v.windows(2).all(|w| w[1] > w[0])
}

fn decreasing(v: &[f64]) -> bool {
    v.windows(2).all(|w| w[1] < w[0])
}

/// Whether any of `angles` lies within `tol` of `target` (deg).
fn within(angles: &[f64], target: f64, tol: f64) -> bool {
    angles.iter().any(|&a| angle_distance(a, target) <= tol)
}

/// mean ± sd of a quantity across several ensembles, joined by " / ".
fn across<E>(
    ensembles: &[&E],
    stat: impl Fn(&E) -> Distribution,
    scale: f64,
    digits: usize,
) -> String {
    ensembles
        .iter()
        .map(|e| stat(e).mean_sd(scale, digits))
        .collect::<Vec<_>>()
        .join(" / ")
}

/// Angle of a member's deepest wear region (deg), NaN without regions (left out of the
/// statistics).
fn deepest_angle(m: &WearMember) -> f64 {
    m.deepest_angle().unwrap_or(f64::NAN)
}
