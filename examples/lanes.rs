//! Several ensemble members in one evaluation, measured: `cargo run --release --example lanes`.
//!
//! One evaluation of the standard scene waits on a chain of dependent operations (sines of
//! the two angles, the contact angle's arctangent, the wear profile, the contact force, the
//! solve), and two evaluations in a row do not overlap: one is longer than the processor's
//! out-of-order window (the program times that too). The way to fill the idle slots is to
//! evaluate members side by side, each operation on a pair (or quadruple) of members at once.
//! This standalone prototype writes the scene's right-hand side once for `L` members: the
//! crank driven, the rod's angle φ and the slider's position x free, the hybrid law (eq. 1-3,
//! its elastic term as the library folds it) at the rod-slider pin, the contact angle by a
//! Cephes arctangent and the angles' sines by Cephes' `sincos`, as the library computes them
//! (its `cephes` coefficients and kernel). Every operation is lane by lane on `[f64; L]` and
//! every branch a selection, so that the compiler can emit packed instructions; the wear
//! profile's lookup and eq. 4's friction coefficient are the library's own
//! (`WearProfile::depth_at`, `FrictionModel::coefficient`), called lane by lane.
//!
//! Its inputs are [`SAMPLES`] states of runs of members 0-3 (seed 1): free flight, impacts and
//! continuous contact on worn profiles, contact angles all round the bearing. At each it checks
//! the accelerations against the library's (`Mechanism::rhs`, absolute coordinates, to 1e-8:
//! it is the library's model without the library's generality, any tree, any law, event values
//! and energy terms) and each lane's bits, with the lanes holding states of different regimes,
//! against the one-lane evaluation of its state: lanes change the cost, not the numbers. It
//! then times `L` chains of evaluations in which each member's next state waits for its last
//! derivative (as the stages of a Runge-Kutta step do), every input through `black_box`, and
//! reports ns per member evaluation.

use jointwear::laws::friction::FrictionModel;
use jointwear::laws::wear::WearProfile;
use jointwear::mechanism::{cephes, RunState};
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::ensemble::{member_simulation, EnsembleSettings};
use jointwear::simulation::Scene;
use std::array::from_fn;
use std::f64::consts::{FRAC_2_PI, FRAC_PI_2, FRAC_PI_4, PI, TAU};
use std::hint::black_box;
use std::time::Instant;

/// `L` members' values of one quantity.
type V<const L: usize> = [f64; L];

/// Crank length (m), rod length and its centre of mass from the crank pin (m).
const CRANK: f64 = 0.05;
const ROD: f64 = 0.12;
const ROD_CG: f64 = 0.06;
/// Rod and slider masses (kg), rod inertia (kg m²), gravity (m/s²).
const ROD_MASS: f64 = 0.21;
const ROD_INERTIA: f64 = 0.001;
const SLIDER_MASS: f64 = 0.14;
const GRAVITY: f64 = 9.81;
/// Crank speed (rad/s): −2000 r/min.
const OMEGA: f64 = -2000.0 * TAU / 60.0;
/// Radial clearance (m), journal radius (m), compound modulus (Pa).
const CLEARANCE: f64 = 2e-5;
const R_JOURNAL: f64 = 0.00998;
const E_STAR: f64 = 207e9 / (2.0 * (1.0 - 0.3 * 0.3));
/// The hybrid law's folded factor ((π/8)·√2) and eq. 3's χ (the paper's law at c_e = 0.9).
const HYBRID: f64 = PI / 8.0 * std::f64::consts::SQRT_2;
/// (e^0.2 written out: `exp` is not a const fn.)
const CHI: f64 = 0.75 * (1.0 - 0.9 * 0.9) * 1.221_402_758_160_170_3;
/// Eq. 4 as the scene has it, and its μ_d and v_d for the all-lanes fast path.
const MU_D: f64 = 0.01;
const V_D: f64 = 1e-3;
const FRICTION: FrictionModel = FrictionModel::Modified {
    mu_s: 0.015,
    mu_d: MU_D,
    v_s: 1e-4,
    v_d: V_D,
};
/// States sampled from runs (a multiple of 4).
const SAMPLES: usize = 32;

/// Lane-wise selection: `a` where `c`, else `b`.
#[inline(always)]
fn select<const L: usize>(c: [bool; L], a: V<L>, b: V<L>) -> V<L> {
    from_fn(|i| if c[i] { a[i] } else { b[i] })
}

/// Cephes `sincos` lane by lane (the library's reduction, the octant through i32: the
/// prototype's angles stay far below 2³¹ octants).
#[inline(always)]
fn sincos<const L: usize>(x: V<L>) -> (V<L>, V<L>) {
    use cephes::{COS, PI_4_PARTS as DP, SIN};
    let ax: V<L> = from_fn(|i| x[i].abs());
    let j: [i32; L] = from_fn(|i| {
        let j = (ax[i] * FRAC_2_PI * 2.0) as i32;
        j + (j & 1)
    });
    let z: V<L> = from_fn(|i| {
        let y = j[i] as f64;
        ((ax[i] - y * DP[0]) - y * DP[1]) - y * DP[2]
    });
    let zz: V<L> = from_fn(|i| z[i] * z[i]);
    let poly = |c: [f64; 6], i: usize| {
        let zz = zz[i];
        ((((c[0] * zz + c[1]) * zz + c[2]) * zz + c[3]) * zz + c[4]) * zz + c[5]
    };
    let s: V<L> = from_fn(|i| z[i] + z[i] * zz[i] * poly(SIN, i));
    let c: V<L> = from_fn(|i| 1.0 - 0.5 * zz[i] + zz[i] * zz[i] * poly(COS, i));
    let q: [i32; L] = from_fn(|i| j[i] >> 1);
    let swap: [bool; L] = from_fn(|i| q[i] & 1 != 0);
    let (sin, cos) = (select(swap, c, s), select(swap, s, c));
    let sin_negative: [bool; L] = from_fn(|i| (q[i] & 2 != 0) != (x[i] < 0.0));
    let cos_negative: [bool; L] = from_fn(|i| (q[i] + 1) & 2 != 0);
    (
        from_fn(|i| if sin_negative[i] { -sin[i] } else { sin[i] }),
        from_fn(|i| if cos_negative[i] { -cos[i] } else { cos[i] }),
    )
}

/// The library's arctangent kernel ([`cephes::atan_kernel`], inlined) lane by lane.
#[inline(always)]
fn atan_kernel<const L: usize>(t: V<L>) -> V<L> {
    from_fn(|i| cephes::atan_kernel(t[i]))
}

/// The angle of (x, y) in (−π, π], branch-free: one division picks t or (t − 1)/(t + 1).
#[inline(always)]
fn direction_angle<const L: usize>(x: V<L>, y: V<L>) -> V<L> {
    const LOW: f64 = 6.123_233_995_736_766e-17;
    let (ax, ay): (V<L>, V<L>) = (from_fn(|i| x[i].abs()), from_fn(|i| y[i].abs()));
    let steep: [bool; L] = from_fn(|i| ay[i] > ax[i]);
    let t: V<L> = from_fn(|i| {
        let (num, den) = if steep[i] {
            (ax[i], ay[i])
        } else {
            (ay[i], ax[i])
        };
        num / den
    });
    let big: [bool; L] = from_fn(|i| t[i] > 0.66);
    let arg: V<L> = from_fn(|i| {
        let b = if big[i] { 1.0 } else { 0.0 };
        (t[i] - b) / (1.0 + b * t[i])
    });
    let k = atan_kernel(arg);
    from_fn(|i| {
        let mut a = if big[i] {
            FRAC_PI_4 + (k[i] + 0.5 * LOW)
        } else {
            k[i]
        };
        if steep[i] {
            a = FRAC_PI_2 - a + LOW;
        }
        if x[i] < 0.0 {
            a = PI - a + 2.0 * LOW;
        }
        if y[i] < 0.0 {
            -a
        } else {
            a
        }
    })
}

/// `dz = f(t, z)` for `L` members, `z = (φ, x, φ̇, ẋ)` each, member `i` with its own time,
/// profile and onset velocity.
#[inline(always)]
fn rhs<const L: usize>(
    t: &V<L>,
    z: &[V<L>; 4],
    profiles: &[&WearProfile; L],
    onset: &V<L>,
    dz: &mut [V<L>; 4],
) {
    let [phi, x, w, xd] = *z;
    let (s1, c1) = sincos::<L>(from_fn(|i| OMEGA * t[i]));
    let (s2, c2) = sincos(phi);
    // Crank pin A, journal B on the rod, bearing centre C on the slider.
    let (ax, ay): (V<L>, V<L>) = (from_fn(|i| CRANK * c1[i]), from_fn(|i| CRANK * s1[i]));
    let (vax, vay): (V<L>, V<L>) = (from_fn(|i| -OMEGA * ay[i]), from_fn(|i| OMEGA * ax[i]));
    let ex: V<L> = from_fn(|i| ax[i] + ROD * c2[i] - x[i]);
    let ey: V<L> = from_fn(|i| ay[i] + ROD * s2[i]);
    let edx: V<L> = from_fn(|i| vax[i] - ROD * w[i] * s2[i] - xd[i]);
    let edy: V<L> = from_fn(|i| vay[i] + ROD * w[i] * c2[i]);
    let dist: V<L> = from_fn(|i| (ex[i] * ex[i] + ey[i] * ey[i]).sqrt());
    let inv: V<L> = from_fn(|i| 1.0 / dist[i]);
    let (nx, ny): (V<L>, V<L>) = (from_fn(|i| ex[i] * inv[i]), from_fn(|i| ey[i] * inv[i]));
    // The contact angle on the slider (angle 0) and the wear profile's depth there, the
    // library's Catmull-Rom lookup lane by lane.
    let theta = direction_angle(ex, ey);
    let tdot: V<L> = from_fn(|i| (nx[i] * edy[i] - ny[i] * edx[i]) * inv[i]);
    let (mut h, mut dh) = ([0.0; L], [0.0; L]);
    for i in 0..L {
        (h[i], dh[i]) = profiles[i].depth_at(theta[i]);
    }
    let delta: V<L> = from_fn(|i| dist[i] - CLEARANCE - h[i]);
    let delta_dot: V<L> = from_fn(|i| nx[i] * edx[i] + ny[i] * edy[i] - dh[i] * tdot[i]);
    // Eq. 1-3, the elastic term folded as the library does, the span from |e|.
    let fnormal: V<L> = from_fn(|i| {
        let (d, span) = (delta[i], dist[i]);
        let elastic =
            HYBRID * E_STAR * (3.0 * (CLEARANCE + h[i]) + 2.0 * d) * d * d / (span * span.sqrt());
        let per_onset = CHI / onset[i].max(1e-3);
        let f = (elastic * (1.0 + delta_dot[i] * per_onset)).max(0.0);
        if d > 0.0 {
            f
        } else {
            0.0
        }
    });
    let vt: V<L> = from_fn(|i| nx[i] * edy[i] - ny[i] * edx[i] + w[i] * R_JOURNAL);
    // Eq. 4: one test for all lanes sliding fast, the usual case.
    let mu: V<L> = if vt.iter().all(|v| v.abs() > V_D) {
        [MU_D; L]
    } else {
        from_fn(|i| FRICTION.coefficient(vt[i]))
    };
    let ft: V<L> = from_fn(|i| -mu[i] * fnormal[i] * vt[i].signum());
    // Force on the journal: −F_n n + F_t t; the slider takes the opposite.
    let fx: V<L> = from_fn(|i| -fnormal[i] * nx[i] - ft[i] * ny[i]);
    let fy: V<L> = from_fn(|i| -fnormal[i] * ny[i] + ft[i] * nx[i]);
    // Lagrange over (φ, x): the rod's centre and journal move with φ, the slider with x.
    let (jx, jy): (V<L>, V<L>) = (from_fn(|i| -ROD_CG * s2[i]), from_fn(|i| ROD_CG * c2[i]));
    let mass11: V<L> = from_fn(|i| ROD_MASS * (jx[i] * jx[i] + jy[i] * jy[i]) + ROD_INERTIA);
    let rhs1: V<L> = from_fn(|i| {
        // The rod centre's acceleration at φ̈ = 0: the crank pin's and the rod's spin.
        let arx = -OMEGA * OMEGA * ax[i] - ROD_CG * w[i] * w[i] * c2[i];
        let ary = -OMEGA * OMEGA * ay[i] - ROD_CG * w[i] * w[i] * s2[i];
        let gx = -ROD_MASS * arx;
        let gy = -ROD_MASS * (GRAVITY + ary);
        jx[i] * gx + jy[i] * gy + 2.0 * (jx[i] * fx[i] + jy[i] * fy[i]) + ft[i] * R_JOURNAL
    });
    let rhs2: V<L> = from_fn(|i| -fx[i]);
    // L D Lᵀ of the 2 × 2 mass matrix (its off-diagonal is zero here, but formed).
    let l21: V<L> = from_fn(|i| (jx[i] * 0.0 + jy[i] * 0.0) / mass11[i]);
    let d2: V<L> = from_fn(|i| SLIDER_MASS - l21[i] * l21[i] * mass11[i]);
    let acc2: V<L> = from_fn(|i| (rhs2[i] - l21[i] * rhs1[i]) / d2[i]);
    let acc1: V<L> = from_fn(|i| rhs1[i] / mass11[i] - l21[i] * acc2[i]);
    *dz = [w, xd, acc1, acc2];
}

/// One state of a run of the standard scene: time, the prototype's (φ, x, φ̇, ẋ), the worn
/// profile, eq. 3's held onset velocity, and the library's own state and run state there.
struct Sample {
    t: f64,
    z: [f64; 4],
    profile: WearProfile,
    onset: f64,
    y: Vec<f64>,
    run: RunState,
}

/// [`SAMPLES`] states from runs of members 0-3 of seed 1: per member, times spread over its
/// first rotation (free flight, impacts, onsets below the grazing floor) and later ones
/// (continuous contact on a worn bearing), at contact angles all round the bearing.
fn samples(scene: &Scene) -> Result<Vec<Sample>, Box<dyn std::error::Error>> {
    let period = scene.period();
    let mut out = Vec::new();
    for member in 0..4 {
        let ensemble = EnsembleSettings {
            members: 4,
            seed: 1,
            ..EnsembleSettings::default()
        };
        let mut sim = member_simulation(scene, &scene.run, &ensemble, member)?;
        let mut y = vec![0.0; scene.mechanism.state_len()];
        for k in 0..SAMPLES / 4 {
            let at =
                (0.05 + 0.17 * k as f64 + 0.9 * (k / 4) as f64 + 0.04 * member as f64) * period;
            while sim.time() < at {
                sim.advance_step()?;
            }
            sim.y_into(&mut y);
            let joint = &sim.state().joints[0];
            out.push(Sample {
                t: sim.time(),
                z: [y[5], y[6], y[9 + 5], y[9 + 6]],
                profile: joint.wear.clone(),
                onset: joint.onset_velocity,
                y: y.clone(),
                run: sim.state().clone(),
            });
        }
    }
    Ok(out)
}

/// ns per member evaluation of `L` dependent chains started at `samples[first..first + L]`,
/// best of five runs of `n` evaluations each, and the last derivatives. Every input of the
/// evaluation goes through `black_box`, so that none of its work is hoisted out of the loop.
fn time<const L: usize>(samples: &[Sample], first: usize, n: usize) -> (f64, [V<L>; 4]) {
    let s: [&Sample; L] = from_fn(|i| &samples[(first + i) % samples.len()]);
    let t: V<L> = from_fn(|i| s[i].t);
    let z0: [V<L>; 4] = from_fn(|c| from_fn(|i| s[i].z[c]));
    let prof: [&WearProfile; L] = from_fn(|i| &s[i].profile);
    let onset: V<L> = from_fn(|i| s[i].onset);
    let mut dz = [[0.0; L]; 4];
    let mut z = z0;
    let ns = best_of_five(n * L, || {
        for _ in 0..n {
            rhs(
                black_box(&t),
                black_box(&z),
                &prof,
                black_box(&onset),
                &mut dz,
            );
            // The next state waits for this derivative and equals z0 to the bit.
            z = from_fn(|c| from_fn(|i| z0[c][i] + 1e-300 * dz[c][i]));
        }
    });
    (ns, dz)
}

/// The least wall time (ns) per one of `evaluations` that five runs of `run` take.
fn best_of_five(evaluations: usize, mut run: impl FnMut()) -> f64 {
    (0..5)
        .map(|_| {
            let clock = Instant::now();
            run();
            clock.elapsed().as_secs_f64() * 1e9 / evaluations as f64
        })
        .fold(f64::INFINITY, f64::min)
}

/// ns per member evaluation of two one-lane chains evaluated one after the other in the same
/// loop (independent of each other): whether the processor overlaps consecutive evaluations.
fn time_two_in_a_row(samples: &[Sample], n: usize) -> f64 {
    let (a, b) = (&samples[0], &samples[samples.len() / 2]);
    let (za0, zb0) = (a.z.map(|v| [v]), b.z.map(|v| [v]));
    let (mut za, mut zb) = (za0, zb0);
    let (mut da, mut db) = ([[0.0; 1]; 4], [[0.0; 1]; 4]);
    best_of_five(2 * n, || {
        for _ in 0..n {
            rhs(
                black_box(&[a.t]),
                black_box(&za),
                &[&a.profile],
                black_box(&[a.onset]),
                &mut da,
            );
            rhs(
                black_box(&[b.t]),
                black_box(&zb),
                &[&b.profile],
                black_box(&[b.onset]),
                &mut db,
            );
            za = from_fn(|c| [za0[c][0] + 1e-300 * da[c][0]]);
            zb = from_fn(|c| [zb0[c][0] + 1e-300 * db[c][0]]);
        }
    })
}

/// The library's accelerations of the rod's angle and the slider's position at `s`, from its
/// absolute formulation (`Mechanism::rhs`; at a state of a run in joint coordinates the ideal
/// joints close to rounding, so Baumgarte's terms vanish to rounding).
fn library(scene: &Scene, s: &Sample) -> Result<(f64, f64), Box<dyn std::error::Error>> {
    let mech = &scene.mechanism;
    let mut dy = vec![0.0; s.y.len()];
    mech.rhs(&s.run, &mut mech.workspace(), s.t, &s.y, &mut dy)?;
    Ok((dy[9 + 5], dy[9 + 6]))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut file = SceneFile::read(scene_path("standard"))?;
    file.run.record_rotations = 0;
    let scene = file.build()?;
    let samples = samples(&scene)?;
    // The prototype against the library, and each lane against its state evaluated alone,
    // over every sample with the lanes mixing states of different regimes.
    let mut worst: f64 = 0.0;
    let mut contact = 0;
    for (k, s) in samples.iter().enumerate() {
        let (_, alone) = time::<1>(&samples, k, 1);
        let (phi_dd, x_dd) = library(&scene, s)?;
        // The same model to rounding: the library's absolute formulation closes the ideal
        // joints to about 1e-15 m, which moves a contact force by parts in 1e10.
        let scale = phi_dd.abs().max(1.0);
        let (e1, e2) = (
            (alone[2][0] - phi_dd).abs() / scale,
            (alone[3][0] - x_dd).abs() / x_dd.abs().max(1.0),
        );
        worst = worst.max(e1).max(e2);
        if worst > 1e-8 {
            return Err(format!(
                "sample {k}: the prototype's accelerations ({:e}, {:e}) differ from the library's ({phi_dd:e}, {x_dd:e})",
                alone[2][0], alone[3][0]
            )
            .into());
        }
        contact += usize::from(x_dd.abs() > 1e3);
        let (_, four) = time::<4>(&samples, k, 1);
        let (_, two) = time::<2>(&samples, k, 1);
        for c in 0..4 {
            if alone[c][0].to_bits() != four[c][0].to_bits()
                || alone[c][0].to_bits() != two[c][0].to_bits()
            {
                return Err(
                    format!("sample {k}: a lane's bits differ from the state alone").into(),
                );
            }
        }
    }
    let angles: Vec<f64> = samples
        .iter()
        .map(|s| {
            let (ex, ey) = (
                s.y[3] + ROD_CG * s.z[0].cos() - s.z[1],
                s.y[4] + ROD_CG * s.z[0].sin(),
            );
            ey.atan2(ex).to_degrees()
        })
        .collect();
    println!(
        "{} states of members 0-3 (seed 1), times {:.4}-{:.4} s, contact angles {:.0} to {:.0} deg; {} pressing hard \
         (|x''| > 1e3 m/s2)",
        samples.len(),
        samples.iter().map(|s| s.t).fold(f64::INFINITY, f64::min),
        samples.iter().map(|s| s.t).fold(0.0, f64::max),
        angles.iter().cloned().fold(f64::INFINITY, f64::min),
        angles.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        contact,
    );
    println!("largest relative difference from the library's accelerations: {worst:.1e}; every lane bit-identical to its state alone");
    let n = 2_000_000;
    let one = time::<1>(&samples, 0, n).0;
    let in_a_row = time_two_in_a_row(&samples, n);
    let two = time::<2>(&samples, 0, n).0;
    let four = time::<4>(&samples, 0, n).0;
    println!("ns per member evaluation, best of 5 x {n} dependent evaluations per chain:");
    println!("  1 lane:                                 {one:.1}");
    println!("  1 lane, two members one after the other: {in_a_row:.1}");
    println!(
        "  2 lanes:                                {two:.1} ({:.2}x the throughput)",
        one / two
    );
    println!(
        "  4 lanes:                                {four:.1} ({:.2}x the throughput)",
        one / four
    );
    Ok(())
}
