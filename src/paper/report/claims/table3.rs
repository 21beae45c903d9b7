//! The claims of section 6.4 of the paper (Table 3: the motion state of each case and the
//! concordance of the wear rate with the contact pressure, P-w, and the sliding distance,
//! s-w) and conclusion 3 (pressure dominates once impact occurs, sliding distance in
//! permanent contact).

use super::{Claims, Ensembles, Member};
use crate::paper::cases::{PerCase, SteadyEnsemble, SteadyMember};
use crate::paper::golden::{Golden, Table3Golden};
use crate::paper::studies::accuracy::Table3Test;

/// Whether a member's case follows conclusion 3: P-w dominates exactly when it is not in
/// continuous contact.
fn follows_conclusion(s: &SteadyMember) -> bool {
    (s.concordance.dominant() == "P-w") != s.motion.continuous()
}

/// A member's steady run of each case beside the paper's Table 3 row, in Table 3's order.
fn case_members<'a>(
    m: &Member<'a>,
    golden: &'a Golden,
) -> [(&'a SteadyMember, &'a Table3Golden); 5] {
    m.steady.zip(&golden.table3).list().map(|&(s, g)| (*s, g))
}

/// `f` of each case, joined by " / " in Table 3's order.
fn per_case<T>(values: &PerCase<T>, f: impl Fn(&T) -> String) -> String {
    values.list().map(f).join(" / ")
}

/// Adds the claims of Table 3 and conclusion 3.
pub(super) fn claims(c: &mut Claims, e: &Ensembles, golden: &Golden) {
    let n = e.n;
    let ctol = golden.concordance_tolerance;
    let ensembles =
        |what: &dyn Fn(&SteadyEnsemble) -> usize| per_case(&e.steady, |e| what(e).to_string());
    c.claim(
        "Table 3",
        "motion state of each case",
        "all five as in the paper",
        format!(
            "members in continuous contact at 30 / 600 / 2000 r/min, 0.2 / 0.5 mm: {} of {n} (paper: {})",
            ensembles(&|e| e.continuous()),
            per_case(&golden.table3, |g| {
                let continuous = g.motion == "continuous contact";
                String::from(if continuous { "yes" } else { "no" })
            })
        ),
        &|m| Some(case_members(m, golden).iter().map(|(s, g)| Table3Test::new(g, golden).motion(s.motion.mode())).collect()),
    );
    c.claim(
        "Table 3",
        "P-w dominates in the impact cases, s-w in the continuous-contact cases",
        "all five dominances as in the paper",
        format!(
            "members with P-w dominant: {} of {n} (paper: {})",
            ensembles(&|e| e.pressure_dominated()),
            per_case(&golden.table3, |g| g.dominant().to_string())
        ),
        &|m| {
            Some(
                case_members(m, golden)
                    .iter()
                    .map(|(s, g)| Table3Test::new(g, golden).dominance(s.concordance.dominant()))
                    .collect(),
            )
        },
    );
    let within_tolerance = |ok: &dyn Fn(&SteadyMember, &Table3Golden) -> bool| {
        per_case(&e.steady.zip(&golden.table3), |(e, g)| {
            e.members.iter().filter(|m| ok(m, g)).count().to_string()
        })
    };
    c.claim(
        "Table 3",
        "the ten concordance values",
        "all 10 within the golden tolerance of the paper",
        format!(
            "members with each value within {ctol} of the paper's, per case: P-w {}, s-w {} of {n}",
            within_tolerance(&|m, g| Table3Test::new(g, golden).pw(m.concordance.pressure_wear)),
            within_tolerance(&|m, g| Table3Test::new(g, golden).sw(m.concordance.sliding_wear))
        ),
        &|m| {
            Some(
                case_members(m, golden)
                    .iter()
                    .flat_map(|(s, g)| {
                        let t = Table3Test::new(g, golden);
                        [
                            t.pw(s.concordance.pressure_wear),
                            t.sw(s.concordance.sliding_wear),
                        ]
                    })
                    .collect(),
            )
        },
    );
    let all_follow = |m: &Member| m.steady.list().iter().all(|s| follows_conclusion(s));
    let following = c.members.iter().filter(|m| all_follow(m)).count();
    c.claim(
        "Conclusion 3",
        "contact pressure dominates the wear rate once impact occurs; sliding distance dominates in permanent contact",
        "in the member, every case follows the rule, and both motion modes occur",
        format!("members whose five cases all follow the rule: {following} of {n}"),
        &|m| {
            let cases = m.steady.list();
            let impact = cases
                .iter()
                .filter(|s| !s.motion.continuous())
                .count();
            Some(vec![all_follow(m), impact > 0 && impact < cases.len()])
        },
    );
}
