//! Clearance-joint kinematics (paper eq. 1 and section 2): the eccentricity `e = r_J − r_B`,
//! normal `n = e/|e|`, contact angle θ in the bearing frame, penetration
//! `δ = |e| − c − h(θ)` with the worn depth `h` of the run state, its rate, and the sliding
//! velocity `v_t = ė·t + φ̇_J R_J − φ̇_B R_B`; with forces from [`crate::laws`].

use super::{BodyIndex, Mechanism, RunState};
use crate::laws::friction::FrictionModel;
use crate::laws::wear::wrap_angle;
use crate::ode::EventValue;
use nalgebra::Vector2;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Kinematics and forces of one clearance joint at one state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactState {
    /// Journal centre relative to bearing centre, global frame (m).
    pub e: Vector2<f64>,
    /// Contact normal e/|e| (zero when exactly centred).
    pub n: Vector2<f64>,
    /// Contact angle in the bearing frame, in [0, 2π) (rad).
    pub theta: f64,
    /// Penetration δ (m); negative while the journal flies free.
    pub delta: f64,
    /// dδ/dt (m/s).
    pub delta_dot: f64,
    /// Local radial clearance including wear, c + h(θ) (m).
    pub local_clearance: f64,
    /// Distance of the centres |e| (m): `local_clearance + delta`, known before the wear
    /// depth.
    pub distance: f64,
    /// Relative tangential (sliding) velocity (m/s).
    pub v_t: f64,
    /// Normal force magnitude (N), ≥ 0.
    pub f_n: f64,
    /// Friction force along the tangent on the journal (N).
    pub f_t: f64,
    /// d|e|/dt (m/s), for the power of the normal force.
    pub e_rate: f64,
}

impl ContactState {
    /// Whether the bodies touch (eq. 12's unit step).
    pub fn in_contact(&self) -> bool {
        self.delta >= 0.0
    }
}

#[inline]
pub(super) fn perp(v: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}

/// Cephes' coefficients (Moshier) of the contact angle's arctangent and of the angles' sines
/// and cosines, as the library's `sincos` and `atan` use them; public so that
/// `examples/lanes.rs` evaluates the same arithmetic lane by lane.
pub mod cephes {
    /// Numerator of `atan t = t + t³ P(t²)/Q(t²)`, highest power first.
    pub const ATAN_P: [f64; 5] = [
        -8.750_608_600_031_904e-1,
        -1.615_753_718_733_365e1,
        -7.500_855_792_314_705e1,
        -1.228_866_684_490_136_2e2,
        -6.485_021_904_942_025e1,
    ];
    /// Denominator (monic, its leading 1 left out), highest power first.
    pub const ATAN_Q: [f64; 5] = [
        2.485_846_490_142_306e1,
        1.650_270_098_316_988_5e2,
        4.328_810_604_912_903e2,
        4.853_903_996_359_137e2,
        1.945_506_571_482_614e2,
    ];
    /// π/4 in three parts (Cody and Waite), for an exact reduction.
    pub const PI_4_PARTS: [f64; 3] = [
        7.853_981_256_484_985e-1,
        3.774_894_707_930_798e-8,
        2.695_151_429_079_059_5e-15,
    ];
    /// `sin z = z + z³ S(z²)` on |z| ≤ π/4, highest power first.
    pub const SIN: [f64; 6] = [
        1.589_623_015_765_465_7e-10,
        -2.505_074_776_285_780_7e-8,
        2.755_731_362_138_572e-6,
        -1.984_126_982_958_954e-4,
        8.333_333_333_322_118e-3,
        -1.666_666_666_666_663e-1,
    ];
    /// `cos z = 1 − z²/2 + z⁴ C(z²)` on |z| ≤ π/4, highest power first.
    pub const COS: [f64; 6] = [
        -1.135_853_652_138_768_2e-11,
        2.087_570_084_197_473e-9,
        -2.755_731_417_929_674e-7,
        2.480_158_728_885_170_5e-5,
        -1.388_888_888_887_305_6e-3,
        4.166_666_666_666_659e-2,
    ];

    /// `atan t` for `|t| ≤ 0.66`: Moshier's rational approximation (the Cephes library's
    /// `atan`), within an ulp.
    #[inline(always)]
    pub fn atan_kernel(t: f64) -> f64 {
        use self::{ATAN_P as P, ATAN_Q as Q};
        // Estrin's scheme: the pairs wait only for z, z² and z⁴, not for each other (Horner's
        // five dependent steps were on the contact force's path).
        let z = t * t;
        let (z2, tz) = (z * z, t * z);
        let z4 = z2 * z2;
        let p = (P[3] * z + P[4]) + z2 * (P[1] * z + P[2]) + z4 * P[0];
        let q = (Q[3] * z + Q[4]) + z2 * (Q[1] * z + Q[2]) + z4 * (z + Q[0]);
        t + tz * p / q
    }
}

/// The angle of `v` from the x axis in (−π, π] (rad): `v.y.atan2(v.x)` to an ulp, at a
/// third of libm's cost (the contact angle is taken at every evaluation). Reduced to the
/// first octant, then to `|t| ≤ 0.66` about π/4 as in Cephes; `LOW` restores the bits of
/// π/2 that `FRAC_PI_2` drops.
#[inline]
fn direction_angle(v: Vector2<f64>) -> f64 {
    const LOW: f64 = 6.123_233_995_736_766e-17;
    let (ax, ay) = (v.x.abs(), v.y.abs());
    let steep = ay > ax;
    let t = if steep { ax / ay } else { ay / ax };
    let mut a = if t > 0.66 {
        FRAC_PI_4 + (cephes::atan_kernel((t - 1.0) / (t + 1.0)) + 0.5 * LOW)
    } else {
        cephes::atan_kernel(t)
    };
    if steep {
        a = FRAC_PI_2 - a + LOW;
    }
    if v.x < 0.0 {
        a = PI - a + 2.0 * LOW;
    }
    if v.y < 0.0 {
        -a
    } else {
        a
    }
}

/// Largest `|x|` (rad) that [`sincos`] reduces itself: below 2³⁰ the products of the
/// reduction's multiple of π/4 with its first two parts are exact (the multiple is even and
/// below 2³¹, so it has at most 30 significant bits; the parts have 23 and 21). Beyond it (a driver 170 million turns on) it calls libm.
const SINCOS_LIMIT: f64 = 1_073_741_824.0;

/// `(sin x, cos x)` within 2 ulp of libm's `x.sin_cos()` (plus 2⁻⁷⁰ absolute near their zeros;
/// the test below), at a fraction of its cost: the two angles of every evaluation. Moshier's
/// Cephes `sin`/`cos`: `x` less the nearest even multiple `y` of π/4, with π/4 in three parts
/// (Cody and Waite) so that the reduction stays exact for any `|x|` ≤ [`SINCOS_LIMIT`], then
/// minimax polynomials on `|z|` ≤ π/4.
#[inline(always)]
pub(super) fn sincos(x: f64) -> (f64, f64) {
    use cephes::{COS, PI_4_PARTS as DP, SIN};
    let ax = x.abs();
    // Beyond the limit or NaN in one comparison (a NaN is not below the limit).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let outside = !(ax <= SINCOS_LIMIT);
    if outside {
        return libm_sin_cos(x);
    }
    // The octant, rounded up to even: `ax = y π/4 + z` with `y = 2 q`, `|z|` ≤ π/4. Through
    // i64, not u64: below the limit both give the same integer, and x86-64 converts to and
    // from a signed integer in one instruction (to u64 in about twenty).
    let mut j = (ax * std::f64::consts::FRAC_2_PI * 2.0) as i64;
    j += j & 1;
    let y = j as f64;
    let z = ((ax - y * DP[0]) - y * DP[1]) - y * DP[2];
    let zz = z * z;
    let poly =
        |c: [f64; 6]| ((((c[0] * zz + c[1]) * zz + c[2]) * zz + c[3]) * zz + c[4]) * zz + c[5];
    let s = z + z * zz * poly(SIN);
    let c = 1.0 - 0.5 * zz + zz * zz * poly(COS);
    // Quadrant q = j / 2: (sin, cos) of z turned by q quarter turns are (s, c), (c, −s),
    // (−s, −c), (−c, s); signs flipped by their bit, the sine's also for a negative x.
    let q = (j >> 1) as u64;
    let (sin, cos) = if q & 1 == 0 { (s, c) } else { (c, s) };
    let sin_sign = ((q & 2) << 62) ^ (x.to_bits() & SIGN);
    let cos_sign = ((q + 1) & 2) << 62;
    (
        f64::from_bits(sin.to_bits() ^ sin_sign),
        f64::from_bits(cos.to_bits() ^ cos_sign),
    )
}

/// The sign bit of an `f64`.
const SIGN: u64 = 1 << 63;

/// libm's `x.sin_cos()`, out of line: inlined, the compiler computes it on every call (it
/// is free of side effects) and selects it only beyond [`SINCOS_LIMIT`].
#[cold]
#[inline(never)]
fn libm_sin_cos(x: f64) -> (f64, f64) {
    x.sin_cos()
}

/// Rotates `v` by the angle whose `(sin, cos)` is `sc`.
#[inline]
pub(super) fn rotate((s, c): (f64, f64), v: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Position, angle, velocity, angular velocity and `(sin, cos)` of the angle of a body
/// (ground: at rest at the origin, angle 0).
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    pub(super) r: Vector2<f64>,
    pub(super) phi: f64,
    pub(super) rd: Vector2<f64>,
    pub(super) w: f64,
    pub(super) sc: (f64, f64),
}

impl Frame {
    /// The ground's frame: at rest at the origin, angle 0.
    pub(super) const GROUND: Frame = Frame {
        r: Vector2::new(0.0, 0.0),
        phi: 0.0,
        rd: Vector2::new(0.0, 0.0),
        w: 0.0,
        sc: (0.0, 1.0),
    };

    /// `sc` gives the `(sin, cos)` of a body's angle: cached, or computed on demand.
    #[inline(always)]
    pub(super) fn of(
        q: &[f64],
        v: &[f64],
        b: BodyIndex,
        sc: impl Fn(usize) -> (f64, f64),
    ) -> Frame {
        match b {
            Some(i) => {
                let k = 3 * i;
                Frame {
                    r: Vector2::new(q[k], q[k + 1]),
                    phi: q[k + 2],
                    rd: Vector2::new(v[k], v[k + 1]),
                    w: v[k + 2],
                    sc: sc(i),
                }
            }
            None => Frame::GROUND,
        }
    }

    /// Global position and velocity of the point at `local`, and its rotated local vector.
    #[inline]
    pub(super) fn point(&self, local: Vector2<f64>) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        let s = rotate(self.sc, local);
        (self.r + s, self.rd + perp(s) * self.w, s)
    }
}

/// `(sin, cos)` of body `i`'s angle, computed from q.
#[inline]
pub(super) fn sin_cos(q: &[f64]) -> impl Fn(usize) -> (f64, f64) + Copy + '_ {
    move |i| sincos(q[3 * i + 2])
}

impl Mechanism {
    /// Penetration δ (m) of clearance joint `k` at state `y` (coordinates, then velocities).
    #[inline]
    pub fn penetration(&self, state: &RunState, k: usize, y: &[f64]) -> f64 {
        self.contact_event(state, k, y).value
    }

    /// Penetration δ (m) of clearance joint `k` and its rate δ̇ (m/s) at state `y`: the event
    /// function of contact onsets.
    #[inline]
    pub fn contact_event(&self, state: &RunState, k: usize, y: &[f64]) -> EventValue {
        let n = self.coordinates();
        let cs = self.contact_kinematics(state, k, &y[..n], &y[n..2 * n]);
        EventValue {
            value: cs.delta,
            rate: cs.delta_dot,
        }
    }

    /// Kinematics of clearance joint `k` at state (q, v), without forces.
    #[inline]
    pub fn contact_kinematics(
        &self,
        state: &RunState,
        k: usize,
        q: &[f64],
        v: &[f64],
    ) -> ContactState {
        self.contact_geometry(state, k, |b| Frame::of(q, v, b, sin_cos(q)))
            .0
    }

    /// Kinematics of clearance joint `k`, with the rotated local vectors of journal and
    /// bearing centre, from the bodies' `frame`s.
    #[inline(always)]
    pub(super) fn contact_geometry(
        &self,
        state: &RunState,
        k: usize,
        frame: impl Fn(BodyIndex) -> Frame,
    ) -> (ContactState, Vector2<f64>, Vector2<f64>) {
        let (journal, bearing) = self.clearance_ends(k);
        self.contact_between(state, k, &frame(journal), &frame(bearing))
    }

    /// [`Mechanism::contact_geometry`] from the frames of the journal's body `fj` and of the
    /// bearing's `fb`.
    #[inline(always)]
    pub(super) fn contact_between(
        &self,
        state: &RunState,
        k: usize,
        fj: &Frame,
        fb: &Frame,
    ) -> (ContactState, Vector2<f64>, Vector2<f64>) {
        let cj = &self.clearance_joints[k];
        let (rj, vj, sj) = fj.point(cj.journal.local);
        let (rb, vb, sb) = fb.point(cj.bearing.local);
        let (wj, wb) = (fj.w, fb.w);
        let e = rj - rb;
        let e_dot = vj - vb;
        let dist = e.norm();
        let c = cj.clearance();
        if dist == 0.0 {
            // Exactly centred: no direction, far from contact.
            let cs = ContactState {
                delta: -c,
                local_clearance: c,
                ..Default::default()
            };
            return (cs, sj, sb);
        }
        let n = e / dist;
        let t = perp(n);
        // θ from e itself, not from n: its path to the force then waits for neither the
        // square root nor the division.
        let theta = wrap_angle(direction_angle(e) - fb.phi);
        let theta_rate = t.dot(&e_dot) / dist - wb;
        let (h, dh) = match cj.wear {
            Some(_) => state.joints[k].wear.depth_at(theta),
            None => (0.0, 0.0),
        };
        let e_rate = n.dot(&e_dot);
        let cs = ContactState {
            e,
            n,
            theta,
            delta: dist - c - h,
            delta_dot: e_rate - dh * theta_rate,
            local_clearance: c + h,
            distance: dist,
            v_t: t.dot(&e_dot) + wj * cj.r_journal - wb * cj.r_bearing,
            f_n: 0.0,
            f_t: 0.0,
            e_rate,
        };
        (cs, sj, sb)
    }

    /// Kinematics and forces of clearance joint `k`.
    #[inline]
    pub fn contact_state(&self, state: &RunState, k: usize, q: &[f64], v: &[f64]) -> ContactState {
        self.with_forces(state, k, self.contact_kinematics(state, k, q, v))
    }

    /// Adds the normal and friction forces of clearance joint `k` to its kinematics.
    #[inline(always)]
    pub(super) fn with_forces(
        &self,
        state: &RunState,
        k: usize,
        mut cs: ContactState,
    ) -> ContactState {
        let cj = &self.clearance_joints[k];
        if cs.in_contact() {
            cs.f_n = cj.contact.force_spanning(
                cs.delta,
                cs.delta_dot,
                state.joints[k].onset_velocity,
                cs.local_clearance,
                cs.distance,
            );
            if cj.friction != FrictionModel::None {
                cs.f_t = cj.friction.force(cs.f_n, cs.v_t);
            }
        }
        cs
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `|ours − libm|` over `(sin, cos)` of `x`, in units of libm's result's ulp, with the
    /// reduction's absolute error 2⁻⁷⁰ allowed on top (it matters only within ~1e-6 of a zero).
    fn sincos_error(x: f64) -> f64 {
        let ((s, c), (ls, lc)) = (sincos(x), x.sin_cos());
        // In units of b's own ulp (the gap to the next float away from zero); a NaN is
        // infinitely wrong rather than dropped by `max`.
        let ulps = |a: f64, b: f64| {
            let ulp = b.abs().next_up() - b.abs();
            let e = ((a - b).abs() - 2f64.powi(-70)).max(0.0) / ulp;
            if a.is_finite() {
                e
            } else {
                f64::INFINITY
            }
        };
        ulps(s, ls).max(ulps(c, lc))
    }

    // Fails with the third part of π/4 left out of the reduction (2e11 ulp near the zeros),
    // with SIN[4] cut to 8.333_333_333e-3 (614 ulp) and with the cosine's sign wrong in
    // quadrants 1 and 3: tried. The worst error seen at these points is 1.4 ulp.
    #[test]
    fn sincos_is_libm_within_two_ulp() {
        let mut uniform = crate::test_support::uniform(0x2545_f491_4f6c_dd1d);
        let mut worst: f64 = 0.0;
        for i in 0..200_000 {
            // Half uniform on |x| ≤ 1e6 rad (a driver ~160 000 turns on), half on |x| ≤ 10
            // (the rod's angle; the first turns).
            let range = if i % 2 == 0 { 1e6 } else { 10.0 };
            let x = (2.0 * uniform() - 1.0) * range;
            worst = worst.max(sincos_error(x));
        }
        // Two ulps: one for each function's own rounding (Cephes' sin and cos are within
        // about an ulp; libm's within one).
        assert!(worst <= 2.0, "worst error {worst} ulp");
        // The octant boundaries, zero, and the libm fallback beyond the reduction's range.
        for k in -64..=64 {
            let x = f64::from(k) * std::f64::consts::FRAC_PI_4;
            for x in [x, x.next_up(), x.next_down()] {
                assert!(sincos_error(x) <= 2.0, "{x:e}");
            }
        }
        assert_eq!(sincos(0.0), (0.0, 1.0));
        for x in [2.0 * SINCOS_LIMIT, -3e12, f64::INFINITY] {
            let ((s, c), (ls, lc)) = (sincos(x), x.sin_cos());
            assert!(
                s.to_bits() == ls.to_bits() && c.to_bits() == lc.to_bits(),
                "{x:e}"
            );
        }
    }

    // Fails with a digit of the kernel's coefficients changed (P[1] = -1.6e0): tried.
    #[test]
    fn direction_angle_is_atan2_to_an_ulp() {
        let mut uniform = crate::test_support::uniform(0x9e37_79b9_7f4a_7c15);
        for i in 0..200_000 {
            // reproducible directions all round, of two lengths
            let angle = uniform() * 2.0 * PI - PI;
            let length = if i % 2 == 0 { 1.0 } else { 1e-3 };
            let v = Vector2::new(angle.cos(), angle.sin()) * length;
            let (ours, libm) = (direction_angle(v), v.y.atan2(v.x));
            // Two ulps of the result: one for each function's own rounding.
            assert!(
                (ours - libm).abs() <= 2.0 * f64::EPSILON * libm.abs(),
                "{v:?}: {ours:e} against {libm:e}"
            );
        }
        for (x, y) in [
            (1.0, 0.0),
            (0.0, 1.0),
            (-1.0, 0.0),
            (0.0, -1.0),
            (-1.0, -1.0),
        ] {
            let v = Vector2::new(x, y);
            assert_eq!(direction_angle(v), v.y.atan2(v.x), "{v:?}");
        }
    }
}
