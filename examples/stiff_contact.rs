//! Whether the standard run's slow trajectories are stiff, and whether an L-stable method pays
//! there, measured: `cargo run --release --example stiff_contact [-- MEMBER SEED]` (no
//! arguments: the unperturbed default trajectory; else ensemble member MEMBER of seed SEED).
//!
//! Eq. 3's damping divides by the normal velocity δ̇⁻ of the last contact onset for as long as
//! that contact lasts. A trajectory whose last onset grazed (δ̇⁻ near the scene's floor) then
//! carries a heavily damped contact for the rest of the run. The program runs the standard
//! scene to rotation [`FROM`] and, over the next rotation:
//!
//! 1. at every accepted step, the eigenvalues λ of the right-hand side's Jacobian in the
//!    joint coordinates the run integrates (by differences, as below), by modulus, and h|λ|;
//! 2. from the state at rotation [`FROM`], the right-hand side frozen (the wear profile and δ̇⁻
//!    held), one rotation integrated by the library's Dopri5 and by Rodas4 (Hairer and Wanner,
//!    *Solving ODEs II*, section IV.7: 6 stages, order 4(3), L-stable, stiffly accurate) with
//!    a Jacobian and time derivative by differences at every step (kept over its rejected
//!    attempts); the error is the
//!    largest distance of the journal's eccentricity from a Dopri5 run at rtol 1e-13, at 20
//!    instants of the rotation. Evaluations count every call, the Jacobian's included;
//! 3. from that state, one step of each size by either method, against Dopri5 at rtol 1e-14:
//!    how the local error shrinks with the step;
//! 4. that rotation with the bearing unworn and with a faster onset's δ̇⁻, each against its own
//!    reference as in 2, by Dopri5 (at the scene's rtol and tighter) and by Rodas4: what sets
//!    Dopri5's steps and what its rejections, and whether Rodas4 steps past the stiff mode
//!    where the profile is smooth.

mod common;

use jointwear::mechanism::{Mechanism, RunState, Workspace};
use jointwear::ode::{Integrator, Method, OdeSystem, Tolerances};
use jointwear::scene::{scene_path, SceneFile};
use nalgebra::{Matrix4, Vector4};

/// Errors of the measurements.
type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// The rotation the measurements start at (the default trajectory's last onset is in 15).
const FROM: f64 = 30.0;
/// Instants of the rotation at which the frozen integrations are compared.
const SAMPLES: usize = 20;
/// Difference steps of the Jacobian: the slider's position (m), the rod's angle (rad), their
/// rates, and time (s). Each moves the journal by about 1/1000 of the penetration (3.6 µm) or
/// its rate by as much of eq. 3's velocity scale. Steps of 1.5e-10 of each coordinate drowned
/// the columns in the rounding of the positions' differences (1e-5 relative), and Rodas4's
/// local error then fell only as h² (measured in this program's first version).
const JACOBIAN_STEPS: [f64; 5] = [3.6e-9, 3e-8, 6e-6, 5e-5, 3.6e-10];
/// δ̇⁻ (m/s) of section 4's faster onset: about what member 3 of seed 1 holds late in its run
/// (19-21 mm/s).
const FASTER_ONSET: f64 = 0.02;

/// The run's right-hand side at a frozen run state, counting its evaluations.
struct Frozen<'a> {
    m: &'a Mechanism,
    state: RunState,
    ws: Workspace,
    evaluations: u64,
    /// Of [`Frozen::evaluations`], those of the Jacobians by differences.
    jacobian_evaluations: u64,
}

impl OdeSystem for Frozen<'_> {
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&mut self, t: f64, z: &[f64], dz: &mut [f64]) -> jointwear::Result<()> {
        self.evaluations += 1;
        self.m.ode_rhs(&self.state, &mut self.ws, t, z, dz)
    }
}

impl Frozen<'_> {
    fn f(&mut self, t: f64, z: &Vector4<f64>) -> jointwear::Result<Vector4<f64>> {
        let mut d = Vector4::zeros();
        self.rhs(t, z.as_slice(), d.as_mut_slice())?;
        Ok(d)
    }

    /// The journal's eccentricity (m) at (t, z).
    fn eccentricity(&self, t: f64, z: &[f64]) -> [f64; 2] {
        let n = self.m.coordinates();
        let mut y = vec![0.0; self.m.state_len()];
        self.m.absolute_state(t, z, &mut y);
        let c = self.m.contact_state(&self.state, 0, &y[..n], &y[n..2 * n]);
        [c.e.x, c.e.y]
    }

    /// ∂f/∂z and ∂f/∂t at (t, z) (20 evaluations): Richardson's extrapolation of central
    /// differences over [`JACOBIAN_STEPS`] and twice them.
    fn jacobian(&mut self, t: f64, z: &Vector4<f64>) -> Res<(Matrix4<f64>, Vector4<f64>)> {
        let before = self.evaluations;
        let jacobian = self.jacobian_uncounted(t, z);
        self.jacobian_evaluations += self.evaluations - before;
        jacobian
    }

    /// [`Frozen::jacobian`], its evaluations counted as any.
    fn jacobian_uncounted(
        &mut self,
        t: f64,
        z: &Vector4<f64>,
    ) -> Res<(Matrix4<f64>, Vector4<f64>)> {
        let mut j = Matrix4::zeros();
        let [steps @ .., et] = JACOBIAN_STEPS;
        let mut central =
            |t: f64, z: &Vector4<f64>, c: usize, e: f64| -> jointwear::Result<Vector4<f64>> {
                let (mut zp, mut zm) = (*z, *z);
                zp[c] += e;
                zm[c] -= e;
                Ok((self.f(t, &zp)? - self.f(t, &zm)?) / (2.0 * e))
            };
        for (c, &step) in steps.iter().enumerate() {
            let d1 = central(t, z, c, step)?;
            let d2 = central(t, z, c, 2.0 * step)?;
            j.set_column(c, &((4.0 * d1 - d2) / 3.0));
        }
        let d1 = (self.f(t + et, z)? - self.f(t - et, z)?) / (2.0 * et);
        let d2 = (self.f(t + 2.0 * et, z)? - self.f(t - 2.0 * et, z)?) / (4.0 * et);
        Ok((j, (4.0 * d1 - d2) / 3.0))
    }
}

/// Rodas4's coefficients in Hairer and Wanner's transformed form (their code RODAS).
mod rodas4 {
    pub const GAMMA: f64 = 0.25;
    pub const C: [f64; 6] = [0.0, 0.386, 0.21, 0.63, 1.0, 1.0];
    pub const D: [f64; 4] = [0.25, -0.1043, 0.1035, -0.0362];
    /// Row i: the stage i + 1's argument y + Σ a_ik u_k.
    pub const A: [[f64; 5]; 5] = [
        [1.544, 0., 0., 0., 0.],
        [0.9466785280815826, 0.2557011698983284, 0., 0., 0.],
        [
            3.314825187068521,
            2.896124015972201,
            0.9986419139977817,
            0.,
            0.,
        ],
        [
            1.221224509226641,
            6.019134481288629,
            12.53708332932087,
            -0.687886036105895,
            0.,
        ],
        [
            1.221224509226641,
            6.019134481288629,
            12.53708332932087,
            -0.687886036105895,
            1.0,
        ],
    ];
    /// Row i: the stage i + 1's terms Σ (c_ik / h) u_k.
    pub const CC: [[f64; 5]; 5] = [
        [-5.6688, 0., 0., 0., 0.],
        [-2.430093356833875, -0.2063599157091915, 0., 0., 0.],
        [
            -0.1073529058151375,
            -9.594562251023355,
            -20.47028614809616,
            0.,
            0.,
        ],
        [
            7.496443313967647,
            -10.24680431464352,
            -33.99990352819905,
            11.7089089320616,
            0.,
        ],
        [
            8.083246795921522,
            -7.981132988064893,
            -31.52159432874371,
            16.31930543123136,
            -6.058818238834054,
        ],
    ];
}

/// One Rodas4 step of size h from (t, z) with f(t, z) = f0: the new state and the error
/// estimate (the last stage).
fn rodas_step(
    s: &mut Frozen,
    t: f64,
    z: &Vector4<f64>,
    f0: &Vector4<f64>,
    (j, ft): &(Matrix4<f64>, Vector4<f64>),
    h: f64,
) -> Res<(Vector4<f64>, Vector4<f64>)> {
    use rodas4::*;
    let lu = (Matrix4::identity() / (h * GAMMA) - j).lu();
    let mut u = [Vector4::zeros(); 6];
    for i in 0..6 {
        let mut arg = *z;
        let mut r = if i == 0 { *f0 } else { Vector4::zeros() };
        for k in 0..i {
            arg += A[i - 1][k] * u[k];
            r += (CC[i - 1][k] / h) * u[k];
        }
        if i > 0 {
            r += s.f(t + C[i] * h, &arg)?;
        }
        if i < 4 {
            r += h * D[i] * ft;
        }
        u[i] = lu.solve(&r).ok_or("Rodas4's matrix is singular")?;
    }
    let z_new = (0..5).fold(*z + u[5], |acc, k| acc + A[4][k] * u[k]);
    Ok((z_new, u[5]))
}

/// Work of one integration over the samples, and its states there.
struct Work {
    steps: u64,
    rejected: u64,
    states: Vec<Vec<f64>>,
}

/// Rodas4 with Hairer's step control (safety 0.9, factors 0.2-6, order 4 for the exponent),
/// landing on each sample instant.
fn rodas(s: &mut Frozen, t0: f64, z0: &[f64], samples: &[f64], rtol: f64) -> Res<Work> {
    let atol = 1e-3 * rtol;
    let (mut t, mut z, mut h) = (t0, Vector4::from_column_slice(z0), 1e-6_f64);
    let mut w = Work {
        steps: 0,
        rejected: 0,
        states: Vec::new(),
    };
    let mut f0 = s.f(t, &z)?;
    // The Jacobian at (t, z), kept over rejected attempts from there, as Hairer's RODAS does.
    let mut kept = None;
    for &sample in samples {
        while t < sample {
            let hh = h.min(sample - t);
            let jac = match kept {
                Some(jac) => jac,
                None => *kept.insert(s.jacobian(t, &z)?),
            };
            // A stage outside the contact laws' range fails, as in the library's integrator:
            // the attempt is rejected and the step cut.
            let Ok((z_new, err)) = rodas_step(s, t, &z, &f0, &jac, hh) else {
                w.rejected += 1;
                h = 0.2 * hh;
                continue;
            };
            let norm = ((0..4)
                .map(|i| (err[i] / (atol + rtol * z[i].abs().max(z_new[i].abs()))).powi(2))
                .sum::<f64>()
                / 4.0)
                .sqrt();
            let fac = (0.9 / norm.powf(0.25)).clamp(0.2, 6.0);
            if norm <= 1.0 {
                (t, z) = (t + hh, z_new);
                f0 = s.f(t, &z)?;
                kept = None;
                w.steps += 1;
                if hh == h || fac < 1.0 {
                    h = hh * fac;
                }
            } else {
                w.rejected += 1;
                h = hh * fac.min(1.0);
            }
        }
        w.states.push(z.as_slice().to_vec());
    }
    Ok(w)
}

/// The library's Dopri5 (the scenes' largest step), its dense output at the samples.
fn dopri5(
    s: &mut Frozen,
    t0: f64,
    z0: &[f64],
    samples: &[f64],
    rtol: f64,
    max_step: f64,
) -> Res<Work> {
    let tol = Tolerances {
        rtol,
        atol: 1e-3 * rtol,
        max_step,
        initial_step: 0.0,
    };
    let mut ig = Integrator::new(Method::Dopri5, 4, 4, tol);
    ig.reset(s, t0, z0)?;
    let mut states = Vec::new();
    let mut buf = vec![0.0; 4];
    while states.len() < samples.len() {
        ig.step(s, samples[samples.len() - 1])?;
        while states.len() < samples.len() && samples[states.len()] <= ig.t() {
            ig.dense(samples[states.len()], &mut buf);
            states.push(buf.clone());
        }
    }
    let stats = ig.stats();
    Ok(Work {
        steps: stats.steps,
        rejected: stats.rejected,
        states,
    })
}

/// 5 %, 50 % and 95 % quantiles.
fn quantiles(mut v: Vec<f64>) -> String {
    v.sort_by(f64::total_cmp);
    let q = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
    format!("{:.3e} ({:.3e}-{:.3e})", q(0.5), q(0.05), q(0.95))
}

fn main() -> Res<()> {
    let mut file = SceneFile::read(scene_path("standard"))?;
    file.run.record_rotations = 0;
    let scene = file.build()?;
    let mut sim = common::named_trajectory(&scene)?;
    let period = scene.period();
    while sim.time() < FROM * period {
        sim.advance_step()?;
    }
    let m = sim.mechanism().clone();
    if m.ode_len() != 4 {
        return Err("the standard scene is expected in joint coordinates (4 components)".into());
    }
    let (t0, z0) = (sim.time(), m.ode_state(&sim.y()));
    let frozen = sim.state().clone();
    let mut s = Frozen {
        m: &m,
        state: frozen.clone(),
        ws: m.workspace(),
        evaluations: 0,
        jacobian_evaluations: 0,
    };
    println!(
        "rotation {FROM}: onset velocity held {:.3} mm/s",
        s.state.joints[0].onset_velocity * 1e3
    );

    // 1. The eigenvalues along the run's next rotation.
    let mut rows: Vec<(f64, Vec<f64>)> = Vec::new();
    while sim.time() < (FROM + 1.0) * period {
        let t = sim.time();
        sim.advance_step()?;
        let z = Vector4::from_column_slice(&m.ode_state(&sim.y()));
        s.state = sim.state().clone();
        let (j, _) = s.jacobian(sim.time(), &z)?;
        let mut moduli: Vec<f64> = j.complex_eigenvalues().iter().map(|l| l.norm()).collect();
        moduli.sort_by(|a, b| b.total_cmp(a));
        rows.push((sim.time() - t, moduli));
    }
    println!(
        "{} accepted steps; step (s) {}",
        rows.len(),
        quantiles(rows.iter().map(|r| r.0).collect())
    );
    for k in 0..4 {
        println!(
            "eigenvalue {} by modulus: |l| (1/s) {}, h|l| {}",
            k + 1,
            quantiles(rows.iter().map(|r| r.1[k]).collect()),
            quantiles(rows.iter().map(|r| r.0 * r.1[k]).collect())
        );
    }

    // 2. Dopri5 against Rodas4 on the frozen rotation.
    s.state = frozen;
    let samples: Vec<f64> = (1..=SAMPLES)
        .map(|k| t0 + period * k as f64 / SAMPLES as f64)
        .collect();
    // The journal's eccentricity at the samples by Dopri5 at rtol 1e-13, of the state held.
    let reference = |s: &mut Frozen| -> Res<Vec<[f64; 2]>> {
        let r = dopri5(s, t0, &z0, &samples, 1e-13, 2e-6)?;
        Ok((samples.iter().zip(&r.states))
            .map(|(&t, z)| s.eccentricity(t, z))
            .collect())
    };
    let error = |s: &Frozen, w: &Work, reference: &[[f64; 2]]| {
        samples
            .iter()
            .zip(&w.states)
            .zip(reference)
            .map(|((&t, z), r)| {
                let e = s.eccentricity(t, z);
                (e[0] - r[0]).hypot(e[1] - r[1])
            })
            .fold(0.0, f64::max)
    };
    // One integration of the frozen rotation by `method` at `rtol`: its work and its error
    // against `reference`, as a table's last five columns.
    let measured =
        |s: &mut Frozen, method: &str, rtol: f64, reference: &[[f64; 2]]| -> Res<String> {
            (s.evaluations, s.jacobian_evaluations) = (0, 0);
            let w = match method {
                "dopri5" => dopri5(s, t0, &z0, &samples, rtol, scene.run.tolerances.max_step)?,
                _ => rodas(s, t0, &z0, &samples, rtol)?,
            };
            Ok(format!(
                "{} | {} | {} | {} | {:.3}",
                w.steps,
                w.rejected,
                s.evaluations,
                s.evaluations - s.jacobian_evaluations,
                error(s, &w, reference) * 1e9
            ))
        };
    // 3. One step of each size from the state at rotation FROM: how each method's local error
    // shrinks with the step (the rates' error; h^5 or h^6 for a smooth system).
    println!(
        "h (s) | Dopri5's local error in the slider's velocity (m/s), the rod's rate (rad/s) | \
         Rodas4's"
    );
    let z = Vector4::from_column_slice(&z0);
    let (f0, jac) = (s.f(t0, &z)?, s.jacobian(t0, &z)?);
    for h in [1e-7, 2e-7, 4e-7, 8e-7, 1.6e-6, 3.2e-6] {
        let exact = dopri5(&mut s, t0, &z0, &[t0 + h], 1e-14, 1e-8)?
            .states
            .remove(0);
        let rates_errors = |z: &[f64]| format!("{:.3e}, {:.3e}", z[2] - exact[2], z[3] - exact[3]);
        // Tolerances no step can miss: one step of exactly h.
        let tol = Tolerances {
            rtol: 1e10,
            atol: 1e10,
            max_step: h,
            initial_step: h,
        };
        let mut one = Integrator::new(Method::Dopri5, 4, 4, tol);
        one.reset(&mut s, t0, &z0)?;
        one.step(&mut s, t0 + h)?;
        let (rodas_z, _) = rodas_step(&mut s, t0, &z, &f0, &jac, h)?;
        println!(
            "{h:e} | {} | {}",
            rates_errors(one.y()),
            rates_errors(rodas_z.as_slice())
        );
    }

    let worn_reference = reference(&mut s)?;
    println!(
        "method | rtol | steps | rejected | evaluations | without the Jacobians' | largest \
         eccentricity error (nm)"
    );
    for (name, rtols) in [
        ("dopri5", [1e-6, 3e-7, 1.5e-7, 1e-7, 3e-8, 1e-8]),
        ("rodas4", [1e-5, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8]),
    ] {
        for rtol in rtols {
            let work = measured(&mut s, name, rtol, &worn_reference)?;
            println!("{name} | {rtol:e} | {work}");
        }
    }

    // 4. What sets Dopri5's steps and what its rejections: the same frozen rotation with the
    // bearing unworn (no sector kinks) and with δ̇⁻ of a faster onset, eq. 3's damping a tenth;
    // and whether Rodas4 steps past the stiff mode where the profile is smooth. Each against
    // its own reference.
    println!(
        "frozen rotation | method | rtol | steps | rejected | evaluations | without the \
         Jacobians' | largest eccentricity error (nm)"
    );
    let worn = s.state.clone();
    let mut unworn = m.initial_state();
    unworn.joints[0].onset_velocity = worn.joints[0].onset_velocity;
    let faster = |mut state: RunState| {
        state.joints[0].onset_velocity = FASTER_ONSET;
        state
    };
    for (name, state) in [
        ("as frozen", worn.clone()),
        ("bearing unworn", unworn.clone()),
        ("onset velocity 20 mm/s", faster(worn)),
        ("both", faster(unworn)),
    ] {
        s.state = state;
        let reference = reference(&mut s)?;
        let runs = [scene.run.tolerances.rtol, 1e-7, 3e-8]
            .map(|rtol| ("dopri5", rtol))
            .into_iter()
            .chain([1e-6, 3e-7, 1e-7].map(|rtol| ("rodas4", rtol)));
        for (method, rtol) in runs {
            let work = measured(&mut s, method, rtol, &reference)?;
            println!("{name} | {method} | {rtol:e} | {work}");
        }
    }
    Ok(())
}
