//! The constraint equations Φ(q, t) = 0 of the ideal joints and the driver (eq. 10), their
//! Jacobian and `γ = −(Φ_q q̇)_q q̇ − 2Φ_qt q̇ − Φ_tt`, and the accelerations
//! `q̈ = M⁻¹ (F − Φ_qᵀ λ)` with Baumgarte's `γ̂ = γ − 2α Φ̇ − β² Φ`.

use super::kinematics::{perp, rotate, sincos, Frame};
use super::workspace::{Sink, Workspace};
use super::{BodyIndex, Mechanism};
use crate::{Error, Result};

impl Mechanism {
    /// Fills the body rotations of the workspace and, for every equation, Φ_q and
    /// γ = −(Φ_q q̇)_q q̇ (with M⁻¹ Φ_qᵀ for the rows), and Φ (of the rows into `phi` if given).
    pub(super) fn constraints(
        &self,
        ws: &mut Workspace,
        t: f64,
        q: &[f64],
        v: &[f64],
        phi: Option<&mut [f64]>,
    ) {
        for (i, (rot, _)) in (ws.rot.iter_mut().zip(&ws.rotates))
            .enumerate()
            .filter(|(_, (_, &r))| r)
        {
            *rot = sincos(q[3 * i + 2]);
        }
        let rot = &ws.rot;
        let frame = |b: BodyIndex| Frame::of(q, v, b, |i| rot[i]);
        let mut sink = Sink {
            rows: &mut ws.rows,
            gamma: &mut ws.gamma,
            solved: &mut ws.solved,
            slot: &ws.slot,
            phi,
            e: 0,
        };
        for j in &self.revolutes {
            let (fa, fb) = (frame(j.a.body), frame(j.b.body));
            let (ra, _, sa) = fa.point(j.a.local);
            let (rb, _, sb) = fb.point(j.b.local);
            let (pa, pb) = (perp(sa), perp(sb));
            let (g, d) = (sa * fa.w * fa.w - sb * fb.w * fb.w, ra - rb);
            let x = [(j.a.body, [1.0, 0.0, pa.x]), (j.b.body, [-1.0, 0.0, -pb.x])];
            sink.set(x, g.x, d.x, 0.0);
            let y = [(j.a.body, [0.0, 1.0, pa.y]), (j.b.body, [0.0, -1.0, -pb.y])];
            sink.set(y, g.y, d.y, 0.0);
        }
        for j in &self.translationals {
            let (fa, fb) = (frame(j.a.body), frame(j.b.body));
            let (ra, va, sa) = fa.point(j.a.local);
            let (rb, vb, sb) = fb.point(j.b.local);
            let (wa, wb) = (fa.w, fb.w);
            let nrm = rotate(fb.sc, j.normal);
            let d = ra - rb;
            let d_dot = va - vb;
            let angle = [(j.a.body, [0.0, 0.0, 1.0]), (j.b.body, [0.0, 0.0, -1.0])];
            sink.set(angle, 0.0, fa.phi - fb.phi - j.relative_angle, 0.0);
            let line = [
                (j.a.body, [nrm.x, nrm.y, nrm.dot(&perp(sa))]),
                (
                    j.b.body,
                    [-nrm.x, -nrm.y, perp(nrm).dot(&d) - nrm.dot(&perp(sb))],
                ),
            ];
            let g = nrm.dot(&d) * wb * wb - 2.0 * wb * perp(nrm).dot(&d_dot)
                + nrm.dot(&(sa * wa * wa - sb * wb * wb));
            sink.set(line, g, nrm.dot(&d), 0.0);
        }
        let dr = &self.driver;
        let driver = [(Some(dr.body), [0.0, 0.0, 1.0]), (None, [0.0; 3])];
        let angle = q[3 * dr.body + 2] - dr.angle0 - dr.omega * t;
        sink.set(driver, 0.0, angle, -dr.omega);
        // A ground block has zero columns: any weight gives zero.
        for r in &mut ws.rows {
            for (&at, (c, wc)) in r.at.iter().zip(r.col.iter().zip(&mut r.wcol)) {
                *wc = std::array::from_fn(|k| c[k] * ws.inv_mass[at + k]);
            }
        }
    }

    /// q̈ = M⁻¹ (F − Φ_qᵀ λ) for the constraints, Φ (in `ws.lambda`) and applied forces in
    /// the workspace, the solved coordinates first; leaves the rows' λ in the workspace.
    pub(super) fn accelerations(
        &self,
        ws: &mut Workspace,
        t: f64,
        v: &[f64],
        acc: &mut [f64],
    ) -> Result<()> {
        let (alpha, beta) = self.baumgarte;
        for (a, (f, w)) in acc
            .iter_mut()
            .zip(ws.force.as_flattened().iter().zip(&ws.inv_mass))
        {
            *a = f * w;
        }
        for ((b, row), g) in ws.lambda.iter_mut().zip(&ws.rows).zip(&ws.gamma) {
            *b = g - 2.0 * alpha * row.dot(v) - beta * beta * *b;
        }
        ws.solve_fixed(acc, |s| {
            s.gamma - 2.0 * alpha * (s.row.dot(v) + s.phi_t) - beta * beta * s.phi
        });
        let dependent = match ws.project(acc) {
            Ok(()) => return Ok(()),
            Err(d) => d,
        };
        // A blown-up state also breaks the solve; only a finite one means bad joints.
        let cause = if v
            .iter()
            .chain(ws.force.as_flattened())
            .all(|x| x.is_finite())
        {
            format!(
                "the linkage locks at driver angle {}: the constraints of {} are dependent \
                 (a dead-centre position, links that cannot reach, or redundant joints)",
                self.driver_angle_text(t),
                self.joints_of_rows(ws, &dependent.0, &[]).join(", ")
            )
        } else {
            "non-finite state: the step is too large for the contact stiffness".into()
        };
        Err(Error::Integration { time: t, cause })
    }

    /// Dense copy of the constraint Jacobian and γ at (q, v), for tests and diagnostics: the
    /// rows of [`Mechanism::constraint_vector`].
    pub fn jacobian(&self, ws: &mut Workspace, q: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.constraints(ws, 0.0, q, v, None);
        let n = self.coordinates();
        let rows = ws.rows.iter().zip(ws.gamma.iter().copied());
        let solved = ws.solved.iter().map(|s| (&s.row, s.gamma));
        let mut jac = vec![0.0; self.constraint_count() * n];
        let mut gamma = Vec::new();
        for (out, (r, g)) in jac.chunks_exact_mut(n).zip(rows.chain(solved)) {
            for (k, c) in r.entries() {
                out[k] = c;
            }
            gamma.push(g);
        }
        (jac, gamma)
    }

    /// Constraint residual vector Φ(q, t): the rows of the constraint system, then the
    /// equations solved for one coordinate, in their order.
    pub fn constraint_vector(&self, ws: &mut Workspace, t: f64, q: &[f64]) -> Vec<f64> {
        let rows = ws.rows.len();
        let mut phi = vec![0.0; rows];
        let zeros = vec![0.0; q.len()];
        self.constraints(ws, t, q, &zeros, Some(&mut phi));
        phi.extend(ws.solved.iter().map(|s| s.phi));
        phi
    }
}
