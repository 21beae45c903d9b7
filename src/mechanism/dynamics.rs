//! The right-hand side of eq. 10-12: gravity and the clearance joints' contact and friction
//! forces (eq. 11, switched by eq. 12's unit step) as applied forces, then the constrained
//! accelerations; and the energy powers when accounting is on.

use super::kinematics::{perp, Frame};
use super::workspace::Workspace;
use super::{BodyIndex, Mechanism, RunState, MAX_PENETRATION_RATIO};
use crate::io::format::quantity;
use crate::ode::EventValue;
use crate::{Error, Result};
use nalgebra::{Complex, DMatrix, Schur, Vector2};

/// Central-difference steps of [`Mechanism::rhs_jacobian`]: of a coordinate (m or rad) and of a
/// velocity (m/s or rad/s). Fixed rather than relative, so that they do not grow with a
/// body's distance from the origin or the crank's turns: 1e-9 m is small against the
/// micrometre penetrations of the contact laws and 1e-7 m/s against the friction law's
/// 1e-4 m/s, yet both are far above the rounding of coordinates of order 0.1-1000.
pub const JACOBIAN_STEP: [f64; 2] = [1e-9, 1e-7];

/// The eigenvalues of `jacobian` (real Schur decomposition), largest modulus first; `None` if
/// an entry is not finite or the QR iteration does not converge.
pub fn eigenvalues_by_modulus(jacobian: &DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
    if !jacobian.iter().all(|v| v.is_finite()) {
        return None;
    }
    let schur = Schur::try_new(jacobian.clone(), f64::EPSILON, 10_000)?;
    let mut eigenvalues: Vec<Complex<f64>> = schur.complex_eigenvalues().iter().copied().collect();
    eigenvalues.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    Some(eigenvalues)
}

/// Adds a force `f` applied at rotated offset `s` from the centre of mass of body `b`.
#[inline]
fn add_force(force: &mut [[f64; 3]], b: BodyIndex, s: Vector2<f64>, f: Vector2<f64>) {
    if let Some(i) = b {
        let [x, y, torque] = &mut force[i];
        *x += f.x;
        *y += f.y;
        *torque += s.x * f.y - s.y * f.x;
    }
}

impl Mechanism {
    /// Generalised forces into `force` (x, y and torque of each body): gravity plus clearance-joint contact
    /// forces (eq. 11), with the bodies' poses and velocities from `frame`; each joint's
    /// penetration and its rate into `gaps` (one per clearance joint, the first `gaps.len()`).
    /// `ends(k)` names clearance joint `k`'s journal and bearing bodies, so that a caller
    /// that knows them at compile time reads their frames and adds their forces at fixed
    /// places.
    /// Returns (normal-force power, friction power) into the system, or the clearance joint
    /// and penetration beyond [`MAX_PENETRATION_RATIO`] of its journal radius.
    #[inline(always)]
    pub(super) fn applied_forces(
        &self,
        state: &RunState,
        ends: impl Fn(usize) -> (BodyIndex, BodyIndex),
        frame: impl Fn(BodyIndex) -> Frame,
        force: &mut [[f64; 3]],
        gaps: &mut [EventValue],
    ) -> std::result::Result<(f64, f64), (usize, f64)> {
        // Sliced, so that a force array of a length known at compile time unrolls the copy.
        let weights = &self.weights[..force.len()];
        for (f, w) in force.iter_mut().zip(weights) {
            *f = *w;
        }
        let (mut p_normal, mut p_friction) = (0.0, 0.0);
        for (k, gap) in gaps.iter_mut().enumerate() {
            let (journal, bearing) = ends(k);
            let (cs, sj, sb) = self.contact_between(state, k, &frame(journal), &frame(bearing));
            let cs = self.with_forces(state, k, cs);
            let cj = &self.clearance_joints[k];
            *gap = EventValue {
                value: cs.delta,
                rate: cs.delta_dot,
            };
            if cs.delta > MAX_PENETRATION_RATIO * cj.r_journal {
                return Err((k, cs.delta));
            }
            if cs.f_n == 0.0 {
                continue;
            }
            let (n, t) = (cs.n, perp(cs.n));
            let on_journal = -n * cs.f_n + t * cs.f_t;
            add_force(force, journal, sj + n * cj.r_journal, on_journal);
            add_force(force, bearing, sb + n * cj.r_bearing, -on_journal);
            p_normal -= cs.f_n * cs.e_rate;
            p_friction += cs.f_t * cs.v_t;
        }
        Ok((p_normal, p_friction))
    }

    /// The error of clearance joint `k` penetrating `delta` beyond the contact laws at `t`.
    pub(super) fn overload(&self, t: f64, k: usize, delta: f64) -> Error {
        let cj = &self.clearance_joints[k];
        Error::Integration {
            time: t,
            cause: format!(
                "clearance joint `{}` (journal on {}, bearing on {}) penetrates {} at driver \
                 angle {}, beyond {} % of its journal radius ({}) where the \
                 small-strain contact laws hold: the linkage forces the joint apart (links \
                 that cannot reach at this angle lock the mechanism) or a material is far too \
                 soft",
                cj.name,
                self.body_name(cj.journal.body),
                self.body_name(cj.bearing.body),
                quantity(delta * 1e3, "mm"),
                self.driver_angle_text(t),
                100.0 * MAX_PENETRATION_RATIO,
                quantity(MAX_PENETRATION_RATIO * cj.r_journal * 1e3, "mm")
            ),
        }
    }

    /// The Jacobian ∂f/∂y of [`Mechanism::rhs`] in the coordinates and velocities (2n × 2n,
    /// energy integrals left out) at (t, y), by central differences of [`JACOBIAN_STEP`]: for
    /// studies of the system's time scales ([`eigenvalues_by_modulus`]), not for the hot path.
    /// Meaningless across a contact switch (a penetration within a step of zero).
    pub fn rhs_jacobian(
        &self,
        state: &RunState,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
    ) -> Result<DMatrix<f64>> {
        let n = self.coordinates();
        if y.len() < 2 * n {
            return Err(Error::invalid(
                "state",
                format!("{} components", y.len()),
                format!("{} coordinates and velocities", 2 * n),
            ));
        }
        let mut jacobian = DMatrix::zeros(2 * n, 2 * n);
        let (mut y_step, mut plus, mut minus) =
            (y.to_vec(), vec![0.0; y.len()], vec![0.0; y.len()]);
        for j in 0..2 * n {
            let d = JACOBIAN_STEP[usize::from(j >= n)];
            y_step[j] = y[j] + d;
            self.rhs(state, ws, t, &y_step, &mut plus)?;
            y_step[j] = y[j] - d;
            self.rhs(state, ws, t, &y_step, &mut minus)?;
            y_step[j] = y[j];
            for i in 0..2 * n {
                jacobian[(i, j)] = (plus[i] - minus[i]) / (2.0 * d);
            }
        }
        Ok(jacobian)
    }

    /// The right-hand side y' = f(t, y) of eq. 10 with Baumgarte stabilisation, for the wear
    /// profiles and onset velocities of `state`, in the scratch space `ws`.
    pub fn rhs(
        &self,
        state: &RunState,
        ws: &mut Workspace,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
    ) -> Result<()> {
        let n = self.coordinates();
        let (q, v) = (&y[..n], &y[n..2 * n]);
        let mut phi = std::mem::take(&mut ws.lambda);
        self.constraints(ws, t, q, v, Some(&mut phi));
        ws.lambda = phi;
        let mut force = std::mem::take(&mut ws.force);
        let rot = &ws.rot;
        let frame = |b: BodyIndex| Frame::of(q, v, b, |i| rot[i]);
        let ends = |k| self.clearance_ends(k);
        let powers = self.applied_forces(state, ends, frame, &mut force, &mut ws.gaps);
        ws.force = force;
        let (p_normal, p_friction) = powers.map_err(|(k, delta)| self.overload(t, k, delta))?;
        self.accelerations(ws, t, v, &mut dy[n..2 * n])?;
        dy[..n].copy_from_slice(v);
        if self.energy_accounting {
            let driven = 3 * self.driver.body + 2;
            dy[2 * n] = ws.driver_torque(&dy[n..2 * n]) * v[driven];
            dy[2 * n + 1] = p_normal;
            dy[2 * n + 2] = p_friction;
        }
        Ok(())
    }
}
