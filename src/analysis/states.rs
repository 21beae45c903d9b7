//! States of an ensemble: where the members of one scene end in two distinct states (a high-
//! and a low-wear state, say), the pooled mean depends on the share in each, and that share
//! depends on how the members were perturbed; each state's mean does not. So every ensemble
//! statistic that can be bimodal is reported per state beside the pooled value.
//!
//! **Rule (largest gap).** Sort the finite values `x₍₀₎ ≤ … ≤ x₍ₙ₋₁₎`. Among the splits that
//! leave at least [`min_state_members`]`(n)` = max(2, ⌈n/10⌉) members on either side, take the
//! one at the largest gap `g = x₍ₖ₎ − x₍ₖ₋₁₎`; the members fall into two states when either
//!
//! * `g > GAP_OVER_SPREAD · max(1, CALIBRATION_MEMBERS / n) · s_p` ([`gap_over_spread`]),
//!   `s_p` the pooled within-group standard deviation `√(((k−1)s₁² + (n−k−1)s₂²)/(n−2))`; or
//! * `g > GAP_OVER_SIDE_SPREAD · √max(1, CALIBRATION_MEMBERS / n) · s_narrow`
//!   ([`gap_over_side_spread`]) and `g > s_other`, `s_narrow` the sd of the narrower side
//!   holding at least [`MIN_REFERENCE_MEMBERS`] members and `s_other` the other side's: a
//!   narrow state beside a wide one, whose gap the pooled sd, the wide state's, hides. A
//!   narrower side whose values all agree (`s_narrow` = 0) measures no spread and leaves the
//!   pooled bound alone to judge.
//!
//! **Counts** ([`States::of_quantised`]). A quantity on a lattice of known spacing `q`, a count
//! over what it is counted over (contact onsets per rotation, `q` = 1/`run.record_rotations`;
//! a share of samples, crank intervals or 1° bins; a 0-or-1 flag per member), splits by the
//! same rule and only at a gap of at least [`MIN_QUANTA_APART`] = 2 quanta: with a level
//! between the states that no member takes.
//!
//! One split at most: two states. Angles ([`States::of_angles_deg`]) are unwrapped from their
//! largest gap on the circle first and split only at a gap wider than [`MIN_ANGLE_GAP_DEG`].
//!
//! Why the pooled bound: in 2000 draws each of 32 values from unimodal distributions (normal,
//! uniform, lognormal σ = 0.5, Student t₃, exponential) 2 pooled sds split at most 2.3 % of
//! the draws, while two normal states 8 sd apart with 5 of 32 members in the smaller are split
//! in 99 % of the draws. Without the minimum share a skewed sample's two or three extreme
//! members split off in up to 12 % of the draws (exponential, gap ratio 2); a state held by
//! fewer than a tenth of the members is not resolved by 32 members anyway. Fewer members
//! estimate `s_p` worse and leave fewer gaps to pick the largest of, so the same 2 sds split
//! unimodal samples far more often (3000 draws: 16 members, exponential 20 %; 8 members,
//! uniform 37 %; 4 members, normal 25 %): the bound grows as 32/n below 32 members, and still
//! splits two normal states 12 sd apart with 2 of 16 members in the smaller in all of 1000
//! draws (2 of 8: 80 %). Four members split only states far apart (one split, 2 and 2, at 16
//! pooled sds with 2 degrees of freedom): two normal states 12 sd apart in 40 % of the draws,
//! 16 sd in 59 %, 32 sd in 96 %.
//!
//! Why the narrow side's bound: the pooled bound alone lost states of unequal spread. In the
//! contact-law study's 16 members the paper law's P-w concordance (standard case) has four
//! members, the four with contact onsets, within 2.2e-5 and 2.0e-4 below the other twelve,
//! which scatter over 3.8e-4: 2.1 pooled sds against 4, but 19 sds of the four. Liu's time in
//! contact at 0.5 mm has four members in free flight and impact at 45-74 % and twelve in
//! continuous contact at 94-100 %: 3.2 pooled sds, 8.6 sds of the twelve. A side's own sd
//! scatters more than the pooled one, the more so with fewer members, hence the larger bound,
//! growing as √(32/n) below 32 members so that the false splits stay near the pooled bound's
//! at every size, and its four members at least: with two, a unimodal sample's two extreme
//! members agree closely often enough to stand off as a state. The other side's sd keeps a skewed state's
//! dense part from being split off its sparse tail. A narrower side whose values all agree is
//! no reference: its sd of 0 puts any gap infinitely many sds off it, and where a quantity
//! takes a few levels (contact onsets per rotation over two recorded rotations, in steps of
//! 0.5) the other side's sd is below their spacing, so three or four levels split at the
//! lowest one when it held four members ("2.5 ± 0" beside "3.292 ± 0.334"). `cargo run --release --example states_calibration`
//! (10 000 seeded draws a size and distribution) gives the false splits of the rule, against
//! the pooled bound alone: at most 1.8 % (uniform) of 4 members, as before; 2.3 % (exponential,
//! 1.1 % before) of 8; 2.8 % (2.6 %) of 16; 4.2 % (4.0 %) of 20; 4.8 % (4.7 %) of 30; 2.7 %
//! (2.5 %) of 32; normal samples at most 1.0 % (4 members), 0.4 % from 8 on. Two normal
//! states with sds 1:10, the four of 16 the narrow ones, 30 narrow sds apart (3 of the wide)
//! are split exactly in 64 % of the draws against 2.4 % before, 40 apart 93 % against 15 %;
//! with sds 1:30, 90 and 120 apart, 69 % and 93.5 % against 2.6 % and 16 %; five of 32 narrow,
//! 1:10, 30 and 40 apart, 46 % and 91 % against 6.6 % and 54 %. Where the smaller state is the
//! wide one the narrow side is the majority: four of 16 wide, 1:10, 20 and 30 apart, 40 % and
//! 76 % against 24 % and 55 %; five of 32, unchanged (44 % and 79 %). The contact-law study's
//! deepest wear under gonthier (3 members at 0.57-0.61 µm, 13 at 0.66-0.70 µm) and flores (6
//! at 0.57-0.63, 10 at 0.67-0.69), which look like one skewed state, gap 3.9 and 4.1 sds of
//! their narrower side and stay one state.
//!
//! Why counts need their quantum: two adjacent levels of a count agree within each level (sd 0
//! or nearly), so their one-step gap is many sds of either, and a count of few levels splits at
//! its most crowded step whatever it counts: in the calibration's 10 000 draws a size, a 0-or-1
//! flag of probability 1/4 split in 22 % (4 members), 63 % (8), 94 % (16), 98 % (20), 99 % (30)
//! and 97 % (32); 6 + binomial(2, ½) onsets over 2 rotations (the four-bar's 3-4 a rotation) in
//! 21 %, 16 %, 2.2 %, 11 %, 95 % and 100 %; Poisson onsets of 0.5 a rotation over 2 rotations
//! in 17 %, 9.5 %, 2.7 %, 4.8 %, 15 % and 22 %. An empty level between the states brings the
//! worst of six count families (those three, Poisson 3 a rotation over 2 and over 10,
//! binomial(4, ½) over 2) to 3.4 % (4 members, Poisson 0.5 a rotation: two members at 0, two
//! at 1), 0.8 % (8), 1.1 % (16), 1.2 % (20), 0.5 % (30) and 0.2 % (32), within the unimodal
//! samples' rates above; and two states of onsets with empty levels between them are found
//! as often as without the quantum (the smaller at Poisson 3 a rotation, 4 of 16, the others
//! at 0: 42.8 % both; at 0.25 a rotation, 14.7 %; 5 of 32 at 0, 79.3 %).

use super::statistics::Distribution;

/// The largest gap must exceed this many pooled within-state standard deviations in an
/// ensemble of at least [`CALIBRATION_MEMBERS`] (more in a smaller one: [`gap_over_spread`]).
pub const GAP_OVER_SPREAD: f64 = 2.0;

/// The ensemble size [`GAP_OVER_SPREAD`] was chosen on (module documentation).
pub const CALIBRATION_MEMBERS: usize = 32;

/// How many pooled within-state standard deviations the largest gap of `n` finite values must
/// exceed: [`GAP_OVER_SPREAD`] from [`CALIBRATION_MEMBERS`] on, growing as 1/n below it, so
/// that a small ensemble splits unimodal samples about as rarely as 32 members do (module
/// documentation: at most 4.7 % of exponential draws, 30 members, against 2.5 % at 32).
pub fn gap_over_spread(n: usize) -> f64 {
    GAP_OVER_SPREAD * (CALIBRATION_MEMBERS as f64 / n.max(1) as f64).max(1.0)
}

/// The largest gap must exceed this many standard deviations of the narrower side of the split
/// that holds at least [`MIN_REFERENCE_MEMBERS`], in an ensemble of at least
/// [`CALIBRATION_MEMBERS`] (more in a smaller one: [`gap_over_side_spread`]). One side's sd
/// scatters more than the pooled one, hence a larger bound than [`GAP_OVER_SPREAD`].
pub const GAP_OVER_SIDE_SPREAD: f64 = 5.5;

/// The fewest members a side of a split must hold for its own sd to judge the gap: two or
/// three members agree closely by chance often enough that a unimodal sample's sparse tail
/// would stand off them as a state (module documentation).
pub const MIN_REFERENCE_MEMBERS: usize = 4;

/// How many standard deviations of its narrower side (of at least [`MIN_REFERENCE_MEMBERS`])
/// the largest gap of `n` finite values must exceed: [`GAP_OVER_SIDE_SPREAD`] from
/// [`CALIBRATION_MEMBERS`] on, growing as 1/√n below it (module documentation).
pub fn gap_over_side_spread(n: usize) -> f64 {
    GAP_OVER_SIDE_SPREAD
        * (CALIBRATION_MEMBERS as f64 / n.max(1) as f64)
            .max(1.0)
            .sqrt()
}

/// The fewest lattice steps (quanta) the largest gap of a quantised quantity must span for its
/// members to split ([`States::of_quantised`]): two, so that a level between the states is
/// empty. Two adjacent levels of a count are the count's resolution, not two states.
pub const MIN_QUANTA_APART: f64 = 2.0;

/// The smallest gap (deg) between the two states of an angle: the angle tolerance of the
/// paper's wear-region claims (the contact-law study's one-region spread is the same 10°).
/// Deepest sectors closer than that lie in one wear region, and a split between them, which
/// the sectors' 1° steps would allow whenever the members agree within a state, is no second
/// state.
pub const MIN_ANGLE_GAP_DEG: f64 = 10.0;

/// The fewest members a state may hold in an ensemble of `n` finite values: max(2, ⌈n/10⌉).
pub fn min_state_members(n: usize) -> usize {
    n.div_ceil(10).max(2)
}

/// Columns of a quantity's states in a CSV (`ensemble_summary.csv`, `data/table3.csv`): the
/// state count, then the low and the high state's members, mean and sd ([`States::cells`]).
pub const STATE_COLUMNS: [&str; 7] = [
    "states",
    "low_n",
    "low_mean",
    "low_sd",
    "high_n",
    "high_mean",
    "high_sd",
];

/// The counts among [`STATE_COLUMNS`] (the state count and each state's members), by index:
/// written as integers, the others as numbers.
pub const STATE_COUNTS: [usize; 3] = [0, 1, 4];

/// One state of an ensemble.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// The members in it (indices into the values given to [`States::of`]), ascending.
    pub members: Vec<usize>,
    /// Distribution of its values.
    pub distribution: Distribution,
}

/// An ensemble's values split into states by the largest-gap rule (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct States {
    /// Distribution of all finite values.
    pub pooled: Distribution,
    /// One state (no split) or two, the lower first; none without a finite value.
    /// Non-finite values are in none.
    pub states: Vec<State>,
    /// The largest admissible gap over the pooled within-group sd (NaN when no split was
    /// admissible: too few members or no spread); the members split when it exceeds
    /// [`gap_over_spread`] (or `side_gap_ratio` its bound).
    pub gap_ratio: f64,
    /// The same gap over the sd of the narrower side that holds at least
    /// [`MIN_REFERENCE_MEMBERS`]: 0 when neither side does, when the narrower side's values all
    /// agree (sd 0) or when the gap does not exceed the other side's sd, NaN where `gap_ratio`
    /// is; the members split when it exceeds
    /// [`gap_over_side_spread`] (or `gap_ratio` its bound).
    pub side_gap_ratio: f64,
}

impl States {
    /// The states of `values` (member `i` is `values[i]`).
    pub fn of(values: &[f64]) -> States {
        States::split_beyond(values, 0.0)
    }

    /// The states of `values` that lie on a lattice of spacing `quantum` (> 0): a count divided
    /// by what it is counted over, e.g. contact onsets per rotation over `1/quantum` recorded
    /// rotations, or 0 or 1 per member. The rule of [`States::of`], splitting only at a gap of
    /// at least [`MIN_QUANTA_APART`] quanta, across an empty level (module documentation).
    pub fn of_quantised(values: &[f64], quantum: f64) -> States {
        // Half a quantum below the bound: gaps are whole quanta up to the rounding of the
        // division that made the values.
        States::split_beyond(values, (MIN_QUANTA_APART - 0.5) * quantum)
    }

    /// [`States::of`], splitting only at a gap wider than `min_gap`.
    fn split_beyond(values: &[f64], min_gap: f64) -> States {
        let mut order: Vec<usize> = (0..values.len())
            .filter(|&i| values[i].is_finite())
            .collect();
        order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
        let sorted: Vec<f64> = order.iter().map(|&i| values[i]).collect();
        let n = sorted.len();
        let min = min_state_members(n);
        // the first of the largest gaps among admissible splits
        let split = (min..=n.saturating_sub(min)).fold(None, |best: Option<usize>, k| match best {
            Some(b) if sorted[b] - sorted[b - 1] >= sorted[k] - sorted[k - 1] => Some(b),
            _ => Some(k),
        });
        let state = |members: &[usize]| {
            let mut members = members.to_vec();
            members.sort_unstable();
            let distribution = Distribution::of(members.iter().map(|&i| values[i]));
            State {
                members,
                distribution,
            }
        };
        let pooled = Distribution::of(sorted.iter().copied());
        let (gap_ratio, side_gap_ratio) = split.map_or((f64::NAN, f64::NAN), |k| {
            let gap = sorted[k] - sorted[k - 1];
            if gap <= 0.0 {
                return (f64::NAN, f64::NAN);
            }
            let sides = [
                Distribution::of(sorted[..k].iter().copied()),
                Distribution::of(sorted[k..].iter().copied()),
            ];
            let ss =
                (k - 1) as f64 * sides[0].sd.powi(2) + (n - k - 1) as f64 * sides[1].sd.powi(2);
            // A narrow state beside a wide one: the pooled sd is the wide one's, so the gap is
            // judged against the narrow side's own sd too, where it has members to estimate it,
            // provided the gap also clears the other side's sd (else the narrow side is the
            // dense part of one skewed state).
            // A narrower side whose values all agree measures no spread: its ties are a
            // quantity's levels (a count per rotation, a sector) or a bound (a contact
            // fraction of 1), and any gap would be infinitely many of its sds.
            let narrow = usize::from(sides[1].sd < sides[0].sd);
            let (a, b) = (&sides[narrow], &sides[1 - narrow]);
            let reference = match (a.n, b.n) {
                _ if a.sd == 0.0 => None,
                (m, _) if m >= MIN_REFERENCE_MEMBERS => Some((a, b)),
                (_, m) if m >= MIN_REFERENCE_MEMBERS => Some((b, a)),
                _ => None,
            };
            let side = (reference.filter(|(_, other)| gap > other.sd))
                .map_or(0.0, |(narrow, _)| gap / narrow.sd);
            (gap / (ss / (n - 2) as f64).sqrt(), side)
        });
        let states = match split {
            Some(k)
                if (gap_ratio > gap_over_spread(n) || side_gap_ratio > gap_over_side_spread(n))
                    && sorted[k] - sorted[k - 1] > min_gap =>
            {
                vec![state(&order[..k]), state(&order[k..])]
            }
            // no value, no state (a quantity nothing recorded)
            _ if n == 0 => Vec::new(),
            _ => vec![state(&order)],
        };
        States {
            pooled,
            states,
            gap_ratio,
            side_gap_ratio,
        }
    }

    /// The states of angles in degrees: split after unwrapping them from the largest gap on
    /// the circle (so that no cluster straddles the cut, wherever their mean lies), and only at
    /// a gap wider than [`MIN_ANGLE_GAP_DEG`]; the pooled distribution is
    /// [`Distribution::of_angles_deg`]'s and every distribution is wrapped back into [0, 360).
    /// "Low" and "high" are the two sides of the cut, not smaller and larger angles.
    pub fn of_angles_deg(values: impl IntoIterator<Item = f64>) -> States {
        let values: Vec<f64> = values.into_iter().collect();
        let mut s = States::split_beyond(&unwrap_at_largest_gap(&values), MIN_ANGLE_GAP_DEG);
        s.pooled = Distribution::of_angles_deg(values);
        for state in &mut s.states {
            state.distribution = state.distribution.wrapped_deg();
        }
        s
    }

    /// Whether the members fall into two states.
    pub fn split(&self) -> bool {
        self.states.len() == 2
    }

    /// Share of the finite values in state `i` (0 for a state that does not exist).
    pub fn share(&self, i: usize) -> f64 {
        self.states.get(i).map_or(0.0, |s| {
            s.distribution.n as f64 / self.pooled.n.max(1) as f64
        })
    }

    /// The low state and the high one when the members split; `None` otherwise.
    pub fn low_high(&self) -> Option<(&State, &State)> {
        match &self.states[..] {
            [low, high] => Some((low, high)),
            _ => None,
        }
    }

    /// The [`STATE_COLUMNS`] values: the state count, then the low and the high state's
    /// members, mean and sd (those six `None` with one state; all seven `None` without a
    /// finite value, which is in no state).
    pub fn values(&self) -> [Option<f64>; 7] {
        let part = |s: Option<&State>| {
            let d = s.map(|s| &s.distribution);
            [d.map(|d| d.n as f64), d.map(|d| d.mean), d.map(|d| d.sd)]
        };
        let split = self.low_high();
        let ([ln, lm, ls], [hn, hm, hs]) =
            (part(split.map(|(l, _)| l)), part(split.map(|(_, h)| h)));
        let count = (!self.states.is_empty()).then_some(self.states.len() as f64);
        [count, ln, lm, ls, hn, hm, hs]
    }

    /// The [`STATE_COLUMNS`] cells of [`States::values`]: counts (the state count and each
    /// state's members) as integers, means and sds written by `number`, empty where `None`.
    pub fn cells(&self, number: impl Fn(f64) -> String) -> Vec<String> {
        (self.values().iter().enumerate())
            .map(|(i, v)| match v {
                None => String::new(),
                Some(x) if STATE_COUNTS.contains(&i) => (*x as usize).to_string(),
                Some(x) => number(*x),
            })
            .collect()
    }

    /// The pooled `mean ± sd` (values × `scale`, `digits` decimals), followed by the states
    /// when the members split into two, so that no pooled mean is read as a typical member's:
    /// `546 ± 99 (pooled over two states: low 27/32 505 ± 21, high 5/32 772 ± 35)`.
    pub fn mean_sd_with_states(&self, scale: f64, digits: usize) -> String {
        let pooled = self.pooled.mean_sd(scale, digits);
        if self.split() {
            format!(
                "{pooled} (pooled over two states: {})",
                self.describe(scale, digits)
            )
        } else {
            pooled
        }
    }

    /// The states as a person reads them: `no state` (no finite value), `one state` or `low
    /// 5/32 0.601 ± 0.004, high 27/32 0.681 ± 0.006` (values × `scale`, `digits` decimals).
    pub fn describe(&self, scale: f64, digits: usize) -> String {
        match self.low_high() {
            None if self.states.is_empty() => "no state".into(),
            None => "one state".into(),
            Some((low, high)) => {
                let part = |name: &str, s: &State| {
                    format!(
                        "{name} {}/{} {}",
                        s.distribution.n,
                        self.pooled.n,
                        s.distribution.mean_sd(scale, digits)
                    )
                };
                format!("{}, {}", part("low", low), part("high", high))
            }
        }
    }
}

/// Angles in degrees placed in the turn that begins after the largest gap between them on the
/// circle (the gap from the last to the first, one turn on, included); a non-finite value
/// stays NaN.
fn unwrap_at_largest_gap(values: &[f64]) -> Vec<f64> {
    let mut sorted: Vec<f64> = (values.iter())
        .filter(|a| a.is_finite())
        .map(|a| a.rem_euclid(360.0))
        .collect();
    sorted.sort_by(f64::total_cmp);
    let gap_after = |i: usize| match sorted.get(i + 1) {
        Some(next) => next - sorted[i],
        None => sorted[0] + 360.0 - sorted[i],
    };
    // The angle just past the largest gap starts the turn.
    let start = (0..sorted.len())
        .max_by(|&a, &b| gap_after(a).total_cmp(&gap_after(b)))
        .map_or(0.0, |i| sorted[(i + 1) % sorted.len()]);
    (values.iter())
        .map(|&a| {
            if a.is_finite() {
                start + (a - start).rem_euclid(360.0)
            } else {
                f64::NAN
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Deterministic uniform numbers in (0, 1) (SplitMix64's output, top 53 bits).
    fn uniforms(seed: u64) -> impl FnMut() -> f64 {
        let mut z = seed;
        move || {
            z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut x = z;
            x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((x ^ (x >> 31)) >> 11) as f64 / (1u64 << 53) as f64 + 1e-17
        }
    }

    #[test]
    fn two_states_are_split_with_their_shares_and_means() {
        // five low members near 0.60, seven high near 0.68 (µm), interleaved
        let v = [
            0.68, 0.60, 0.67, 0.69, 0.61, 0.68, 0.59, 0.67, 0.60, 0.69, 0.68, 0.60,
        ];
        let s = States::of(&v);
        let (low, high) = s.low_high().expect("two states");
        assert_eq!(low.members, vec![1, 4, 6, 8, 11]);
        assert_eq!(high.members, vec![0, 2, 3, 5, 7, 9, 10]);
        assert_relative_eq!(s.share(0), 5.0 / 12.0);
        assert_relative_eq!(low.distribution.mean, 0.6, max_relative = 1e-12);
        assert_relative_eq!(high.distribution.mean, 4.76 / 7.0, max_relative = 1e-12);
        assert_relative_eq!(s.pooled.mean, 7.76 / 12.0, max_relative = 1e-12);
        // gap 0.67 − 0.61 = 0.06 against a pooled sd of about 0.0078
        assert!(s.gap_ratio > 7.0 && s.gap_ratio < 8.0, "{}", s.gap_ratio);
        assert_eq!(
            s.describe(1.0, 3),
            "low 5/12 0.600 ± 0.007, high 7/12 0.680 ± 0.008"
        );
        assert_eq!(
            s.mean_sd_with_states(1.0, 2),
            "0.65 ± 0.04 (pooled over two states: low 5/12 0.60 ± 0.01, high 7/12 0.68 ± 0.01)"
        );
        // Two regions of the bearing, one across 0°: split as the unwrapped angles are.
        let a = States::of_angles_deg([358.0, 2.0, 0.0, 359.0, 1.0, 150.0, 152.0, 151.0, 149.0]);
        let (low, high) = a.low_high().expect("two regions");
        assert_eq!(
            (low.members.clone(), high.members.clone()),
            (vec![0, 1, 2, 3, 4], vec![5, 6, 7, 8])
        );
        assert_relative_eq!(low.distribution.mean, 0.0, epsilon = 1e-9);
        assert_relative_eq!(high.distribution.mean, 150.5, max_relative = 1e-12);
        assert_eq!(
            a.pooled,
            Distribution::of_angles_deg([358.0, 2.0, 0.0, 359.0, 1.0, 150.0, 152.0, 151.0, 149.0])
        );
        // A region opposite the circular mean (near 0° while most lie near 180°) is one state,
        // not split by a cut through it: the cut lies in the largest gap on the circle.
        let mut v: Vec<f64> = (0..24).map(|i| 177.0 + 0.25 * i as f64).collect();
        v.extend([356.0, 357.0, 358.0, 359.0, 1.0, 2.0, 3.0, 4.0]);
        let (low, high) = States::of_angles_deg(v)
            .low_high()
            .map(|(l, h)| (l.clone(), h.clone()))
            .expect("two regions");
        assert_eq!((low.members.len(), high.members.len()), (8, 24));
        assert_relative_eq!(low.distribution.mean, 0.0, epsilon = 1e-9);
        assert_relative_eq!(high.distribution.mean, 179.875, max_relative = 1e-12);
        // Deepest sectors 4° apart agree within each side: one region, one state.
        assert!(!States::of_angles_deg([184.5, 184.5, 188.5, 188.5]).split());
        let one = States::of(&[1.0, 1.1, 0.9]);
        assert_eq!(one.mean_sd_with_states(1.0, 2), one.pooled.mean_sd(1.0, 2));
        let number = |x: f64| format!("{x:.2}");
        assert_eq!(
            s.cells(number),
            ["2", "5", "0.60", "0.01", "7", "0.68", "0.01"]
        );
        assert_eq!(
            States::of(&[1.0, 1.1, 0.9]).cells(number),
            ["1", "", "", "", "", "", ""]
        );
    }

    /// The contact-law study's 16-member ensembles (`data/contact_law_wear.csv`, seed 1), per
    /// member. Failed with the pooled bound alone: the paper law's P-w concordance (gap 2.1
    /// pooled sds against 4) and liu's contact fraction at 0.5 mm (3.2) made one state.
    #[test]
    fn a_narrow_state_beside_a_wide_one_is_split() {
        // the paper's law, standard case: members 0, 2, 4 and 13 (the four with contact
        // onsets) agree within 2.2e-5, 2.0e-4 below the others, which scatter over 3.8e-4
        let pw = [
            0.920445056,
            0.920847323,
            0.920443930,
            0.920981623,
            0.920423043,
            0.921015425,
            0.921031803,
            0.920649138,
            0.920962868,
            0.920992074,
            0.920933783,
            0.920870460,
            0.921000863,
            0.920431232,
            0.921014445,
            0.921031802,
        ];
        // liu, 0.5 mm: four members in free flight and impact, twelve in continuous contact
        let contact = [
            1.0,
            1.0,
            0.546742210,
            1.0,
            1.0,
            0.453424429,
            0.945009165,
            0.937343776,
            0.740543243,
            1.0,
            1.0,
            0.646725546,
            1.0,
            1.0,
            1.0,
            1.0,
        ];
        for (v, low) in [(&pw, [0, 2, 4, 13]), (&contact, [2, 5, 8, 11])] {
            let s = States::of(v);
            assert!(s.gap_ratio < gap_over_spread(16), "{s:?}");
            assert!(s.side_gap_ratio > gap_over_side_spread(16), "{s:?}");
            assert_eq!(
                s.states.first().map(|s| &s.members[..]),
                Some(&low[..]),
                "{s:?}"
            );
        }
        // against the narrow side's sd (the four's in the first, the twelve's in the second)
        assert_relative_eq!(States::of(&pw).side_gap_ratio, 19.30, max_relative = 1e-3);
        assert_relative_eq!(
            States::of(&contact).side_gap_ratio,
            8.57,
            max_relative = 1e-3
        );
    }

    /// A skewed state's sparse tail is no second state: the deepest wear (µm) under gonthier
    /// (3 members 0.57-0.61, 13 at 0.66-0.70) and flores (6 at 0.57-0.63, 10 at 0.67-0.69)
    /// gap 3.9 and 4.1 sds of their narrower side of at least four. Failed with the side's
    /// bound at the pooled one's 2 × 32/16 = 4 sds (flores split, 6 of 16), with
    /// `MIN_REFERENCE_MEMBERS` at 2, where two close members in a tail make a "state", and
    /// without the other side's sd, where seven equal members of 32 make one.
    #[test]
    fn a_skewed_state_or_a_close_pair_in_its_tail_is_not_split() {
        let gonthier = [
            0.6953928, 0.6904702, 0.6599853, 0.6858684, 0.5781660, 0.6084696, 0.6786635, 0.6568500,
            0.6736768, 0.6901855, 0.6854035, 0.6721942, 0.6713238, 0.6946573, 0.6731712, 0.5727554,
        ];
        let flores = [
            0.6684009, 0.6676638, 0.6897407, 0.5726474, 0.6779137, 0.6870775, 0.6726281, 0.6147027,
            0.6068372, 0.6743711, 0.6724286, 0.6318700, 0.5982532, 0.6884364, 0.6871508, 0.5914543,
        ];
        for (v, side) in [(&gonthier, 3.87), (&flores, 4.11)] {
            let s = States::of(v);
            assert!(!s.split(), "{s:?}");
            assert_relative_eq!(s.side_gap_ratio, side, max_relative = 2e-3);
        }
        // fourteen members spread evenly over 0-2.6 and two 0.01 apart at 3.5: the pair's own
        // sd (0.007) is no measure of a state's spread, the fourteen's (0.8) is
        let mut v: Vec<f64> = (0..14).map(|i| 0.2 * i as f64).collect();
        v.extend([3.5, 3.51]);
        let s = States::of(&v);
        assert!(!s.split(), "{s:?}");
        let fourteen = Distribution::of(v[..14].iter().copied());
        assert_relative_eq!(s.side_gap_ratio, 0.9 / fourteen.sd, max_relative = 1e-12);
        // five levels 0.001 apart, six or seven members on each: the seven on the lowest
        // agree exactly (sd 0), but the gap above them is no wider than the others' spacing
        // and within their sd (0.0011)
        let levels: Vec<f64> = (0..32).map(|i| 0.91 + 0.001 * (i % 5) as f64).collect();
        let s = States::of(&levels);
        assert!(!s.split(), "{s:?}");
        assert_eq!(s.side_gap_ratio, 0.0);
    }

    /// `k` members at `x` for each `(x, k)` of `counts`, in that order.
    fn level(counts: &[(f64, usize)]) -> Vec<f64> {
        (counts.iter())
            .flat_map(|&(x, k)| std::iter::repeat_n(x, k))
            .collect()
    }

    /// A quantity of few levels is not split at one of them: contact onsets per rotation of
    /// the four-bar's 16 members over 2 recorded rotations (`run data/scenes/fourbar.toml
    /// --ensemble 16 --rotations 10 --seed 3`), in steps of 0.5, and a count of three levels.
    /// The lowest level's members agree exactly (sd 0), so the gap above them was infinitely
    /// many of their sds and cleared the other side's sd (0.33): failed before the narrower
    /// side had to have a spread ("low 4 of 16: 2.5 ± 0, high 12 of 16: 3.292 ± 0.334").
    #[test]
    fn a_quantity_of_few_levels_is_not_split_at_a_level() {
        for v in [
            level(&[(2.5, 4), (3.0, 6), (3.5, 5), (4.0, 1)]),
            level(&[(3.0, 4), (4.0, 5), (5.0, 3)]),
        ] {
            let s = States::of(&v);
            assert!(!s.split(), "{v:?}: {s:?}");
            assert_eq!(s.side_gap_ratio, 0.0, "{v:?}");
            assert!(s.gap_ratio < gap_over_spread(v.len()), "{v:?}: {s:?}");
        }
        // a narrow side with a spread is still judged against it (four onsets within 2.2e-5)
        assert!(States::of(&[
            0.920445, 0.920444, 0.920423, 0.920431, 0.92085, 0.92098, 0.92102, 0.92103, 0.92065,
            0.92096, 0.92099, 0.92093, 0.92087, 0.92100, 0.92101, 0.92103,
        ])
        .split());
    }

    /// Counts split only across an empty level. The four-bar's contact onsets per rotation over
    /// 2 recorded rotations (`run data/scenes/fourbar.toml --ensemble 16 --rotations 10 --seed
    /// 2`: 9 members at 3, 6 at 3.5, 1 at 4) split into "low 9/16 3 ± 0, high 7/16 3.57 ± 0.19"
    /// without the quantum, the gap of one onset 4.0 pooled sds (bound 4); the contact-law
    /// study's hunt-crossley onsets (14 at 0, 0.5 and 1) into "high 2/16 0.75 ± 0.35"; a 0-or-1
    /// flag of 12 and 4 members into its two values.
    #[test]
    fn a_count_splits_only_across_an_empty_level() {
        for (v, quantum) in [
            (level(&[(3.0, 9), (3.5, 6), (4.0, 1)]), 0.5),
            (level(&[(0.0, 14), (0.5, 1), (1.0, 1)]), 0.5),
            (level(&[(0.0, 12), (1.0, 4)]), 1.0),
        ] {
            assert!(States::of(&v).split(), "{v:?}");
            let s = States::of_quantised(&v, quantum);
            assert!(!s.split(), "{v:?}: {s:?}");
            assert_eq!(s.pooled, States::of(&v).pooled);
        }
        // 0 onsets per rotation in 12 members, 3 in 4, nothing at 0.5 to 2.5 (the contact-law
        // study's paper law, standard case): two states, as without the quantum
        let v = level(&[(0.0, 6), (3.0, 4), (0.0, 6)]);
        let s = States::of_quantised(&v, 0.5);
        assert_eq!(s, States::of(&v));
        assert_eq!(s.states[1].members, [6, 7, 8, 9]);
        // two levels with one empty between them split, however the division rounded: 10
        // members at 1 onset over 10 rotations, 6 at 3 (0.3 − 0.1 is 0.19999999999999998)
        let v = level(&[(1.0 / 10.0, 10), (3.0 / 10.0, 6)]);
        assert!(States::of_quantised(&v, 1.0 / 10.0).split());
        // and a gap of two levels is judged by the spreads as before: 0-2 per rotation in 14,
        // 3 and 3.5 in two, 2.1 pooled sds (bound 4 at 16 members)
        let v = level(&[(0.0, 5), (0.5, 5), (1.0, 3), (2.0, 1), (3.0, 1), (3.5, 1)]);
        assert!(!States::of_quantised(&v, 0.5).split());
    }

    /// Deepest sectors of four members within 1° of 46°, of twelve scattered over 120-200°:
    /// two regions, though the gap of 73° is 3.1 pooled sds (the scattered twelve's) against
    /// 4. Failed with the pooled bound alone (one state). A gap under 10° stays one region
    /// however narrow the sides.
    #[test]
    fn angles_of_a_narrow_region_beside_a_scattered_one_split() {
        let scattered = (0..12).map(|i| 120.0 + 80.0 * i as f64 / 11.0);
        let narrow = [46.0, 46.5, 47.0, 46.0];
        let s = States::of_angles_deg(narrow.into_iter().chain(scattered.clone()));
        assert!(s.gap_ratio < gap_over_spread(16), "{s:?}");
        let (low, high) = s.low_high().expect("two regions");
        assert_eq!(
            (low.members.clone(), high.distribution.n),
            (vec![0, 1, 2, 3], 12)
        );
        assert_relative_eq!(low.distribution.mean, 46.375, max_relative = 1e-12);
        // four within 0.3° and twelve within 1.1°, 9.6° apart: one region
        let near = [184.0, 184.1, 184.2, 184.3];
        let far = (0..12).map(|i| 193.9 + 0.1 * i as f64);
        let s = States::of_angles_deg(near.into_iter().chain(far));
        assert!(s.side_gap_ratio > gap_over_side_spread(16), "{s:?}");
        assert!(!s.split(), "{s:?}");
    }

    #[test]
    fn a_lone_outlier_or_identical_values_make_no_state() {
        // one member far off: below the minimum state size of 2
        let s = States::of(&[1.0, 1.1, 0.9, 1.05, 0.95, 3.0]);
        assert!(!s.split());
        assert_eq!(s.states[0].members.len(), 6);
        assert!(!States::of(&[2.0; 8]).split());
        assert!(!States::of(&[1.0, 2.0, 3.0]).split());
        // non-finite values belong to no state
        let s = States::of(&[1.0, f64::NAN, 1.0, 5.0, 5.0]);
        assert!(s.split());
        assert_eq!(s.states[1].members, vec![3, 4]);
        assert_eq!(s.pooled.n, 4);
        // No finite value (nothing recorded): no state, every state column empty. Was one
        // state of no members, `states` 1 beside n = 0.
        for none in [States::of(&[f64::NAN; 3]), States::of_angles_deg([])] {
            assert!(none.states.is_empty(), "{none:?}");
            assert_eq!(none.values(), [None; 7]);
            assert_eq!(none.cells(|x| x.to_string()), [""; 7]);
            assert_eq!(none.describe(1.0, 2), "no state");
        }
    }

    #[test]
    fn unimodal_samples_rarely_split() {
        // 400 exponential samples of 32 (the most skewed distribution the constant was chosen
        // on: 2.3 % split). Checked to fail: with GAP_OVER_SPREAD = 1, 111 of the 400 split;
        // with a minimum state of 2 members instead of ⌈n/10⌉, 47.
        let mut u = uniforms(11);
        let split = (0..400)
            .filter(|_| {
                let v: Vec<f64> = (0..32).map(|_| -u().ln()).collect();
                States::of(&v).split()
            })
            .count();
        assert!(split <= 20, "{split} of 400 unimodal samples split");
        // and two states 8 sd apart, 5 of 32 in the lower, are found nearly always
        let mut u = uniforms(12);
        let mut normal = move || (-2.0 * u().ln()).sqrt() * (std::f64::consts::TAU * u()).cos();
        let found = (0..100)
            .filter(|_| {
                let v: Vec<f64> = (0..32)
                    .map(|i| if i < 5 { 0.0 } else { 8.0 } + normal())
                    .collect();
                States::of(&v).split() && States::of(&v).states[0].members == [0, 1, 2, 3, 4]
            })
            .count();
        assert!(found >= 95, "{found} of 100 bimodal samples split rightly");
    }

    /// Smaller ensembles than the 32 the constant was chosen on (`run --ensemble 4`, 8 or 16,
    /// the contact-law study's 16) split unimodal samples as rarely. Failed with the gap held
    /// to 2 pooled sds at every size: of 400 draws, exponential 81 split at 16 members, 119 at
    /// 8 and 108 at 4, normal 16, 98 and 99 ("two states: low 2 of 4 …, high 2 of 4" for the
    /// standard scene's deepest wear, one state in its 16 and 32 members).
    #[test]
    fn small_ensembles_of_unimodal_samples_rarely_split() {
        let mut u = uniforms(13);
        for n in [4, 8, 16] {
            let mut exponential = || -u().ln();
            let split = (0..400)
                .filter(|_| States::of(&(0..n).map(|_| exponential()).collect::<Vec<_>>()).split())
                .count();
            assert!(
                split <= 16,
                "{split} of 400 exponential samples of {n} split"
            );
            let mut normal = || (-2.0 * u().ln()).sqrt() * (std::f64::consts::TAU * u()).cos();
            let split = (0..400)
                .filter(|_| States::of(&(0..n).map(|_| normal()).collect::<Vec<_>>()).split())
                .count();
            assert!(split <= 8, "{split} of 400 normal samples of {n} split");
        }
        // and states 12 sd apart, 3 of 16 in the lower, are still found nearly always
        let mut normal = || (-2.0 * u().ln()).sqrt() * (std::f64::consts::TAU * u()).cos();
        let found = (0..100)
            .filter(|_| {
                let v: Vec<f64> = (0..16)
                    .map(|i| if i < 3 { 0.0 } else { 12.0 } + normal())
                    .collect();
                States::of(&v)
                    .states
                    .first()
                    .is_some_and(|s| s.members == [0, 1, 2])
            })
            .count();
        assert!(
            found >= 95,
            "{found} of 100 bimodal samples of 16 split rightly"
        );
    }
}
