//! Coordinate partitioning (Wehage and Haug, 1982) for a closed loop of ideal joints, measured
//! against the absolute coordinates with Baumgarte-stabilised constraints (eq. 10) that such
//! a linkage runs in: `cargo run --release --example partitioning`.
//!
//! Partitioning integrates only the independent coordinates `q_i` and their rates (chosen
//! once by full pivoting on the constraint Jacobian at the start); every evaluation solves
//! the position constraints Φ(q, t) = 0 for the dependent `q_d` by Newton's method, the
//! velocity constraints `Φ_q q̇ = −Φ_t` for their rates, and takes the independent
//! accelerations from the constrained equations of motion at that closed state (where
//! Baumgarte's terms vanish). So each of its evaluations costs one absolute evaluation
//! plus the Newton and velocity solves; it can pay only by needing fewer evaluations, its
//! error norm running over the 2 f independent components instead of all 6 per body.
//!
//! The scene is `tests/scenes/fourbar_flail.toml` (4 bodies, 12 coordinates, 9 constraint
//! rows, 3 freedoms). Both formulations integrate the same smooth ODE over one crank
//! rotation: wear off and the onset velocity of eq. 3 held at [`ONSET_VELOCITY`] (a run
//! captures it at each located onset, which would make the two ODEs differ by where each
//! locates it). Errors are of the flail's centre of mass against a reference integration
//! of the absolute coordinates at rtol 1e-12, at every [`SAMPLE`] of the rotation.
//! The prototype calls the library's allocating diagnostics (`Mechanism::jacobian`,
//! `constraint_vector`) and a dense LU in its Newton solve: its time per evaluation is an
//! upper bound for partitioning, the counts of evaluations and Newton iterations are not.

use jointwear::mechanism::{Mechanism, RunState, Workspace};
use jointwear::ode::{Integrator, Method, OdeSystem, Tolerances};
use jointwear::scene::SceneFile;
use jointwear::simulation::Simulation;
use nalgebra::{DMatrix, DVector};
use std::path::Path;
use std::time::Instant;

/// Normal velocity at contact onset held for the whole integration (m/s), eq. 3's δ̇⁻.
const ONSET_VELOCITY: f64 = 0.1;

/// Spacing of the error samples (s).
const SAMPLE: f64 = 1e-4;

/// Newton's stopping rule: the correction below this (m or rad) ends the iteration.
const NEWTON_TOLERANCE: f64 = 1e-14;

/// The absolute-coordinate right-hand side, as a run evaluates it.
struct Absolute<'a> {
    m: &'a Mechanism,
    state: &'a RunState,
    ws: Workspace,
}

impl OdeSystem for Absolute<'_> {
    fn dim(&self) -> usize {
        2 * self.m.coordinates()
    }

    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> jointwear::Result<()> {
        self.m.rhs(self.state, &mut self.ws, t, y, dy)
    }
}

/// The partitioned right-hand side: state `(q_i, q̇_i)`.
struct Partitioned<'a> {
    m: &'a Mechanism,
    state: &'a RunState,
    ws: Workspace,
    independent: Vec<usize>,
    dependent: Vec<usize>,
    /// The closed absolute state of the last evaluation: Newton's first guess (so an evaluation
    /// depends on the one before at the level of [`NEWTON_TOLERANCE`]).
    y: Vec<f64>,
    newton_iterations: u64,
    evaluations: u64,
}

impl Partitioned<'_> {
    /// The constraint Jacobian at `q`, dense (rows × coordinates).
    fn jacobian(&mut self, q: &[f64]) -> DMatrix<f64> {
        let n = self.m.coordinates();
        let (jac, _) = self.m.jacobian(&mut self.ws, q, &vec![0.0; n]);
        DMatrix::from_row_slice(jac.len() / n, n, &jac)
    }

    /// Closes `self.y` at time `t` for the independent `z`: positions by Newton, then
    /// velocities.
    fn close(&mut self, t: f64, z: &[f64]) -> jointwear::Result<()> {
        let n = self.m.coordinates();
        let f = self.independent.len();
        for (k, &i) in self.independent.iter().enumerate() {
            self.y[i] = z[k];
            self.y[n + i] = z[f + k];
        }
        let mut converged = false;
        for _ in 0..20 {
            let q = self.y[..n].to_vec();
            let phi = DVector::from_vec(self.m.constraint_vector(&mut self.ws, t, &q));
            let step = (self.jacobian(&q).select_columns(&self.dependent))
                .lu()
                .solve(&phi)
                .ok_or_else(singular)?;
            self.newton_iterations += 1;
            for (k, &i) in self.dependent.iter().enumerate() {
                self.y[i] -= step[k];
            }
            if step.amax() <= NEWTON_TOLERANCE {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(jointwear::Error::invalid(
                "Newton's method on the position constraints",
                "no convergence in 20 iterations",
                format!("a correction below {NEWTON_TOLERANCE:e}"),
            ));
        }
        // Φ_q q̇ = −Φ_t; Φ is linear in t (the driver's constant speed), so the central
        // difference of Φ over ±1 ms is its exact rate up to rounding.
        let q = self.y[..n].to_vec();
        let (plus, minus) = (
            self.m.constraint_vector(&mut self.ws, t + 1e-3, &q),
            self.m.constraint_vector(&mut self.ws, t - 1e-3, &q),
        );
        let jac = self.jacobian(&q);
        let (jd, ji) = (
            jac.select_columns(&self.dependent),
            jac.select_columns(&self.independent),
        );
        let vi = DVector::from_fn(f, |k, _| z[f + k]);
        let phi_t = DVector::from_fn(plus.len(), |r, _| (plus[r] - minus[r]) / 2e-3);
        let vd = jd.lu().solve(&(-(ji * vi) - phi_t)).ok_or_else(singular)?;
        for (k, &i) in self.dependent.iter().enumerate() {
            self.y[n + i] = vd[k];
        }
        Ok(())
    }
}

impl OdeSystem for Partitioned<'_> {
    fn dim(&self) -> usize {
        2 * self.independent.len()
    }

    fn rhs(&mut self, t: f64, z: &[f64], dz: &mut [f64]) -> jointwear::Result<()> {
        self.evaluations += 1;
        self.close(t, z)?;
        let n = self.m.coordinates();
        let mut dy = vec![0.0; self.y.len()];
        self.m.rhs(self.state, &mut self.ws, t, &self.y, &mut dy)?;
        let f = self.independent.len();
        for (k, &i) in self.independent.iter().enumerate() {
            dz[k] = z[f + k];
            dz[f + k] = dy[n + i];
        }
        Ok(())
    }
}

/// The error of a dependent block that turned singular (the partition chosen at the start no
/// longer holds: a lock position of the loop).
fn singular() -> jointwear::Error {
    jointwear::Error::invalid(
        "the dependent coordinates",
        "a singular block of the constraint Jacobian",
        "a regular one (choose the partition again)",
    )
}

/// The dependent columns of the `rows × n` Jacobian `jac` by full pivoting (the columns of
/// the largest remaining pivots, in their order), then the independent ones. (nalgebra's
/// `full_piv_lu` picks the same columns in another order, which moves the rounding of this
/// chaotic comparison: the numbers quoted in paper.md come from this order.)
fn partition(jac: &[f64], n: usize) -> (Vec<usize>, Vec<usize>) {
    let rows = jac.len() / n;
    let mut a = DMatrix::from_row_slice(rows, n, jac);
    let mut dependent = Vec::new();
    for r in 0..rows {
        let (mut best, mut at) = (0.0, (r, 0));
        for i in r..rows {
            for j in (0..n).filter(|j| !dependent.contains(j)) {
                if a[(i, j)].abs() > best {
                    (best, at) = (a[(i, j)].abs(), (i, j));
                }
            }
        }
        a.swap_rows(r, at.0);
        let (p, col) = (a[(r, at.1)], at.1);
        for i in r + 1..rows {
            let factor = a[(i, col)] / p;
            for j in 0..n {
                a[(i, j)] -= factor * a[(r, j)];
            }
        }
        dependent.push(col);
    }
    let independent = (0..n).filter(|j| !dependent.contains(j)).collect();
    (dependent, independent)
}

/// The flail's centre of mass (its body is the last) at the sample times, with the
/// evaluations taken and the wall time, for a system integrated at `rtol`.
fn integrate(
    sys: &mut impl OdeSystem,
    y0: &[f64],
    rtol: f64,
    end: f64,
    flail: impl Fn(&[f64]) -> [f64; 2],
) -> (Vec<[f64; 2]>, u64, f64) {
    let tol = Tolerances {
        rtol,
        atol: 1e-3 * rtol,
        max_step: 1e-4,
        initial_step: 0.0,
    };
    let mut integrator = Integrator::new(Method::Dopri5, y0.len(), y0.len(), tol);
    let start = Instant::now();
    integrator.reset(sys, 0.0, y0).expect("a regular start");
    let (mut samples, mut next, mut out) = (Vec::new(), 0.0, vec![0.0; y0.len()]);
    while integrator.t() < end {
        integrator.step(sys, end).expect("the integration runs");
        while next <= integrator.t() {
            integrator.dense(next, &mut out);
            samples.push(flail(&out));
            next += SAMPLE;
        }
    }
    let wall = start.elapsed().as_secs_f64();
    (samples, integrator.stats().evaluations, wall)
}

/// The largest distance between two sample series (m).
fn largest_error(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0, f64::max)
}

fn main() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/fourbar_flail.toml");
    let scene = SceneFile::read(&path)
        .and_then(|f| f.build())
        .expect("the test scene");
    let sim = Simulation::start(&scene).expect("the scene starts");
    let m = sim.mechanism().clone();
    let mut state = sim.state().clone();
    for j in &mut state.joints {
        j.onset_velocity = ONSET_VELOCITY;
    }
    let n = m.coordinates();
    let y0 = sim.y()[..2 * n].to_vec();
    let end = 60.0 / 1000.0; // one rotation at the scene's 1000 r/min
    let flail_body = 3 * (m.bodies().len() - 1);
    let absolute_flail = |y: &[f64]| [y[flail_body], y[flail_body + 1]];
    let mut ws = m.workspace();
    let (jac, _) = m.jacobian(&mut ws, &y0[..n], &y0[n..]);
    let (dependent, independent) = partition(&jac, n);
    println!("independent coordinates {independent:?} (the flail's x, y, angle are 9, 10, 11)");
    let at = |i: usize| independent.iter().position(|&k| k == flail_body + i);
    let (fx, fy) = (at(0).expect("x independent"), at(1).expect("y independent"));

    let mut reference = Absolute {
        m: &m,
        state: &state,
        ws: m.workspace(),
    };
    let (truth, _, _) = integrate(&mut reference, &y0, 1e-12, end, absolute_flail);
    println!(
        "One crank rotation (0.06 s), Dopri5 at atol = 1e-3 rtol, maximum step 1e-4 s; error: \
         the largest distance of the flail's centre of mass from the reference's over the \
         rotation's samples every 0.1 ms (m); time: wall time per evaluation, integrator \
         included (s)."
    );
    println!(
        "rtol | absolute: evaluations, error, time | partitioned: evaluations, error, time, \
         Newton iterations per evaluation"
    );
    for rtol in [1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9] {
        let mut abs = Absolute {
            m: &m,
            state: &state,
            ws: m.workspace(),
        };
        let (a, a_evals, a_wall) = integrate(&mut abs, &y0, rtol, end, absolute_flail);
        let mut part = Partitioned {
            m: &m,
            state: &state,
            ws: m.workspace(),
            independent: independent.clone(),
            dependent: dependent.clone(),
            y: y0.clone(),
            newton_iterations: 0,
            evaluations: 0,
        };
        let z0: Vec<f64> = (independent.iter().map(|&i| y0[i]))
            .chain(independent.iter().map(|&i| y0[n + i]))
            .collect();
        let (p, p_evals, p_wall) = integrate(&mut part, &z0, rtol, end, |z| [z[fx], z[fy]]);
        println!(
            "{rtol:e} | {a_evals} {:.3e} {:.3e} | {p_evals} {:.3e} {:.3e} {:.2}",
            largest_error(&a, &truth),
            a_wall / a_evals as f64,
            largest_error(&p, &truth),
            p_wall / p_evals as f64,
            part.newton_iterations as f64 / part.evaluations as f64,
        );
    }
}
