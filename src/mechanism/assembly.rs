//! Assembly of a consistent initial state (every clearance joint held ideal: Newton
//! iterations on Φ(q, 0) = 0, then Φ_q q̇ = −Φ_t), and the messages that name the joints of
//! a loop that cannot close or a linkage that locks.

use super::workspace::{Dependent, Solved, Workspace};
use super::{BodyIndex, BodyPoint, ClearanceJoint, Mechanism, Revolute};
use crate::{Error, Result};

impl Mechanism {
    /// Consistent initial state at t = 0 with every clearance joint ideal (journal centred):
    /// positions by Newton iterations from the scene's guess, velocities from Φ_q q̇ = −Φ_t.
    /// Mass-weighted minimum-norm corrections make it work for any number of degrees of freedom.
    pub fn assemble(&self, guess: &[f64]) -> Result<Vec<f64>> {
        let mut ideal = self.clone();
        for cj in &self.clearance_joints {
            ideal.revolutes.push(Revolute {
                a: cj.journal,
                b: cj.bearing,
            });
        }
        ideal.clearance_joints.clear();
        ideal.energy_accounting = false;
        let mut ws = Workspace::new(&ideal)?;
        let held = &self.clearance_joints;
        let n = self.coordinates();
        let zeros = vec![0.0; n];
        let mut q = guess.to_vec();
        for iteration in 0.. {
            let phi = ideal.constraint_vector(&mut ws, 0.0, &q);
            let residual = phi.iter().fold(0.0f64, |a, p| a.max(p.abs()));
            if residual < 1e-13 {
                break;
            }
            if iteration == 50 || !residual.is_finite() {
                return Err(ideal.unclosed(&ws, &phi, iteration, held));
            }
            // Newton step Δq with Φ_q Δq = −Φ (the rows' part of Φ first).
            for (b, p) in ws.lambda.iter_mut().zip(&phi) {
                *b = -p;
            }
            for (q, dq) in q
                .iter_mut()
                .zip(ideal.min_norm_step(&mut ws, |s| -s.phi, held)?)
            {
                *q += dq;
            }
        }
        // Velocities: Φ_q q̇ = −Φ_t.
        ideal.constraints(&mut ws, 0.0, &q, &zeros, None);
        ws.lambda.fill(0.0);
        let v = ideal.min_norm_step(&mut ws, |s| -s.phi_t, held)?;
        let mut y = vec![0.0; self.state_len()];
        y[..n].copy_from_slice(&q);
        y[n..2 * n].copy_from_slice(&v);
        Ok(y)
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
        let mut order: Vec<usize> = (0..phi.len()).collect();
        order.sort_by(|&a, &b| phi[b].abs().total_cmp(&phi[a].abs()));
        let largest = phi[order[0]].abs();
        let mut joints: Vec<(String, f64)> = Vec::new();
        // The joints whose residual is of the order of the largest: where the loop breaks.
        let near_largest = |i: &&usize| phi[**i].abs() >= 0.1 * largest || phi[**i].is_nan();
        for &i in order.iter().take_while(near_largest) {
            let joint = self.equation_joint(ws.vector_equation(i), held);
            if !joints.iter().any(|(j, _)| *j == joint) {
                joints.push((joint, phi[i].abs()));
            }
        }
        let list: Vec<String> = joints
            .iter()
            .map(|(j, r)| format!("{j} by {r:.3e}"))
            .collect();
        Error::invalid(
            "joints (assembly)",
            format!(
                "the loop cannot close: after {iterations} Newton iterations it stays open at {} \
                 (constraint residual, m or rad)",
                list.join(", ")
            ),
            "links whose lengths can close every loop at the driver's initial angle, and a \
             pose guess (bodies' position_mm, angle_deg) near an assembled pose",
        )
    }

    /// Name of body `b` as the scene writes it (`ground` for the ground).
    pub(super) fn body_name(&self, b: BodyIndex) -> &str {
        b.map_or("ground", |i| &self.bodies[i].name)
    }

    /// The joint of constraint equation `e`, named as in the scene (`revolute[1] (crank-rod)`),
    /// in constraint order: two equations per revolute, two per translational joint, then the
    /// driver. The last `held.len()` revolutes are those clearance joints held ideal (assembly).
    fn equation_joint(&self, e: usize, held: &[ClearanceJoint]) -> String {
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

    /// The driver's prescribed angle at time `t`, for messages (deg in [0, 360)).
    pub(super) fn driver_angle_text(&self, t: f64) -> String {
        let d = &self.driver;
        format!(
            "{:.1} deg",
            (d.angle0 + d.omega * t).to_degrees().rem_euclid(360.0)
        )
    }
}
