//! Assembly of a consistent initial state (every clearance joint held ideal: Newton
//! iterations on Φ(q, 0) = 0, then Φ_q q̇ = −Φ_t), the kinematic sweep of one driver rotation
//! that finds where the loop cannot close ([`Mechanism::check_rotation`]), and the messages
//! that name the joints of a loop that cannot close or a linkage that locks.

use super::workspace::{Dependent, Solved, Workspace};
use super::{BodyIndex, BodyPoint, ClearanceJoint, Mechanism, Revolute};
use crate::io::format::quantity;
use crate::{Error, Result};

impl Mechanism {
    /// Consistent initial state at t = 0 with every clearance joint ideal (journal centred):
    /// positions by Newton iterations from the scene's guess, velocities from Φ_q q̇ = −Φ_t.
    /// Mass-weighted minimum-norm corrections make it work for any number of degrees of freedom.
    pub fn assemble(&self, guess: &[f64]) -> Result<Vec<f64>> {
        let ideal = self.held_ideal();
        let held = &self.clearance_joints;
        let mut ws = Workspace::holding(&ideal, held)?;
        let n = self.coordinates();
        let zeros = vec![0.0; n];
        let mut q = guess.to_vec();
        ideal.close(&mut ws, 0.0, &mut q, held)?;
        // Velocities: Φ_q q̇ = −Φ_t.
        ideal.constraints(&mut ws, 0.0, &q, &zeros, None);
        ws.lambda.fill(0.0);
        let v = ideal.min_norm_step(&mut ws, |s| -s.phi_t, held)?;
        let mut y = vec![0.0; self.state_len()];
        y[..n].copy_from_slice(&q);
        y[n..2 * n].copy_from_slice(&v);
        Ok(y)
    }

    /// The ideal loop of this mechanism: every clearance joint held as a revolute (journal
    /// centred), no energy states.
    fn held_ideal(&self) -> Mechanism {
        let mut ideal = self.clone();
        for cj in &self.clearance_joints {
            ideal.revolutes.push(Revolute {
                a: cj.journal,
                b: cj.bearing,
            });
        }
        ideal.clearance_joints.clear();
        ideal.energy_accounting = false;
        ideal
    }

    /// Newton iterations on Φ(q, t) = 0 from `q`, which they move to the closed pose (or leave
    /// at the last iterate if the loop stays open). `held`: the clearance joints held ideal.
    fn close(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &mut [f64],
        held: &[ClearanceJoint],
    ) -> Result<()> {
        for iteration in 0.. {
            let phi = self.constraint_vector(ws, t, q);
            let residual = phi.iter().fold(0.0f64, |a, p| a.max(p.abs()));
            if residual < 1e-13 {
                break;
            }
            if iteration == 50 || !residual.is_finite() {
                return Err(self.unclosed(ws, &phi, iteration, held));
            }
            // Newton step Δq with Φ_q Δq = −Φ (the rows' part of Φ first).
            for (b, p) in ws.lambda.iter_mut().zip(&phi) {
                *b = -p;
            }
            for (q, dq) in q.iter_mut().zip(self.min_norm_step(ws, |s| -s.phi, held)?) {
                *q += dq;
            }
        }
        Ok(())
    }

    /// Turns the driver of the ideal loop (clearance joints held centred) through one rotation
    /// from time `t0` at coordinates `q0` (assembled, or close to it), closing the loop every
    /// [`SWEEP_STEP_DEG`] by Newton iterations from the secant through the last two poses:
    /// where it cannot close, the links cannot reach, and a run locks there; where it fails at
    /// one step but closes at the next, that was a singular pose the loop passes (a rod as long
    /// as its crank), not a lock. Returns that range of driver angles (found
    /// turning forwards and backwards from the start, to [`SWEEP_RESOLUTION_DEG`]) and the
    /// joints left open, or `None` if the loop closes at every angle.
    pub fn check_rotation(&self, t0: f64, q0: &[f64]) -> Result<Option<Lock>> {
        let ideal = self.held_ideal();
        let held = &self.clearance_joints;
        let mut ws = Workspace::holding(&ideal, held)?;
        let mut q = q0[..self.coordinates()].to_vec();
        ideal.close(&mut ws, t0, &mut q, held)?;
        let step = SWEEP_STEP_DEG.to_radians() / self.driver.omega.abs();
        let Some((from, joints)) = ideal.first_open(&mut ws, t0, &q, step, held) else {
            return Ok(None);
        };
        let to = ideal
            .first_open(&mut ws, t0, &q, -step, held)
            .map_or(from, |(t, _)| t);
        Ok(Some(Lock {
            start: self.driver_angle(t0),
            from: self.driver_angle(from),
            to: self.driver_angle(to),
            counter_clockwise: self.driver.omega > 0.0,
            joints,
        }))
    }

    /// The first time, from `t0` in steps of `step` (s, negative: backwards) over one
    /// rotation, at which the loop closed at `q0` cannot close, refined by bisection, and the
    /// joints open there; `None` if it closes throughout.
    fn first_open(
        &self,
        ws: &mut Workspace,
        t0: f64,
        q0: &[f64],
        step: f64,
        held: &[ClearanceJoint],
    ) -> Option<(f64, Vec<String>)> {
        let steps = (360.0 / SWEEP_STEP_DEG).round() as usize;
        let mut q = q0.to_vec();
        // The pose before `q` and its time, for a secant predictor (none yet: `q` itself).
        let (mut before, mut t_before) = (q.clone(), t0);
        let mut trial = q.clone();
        let (mut closed, mut open) = (t0, None);
        let mut i = 1;
        while i <= steps {
            let t = t0 + i as f64 * step;
            // A singular pose (the change point of a slider-crank whose rod is as long as its
            // crank, where both branches cross) defeats Newton although the loop closes there
            // and beyond: closing one step further along the secant tells it from a lock.
            let tries = if i < steps { 2 } else { 1 };
            let reached = [(t, 1), (t + step, 2)]
                .into_iter()
                .take(tries)
                .find(|&(at, _)| {
                    predict(&before, t_before, &q, closed, at, &mut trial);
                    self.close(ws, at, &mut trial, held).is_ok()
                });
            let Some((at, advance)) = reached else {
                open = Some(t);
                break;
            };
            std::mem::swap(&mut before, &mut q);
            q.copy_from_slice(&trial);
            (t_before, closed) = (closed, at);
            i += advance;
        }
        let mut open = open?;
        let halvings = (SWEEP_STEP_DEG / SWEEP_RESOLUTION_DEG).log2().ceil() as usize;
        for _ in 0..halvings {
            let t = 0.5 * (closed + open);
            trial.copy_from_slice(&q);
            if self.close(ws, t, &mut trial, held).is_ok() {
                q.copy_from_slice(&trial);
                closed = t;
            } else {
                open = t;
            }
        }
        trial.copy_from_slice(&q);
        let _ = self.close(ws, open, &mut trial, held);
        let phi = self.constraint_vector(ws, open, &trial);
        let joints = self
            .largest_residuals(ws, &phi, held)
            .into_iter()
            .map(|(joint, _)| joint)
            .collect();
        Some((closed, joints))
    }

    /// The mass-weighted minimum-norm x with `J x = b` (the rows' b in `ws.lambda`, the
    /// solved equations' from `target`), for the state of the last `constraints` call.
    /// `held`: the clearance joints held ideal, for messages ([`Mechanism::equation_joint`]).
    fn min_norm_step(
        &self,
        ws: &mut Workspace,
        target: impl Fn(&Solved) -> f64,
        held: &[ClearanceJoint],
    ) -> Result<Vec<f64>> {
        let mut x = vec![0.0; self.coordinates()];
        ws.solve_fixed(&mut x, target);
        ws.project(&mut x).map_err(|Dependent(rows)| {
            Error::invalid(
                "joints (assembly)",
                format!(
                    "the constraints of {} are dependent at a pose the assembly reached",
                    self.joints_of_rows(ws, &rows, held).join(", ")
                ),
                "independent joints away from a dead-centre position (no locked or redundant \
                 joint; a driver angle at a dead centre needs another one)",
            )
        })?;
        Ok(x)
    }

    /// The error of an assembly whose Newton iterations did not close the constraints `phi`
    /// (in [`Mechanism::constraint_vector`] order): the joints with the largest residuals.
    fn unclosed(
        &self,
        ws: &Workspace,
        phi: &[f64],
        iterations: usize,
        held: &[ClearanceJoint],
    ) -> Error {
        let list: Vec<String> = self
            .largest_residuals(ws, phi, held)
            .iter()
            .map(|(j, r)| format!("{j} by {r}"))
            .collect();
        Error::invalid(
            "joints (assembly)",
            format!(
                "the loop cannot close: after {iterations} Newton iterations it stays open at {}",
                list.join(", ")
            ),
            "links whose lengths can close every loop at the driver's initial angle, and a \
             pose guess (bodies' position_mm, angle_deg) near an assembled pose",
        )
    }

    /// The joints whose residual in `phi` is of the order of the largest (where the loop
    /// breaks), largest first, with their residual in the scene's units (mm, deg).
    fn largest_residuals(
        &self,
        ws: &Workspace,
        phi: &[f64],
        held: &[ClearanceJoint],
    ) -> Vec<(String, String)> {
        let mut order: Vec<usize> = (0..phi.len()).collect();
        order.sort_by(|&a, &b| phi[b].abs().total_cmp(&phi[a].abs()));
        let largest = order.first().map_or(0.0, |&i| phi[i].abs());
        let mut joints: Vec<(String, String)> = Vec::new();
        let near_largest = |i: &&usize| phi[**i].abs() >= 0.1 * largest || phi[**i].is_nan();
        for &i in order.iter().take_while(near_largest) {
            let e = ws.vector_equation(i);
            let joint = self.equation_joint(e, held);
            if !joints.iter().any(|(j, _)| *j == joint) {
                let r = phi[i].abs();
                let residual = if self.angle_equation(e) {
                    quantity(r.to_degrees(), "deg")
                } else {
                    quantity(r * 1e3, "mm")
                };
                joints.push((joint, residual));
            }
        }
        joints
    }

    /// Whether constraint equation `e` (ordered as in [`Self::equation_joint`]) holds an angle
    /// (rad) rather than a length (m): a translational joint's first, and the driver's.
    fn angle_equation(&self, e: usize) -> bool {
        let (r, t) = (self.revolutes.len(), self.translationals.len());
        match e / 2 {
            i if i < r => false,
            i if i < r + t => e.is_multiple_of(2),
            _ => true,
        }
    }

    /// Name of body `b` as the scene writes it (`ground` for the ground).
    pub(super) fn body_name(&self, b: BodyIndex) -> &str {
        b.map_or("ground", |i| &self.bodies[i].name)
    }

    /// The joint of constraint equation `e`, named as in the scene (`revolute[1] (crank-rod)`),
    /// in constraint order: two equations per revolute, two per translational joint, then the
    /// driver. The last `held.len()` revolutes are those clearance joints held ideal (assembly).
    pub(super) fn equation_joint(&self, e: usize, held: &[ClearanceJoint]) -> String {
        let (r, t) = (self.revolutes.len(), self.translationals.len());
        let pair = |a: &BodyPoint, b: &BodyPoint| {
            format!("{}-{}", self.body_name(a.body), self.body_name(b.body))
        };
        let own = r - held.len();
        match e / 2 {
            i if i < own => format!(
                "revolute[{i}] ({})",
                pair(&self.revolutes[i].a, &self.revolutes[i].b)
            ),
            i if i < r => {
                let cj = &held[i - own];
                format!(
                    "clearance joint `{}` ({}, held ideal)",
                    cj.name,
                    pair(&cj.journal, &cj.bearing)
                )
            }
            i if i < r + t => {
                let j = &self.translationals[i - r];
                format!("translational[{}] ({})", i - r, pair(&j.a, &j.b))
            }
            _ => format!("driver ({})", self.body_name(Some(self.driver.body))),
        }
    }

    /// The joints of rows of the constraint system, in order, without repeats.
    pub(super) fn joints_of_rows(
        &self,
        ws: &Workspace,
        rows: &[usize],
        held: &[ClearanceJoint],
    ) -> Vec<String> {
        let mut joints: Vec<String> = Vec::new();
        for &row in rows {
            let joint = self.equation_joint(ws.vector_equation(row), held);
            if !joints.contains(&joint) {
                joints.push(joint);
            }
        }
        joints
    }

    /// The driver's prescribed angle at time `t` (deg in [0, 360)).
    pub fn driver_angle(&self, t: f64) -> f64 {
        let d = &self.driver;
        (d.angle0 + d.omega * t).to_degrees().rem_euclid(360.0)
    }

    /// The driver's prescribed angle at time `t`, for messages.
    pub(super) fn driver_angle_text(&self, t: f64) -> String {
        format!("{:.1} deg", self.driver_angle(t))
    }
}

/// Into `out`, the pose at time `t` on the secant through `before` (at `t_before`) and `q`
/// (at `t_q`); `q` itself when the two times coincide (the sweep's first step).
fn predict(before: &[f64], t_before: f64, q: &[f64], t_q: f64, t: f64, out: &mut [f64]) {
    let span = t_q - t_before;
    let ahead = if span == 0.0 { 0.0 } else { (t - t_q) / span };
    for ((o, b), q) in out.iter_mut().zip(before).zip(q) {
        *o = q + ahead * (q - b);
    }
}

/// Driver step of [`Mechanism::check_rotation`] (deg): 360 closures of a few Newton
/// iterations each, a millisecond for a four-bar.
pub const SWEEP_STEP_DEG: f64 = 1.0;

/// How closely [`Mechanism::check_rotation`] locates where the loop stops closing (deg).
pub const SWEEP_RESOLUTION_DEG: f64 = 1e-3;

/// Where the ideal loop of a mechanism cannot close over one driver rotation
/// ([`Mechanism::check_rotation`]): the driver cannot turn through these angles.
#[derive(Clone, Debug, PartialEq)]
pub struct Lock {
    /// Driver angle (deg, [0, 360)) at the start of the sweep.
    pub start: f64,
    /// Driver angle (deg, [0, 360)) where the loop, turned in the driver's direction from the
    /// start, last closes.
    pub from: f64,
    /// Driver angle (deg) where it closes again: the last one reached turning backwards from
    /// the start (`from` if it closes nowhere else).
    pub to: f64,
    /// The driver turns counter-clockwise (its angle grows from `from` to `to`).
    pub counter_clockwise: bool,
    /// The joints left open just past `from`, in the scene's words.
    pub joints: Vec<String>,
}

impl Lock {
    /// What the sweep found, for messages: how far the loop closes each way from the start
    /// (it fails within [`SWEEP_RESOLUTION_DEG`] past each end), the angles the driver cannot
    /// turn through, and the open joints. Only the ends are found: between them the loop may
    /// close in another assembly (a four-bar whose coupler and rocker reach the crank pin only
    /// at middle distances closes on two separate ranges of crank angle), which the driver,
    /// turning continuously, still cannot reach.
    pub fn describe(&self) -> String {
        let (ahead, back) = if self.counter_clockwise {
            ("counter-clockwise", "clockwise")
        } else {
            ("clockwise", "counter-clockwise")
        };
        format!(
            "turned from its start at {:.1} deg in steps of {SWEEP_STEP_DEG} deg, the ideal loop \
             (clearance joints centred) closes {ahead} as far as {:.3} deg and {back} as far \
             as {:.3} deg, and fails to close within {SWEEP_RESOLUTION_DEG} deg past each: the \
             driver cannot turn from {:.1} to {:.1} deg of driver angle (turning {ahead}); past \
             {:.3} deg the loop stays open at {}",
            self.start,
            self.from,
            self.to,
            self.from,
            self.to,
            self.from,
            self.joints.join(", ")
        )
    }

    /// The error of a scene whose driver cannot turn a whole rotation (bad input).
    pub fn error(&self) -> Error {
        Error::invalid(
            "joints (one driver rotation)",
            self.describe(),
            "links whose lengths close every loop at every driver angle (a slider-crank's \
             crank turns fully when its rod is no shorter than the crank plus the slider \
             guide's offset from the crank pivot; a four-bar's when its shortest and longest \
             links together are no longer than the other two, the crank being the shortest); \
             likely cause: a link length or a pivot in the wrong place",
        )
    }
}
