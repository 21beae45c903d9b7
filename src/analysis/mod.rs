//! Analysis of simulated results: wear peaks on the circular profile, motion mode of the
//! journal, and cycle-to-cycle steady state; over ensembles, [`statistics`], the [`states`]
//! members fall into, and [`significance`] tests of two ensembles' difference.
//!
//! * **Peaks** are local maxima of the circular sector profile ranked by depth; each carries
//!   its topographic prominence (depth above the higher of the two lowest points separating
//!   it from a deeper peak, or from itself around the circle) and its full width at half
//!   prominence. Peaks whose prominence is below `min_prominence` × the deepest depth are
//!   dropped, so sector-scale ripples are not reported as wear regions.
//! * **Motion mode** (Table 3's "free flight and impact" or "continuous contact"): the
//!   fraction of recorded time in contact, contact onsets per rotation, and the mean
//!   free-flight time. Rule: continuous contact when the journal is in contact at least
//!   [`CONTINUOUS_CONTACT_FRACTION`] of the time, otherwise free flight and impact. This is the
//!   one classification of a run's motion: every table, figure line and claim of the report
//!   uses [`Motion::continuous`] / [`Motion::mode`], never a threshold of its own.

pub mod concordance;
pub mod significance;
pub mod states;
pub mod statistics;

/// A wear region on the bearing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// Index of the deepest sector.
    pub sector: usize,
    /// Angle of the deepest sector (deg, counter-clockwise from the bearing's +x).
    pub angle_deg: f64,
    /// Wear depth at the peak (m).
    pub depth: f64,
    /// Prominence (m).
    pub prominence: f64,
    /// Full width at half prominence (deg).
    pub width_deg: f64,
}

/// Minimum prominence of a reported wear peak, as a fraction of the deepest wear: the
/// threshold the reproduction and `jointwear sweep` use.
pub const PEAK_PROMINENCE: f64 = 0.05;

/// Peaks of a circular profile `depths` (sector i centred at (i + 0.5)·360/N deg), deepest first.
pub fn peaks(depths: &[f64], min_prominence: f64) -> Vec<Peak> {
    let n = depths.len();
    let top = depths.iter().cloned().fold(0.0, f64::max);
    if n < 3 || top <= 0.0 {
        return Vec::new();
    }
    let width = 360.0 / n as f64;
    let at = |i: isize| depths[i.rem_euclid(n as isize) as usize];
    let mut found = Vec::new();
    for i in 0..n as isize {
        let d = at(i);
        // a plateau counts once, at its first sector
        if !(d > at(i - 1) && d >= at(i + 1)) {
            continue;
        }
        // walk each way until a deeper point (or all around), tracking the lowest point
        let walk = |dir: isize| {
            let mut low = d;
            for k in 1..n as isize {
                let v = at(i + dir * k);
                if v > d {
                    break;
                }
                low = low.min(v);
            }
            low
        };
        let prominence = d - walk(-1).max(walk(1));
        if prominence < min_prominence * top {
            continue;
        }
        let half = d - 0.5 * prominence;
        let extent = |dir: isize| {
            (1..n as isize)
                .take_while(|&k| at(i + dir * k) > half)
                .count() as f64
        };
        found.push(Peak {
            sector: i as usize,
            angle_deg: (i as f64 + 0.5) * width,
            depth: d,
            prominence,
            width_deg: (1.0 + extent(-1) + extent(1)) * width,
        });
    }
    found.sort_by(|a, b| b.depth.total_cmp(&a.depth));
    found
}

/// In-contact time fraction at or above which a run is "continuous contact".
pub const CONTINUOUS_CONTACT_FRACTION: f64 = 0.9;

/// Journal motion over the recorded rotations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Fraction of recorded samples in contact (δ ≥ 0).
    pub contact_fraction: f64,
    /// Contact onsets per driver rotation.
    pub impacts_per_rotation: f64,
    /// Mean duration of free-flight intervals (s), 0 if none.
    pub mean_flight_time: f64,
}

impl Motion {
    /// Classifies a penetration series sampled every `dt` seconds over `rotations` rotations.
    pub fn classify(delta: &[f64], dt: f64, rotations: f64) -> Motion {
        let contact = delta.iter().filter(|&&d| d >= 0.0).count();
        let onsets = delta
            .windows(2)
            .filter(|w| w[0] < 0.0 && w[1] >= 0.0)
            .count();
        let flights = delta
            .windows(2)
            .filter(|w| w[0] >= 0.0 && w[1] < 0.0)
            .count();
        let flight_samples = delta.len() - contact;
        Motion {
            contact_fraction: contact as f64 / delta.len().max(1) as f64,
            impacts_per_rotation: onsets as f64 / rotations,
            mean_flight_time: if flights > 0 {
                flight_samples as f64 * dt / flights as f64
            } else {
                0.0
            },
        }
    }

    /// Whether the motion is continuous contact: in contact at least
    /// [`CONTINUOUS_CONTACT_FRACTION`] of the time (brief separations, contact onsets, allowed).
    pub fn continuous(&self) -> bool {
        self.contact_fraction >= CONTINUOUS_CONTACT_FRACTION
    }

    /// "continuous contact" or "free flight and impact" ([`Motion::continuous`]).
    pub fn mode(&self) -> &'static str {
        if self.continuous() {
            "continuous contact"
        } else {
            "free flight and impact"
        }
    }
}

/// Angle (deg, sector centre of 360) that collects most of the recorded wear `rate · dt`.
pub fn wear_location(theta: &[f64], rate: &[f64]) -> f64 {
    let mut bins = [0.0; 360];
    for (t, r) in theta.iter().zip(rate) {
        bins[(t.to_degrees() as usize).min(359)] += r;
    }
    let (i, _) = bins
        .iter()
        .enumerate()
        .fold((0, 0.0), |a, (i, &v)| if v > a.1 { (i, v) } else { a });
    i as f64 + 0.5
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn bumps(centres: &[(f64, f64)]) -> Vec<f64> {
        (0..360)
            .map(|i| {
                let a = i as f64 + 0.5;
                centres
                    .iter()
                    .map(|&(c, h)| {
                        let d = ((a - c + 180.0).rem_euclid(360.0)) - 180.0;
                        h * (-(d / 10.0).powi(2)).exp()
                    })
                    .sum()
            })
            .collect()
    }

    #[test]
    fn finds_three_regions_deepest_first_across_the_seam() {
        // bumps centred on sector centres, so no two sectors tie for the top
        let p = peaks(&bumps(&[(50.5, 1.0), (180.5, 3.0), (355.5, 2.0)]), 0.05);
        assert_eq!(p.len(), 3);
        let angles: Vec<f64> = p.iter().map(|p| p.angle_deg).collect();
        assert_eq!(angles, vec![180.5, 355.5, 50.5]);
        // Gaussian of σ = 10/√2 deg: full width at half maximum 2·sqrt(ln 2)·10 ≈ 16.7 deg
        assert!((p[0].width_deg - 16.7).abs() <= 1.0, "{:?}", p[0]);
        assert_relative_eq!(p[0].depth, 3.0, max_relative = 1e-2);
    }

    #[test]
    fn ripples_are_not_peaks() {
        let mut d = bumps(&[(90.0, 1.0)]);
        for (i, x) in d.iter_mut().enumerate() {
            *x += 1e-3 * ((i as f64) * 2.0).sin();
        }
        assert_eq!(peaks(&d, 0.05).len(), 1);
        assert!(peaks(&[0.0; 36], 0.05).is_empty());
    }

    #[test]
    fn motion_modes() {
        let cont = Motion::classify(&[1.0; 100], 1e-3, 1.0);
        assert_eq!(cont.mode(), "continuous contact");
        let delta: Vec<f64> = (0..100)
            .map(|i| if i % 10 < 3 { 1.0 } else { -1.0 })
            .collect();
        let imp = Motion::classify(&delta, 1e-3, 2.0);
        assert_eq!(imp.mode(), "free flight and impact");
        assert_relative_eq!(imp.impacts_per_rotation, 4.5);
        assert_relative_eq!(imp.mean_flight_time, 7e-3, max_relative = 1e-9);
    }
}
