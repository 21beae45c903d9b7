//! Planar multibody dynamics with clearance joints as force elements (paper eq. 10-12).
//!
//! ```text
//! M q̈ + Φ_qᵀ λ = F + F_c,     Φ(q, t) = 0                                   (10)
//! F_c = u(δ) (F_n + F_t),      u(δ) = 1 for δ ≥ 0, 0 otherwise              (11, 12)
//! ```
//! Each body has absolute coordinates `(x, y, φ)` of its centre of mass; M is diagonal
//! (`m, m, J` per body), so the multipliers come from the small SPD system
//! `(Φ_q M⁻¹ Φ_qᵀ) λ = Φ_q M⁻¹ F − γ̂` and `q̈ = M⁻¹ (F − Φ_qᵀ λ)`; no n×n matrix is ever formed.
//! The paper's `C q̇ + K_g q` terms are zero for rigid bodies and are not modelled.
//!
//! Constraint stabilisation is Baumgarte's, `γ̂ = γ − 2α Φ̇ − β² Φ`. It keeps the right-hand
//! side a smooth ODE, which the adaptive integrator's error control, dense output and
//! contact-onset location rely on; a post-step projection would change the state between
//! steps and invalidate the first-same-as-last stage and the dense output.
//!
//! A clearance joint connects a journal point on one body to a bearing point on another.
//! With `e = r_J − r_B`, the contact normal is `n = e/|e|`, the contact angle θ is the
//! angle of `n` in the bearing body's frame (counter-clockwise from its +x axis), and the
//! penetration is `δ = |e| − c − h(θ)` with `h` the bearing's wear depth ([`crate::wear`]).
//! The normal force is [`crate::contact`]'s law; friction ([`crate::friction`]) acts along the
//! tangent `t = (−n_y, n_x)` against the relative velocity of the material points in contact,
//! `v_t = ė·t + φ̇_J R_J − φ̇_B R_B`.

use crate::contact::ContactLaw;
use crate::friction::FrictionModel;
use crate::wear::{WearLaw, WearProfile};
use crate::{Error, Result};
use nalgebra::Vector2;

/// A body's coordinate index, or `None` for the ground (fixed, at the origin, angle 0).
pub type BodyIndex = Option<usize>;

/// Rigid body: mass (kg) and moment of inertia about its centre of mass (kg m²).
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub name: String,
    pub mass: f64,
    pub inertia: f64,
}

/// A point fixed in a body: body index and local coordinates (m) from its centre of mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPoint {
    pub body: BodyIndex,
    pub local: Vector2<f64>,
}

/// Ideal revolute joint: two body points coincide (2 equations).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Revolute {
    pub a: BodyPoint,
    pub b: BodyPoint,
}

/// Ideal translational joint: body `a` keeps its angle relative to `b`, and point `a` stays
/// on the line through point `b` whose unit normal is `normal` in `b`'s frame (2 equations).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Translational {
    pub a: BodyPoint,
    pub b: BodyPoint,
    pub normal: Vector2<f64>,
    /// φ_a − φ_b held constant (rad).
    pub relative_angle: f64,
}

/// Constant-speed driver: `φ_body = angle0 + ω t` (1 equation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Driver {
    pub body: usize,
    /// Angular speed ω (rad/s), positive counter-clockwise.
    pub omega: f64,
    /// Angle at t = 0 (rad).
    pub angle0: f64,
}

/// A clearance revolute joint with its contact, friction and (optional) wear models.
#[derive(Clone, Debug, PartialEq)]
pub struct ClearanceJoint {
    pub name: String,
    pub journal: BodyPoint,
    pub bearing: BodyPoint,
    /// Journal radius R_j (m).
    pub r_journal: f64,
    /// Unworn bearing radius R_i (m).
    pub r_bearing: f64,
    pub contact: ContactLaw,
    pub friction: FrictionModel,
    /// `None`: the scene computes no wear.
    pub wear: Option<WearLaw>,
    pub profile: WearProfile,
    /// Normal velocity captured at the onset of the current contact (m/s).
    pub impact_velocity: f64,
}

/// Kinematics and forces of one clearance joint at one state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactState {
    /// Journal centre relative to bearing centre, global frame (m).
    pub e: Vector2<f64>,
    /// Contact angle in the bearing frame, in [0, 2π) (rad).
    pub theta: f64,
    /// Penetration δ (m); negative while the journal flies free.
    pub delta: f64,
    /// dδ/dt (m/s).
    pub delta_dot: f64,
    /// Local radial clearance including wear, c + h(θ) (m).
    pub local_clearance: f64,
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

/// Powers integrated when energy accounting is on (extra ODE states, outside error control).
pub const ENERGY_STATES: usize = 3;

/// A planar mechanism: bodies, ideal joints, one driver, clearance joints, gravity.
#[derive(Clone, Debug)]
pub struct Mechanism {
    pub bodies: Vec<Body>,
    pub revolutes: Vec<Revolute>,
    pub translationals: Vec<Translational>,
    pub driver: Driver,
    pub clearance_joints: Vec<ClearanceJoint>,
    /// Gravitational acceleration (m/s²).
    pub gravity: Vector2<f64>,
    /// Baumgarte parameters α, β (1/s).
    pub baumgarte: (f64, f64),
    /// Integrate driver work, normal-contact work and friction work as extra states.
    pub energy_accounting: bool,
    ws: Workspace,
}

/// Scratch buffers sized once, so that a right-hand side allocates nothing.
#[derive(Clone, Debug, Default)]
struct Workspace {
    force: Vec<f64>,
    jac: Vec<f64>,
    gamma: Vec<f64>,
    schur: Vec<f64>,
    lambda: Vec<f64>,
}

#[inline]
fn perp(v: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}

#[inline]
fn rotate(phi: f64, v: Vector2<f64>) -> Vector2<f64> {
    let (s, c) = phi.sin_cos();
    Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Position, angle, velocity and angular velocity of a body (ground: all zero).
#[inline]
fn body_state(q: &[f64], v: &[f64], b: BodyIndex) -> (Vector2<f64>, f64, Vector2<f64>, f64) {
    match b {
        Some(i) => {
            let k = 3 * i;
            (
                Vector2::new(q[k], q[k + 1]),
                q[k + 2],
                Vector2::new(v[k], v[k + 1]),
                v[k + 2],
            )
        }
        None => (Vector2::zeros(), 0.0, Vector2::zeros(), 0.0),
    }
}

/// Global position and velocity of a body point, and its rotated local vector.
#[inline]
fn point_state(
    q: &[f64],
    v: &[f64],
    p: &BodyPoint,
) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>, f64) {
    let (r, phi, rd, w) = body_state(q, v, p.body);
    let s = rotate(phi, p.local);
    (r + s, rd + perp(s) * w, s, w)
}

/// Adds a force `f` applied at rotated offset `s` from the centre of mass of body `b`.
#[inline]
fn add_force(force: &mut [f64], b: BodyIndex, s: Vector2<f64>, f: Vector2<f64>) {
    if let Some(i) = b {
        force[3 * i] += f.x;
        force[3 * i + 1] += f.y;
        force[3 * i + 2] += s.x * f.y - s.y * f.x;
    }
}

impl Mechanism {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        bodies: Vec<Body>,
        revolutes: Vec<Revolute>,
        translationals: Vec<Translational>,
        driver: Driver,
        clearance_joints: Vec<ClearanceJoint>,
        gravity: Vector2<f64>,
        baumgarte: (f64, f64),
        energy_accounting: bool,
    ) -> Self {
        let mut m = Mechanism {
            bodies,
            revolutes,
            translationals,
            driver,
            clearance_joints,
            gravity,
            baumgarte,
            energy_accounting,
            ws: Workspace::default(),
        };
        m.resize_workspace(m.constraint_count());
        m
    }

    fn resize_workspace(&mut self, rows: usize) {
        let n = self.coordinates();
        self.ws = Workspace {
            force: vec![0.0; n],
            jac: vec![0.0; rows * n],
            gamma: vec![0.0; rows],
            schur: vec![0.0; rows * rows],
            lambda: vec![0.0; rows],
        };
    }

    /// Number of generalised coordinates, 3 per body.
    pub fn coordinates(&self) -> usize {
        3 * self.bodies.len()
    }

    /// Number of constraint equations.
    pub fn constraint_count(&self) -> usize {
        2 * self.revolutes.len() + 2 * self.translationals.len() + 1
    }

    /// Length of the ODE state: positions, velocities, and the energy quadratures if on.
    pub fn state_len(&self) -> usize {
        2 * self.coordinates()
            + if self.energy_accounting {
                ENERGY_STATES
            } else {
                0
            }
    }

    /// Index of the driver's row in λ (the last one).
    fn driver_row(&self) -> usize {
        self.constraint_count() - 1
    }

    /// Fills Φ (into `phi` if given), the Jacobian Φ_q, and γ = −(Φ_q q̇)_q q̇ of the ideal joints.
    fn constraints(&mut self, t: f64, q: &[f64], v: &[f64], mut phi: Option<&mut [f64]>) {
        let n = self.coordinates();
        let ws = &mut self.ws;
        ws.jac.fill(0.0);
        let mut row = 0;
        let set = |jac: &mut [f64], row: usize, b: BodyIndex, vals: [f64; 3]| {
            if let Some(i) = b {
                jac[row * n + 3 * i..row * n + 3 * i + 3].copy_from_slice(&vals);
            }
        };
        for j in &self.revolutes {
            let (ra, _, sa, wa) = point_state(q, v, &j.a);
            let (rb, _, sb, wb) = point_state(q, v, &j.b);
            let (pa, pb) = (perp(sa), perp(sb));
            set(&mut ws.jac, row, j.a.body, [1.0, 0.0, pa.x]);
            set(&mut ws.jac, row + 1, j.a.body, [0.0, 1.0, pa.y]);
            set(&mut ws.jac, row, j.b.body, [-1.0, 0.0, -pb.x]);
            set(&mut ws.jac, row + 1, j.b.body, [0.0, -1.0, -pb.y]);
            let g = sa * wa * wa - sb * wb * wb;
            ws.gamma[row] = g.x;
            ws.gamma[row + 1] = g.y;
            if let Some(phi) = phi.as_deref_mut() {
                let d = ra - rb;
                phi[row] = d.x;
                phi[row + 1] = d.y;
            }
            row += 2;
        }
        for j in &self.translationals {
            let (ra, va, sa, wa) = point_state(q, v, &j.a);
            let (rb, vb, sb, wb) = point_state(q, v, &j.b);
            let (fa, fb) = (body_state(q, v, j.a.body).1, body_state(q, v, j.b.body).1);
            let nrm = rotate(fb, j.normal);
            let d = ra - rb;
            let d_dot = va - vb;
            set(&mut ws.jac, row, j.a.body, [0.0, 0.0, 1.0]);
            set(&mut ws.jac, row, j.b.body, [0.0, 0.0, -1.0]);
            ws.gamma[row] = 0.0;
            set(
                &mut ws.jac,
                row + 1,
                j.a.body,
                [nrm.x, nrm.y, nrm.dot(&perp(sa))],
            );
            set(
                &mut ws.jac,
                row + 1,
                j.b.body,
                [-nrm.x, -nrm.y, perp(nrm).dot(&d) - nrm.dot(&perp(sb))],
            );
            ws.gamma[row + 1] = nrm.dot(&d) * wb * wb - 2.0 * wb * perp(nrm).dot(&d_dot)
                + nrm.dot(&(sa * wa * wa - sb * wb * wb));
            if let Some(phi) = phi.as_deref_mut() {
                phi[row] = fa - fb - j.relative_angle;
                phi[row + 1] = nrm.dot(&d);
            }
            row += 2;
        }
        let dr = &self.driver;
        set(&mut ws.jac, row, Some(dr.body), [0.0, 0.0, 1.0]);
        ws.gamma[row] = 0.0;
        if let Some(phi) = phi {
            phi[row] = q[3 * dr.body + 2] - dr.angle0 - dr.omega * t;
        }
    }

    /// Solves `(J W Jᵀ) λ = r` (W = M⁻¹) by Cholesky, with r in `ws.lambda` on entry and λ on exit.
    fn solve_schur(&mut self) -> std::result::Result<(), ()> {
        let n = self.coordinates();
        let m = self.ws.gamma.len();
        let ws = &mut self.ws;
        for i in 0..m {
            for j in 0..=i {
                let mut s = 0.0;
                for k in 0..n {
                    let (a, b) = (ws.jac[i * n + k], ws.jac[j * n + k]);
                    if a != 0.0 && b != 0.0 {
                        let body = &self.bodies[k / 3];
                        s += a * b / if k % 3 == 2 { body.inertia } else { body.mass };
                    }
                }
                ws.schur[i * m + j] = s;
            }
        }
        cholesky_solve(&mut ws.schur, &mut ws.lambda, m)
    }

    /// Kinematics of clearance joint `k` at state (q, v), without forces.
    #[inline]
    pub fn contact_kinematics(&self, k: usize, q: &[f64], v: &[f64]) -> ContactState {
        let cj = &self.clearance_joints[k];
        let (rj, vj, _, wj) = point_state(q, v, &cj.journal);
        let (rb, vb, _, wb) = point_state(q, v, &cj.bearing);
        let phib = body_state(q, v, cj.bearing.body).1;
        let e = rj - rb;
        let e_dot = vj - vb;
        let dist = e.norm();
        let c = cj.r_bearing - cj.r_journal;
        if dist == 0.0 {
            // Exactly centred: no direction, far from contact.
            return ContactState {
                delta: -c,
                local_clearance: c,
                ..Default::default()
            };
        }
        let n = e / dist;
        let t = perp(n);
        let theta = (n.y.atan2(n.x) - phib).rem_euclid(std::f64::consts::TAU);
        let theta_rate = t.dot(&e_dot) / dist - wb;
        let (h, dh) = match cj.wear {
            Some(_) => cj.profile.depth_at(theta),
            None => (0.0, 0.0),
        };
        let e_rate = n.dot(&e_dot);
        ContactState {
            e,
            theta,
            delta: dist - c - h,
            delta_dot: e_rate - dh * theta_rate,
            local_clearance: c + h,
            v_t: t.dot(&e_dot) + wj * cj.r_journal - wb * cj.r_bearing,
            f_n: 0.0,
            f_t: 0.0,
            e_rate,
        }
    }

    /// Kinematics and forces of clearance joint `k`.
    #[inline]
    pub fn contact_state(&self, k: usize, q: &[f64], v: &[f64]) -> ContactState {
        let cj = &self.clearance_joints[k];
        let mut cs = self.contact_kinematics(k, q, v);
        if cs.in_contact() {
            cs.f_n = cj.contact.force(
                cs.delta,
                cs.delta_dot,
                cj.impact_velocity,
                cs.local_clearance,
            );
            if cj.friction != FrictionModel::None {
                cs.f_t = cj.friction.force(cs.f_n, cs.v_t);
            }
        }
        cs
    }

    /// Generalised forces: gravity plus clearance-joint contact forces (eq. 11).
    /// Returns (normal-force power, friction power) into the system.
    fn applied_forces(&mut self, q: &[f64], v: &[f64]) -> (f64, f64) {
        let mut force = std::mem::take(&mut self.ws.force);
        for (i, b) in self.bodies.iter().enumerate() {
            force[3 * i] = b.mass * self.gravity.x;
            force[3 * i + 1] = b.mass * self.gravity.y;
            force[3 * i + 2] = 0.0;
        }
        let (mut p_normal, mut p_friction) = (0.0, 0.0);
        for k in 0..self.clearance_joints.len() {
            let cs = self.contact_state(k, q, v);
            if cs.f_n == 0.0 {
                continue;
            }
            let cj = &self.clearance_joints[k];
            let n = cs.e / cs.e.norm();
            let t = perp(n);
            let on_journal = -n * cs.f_n + t * cs.f_t;
            let sj =
                rotate(body_state(q, v, cj.journal.body).1, cj.journal.local) + n * cj.r_journal;
            let sb =
                rotate(body_state(q, v, cj.bearing.body).1, cj.bearing.local) + n * cj.r_bearing;
            add_force(&mut force, cj.journal.body, sj, on_journal);
            add_force(&mut force, cj.bearing.body, sb, -on_journal);
            p_normal -= cs.f_n * cs.e_rate;
            p_friction += cs.f_t * cs.v_t;
        }
        self.ws.force = force;
        (p_normal, p_friction)
    }

    /// The right-hand side y' = f(t, y) of eq. 10 with Baumgarte stabilisation.
    pub fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        let n = self.coordinates();
        let (q, v) = (&y[..n], &y[n..2 * n]);
        let (p_normal, p_friction) = self.applied_forces(q, v);
        self.accelerations(t, q, v, &mut dy[n..2 * n])?;
        dy[..n].copy_from_slice(v);
        if self.energy_accounting {
            let d = &self.driver;
            dy[2 * n] = -self.ws.lambda[self.driver_row()] * v[3 * d.body + 2];
            dy[2 * n + 1] = p_normal;
            dy[2 * n + 2] = p_friction;
        }
        Ok(())
    }

    /// q̈ for the applied forces already in the workspace; leaves λ in the workspace.
    fn accelerations(&mut self, t: f64, q: &[f64], v: &[f64], acc: &mut [f64]) -> Result<()> {
        let n = self.coordinates();
        let m = self.constraint_count();
        let mut phi = std::mem::take(&mut self.ws.lambda);
        self.constraints(t, q, v, Some(&mut phi));
        let (alpha, beta) = self.baumgarte;
        let omega = self.driver.omega;
        let ws = &mut self.ws;
        for (i, (p, row)) in phi.iter_mut().zip(ws.jac.chunks_exact(n)).enumerate() {
            let mut phi_dot = 0.0;
            let mut jwf = 0.0;
            for k in 0..n {
                if row[k] != 0.0 {
                    let b = &self.bodies[k / 3];
                    let w = if k % 3 == 2 {
                        1.0 / b.inertia
                    } else {
                        1.0 / b.mass
                    };
                    phi_dot += row[k] * v[k];
                    jwf += row[k] * w * ws.force[k];
                }
            }
            if i == m - 1 {
                phi_dot -= omega;
            }
            *p = jwf - (ws.gamma[i] - 2.0 * alpha * phi_dot - beta * beta * *p);
        }
        ws.lambda = phi;
        self.solve_schur().map_err(|_| Error::Integration {
            time: t,
            cause: "singular constraint Jacobian (locked or redundant joints)".into(),
        })?;
        let ws = &self.ws;
        for (k, a) in acc.iter_mut().enumerate() {
            let mut s = ws.force[k];
            for i in 0..m {
                s -= ws.jac[i * n + k] * ws.lambda[i];
            }
            let b = &self.bodies[k / 3];
            *a = s / if k % 3 == 2 { b.inertia } else { b.mass };
        }
        Ok(())
    }

    /// Kinetic energy (J).
    pub fn kinetic_energy(&self, v: &[f64]) -> f64 {
        self.bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                0.5 * b.mass * (v[3 * i].powi(2) + v[3 * i + 1].powi(2))
                    + 0.5 * b.inertia * v[3 * i + 2].powi(2)
            })
            .sum()
    }

    /// Gravitational potential energy (J), zero at the origin.
    pub fn potential_energy(&self, q: &[f64]) -> f64 {
        self.bodies
            .iter()
            .enumerate()
            .map(|(i, b)| -b.mass * (self.gravity.x * q[3 * i] + self.gravity.y * q[3 * i + 1]))
            .sum()
    }

    /// Elastic energy stored in all clearance contacts (J).
    pub fn contact_energy(&self, q: &[f64], v: &[f64]) -> f64 {
        (0..self.clearance_joints.len())
            .map(|k| {
                let cs = self.contact_kinematics(k, q, v);
                self.clearance_joints[k]
                    .contact
                    .elastic_energy(cs.delta, cs.local_clearance)
            })
            .sum()
    }

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
        let m = ideal.constraint_count();
        ideal.resize_workspace(m);
        let n = self.coordinates();
        let zeros = vec![0.0; n];
        let mut q = guess.to_vec();
        let mut phi = vec![0.0; m];
        for iteration in 0.. {
            ideal.constraints(0.0, &q, &zeros, Some(&mut phi));
            let residual = phi.iter().fold(0.0f64, |a, p| a.max(p.abs()));
            if residual < 1e-13 {
                break;
            }
            if iteration == 50 || !residual.is_finite() {
                return Err(Error::invalid(
                    "bodies (initial positions)",
                    format!(
                        "constraint residual {residual:.3e} after {iteration} Newton iterations"
                    ),
                    "positions close enough to an assembled configuration",
                ));
            }
            ideal.ws.lambda.copy_from_slice(&phi);
            ideal.min_norm_step(&mut q, -1.0)?;
        }
        // Velocities: Φ_q q̇ = (0, …, ω).
        let mut v = vec![0.0; n];
        ideal.constraints(0.0, &q, &zeros, None);
        ideal.ws.lambda.fill(0.0);
        ideal.ws.lambda[m - 1] = self.driver.omega;
        ideal.min_norm_step(&mut v, 1.0)?;
        let mut y = vec![0.0; self.state_len()];
        y[..n].copy_from_slice(&q);
        y[n..2 * n].copy_from_slice(&v);
        Ok(y)
    }

    /// x += sign · W Jᵀ (J W Jᵀ)⁻¹ r, with r in `ws.lambda` and J in `ws.jac`.
    fn min_norm_step(&mut self, x: &mut [f64], sign: f64) -> Result<()> {
        self.solve_schur().map_err(|_| {
            Error::invalid(
                "joints",
                "a singular constraint Jacobian",
                "independent joints (no locked or redundant joint)",
            )
        })?;
        let n = self.coordinates();
        let m = self.ws.lambda.len();
        for (k, xk) in x.iter_mut().enumerate() {
            let b = &self.bodies[k / 3];
            let w = if k % 3 == 2 {
                1.0 / b.inertia
            } else {
                1.0 / b.mass
            };
            let s: f64 = (0..m)
                .map(|i| self.ws.jac[i * n + k] * self.ws.lambda[i])
                .sum();
            *xk += sign * w * s;
        }
        Ok(())
    }

    /// Largest absolute position-constraint residual at (t, q).
    pub fn constraint_residual(&mut self, t: f64, q: &[f64]) -> f64 {
        let mut phi = vec![0.0; self.constraint_count()];
        let zeros = vec![0.0; q.len()];
        self.constraints(t, q, &zeros, Some(&mut phi));
        phi.iter().fold(0.0, |a, p| a.max(p.abs()))
    }

    /// Dense copy of the constraint Jacobian and γ at (t, q, v), for tests and diagnostics.
    pub fn jacobian(&mut self, t: f64, q: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.constraints(t, q, v, None);
        (self.ws.jac.clone(), self.ws.gamma.clone())
    }

    /// Constraint residual vector Φ(q, t).
    pub fn constraint_vector(&mut self, t: f64, q: &[f64]) -> Vec<f64> {
        let mut phi = vec![0.0; self.constraint_count()];
        let zeros = vec![0.0; q.len()];
        self.constraints(t, q, &zeros, Some(&mut phi));
        phi
    }
}

/// In-place Cholesky factorisation and solve of the SPD `m×m` matrix `a` (lower triangle
/// used), overwriting `b` with the solution. Errors if `a` is not positive definite.
fn cholesky_solve(a: &mut [f64], b: &mut [f64], m: usize) -> std::result::Result<(), ()> {
    for j in 0..m {
        let mut d = a[j * m + j];
        for k in 0..j {
            d -= a[j * m + k] * a[j * m + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return Err(());
        }
        let d = d.sqrt();
        a[j * m + j] = d;
        for i in j + 1..m {
            let mut s = a[i * m + j];
            for k in 0..j {
                s -= a[i * m + k] * a[j * m + k];
            }
            a[i * m + j] = s / d;
        }
    }
    for i in 0..m {
        let mut s = b[i];
        for k in 0..i {
            s -= a[i * m + k] * b[k];
        }
        b[i] = s / a[i * m + i];
    }
    for i in (0..m).rev() {
        let mut s = b[i];
        for k in i + 1..m {
            s -= a[k * m + i] * b[k];
        }
        b[i] = s / a[i * m + i];
    }
    Ok(())
}
