//! Archard wear on a sectored bearing profile (paper eq. 5-9).
//!
//! ```text
//! V_w / s = k F_n / H                     (5)
//! dh / ds = k P / H                       (8; eq. 7 of the paper drops P)
//! h_i = h_(i−1) + k P_i Δs_i / H          (9)
//! ```
//! The bearing surface is split into `N` equal sectors (sector `i` spans
//! `[i, i+1)·2π/N`, angles counter-clockwise from the bearing body's +x axis). On every
//! accepted time step with contact, the pressure distribution `p(φ)` around the contact
//! angle is integrated exactly over each sector it covers, so each sector's depth grows by
//! the sector mean of `k p(φ) Δs / H`. This conserves the Archard volume `k F Δs / H`
//! (per unit length) however narrow the contact arc is compared with a sector.
//!
//! The depth between sector centres is a periodic Catmull-Rom spline, which is C¹: the gap
//! `δ = |e| − c − h(θ)` and its rate stay continuous, so the integrator does not crawl over
//! sector edges.
//!
//! Contact pressure from F_n (the paper does not say; both candidates of the notes):
//! * [`PressureModel::HertzLine`]: Hertz line contact of internal cylinders,
//!   `R* = R_i R_j/(R_i − R_j)`, `b = sqrt(4 F R* / (π L E*))`, `p_max = 2F/(π b L)`,
//!   semi-elliptic over the arc half-angle `b / R_i`.
//! * [`PressureModel::ElasticFoundation`]: Winkler overlap of the two circles,
//!   `u(φ) = (ΔR + δ) cos φ − ΔR` for `|φ| ≤ φ₀ = arccos(ΔR/(ΔR + δ))`, `p = C u`, with C
//!   such that the resultant `∫ p cos φ R_i L dφ` equals F.

use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Sector centre angles (deg) of a profile with `n` sectors: sector `i` is centred at
/// `(i + 0.5)·360/n` deg.
pub fn sector_angles_deg(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| (i as f64 + 0.5) * 360.0 / n as f64)
        .collect()
}

/// Contact pressure distribution model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PressureModel {
    /// Hertz line contact of two cylinders (module documentation).
    HertzLine,
    /// Winkler overlap of the two circles (module documentation).
    ElasticFoundation,
}

/// Wear law of one bearing: Archard coefficient, pressure model and the geometry it needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WearLaw {
    /// k/H (1/Pa).
    pub k_over_h: f64,
    /// Contact pressure model.
    pub pressure: PressureModel,
    /// Bearing length L (m).
    pub length: f64,
    /// Compound modulus E* (Pa).
    pub e_star: f64,
    /// Bearing radius R_i (m).
    pub r_bearing: f64,
    /// Journal radius R_j (m).
    pub r_journal: f64,
}

/// Pressure distribution of one contact: peak pressure and angular half-width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pressure {
    /// Peak contact pressure (Pa): the `P` of eq. 9 at the contact centre.
    pub peak: f64,
    /// Half-angle of the contact arc on the bearing (rad).
    pub half_angle: f64,
    shape: Shape,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Shape {
    /// `p = peak · sqrt(1 − (φ/φ₀)²)`.
    SemiEllipse,
    /// `p = peak · ((ΔR+δ) cos φ − ΔR) / δ`.
    Overlap { delta_r: f64, delta: f64 },
}

impl WearLaw {
    /// Pressure for normal force `force` (N), penetration `delta` (m), local radial
    /// clearance `delta_r` (m, includes wear).
    pub fn pressure(&self, force: f64, delta: f64, delta_r: f64) -> Pressure {
        match self.pressure {
            PressureModel::HertzLine => {
                let r_star = self.r_bearing * self.r_journal / (self.r_bearing - self.r_journal);
                let b = (4.0 * force * r_star / (PI * self.length * self.e_star)).sqrt();
                let peak = if b > 0.0 {
                    2.0 * force / (PI * b * self.length)
                } else {
                    0.0
                };
                Pressure {
                    peak,
                    half_angle: b / self.r_bearing,
                    shape: Shape::SemiEllipse,
                }
            }
            PressureModel::ElasticFoundation => {
                let a = delta_r + delta;
                let phi0 = (delta_r / a).acos();
                let (s, c) = phi0.sin_cos();
                // ∫_{−φ0}^{φ0} u(φ) cos φ dφ
                let integral = a * (phi0 + s * c) - 2.0 * delta_r * s;
                let peak = if integral > 0.0 {
                    force * delta / (self.r_bearing * self.length * integral)
                } else {
                    0.0
                };
                Pressure {
                    peak,
                    half_angle: phi0,
                    shape: Shape::Overlap { delta_r, delta },
                }
            }
        }
    }
}

impl Pressure {
    /// ∫₀^φ p dφ' / peak for |φ| ≤ min(half_angle, π) (odd in φ).
    #[inline(always)]
    fn signed_primitive(&self, phi: f64) -> f64 {
        match self.shape {
            // ½ φ₀ (x √(1 − x²) + asin x), x = φ/φ₀ ∈ [−1, 1] as |φ| ≤ φ₀, so 1 − x² ≥ 0.
            Shape::SemiEllipse => {
                let x = phi / self.half_angle;
                0.5 * self.half_angle * (x * (1.0 - x * x).sqrt() + asin(x))
            }
            Shape::Overlap { delta_r, delta } => {
                ((delta_r + delta) * phi.sin() - delta_r * phi) / delta
            }
        }
    }

    /// ∫ p dφ / peak over [a, b] (rad, relative to the contact centre, a ≤ b).
    #[cfg(test)]
    fn integral(&self, a: f64, b: f64) -> f64 {
        let h = self.half_angle;
        self.signed_primitive(b.clamp(-h, h)) - self.signed_primitive(a.clamp(-h, h))
    }
}

/// asin x for |x| ≤ 1, within 2 ulp of libm's (unit test): fdlibm's `e_asin.c` rational
/// approximation inlined, without its extra-precise split of √((1−|x|)/2), since the wear
/// update calls it once per sector edge and libm's costs four times as many instructions.
#[inline(always)]
fn asin(x: f64) -> f64 {
    // asin a = a + a·R(a²) for a < 0.5, with R(t) = t·P(t)/Q(t) (fdlibm's pS0-pS5, qS1-qS4).
    fn r(t: f64) -> f64 {
        let p = t
            * (0.16666666666666666
                + t * (-0.3255658186224009
                    + t * (0.20121253213486293
                        + t * (-0.04005553450067941
                            + t * (0.0007915349942898145 + t * 3.479331075960212e-05)))));
        let q = 1.0
            + t * (-2.403394911734414
                + t * (2.0209457602335057 + t * (-0.6882839716054533 + t * 0.07703815055590194)));
        p / q
    }
    // The low part of π/2 − FRAC_PI_2.
    const PIO2_LO: f64 = 6.123233995736766e-17;
    let a = x.abs();
    let y = if a < 0.5 {
        a + a * r(a * a)
    } else {
        // asin a = π/2 − 2 asin √((1 − a)/2), exact reduction for a ≥ 0.5.
        let t = 0.5 * (1.0 - a);
        let s = t.sqrt();
        FRAC_PI_2 - (2.0 * (s + s * r(t)) - PIO2_LO)
    };
    y.copysign(x)
}

/// `theta` in [0, 2π], as `theta.rem_euclid(2π)` (to the last bit), without its `fmod` for
/// the angles a contact produces, which are at most one turn off.
#[inline]
pub fn wrap_angle(theta: f64) -> f64 {
    if (0.0..TAU).contains(&theta) {
        theta
    } else if (-TAU..0.0).contains(&theta) {
        theta + TAU
    } else {
        theta.rem_euclid(TAU)
    }
}

/// Wear depth of each sector of a bearing (m), with its smooth periodic interpolation.
#[derive(Clone, Debug, PartialEq)]
pub struct WearProfile {
    /// The N sector depths at `2..N + 2`, after copies of the last two and before copies of
    /// the first two: the spline reads four neighbours without wrapping an index.
    padded: Vec<f64>,
    width: f64,
    /// Sectors per radian, `N / 2π` (`1 / width` to rounding): the lookup of every evaluation
    /// multiplies instead of dividing (a division on the path from the contact angle to the
    /// force).
    per_width: f64,
}

impl WearProfile {
    /// An unworn profile of `sectors` sectors (≥ 4).
    pub fn new(sectors: usize) -> Self {
        WearProfile {
            padded: vec![0.0; sectors + 4],
            width: TAU / sectors as f64,
            per_width: sectors as f64 / TAU,
        }
    }

    fn sectors(&self) -> usize {
        self.padded.len() - 4
    }

    /// Sector depths (m), sector `i` centred at `(i + 0.5)·2π/N`.
    pub fn depths(&self) -> &[f64] {
        &self.padded[2..self.padded.len() - 2]
    }

    fn depths_mut(&mut self) -> &mut [f64] {
        let end = self.padded.len() - 2;
        &mut self.padded[2..end]
    }

    /// Copies the first and last two depths into the padding, after the depths changed.
    fn wrap_padding(&mut self) {
        let n = self.sectors();
        let p = &mut self.padded;
        (p[0], p[1], p[n + 2], p[n + 3]) = (p[n], p[n + 1], p[2], p[3]);
    }

    /// Replaces the depths (a resumed run); `false`, changing nothing, unless there is one
    /// finite, non-negative depth per sector.
    pub fn set_depths(&mut self, depths: &[f64]) -> bool {
        let fits =
            depths.len() == self.sectors() && depths.iter().all(|d| d.is_finite() && *d >= 0.0);
        if fits {
            self.depths_mut().copy_from_slice(depths);
            self.wrap_padding();
        }
        fits
    }

    /// Sector centre angles (rad).
    pub fn centres(&self) -> impl Iterator<Item = f64> + '_ {
        (0..self.sectors()).map(|i| (i as f64 + 0.5) * self.width)
    }

    /// Depth h(θ) (m) and slope dh/dθ (m/rad) at bearing angle `theta` (rad, any value).
    #[inline(always)]
    pub fn depth_at(&self, theta: f64) -> (f64, f64) {
        // u ∈ [0.5, N + 0.5]: the spline between the centres of sectors k − 1 and k (mod N),
        // whose neighbours are padded[k..k + 4]. A cast, not `floor` (a libm call without
        // SSE4.1), through i32 as its saturating cast is a third of usize's; the `min` keeps
        // the slice in bounds whatever θ's rounding.
        let u = wrap_angle(theta) * self.per_width + 0.5;
        let k = (u as i32 as usize).min(self.sectors());
        let t = u - k as f64;
        let p = &self.padded[k..k + 4];
        let (p0, p1, p2, p3) = (p[0], p[1], p[2], p[3]);
        let c1 = p2 - p0;
        let c2 = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3;
        let c3 = -p0 + 3.0 * (p1 - p2) + p3;
        // Estrin's pairs: h waits for t² and one product-sum, not three (Horner's).
        let h = 0.5 * ((2.0 * p1 + t * c1) + t * t * (c2 + t * c3));
        let dh = 0.5 * (c1 + t * (2.0 * c2 + 3.0 * t * c3)) * self.per_width;
        (h, dh)
    }

    /// The deepest sector depth (m), 0 for an unworn profile.
    pub fn deepest(&self) -> f64 {
        self.depths().iter().cloned().fold(0.0, f64::max)
    }

    /// The steepest the profile gets against the local clearance it sits on: the largest
    /// |dh/dθ| / (c + h) of the spline [`WearProfile::depth_at`] at the sector centres and
    /// edges (between them the spline's slope is a quadratic; two points a sector catch its
    /// peak within 5 % even for a lone worn sector, the sharpest feature there is, where the
    /// centres alone read 37 % of it), and that angle (rad), for radial clearance `clearance`
    /// (m).
    /// A flat profile is 0 however small the clearance; a NaN depth gives NaN.
    pub fn steepest(&self, clearance: f64) -> (f64, f64) {
        (0..2 * self.sectors())
            .map(|i| {
                let theta = 0.5 * i as f64 * self.width;
                let (h, slope) = self.depth_at(theta);
                let ratio = if slope == 0.0 {
                    0.0
                } else {
                    slope.abs() / (clearance + h)
                };
                (ratio, theta)
            })
            .fold(
                (0.0, 0.0),
                |a, b| if b.0 > a.0 || b.0.is_nan() { b } else { a },
            )
    }

    /// Adds the wear of sliding distance `ds` (m) under `pressure` centred at `theta` (rad):
    /// each covered sector grows by the sector mean of `k_over_h · p(φ) · ds`. Returns the
    /// deepest depth among the sectors it deepened (0 if none), so that a run can stop the
    /// moment wear leaves the model's validity.
    pub fn add_wear(&mut self, theta: f64, pressure: &Pressure, k_over_h: f64, ds: f64) -> f64 {
        let scale = k_over_h * pressure.peak * ds / self.width;
        // A NaN angle would cast to sector 0 and wear a whole arc there; the old walk added
        // nothing for it, and neither does this one.
        if scale <= 0.0 || !theta.is_finite() {
            return 0.0;
        }
        let n = self.sectors();
        let half = pressure.half_angle.min(PI);
        let theta = wrap_angle(theta);
        // Sectors first..=last cover the arc, counted from sector 0 one turn back so that the
        // casts floor (θ ∓ half ∈ [−π, 3π]); their inner edges first+1..=last lie inside it.
        let turn = n as f64;
        // (Through i32: its saturating cast is a third of usize's; sectors ≤ 36000.)
        let first = ((theta - half) / self.width + turn) as i32 as usize;
        let last = ((theta + half) / self.width + turn) as i32 as usize;
        // Adjacent sectors share an edge: the primitive is evaluated once per edge.
        let end = pressure.signed_primitive(half);
        let mut deepest = 0.0_f64;
        let mut deepen = |d: &mut f64, lo: f64, hi: f64| {
            if hi > lo {
                *d += scale * (hi - lo);
                deepest = if *d > deepest { *d } else { deepest };
            }
        };
        let mut i = first % n;
        let mut lo = -end;
        let mut k = (first + 1) as f64 - turn; // the next inner edge, in sector widths
        for _ in first..last {
            // Clamped: rounding must not take an inner edge outside the arc.
            let hi = pressure.signed_primitive((k * self.width - theta).clamp(-half, half));
            deepen(&mut self.padded[i + 2], lo, hi);
            lo = hi;
            k += 1.0;
            i = if i + 1 == n { 0 } else { i + 1 };
        }
        deepen(&mut self.padded[i + 2], lo, end);
        self.wrap_padding();
        deepest
    }

    /// Wear volume per unit bearing length (m²): Σ h_i R_i Δθ.
    pub fn area(&self, r_bearing: f64) -> f64 {
        self.depths().iter().sum::<f64>() * r_bearing * self.width
    }
}

impl WearProfile {
    /// Adds `scale · increments[i]` to the depth of sector `i` (m): the extrapolated wear of a
    /// block of rotations in [`crate::simulation::longlife`]. `increments` holds one value per sector,
    /// taken from a profile with the same sectors.
    pub fn add_depths(&mut self, increments: &[f64], scale: f64) {
        debug_assert_eq!(increments.len(), self.sectors());
        for (d, inc) in self.depths_mut().iter_mut().zip(increments) {
            *d += scale * inc;
        }
        self.wrap_padding();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// The update this module made before its own `asin`: libm's `asin` at every sector edge,
    /// `floor` and `rem_euclid` for the sectors. The oracle of `add_wear`.
    fn asin_formula_add_wear(
        depth: &mut [f64],
        theta: f64,
        p: &Pressure,
        k_over_h: f64,
        ds: f64,
    ) -> f64 {
        let primitive = |phi: f64| {
            let (sign, phi) = (phi.signum(), phi.abs().min(p.half_angle));
            sign * match p.shape {
                Shape::SemiEllipse if phi == p.half_angle => 0.25 * PI * p.half_angle,
                Shape::SemiEllipse => {
                    let x = phi / p.half_angle;
                    0.5 * p.half_angle * (x * (1.0 - x * x).max(0.0).sqrt() + x.asin())
                }
                Shape::Overlap { delta_r, delta } => {
                    ((delta_r + delta) * phi.sin() - delta_r * phi) / delta
                }
            }
        };
        let (n, width) = (depth.len(), TAU / depth.len() as f64);
        let scale = k_over_h * p.peak * ds / width;
        let mut deepest = 0.0_f64;
        if scale <= 0.0 {
            return deepest;
        }
        let half = p.half_angle.min(PI);
        let theta = wrap_angle(theta);
        let first = ((theta - half) / width).floor() as isize;
        let last = ((theta + half) / width).floor() as isize;
        let edge = |k: isize| (k as f64 * width - theta).clamp(-half, half);
        let mut lo = primitive(edge(first));
        for k in first..=last {
            let hi = primitive(edge(k + 1));
            if hi > lo {
                let d = &mut depth[k.rem_euclid(n as isize) as usize];
                *d += scale * (hi - lo);
                deepest = deepest.max(*d);
            }
            lo = hi;
        }
        deepest
    }

    /// Distance in units in the last place between two finite doubles of the same sign.
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    #[test]
    fn asin_is_within_2_ulp_of_libm() {
        // A dense grid of [0, 1], and arguments crowding to 0.5 (the reduction's switch) and
        // 1 (where the reduction cancels); 2 ulp is the worst found (19 % of the arguments
        // differ from libm at all). Injected error: pS5 = 3.48e-5 instead of 3.4793...e-5
        // fails with 28 564 ulp.
        let grid = (0..=400_000).map(|i| i as f64 / 400_000.0);
        let near = (1..=52).flat_map(|k| {
            let e = 2f64.powi(-k);
            [0.5 - e, 0.5 + e, 1.0 - e, e]
        });
        let worst = grid
            .chain(near)
            .map(|x| {
                assert_eq!(asin(-x), -asin(x));
                ulps(asin(x), x.asin())
            })
            .max()
            .unwrap();
        assert!(worst <= 2, "{worst} ulp");
    }

    #[test]
    fn sector_update_matches_the_asin_formula() {
        // Quasi-random contacts (a Kronecker sequence): centres over three turns, including
        // the 0/2π seam; arcs from 1/1000 of a sector to 3 rad; 8 to 36000 sectors; both
        // pressure shapes. Tolerance: 1e-12 of each sector's increment, plus 1e-15 of the
        // whole arc's (the oracle's own rounding: a sector's share is the difference of two
        // primitives of the arc's size, exact only to a few ulp of it; in the sector where
        // the arc ends after a sliver both primitives are nearly the whole arc's).
        // Injected errors, each failing: the edges at (k + 1e-9)·w (2e-9 relative in the first
        // case); the running index one sector late (a sector left at 0 against 4.4e-8 m); no
        // padding refreshed after the update (the seam's depth half the oracle's).
        let l = law(PressureModel::ElasticFoundation);
        let (k_over_h, ds) = (1e-12, 1e-3);
        let alpha = [0.754_877_666_246_693, 0.569_840_290_998_053];
        for i in 0..4000 {
            let u = alpha.map(|a| ((i + 1) as f64 * a).fract());
            let n = [8, 36, 360, 36000][i % 4];
            let theta = -TAU + 3.0 * TAU * u[0];
            let p = if i % 5 == 4 {
                l.pressure(400.0 * u[1] + 1e-3, 2e-6, 2e-5)
            } else {
                let width = TAU / n as f64;
                Pressure {
                    peak: 1e8,
                    half_angle: (1e-3 * width).max(3.0 * u[1].powi(3)),
                    shape: Shape::SemiEllipse,
                }
            };
            let mut prof = WearProfile::new(n);
            let mut oracle = vec![0.0; n];
            let deepest = prof.add_wear(theta, &p, k_over_h, ds);
            let oracle_deepest = asin_formula_add_wear(&mut oracle, theta, &p, k_over_h, ds);
            let arc = k_over_h * p.peak * ds * p.half_angle * n as f64;
            for (s, (new, old)) in prof.depths().iter().zip(&oracle).enumerate() {
                assert!(
                    (new - old).abs() <= 1e-12 * old + 1e-15 * arc,
                    "case {i}, sector {s} of {n}: {new:e} against {old:e}"
                );
            }
            assert_relative_eq!(
                deepest,
                oracle_deepest,
                max_relative = 1e-12,
                epsilon = 1e-15 * arc
            );
            // The padding follows the seam: Catmull-Rom's midpoint of sectors N − 1 and 0.
            let o = &oracle;
            let seam = (9.0 * (o[n - 1] + o[0]) - o[n - 2] - o[1]) / 16.0;
            assert_relative_eq!(
                prof.depth_at(0.0).0,
                seam,
                max_relative = 1e-12,
                epsilon = 1e-14 * arc
            );
        }
    }

    fn law(pressure: PressureModel) -> WearLaw {
        WearLaw {
            k_over_h: 1e-12,
            pressure,
            length: 0.02,
            e_star: 207e9 / 1.82,
            r_bearing: 0.01,
            r_journal: 0.00998,
        }
    }

    #[test]
    fn pressure_integrates_to_the_force() {
        for model in [PressureModel::HertzLine, PressureModel::ElasticFoundation] {
            let l = law(model);
            let (force, delta, dr) = (300.0, 2e-6, 2e-5);
            let p = l.pressure(force, delta, dr);
            // resultant = ∫ p cos φ R L dφ by the midpoint rule
            let m = 20000;
            let h = 2.0 * p.half_angle / m as f64;
            let resultant: f64 = (0..m)
                .map(|i| {
                    let phi = -p.half_angle + (i as f64 + 0.5) * h;
                    p.peak * p.integral(phi - 0.5 * h, phi + 0.5 * h) / h * phi.cos()
                })
                .sum::<f64>()
                * h
                * l.r_bearing
                * l.length;
            // Hertz's semi-ellipse integrates to F along the arc, so its cos-weighted resultant
            // falls short by about φ₀²/8 (0.1% for the 6 deg arc here).
            assert_relative_eq!(resultant, force, max_relative = 2e-3);
        }
    }

    #[test]
    fn hertz_half_width_and_peak() {
        let l = law(PressureModel::HertzLine);
        let p = l.pressure(440.0, 0.0, 2e-5);
        let r_star = 0.01 * 0.00998 / 2e-5;
        let b = (4.0 * 440.0 * r_star / (PI * 0.02 * l.e_star)).sqrt();
        assert_relative_eq!(p.half_angle * 0.01, b, max_relative = 1e-12);
        assert_relative_eq!(p.peak, 2.0 * 440.0 / (PI * b * 0.02), max_relative = 1e-12);
    }

    #[test]
    fn sector_update_conserves_archard_volume() {
        // Volume per unit length = k/H · F/L · ds, whether the arc spans many sectors or a
        // fraction of one, and across the 0/2π seam.
        for (model, force, theta) in [
            (PressureModel::HertzLine, 400.0, 1.0),
            (PressureModel::HertzLine, 1e-3, 2.0),
            (PressureModel::ElasticFoundation, 400.0, 0.01),
        ] {
            let l = law(model);
            let mut prof = WearProfile::new(360);
            let p = l.pressure(force, 2e-6, 2e-5);
            prof.add_wear(theta, &p, l.k_over_h, 1e-3);
            // The semi-ellipse's resultant is its integral only for small arcs (cos φ ≈ 1).
            let expected = l.k_over_h * force / l.length * 1e-3;
            assert_relative_eq!(prof.area(l.r_bearing), expected, max_relative = 0.02);
        }
    }

    #[test]
    fn wear_is_centred_on_the_contact_angle() {
        let l = law(PressureModel::HertzLine);
        let mut prof = WearProfile::new(360);
        let deepest = prof.add_wear(
            180f64.to_radians(),
            &l.pressure(400.0, 0.0, 2e-5),
            1e-12,
            1e-2,
        );
        let (imax, _) = prof
            .depths()
            .iter()
            .enumerate()
            .fold((0, 0.0), |a, (i, &d)| if d > a.1 { (i, d) } else { a });
        assert!(imax == 179 || imax == 180);
        assert_eq!(deepest, prof.depths()[imax]);
        assert_relative_eq!(prof.depths()[175], prof.depths()[184], max_relative = 1e-9);
    }

    #[test]
    fn zero_coefficient_leaves_the_profile_unchanged() {
        let l = law(PressureModel::ElasticFoundation);
        let mut prof = WearProfile::new(90);
        let deepest = prof.add_wear(0.5, &l.pressure(400.0, 2e-6, 2e-5), 0.0, 1.0);
        assert_eq!(deepest, 0.0);
        assert!(prof.depths().iter().all(|&d| d == 0.0));
    }

    #[test]
    fn interpolation_passes_through_centres_and_is_c1() {
        let mut prof = WearProfile::new(36);
        for (i, d) in prof.depths_mut().iter_mut().enumerate() {
            *d = (i as f64 * 0.7).sin() * 1e-6;
        }
        prof.wrap_padding();
        for (i, c) in prof.centres().enumerate().collect::<Vec<_>>() {
            assert_relative_eq!(prof.depth_at(c).0, prof.depths()[i], epsilon = 1e-18);
            // slope continuous across the centre, and matches a finite difference
            let (e, w) = (1e-9, prof.width);
            assert_relative_eq!(
                prof.depth_at(c - e).1,
                prof.depth_at(c + e).1,
                epsilon = 1e-12
            );
            let fd = (prof.depth_at(c + 0.1 * w).0 - prof.depth_at(c + 0.1 * w - 1e-7).0) / 1e-7;
            assert_relative_eq!(fd, prof.depth_at(c + 0.1 * w - 5e-8).1, max_relative = 1e-5);
        }
        // periodic
        assert_relative_eq!(
            prof.depth_at(-0.3).0,
            prof.depth_at(TAU - 0.3).0,
            epsilon = 1e-18
        );
    }

    /// h = a + b sin(θ − θ₀) has the steepest |h′|/(c + h) = b cos x / (c + a + b sin x)
    /// where that is largest; the spline sampled at the centres and edges of 3600 sectors finds
    /// it to 1e-5 and its angle to a sector, also where it lies across the wrap at 0 (θ₀ puts
    /// it at 0.0001 rad). A lone worn sector, the sharpest profile there is, is found within
    /// 5 % of its densely sampled steepness. Fails with the clearance or the depth left out of
    /// the denominator, or with the centres alone (the spike then reads 1.43 against 3.89
    /// sampled densely: tried).
    #[test]
    fn steepest_is_the_largest_slope_against_the_local_clearance() {
        let (a, b, c): (f64, f64, f64) = (2e-6, 1e-6, 2e-5);
        // d/dx [b cos x / (c + a + b sin x)] = 0 at sin x = −b / (c + a)
        let x = (-b / (c + a)).asin();
        let expected = b * x.cos() / (c + a + b * x.sin());
        for theta0 in [1.0, 1e-4 - x] {
            let mut prof = WearProfile::new(3600);
            let depths: Vec<f64> = (prof.centres())
                .map(|t| a + b * (t - theta0).sin())
                .collect();
            assert!(prof.set_depths(&depths));
            let (ratio, at) = prof.steepest(c);
            assert_relative_eq!(ratio, expected, max_relative = 1e-5);
            // as steep at x as at π − x (the cosine changes sign, the sine does not)
            let off = |x: f64| {
                let d = (wrap_angle(theta0 + x) - at).abs();
                d.min(TAU - d)
            };
            assert!(off(x).min(off(PI - x)) <= TAU / 3600.0, "{theta0}: {at}");
        }
        let mut spike = WearProfile::new(360);
        let mut depths = vec![0.0; 360];
        depths[100] = 1e-6;
        assert!(spike.set_depths(&depths));
        let dense = (0..36_000)
            .map(|i| {
                let (h, dh) = spike.depth_at(i as f64 * TAU / 36_000.0);
                dh.abs() / (c + h)
            })
            .fold(0.0, f64::max);
        let (ratio, _) = spike.steepest(c);
        assert!(
            ratio <= dense && ratio > 0.95 * dense,
            "{ratio} against {dense}"
        );
        // flat profiles are 0 even at no clearance; a NaN depth is not passed over
        assert_eq!(WearProfile::new(360).steepest(0.0), (0.0, 0.0));
        spike.add_depths(&[f64::NAN; 360], 1.0);
        assert!(spike.steepest(c).0.is_nan());
    }
}
