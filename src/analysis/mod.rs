//! Analysis of simulated results: wear regions on the circular profile, motion mode of the
//! journal, and cycle-to-cycle steady state; along a long life, the [`life`] changes; over
//! ensembles, [`statistics`], the [`states`]
//! members fall into, and [`significance`] tests of two ensembles' difference.
//!
//! * **Wear regions** ([`regions`]): the humps of the circular wear profile by topographic
//!   prominence, the one definition every output uses.
//! * **Motion mode** (Table 3's "free flight and impact" or "continuous contact"): the
//!   fraction of recorded time in contact, contact onsets per rotation, and the mean
//!   free-flight time. Rule: continuous contact when the journal is in contact at least
//!   [`CONTINUOUS_CONTACT_FRACTION`] of the time, otherwise free flight and impact. This is the
//!   one classification of a run's motion: every table, figure line and claim of the report
//!   uses [`Motion::continuous`] / [`Motion::mode`], never a threshold of its own.

pub mod concordance;
pub mod life;
pub mod regions;
pub mod significance;
pub mod states;
pub mod statistics;

/// The motion modes [`Motion::mode`] names, continuous contact first: what a sweep file's
/// `motion_mode` column may hold.
pub const MOTION_MODES: [&str; 2] = ["continuous contact", "free flight and impact"];

/// In-contact time fraction at or above which a run is "continuous contact".
pub const CONTINUOUS_CONTACT_FRACTION: f64 = 0.9;

/// Journal motion over the recorded rotations.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Motion {
    /// Fraction of recorded samples in contact (δ ≥ 0).
    pub contact_fraction: f64,
    /// Contact onsets per driver rotation.
    pub impacts_per_rotation: f64,
    /// Mean duration (s) of the free-flight intervals that begin and end inside the window
    /// (a contact sample before and after): a flight cut by the window's start or end has no
    /// known duration and is left out. NaN if there is none (`null` in JSON, which has no
    /// NaN, and read back as NaN: a member's summary crosses processes as JSON).
    #[serde(deserialize_with = "null_as_nan")]
    pub mean_flight_time: f64,
}

/// A number that JSON wrote as `null` (serde_json's NaN) read back as NaN.
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

impl Motion {
    /// Classifies a penetration series sampled every `dt` seconds over `rotations` rotations.
    pub fn classify(delta: &[f64], dt: f64, rotations: f64) -> Motion {
        let contact = delta.iter().filter(|&&d| d >= 0.0).count();
        let onsets = delta
            .windows(2)
            .filter(|w| w[0] < 0.0 && w[1] >= 0.0)
            .count();
        // Flights closed on both sides: the samples from the first contact's end to the last
        // contact's start, less those in contact there.
        let (mut flights, mut flight_samples) = (0, 0);
        if let (Some(first), Some(last)) = (
            delta.iter().position(|&d| d >= 0.0),
            delta.iter().rposition(|&d| d >= 0.0),
        ) {
            let inner = &delta[first..=last];
            flights = inner
                .windows(2)
                .filter(|w| w[0] >= 0.0 && w[1] < 0.0)
                .count();
            flight_samples = inner.iter().filter(|&&d| d < 0.0).count();
        }
        Motion {
            contact_fraction: contact as f64 / delta.len().max(1) as f64,
            impacts_per_rotation: onsets as f64 / rotations,
            mean_flight_time: if flights > 0 {
                flight_samples as f64 * dt / flights as f64
            } else {
                f64::NAN
            },
        }
    }

    /// Whether the motion is continuous contact: in contact at least
    /// [`CONTINUOUS_CONTACT_FRACTION`] of the time (brief separations, contact onsets, allowed).
    pub fn continuous(&self) -> bool {
        self.contact_fraction >= CONTINUOUS_CONTACT_FRACTION
    }

    /// "continuous contact" or "free flight and impact" ([`MOTION_MODES`],
    /// [`Motion::continuous`]).
    pub fn mode(&self) -> &'static str {
        MOTION_MODES[usize::from(!self.continuous())]
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
        // A flight cut by the window (5 samples before the first contact, 4 after the last)
        // has no known duration: only the two closed ones (2 and 6 samples) count. Counting
        // every free sample over the flights that end inside, as before, gave 17/3.
        let mut delta = vec![-1.0; 5];
        for run in [(3, 2), (1, 6), (2, 4)] {
            delta.extend(std::iter::repeat_n(1.0, run.0));
            delta.extend(std::iter::repeat_n(-1.0, run.1));
        }
        let cut = Motion::classify(&delta, 1.0, 1.0);
        assert_relative_eq!(cut.mean_flight_time, 4.0);
        assert_eq!(cut.impacts_per_rotation, 3.0);
        assert!(cont.mean_flight_time.is_nan());
        // Through JSON, as a member's summary crosses processes (NaN failed to read back).
        for m in [cont, cut] {
            let back: Motion = serde_json::from_str(&serde_json::to_string(&m).unwrap()).unwrap();
            assert_eq!(
                back.mean_flight_time.to_bits(),
                m.mean_flight_time.to_bits()
            );
        }
    }
}
