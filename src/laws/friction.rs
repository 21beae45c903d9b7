//! Tangential friction in a clearance joint: modified Coulomb law (paper eq. 4).
//!
//! ```text
//! μ(V) = μ_s sin(π|V| / (2V_s))                                     |V| < V_s
//!      = (μ_s + μ_d)/2 + (μ_s − μ_d)/2 · cos(π (|V| − V_s)/(V_d − V_s))   V_s ≤ |V| ≤ V_d
//!      = μ_d                                                        |V| > V_d
//! F_t  = −μ(V) F_n sign(V)
//! ```
//! μ is continuous at V_s and V_d and zero at V = 0, which avoids the stick-slip jump of
//! plain Coulomb friction ([`FrictionModel::Coulomb`], kept for comparison: it is
//! discontinuous at V = 0 and makes an adaptive integrator crawl through sticking).

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Friction law of a clearance joint (SI: velocities in m/s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum FrictionModel {
    /// Frictionless joint: no tangential force is computed at all.
    None,
    /// Plain Coulomb: `μ = mu` for any V ≠ 0.
    Coulomb {
        /// Friction coefficient μ.
        mu: f64,
    },
    /// Paper eq. 4.
    Modified {
        /// Static coefficient μ_s.
        mu_s: f64,
        /// Dynamic coefficient μ_d.
        mu_d: f64,
        /// Stiction velocity v_s (m/s).
        v_s: f64,
        /// Velocity v_d (m/s) above which μ = μ_d.
        v_d: f64,
    },
}

impl FrictionModel {
    /// Friction coefficient at relative tangential speed `v` (m/s, any sign).
    #[inline]
    pub fn coefficient(&self, v: f64) -> f64 {
        let v = v.abs();
        // By reference: copying the whole law out costs as much as the arithmetic.
        match self {
            FrictionModel::None => 0.0,
            &FrictionModel::Coulomb { mu } => {
                if v > 0.0 {
                    mu
                } else {
                    0.0
                }
            }
            &FrictionModel::Modified {
                mu_s,
                mu_d,
                v_s,
                v_d,
            } => {
                if v > v_d {
                    mu_d
                } else if v < v_s {
                    mu_s * (0.5 * PI * v / v_s).sin()
                } else {
                    0.5 * (mu_s + mu_d) + 0.5 * (mu_s - mu_d) * (PI * (v - v_s) / (v_d - v_s)).cos()
                }
            }
        }
    }

    /// Tangential force (N) on the journal along the tangent for sliding velocity `v`
    /// (journal relative to bearing along the same tangent): it opposes `v`.
    #[inline]
    pub fn force(&self, normal_force: f64, v: f64) -> f64 {
        -self.coefficient(v) * normal_force * v.signum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const LAW: FrictionModel = FrictionModel::Modified {
        mu_s: 0.15,
        mu_d: 0.1,
        v_s: 1e-4,
        v_d: 1e-3,
    };

    #[test]
    fn continuous_at_the_switch_velocities() {
        for v in [1e-4, 1e-3] {
            let below = LAW.coefficient(v * (1.0 - 1e-9));
            let above = LAW.coefficient(v * (1.0 + 1e-9));
            assert_relative_eq!(below, above, epsilon = 1e-7);
        }
        assert_relative_eq!(LAW.coefficient(1e-4), 0.15);
        assert_relative_eq!(LAW.coefficient(1e-3), 0.1);
        assert_eq!(LAW.coefficient(0.0), 0.0);
        assert_relative_eq!(LAW.coefficient(5.0), 0.1);
    }

    #[test]
    fn force_opposes_sliding() {
        for v in [-2.0, -5e-4, -1e-5, 1e-5, 5e-4, 2.0] {
            let f = LAW.force(100.0, v);
            assert!(f * v < 0.0, "v = {v}, f = {f}");
            assert!(f.abs() <= 0.15 * 100.0 + 1e-12);
        }
        assert_eq!(FrictionModel::None.force(100.0, 1.0), 0.0);
        assert_relative_eq!(FrictionModel::Coulomb { mu: 0.2 }.force(50.0, -3.0), 10.0);
    }
}
