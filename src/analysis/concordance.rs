//! Index of concordance between wear-rate drivers (paper section 6.4, Table 3).
//!
//! The cosine matching function (CMF) of two series sampled on one uniform time grid:
//! ```text
//! CMF(x, y) = Σ xᵢ yᵢ / sqrt(Σ xᵢ² · Σ yᵢ²)
//! ```
//! Table 3 evaluates it between the contact pressure P and the wear rate w (P-w), and between
//! the incremental sliding distance s and the wear rate (s-w), over the two recorded rotations,
//! with every series zero where the journal flies free. Here P is the peak contact pressure of
//! the pressure model, s is `|v_t| Δt` per grid interval, and w is `k P |v_t| / H`.
//!
//! The paper cites the CMF without its formula. Besides this reading, [`centred_cmf`] gives the
//! second plausible one, the CMF of the mean-removed series (Pearson's correlation); both are
//! reported so the reader can see which matches Table 3.

/// Cosine matching function of two equally long series; 0 if either is all zeros.
pub fn cmf(x: &[f64], y: &[f64]) -> f64 {
    let (mut xy, mut xx, mut yy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        xy += a * b;
        xx += a * a;
        yy += b * b;
    }
    if xx > 0.0 && yy > 0.0 {
        xy / (xx * yy).sqrt()
    } else {
        0.0
    }
}

/// CMF of the mean-removed series (Pearson's correlation coefficient).
pub fn centred_cmf(x: &[f64], y: &[f64]) -> f64 {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let (mx, my) = (mean(x), mean(y));
    let xc: Vec<f64> = x.iter().map(|a| a - mx).collect();
    let yc: Vec<f64> = y.iter().map(|b| b - my).collect();
    cmf(&xc, &yc)
}

/// Concordances of one recorded run of a clearance joint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Concordance {
    /// CMF(P, w).
    pub pressure_wear: f64,
    /// CMF(s, w).
    pub sliding_wear: f64,
    /// Centred CMF(P, w).
    pub pressure_wear_centred: f64,
    /// Centred CMF(s, w).
    pub sliding_wear_centred: f64,
}

impl Concordance {
    /// From pressure (Pa), sliding velocity (m/s) and wear rate (m/s) on a grid of step `dt`.
    pub fn of(
        pressure: &[f64],
        sliding_velocity: &[f64],
        wear_rate: &[f64],
        dt: f64,
    ) -> Concordance {
        let sliding: Vec<f64> = pressure
            .iter()
            .zip(sliding_velocity)
            .map(|(p, v)| if *p > 0.0 { v.abs() * dt } else { 0.0 })
            .collect();
        Concordance {
            pressure_wear: cmf(pressure, wear_rate),
            sliding_wear: cmf(&sliding, wear_rate),
            pressure_wear_centred: centred_cmf(pressure, wear_rate),
            sliding_wear_centred: centred_cmf(&sliding, wear_rate),
        }
    }

    /// Which factor dominates the wear rate: "P-w" or "s-w".
    pub fn dominant(&self) -> &'static str {
        if self.pressure_wear > self.sliding_wear {
            "P-w"
        } else {
            "s-w"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn identical_and_proportional_series_match_fully() {
        let x = [0.0, 1.0, 2.0, 0.5];
        assert_relative_eq!(cmf(&x, &x), 1.0);
        let y: Vec<f64> = x.iter().map(|v| 3.0 * v).collect();
        assert_relative_eq!(cmf(&x, &y), 1.0);
        assert_eq!(cmf(&x, &[0.0; 4]), 0.0);
    }

    #[test]
    fn orthogonal_series_do_not_match() {
        assert_relative_eq!(cmf(&[1.0, 0.0, 1.0, 0.0], &[0.0, 1.0, 0.0, 1.0]), 0.0);
        // centred: anti-correlated
        assert_relative_eq!(
            centred_cmf(&[1.0, 0.0, 1.0, 0.0], &[0.0, 1.0, 0.0, 1.0]),
            -1.0
        );
    }

    #[test]
    fn constant_sliding_makes_pressure_the_only_driver() {
        // w = k P v / H with constant v: w is proportional to P, and s is a constant that
        // only partly matches the varying w.
        let p = [1.0, 5.0, 2.0, 8.0, 0.5];
        let v = [2.0; 5];
        let w: Vec<f64> = p.iter().zip(&v).map(|(a, b)| 1e-12 * a * b).collect();
        let c = Concordance::of(&p, &v, &w, 1e-3);
        assert_relative_eq!(c.pressure_wear, 1.0, max_relative = 1e-12);
        assert!(c.sliding_wear < 0.9);
        assert_eq!(c.dominant(), "P-w");
    }
}
