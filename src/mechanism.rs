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
use crate::wear::{wrap_angle, WearLaw, WearProfile};
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
    /// `(sin φ, cos φ)` of every body: one `sin_cos` per body and evaluation, not per point.
    rot: Vec<(f64, f64)>,
    /// Diagonal of M⁻¹ per body, `(1/m, 1/J)`; refreshed with `rot` (the bodies are public).
    inv_mass: Vec<(f64, f64)>,
    /// Applied forces F, then M⁻¹ F.
    force: Vec<f64>,
    /// Φ_q, sparse: every row touches at most two bodies.
    rows: Vec<Row>,
    /// The non-zero blocks of the lower triangle of Φ_q M⁻¹ Φ_qᵀ: the pairs of row blocks of
    /// the same body. Fixed by the joints, so found once, in `resize_workspace`.
    pairs: Vec<Pair>,
    gamma: Vec<f64>,
    /// J W Jᵀ, then its LDLᵀ factors (row-major m×m, lower triangle).
    schur: Vec<f64>,
    /// The pivots D of the LDLᵀ factorisation.
    pivots: Vec<f64>,
    lambda: Vec<f64>,
}

/// One row of Φ_q: the three columns of each of (at most) two bodies, and the same columns
/// times M⁻¹. A `None` body (ground, or a row of one body) has zero columns, so the products
/// below need no branch.
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    body: [BodyIndex; 2],
    /// Index of each block's first coordinate (0 for a `None` body).
    at: [usize; 2],
    col: [[f64; 3]; 2],
    wcol: [[f64; 3]; 2],
}

/// Rows `i ≥ j` whose blocks `a` and `b` belong to the same body.
#[derive(Clone, Copy, Debug)]
struct Pair {
    i: usize,
    a: usize,
    j: usize,
    b: usize,
}

#[inline]
fn dot3(a: &[f64; 3], b: &[f64]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Row {
    /// Σ columns · x over the row's bodies (x: 3 entries per body).
    #[inline]
    fn dot(&self, x: &[f64]) -> f64 {
        let [a, b] = self.at;
        dot3(&self.col[0], &x[a..a + 3]) + dot3(&self.col[1], &x[b..b + 3])
    }
}

impl Workspace {
    /// x += scale · M⁻¹ Φ_qᵀ λ.
    fn add_weighted_rows(&self, x: &mut [f64], scale: f64) {
        for (r, l) in self.rows.iter().zip(&self.lambda) {
            for (&at, wc) in r.at.iter().zip(&r.wcol) {
                for (x, wc) in x[at..at + 3].iter_mut().zip(wc) {
                    *x += scale * l * wc;
                }
            }
        }
    }
}

#[inline]
fn perp(v: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}

/// Rotates `v` by the angle whose `(sin, cos)` is `sc`.
#[inline]
fn rotate((s, c): (f64, f64), v: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Position, angle, velocity, angular velocity and `(sin, cos)` of the angle of a body
/// (ground: at rest at the origin, angle 0).
#[derive(Clone, Copy, Debug)]
struct Frame {
    r: Vector2<f64>,
    phi: f64,
    rd: Vector2<f64>,
    w: f64,
    sc: (f64, f64),
}

impl Frame {
    /// `sc` gives the `(sin, cos)` of a body's angle: cached, or computed on demand.
    #[inline(always)]
    fn of(q: &[f64], v: &[f64], b: BodyIndex, sc: impl Fn(usize) -> (f64, f64)) -> Frame {
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
            None => Frame {
                r: Vector2::zeros(),
                phi: 0.0,
                rd: Vector2::zeros(),
                w: 0.0,
                sc: (0.0, 1.0),
            },
        }
    }

    /// Global position and velocity of the point at `local`, and its rotated local vector.
    #[inline]
    fn point(&self, local: Vector2<f64>) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        let s = rotate(self.sc, local);
        (self.r + s, self.rd + perp(s) * self.w, s)
    }
}

/// `(sin, cos)` of body `i`'s angle, computed from q.
#[inline]
fn sin_cos(q: &[f64]) -> impl Fn(usize) -> (f64, f64) + Copy + '_ {
    move |i| q[3 * i + 2].sin_cos()
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
        let bodies = self.bodies.len();
        self.ws = Workspace {
            rot: vec![(0.0, 1.0); bodies],
            inv_mass: vec![(0.0, 0.0); bodies],
            force: vec![0.0; 3 * bodies],
            rows: vec![Row::default(); rows],
            pairs: Vec::new(),
            gamma: vec![0.0; rows],
            schur: vec![0.0; rows * rows],
            pivots: vec![0.0; rows],
            lambda: vec![0.0; rows],
        };
        // The rows' bodies do not depend on the state: any state reveals the pattern.
        let zeros = vec![0.0; 3 * bodies];
        self.constraints(0.0, &zeros, &zeros, None);
        let blocks = |i: usize| (0..2).map(move |a| (i, a));
        let rows = &self.ws.rows;
        self.ws.pairs = (0..rows.len())
            .flat_map(blocks)
            .flat_map(|(i, a)| {
                (0..=i)
                    .flat_map(blocks)
                    .map(move |(j, b)| Pair { i, a, j, b })
            })
            .filter(|p| rows[p.i].body[p.a].is_some() && rows[p.i].body[p.a] == rows[p.j].body[p.b])
            .collect();
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

    /// Fills the body rotations and inverse masses of the workspace, Φ (into `phi` if given),
    /// the Jacobian Φ_q (with M⁻¹ Φ_qᵀ), and γ = −(Φ_q q̇)_q q̇ of the ideal joints.
    fn constraints(&mut self, t: f64, q: &[f64], v: &[f64], mut phi: Option<&mut [f64]>) {
        let ws = &mut self.ws;
        for (i, (b, (rot, w))) in self
            .bodies
            .iter()
            .zip(ws.rot.iter_mut().zip(&mut ws.inv_mass))
            .enumerate()
        {
            *rot = q[3 * i + 2].sin_cos();
            *w = (1.0 / b.mass, 1.0 / b.inertia);
        }
        let rot = &ws.rot;
        let frame = |b: BodyIndex| Frame::of(q, v, b, |i| rot[i]);
        let mut rows = ws.rows.iter_mut();
        let mut row = 0;
        let mut set = |a: (BodyIndex, [f64; 3]), b: (BodyIndex, [f64; 3])| {
            let r = rows.next().expect("one row per constraint equation");
            r.body = [a.0, b.0];
            for (s, (body, col)) in [a, b].into_iter().enumerate() {
                (r.at[s], r.col[s]) = match body {
                    Some(i) => (3 * i, col),
                    None => (0, [0.0; 3]),
                };
            }
        };
        for j in &self.revolutes {
            let (fa, fb) = (frame(j.a.body), frame(j.b.body));
            let (ra, _, sa) = fa.point(j.a.local);
            let (rb, _, sb) = fb.point(j.b.local);
            let (pa, pb) = (perp(sa), perp(sb));
            set((j.a.body, [1.0, 0.0, pa.x]), (j.b.body, [-1.0, 0.0, -pb.x]));
            set((j.a.body, [0.0, 1.0, pa.y]), (j.b.body, [0.0, -1.0, -pb.y]));
            let g = sa * fa.w * fa.w - sb * fb.w * fb.w;
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
            let (fa, fb) = (frame(j.a.body), frame(j.b.body));
            let (ra, va, sa) = fa.point(j.a.local);
            let (rb, vb, sb) = fb.point(j.b.local);
            let (wa, wb) = (fa.w, fb.w);
            let nrm = rotate(fb.sc, j.normal);
            let d = ra - rb;
            let d_dot = va - vb;
            set((j.a.body, [0.0, 0.0, 1.0]), (j.b.body, [0.0, 0.0, -1.0]));
            ws.gamma[row] = 0.0;
            set(
                (j.a.body, [nrm.x, nrm.y, nrm.dot(&perp(sa))]),
                (
                    j.b.body,
                    [-nrm.x, -nrm.y, perp(nrm).dot(&d) - nrm.dot(&perp(sb))],
                ),
            );
            ws.gamma[row + 1] = nrm.dot(&d) * wb * wb - 2.0 * wb * perp(nrm).dot(&d_dot)
                + nrm.dot(&(sa * wa * wa - sb * wb * wb));
            if let Some(phi) = phi.as_deref_mut() {
                phi[row] = fa.phi - fb.phi - j.relative_angle;
                phi[row + 1] = nrm.dot(&d);
            }
            row += 2;
        }
        let dr = &self.driver;
        set((Some(dr.body), [0.0, 0.0, 1.0]), (None, [0.0; 3]));
        ws.gamma[row] = 0.0;
        if let Some(phi) = phi {
            phi[row] = q[3 * dr.body + 2] - dr.angle0 - dr.omega * t;
        }
        for r in &mut ws.rows {
            for (b, (c, wc)) in r.body.iter().zip(r.col.iter().zip(&mut r.wcol)) {
                let (wm, wj) = b.map_or((0.0, 0.0), |b| ws.inv_mass[b]);
                *wc = [c[0] * wm, c[1] * wm, c[2] * wj];
            }
        }
    }

    /// Solves `(J W Jᵀ) λ = r` (W = M⁻¹) by LDLᵀ, with r in `ws.lambda` on entry and λ on
    /// exit. Only the blocks of bodies two rows share contribute ([`Workspace::pairs`]).
    fn solve_schur(&mut self) -> std::result::Result<(), ()> {
        let ws = &mut self.ws;
        let m = ws.rows.len();
        ws.schur.fill(0.0);
        for p in &ws.pairs {
            let (ri, rj) = (&ws.rows[p.i], &ws.rows[p.j]);
            ws.schur[p.i * m + p.j] += dot3(&ri.col[p.a], &rj.wcol[p.b]);
        }
        let (a, d, b) = (&mut ws.schur, &mut ws.pivots, &mut ws.lambda);
        // Loop control, not arithmetic, dominates this small solve: with a constant size
        // (ldl_solve is inlined into each arm) the compiler unrolls it and drops the bounds
        // checks, a quarter fewer instructions for the standard scene.
        macro_rules! unrolled {
            ($($size:literal)*) => {
                match m {
                    $($size => ldl_solve(a, d, b, $size),)*
                    _ => ldl_solve(a, d, b, m),
                }
            };
        }
        unrolled!(1 2 3 4 5 6 7 8 9 10)
    }

    /// Kinematics of clearance joint `k` at state (q, v), without forces.
    #[inline]
    pub fn contact_kinematics(&self, k: usize, q: &[f64], v: &[f64]) -> ContactState {
        self.contact_geometry(k, q, v, sin_cos(q)).0
    }

    /// Kinematics of clearance joint `k`, with the rotated local vectors of journal and
    /// bearing centre (`sc`: the bodies' `(sin, cos)`, see [`Frame::of`]).
    #[inline]
    fn contact_geometry(
        &self,
        k: usize,
        q: &[f64],
        v: &[f64],
        sc: impl Fn(usize) -> (f64, f64) + Copy,
    ) -> (ContactState, Vector2<f64>, Vector2<f64>) {
        let cj = &self.clearance_joints[k];
        let fj = Frame::of(q, v, cj.journal.body, sc);
        let fb = Frame::of(q, v, cj.bearing.body, sc);
        let (rj, vj, sj) = fj.point(cj.journal.local);
        let (rb, vb, sb) = fb.point(cj.bearing.local);
        let (wj, wb) = (fj.w, fb.w);
        let e = rj - rb;
        let e_dot = vj - vb;
        let dist = e.norm();
        let c = cj.r_bearing - cj.r_journal;
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
        let theta = wrap_angle(n.y.atan2(n.x) - fb.phi);
        let theta_rate = t.dot(&e_dot) / dist - wb;
        let (h, dh) = match cj.wear {
            Some(_) => cj.profile.depth_at(theta),
            None => (0.0, 0.0),
        };
        let e_rate = n.dot(&e_dot);
        let cs = ContactState {
            e,
            theta,
            delta: dist - c - h,
            delta_dot: e_rate - dh * theta_rate,
            local_clearance: c + h,
            v_t: t.dot(&e_dot) + wj * cj.r_journal - wb * cj.r_bearing,
            f_n: 0.0,
            f_t: 0.0,
            e_rate,
        };
        (cs, sj, sb)
    }

    /// Kinematics and forces of clearance joint `k`.
    #[inline]
    pub fn contact_state(&self, k: usize, q: &[f64], v: &[f64]) -> ContactState {
        self.with_forces(k, self.contact_kinematics(k, q, v))
    }

    /// Adds the normal and friction forces of clearance joint `k` to its kinematics.
    #[inline]
    fn with_forces(&self, k: usize, mut cs: ContactState) -> ContactState {
        let cj = &self.clearance_joints[k];
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

    /// Generalised forces: gravity plus clearance-joint contact forces (eq. 11), with the body
    /// rotations of the last [`Mechanism::constraints`] call.
    /// Returns (normal-force power, friction power) into the system.
    fn applied_forces(&mut self, q: &[f64], v: &[f64]) -> (f64, f64) {
        let mut force = std::mem::take(&mut self.ws.force);
        for (i, b) in self.bodies.iter().enumerate() {
            force[3 * i] = b.mass * self.gravity.x;
            force[3 * i + 1] = b.mass * self.gravity.y;
            force[3 * i + 2] = 0.0;
        }
        let (mut p_normal, mut p_friction) = (0.0, 0.0);
        let rot = &self.ws.rot;
        for k in 0..self.clearance_joints.len() {
            let (cs, sj, sb) = self.contact_geometry(k, q, v, |i| rot[i]);
            let cs = self.with_forces(k, cs);
            if cs.f_n == 0.0 {
                continue;
            }
            let cj = &self.clearance_joints[k];
            let n = cs.e / cs.e.norm();
            let t = perp(n);
            let on_journal = -n * cs.f_n + t * cs.f_t;
            add_force(
                &mut force,
                cj.journal.body,
                sj + n * cj.r_journal,
                on_journal,
            );
            add_force(
                &mut force,
                cj.bearing.body,
                sb + n * cj.r_bearing,
                -on_journal,
            );
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
        let mut phi = std::mem::take(&mut self.ws.lambda);
        self.constraints(t, q, v, Some(&mut phi));
        self.ws.lambda = phi;
        let (p_normal, p_friction) = self.applied_forces(q, v);
        self.accelerations(t, v, &mut dy[n..2 * n])?;
        dy[..n].copy_from_slice(v);
        if self.energy_accounting {
            let d = &self.driver;
            dy[2 * n] = -self.ws.lambda[self.driver_row()] * v[3 * d.body + 2];
            dy[2 * n + 1] = p_normal;
            dy[2 * n + 2] = p_friction;
        }
        Ok(())
    }

    /// q̈ = M⁻¹ (F − Φ_qᵀ λ) for the constraints, Φ (in `ws.lambda`) and applied forces in
    /// the workspace; leaves λ in the workspace.
    fn accelerations(&mut self, t: f64, v: &[f64], acc: &mut [f64]) -> Result<()> {
        let (alpha, beta) = self.baumgarte;
        let omega = self.driver.omega;
        let ws = &mut self.ws;
        for (f, w) in ws.force.chunks_exact_mut(3).zip(&ws.inv_mass) {
            f[0] *= w.0;
            f[1] *= w.0;
            f[2] *= w.1;
        }
        let m = ws.rows.len();
        for (i, (p, row)) in ws.lambda.iter_mut().zip(&ws.rows).enumerate() {
            let mut phi_dot = row.dot(v);
            if i == m - 1 {
                phi_dot -= omega;
            }
            *p = row.dot(&ws.force) - (ws.gamma[i] - 2.0 * alpha * phi_dot - beta * beta * *p);
        }
        self.solve_schur().map_err(|_| Error::Integration {
            time: t,
            // A blown-up state also breaks the solve; only a finite one means bad joints.
            cause: if v.iter().chain(&self.ws.force).all(|x| x.is_finite()) {
                "singular constraint Jacobian (locked or redundant joints)".into()
            } else {
                "non-finite state: the step is too large for the contact stiffness".into()
            },
        })?;
        let ws = &self.ws;
        acc.copy_from_slice(&ws.force);
        ws.add_weighted_rows(acc, -1.0);
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
        self.ws.add_weighted_rows(x, sign);
        Ok(())
    }

    /// Dense copy of the constraint Jacobian and γ at (t, q, v), for tests and diagnostics.
    pub fn jacobian(&mut self, t: f64, q: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.constraints(t, q, v, None);
        let n = self.coordinates();
        let mut jac = vec![0.0; self.ws.rows.len() * n];
        for (row, r) in jac.chunks_exact_mut(n).zip(&self.ws.rows) {
            for (&at, c) in r.at.iter().zip(&r.col) {
                for (x, c) in row[at..at + 3].iter_mut().zip(c) {
                    *x += c;
                }
            }
        }
        (jac, self.ws.gamma.clone())
    }

    /// Constraint residual vector Φ(q, t).
    pub fn constraint_vector(&mut self, t: f64, q: &[f64]) -> Vec<f64> {
        let mut phi = vec![0.0; self.constraint_count()];
        let zeros = vec![0.0; q.len()];
        self.constraints(t, q, &zeros, Some(&mut phi));
        phi
    }
}

/// In-place LDLᵀ factorisation and solve of the SPD `m×m` matrix `a` (row-major, lower
/// triangle used), overwriting `b` with the solution. Errors if `a` is not positive definite.
/// On exit the strict lower triangle holds L, the diagonal 1/D and `pivots` D. No square
/// roots and one division per column: the solve is bound by latency, not by its flops.
#[inline(always)]
fn ldl_solve(
    a: &mut [f64],
    pivots: &mut [f64],
    b: &mut [f64],
    m: usize,
) -> std::result::Result<(), ()> {
    let (a, pivots, b) = (&mut a[..m * m], &mut pivots[..m], &mut b[..m]);
    for j in 0..m {
        let mut d = a[j * m + j];
        for k in 0..j {
            d -= a[j * m + k] * a[j * m + k] * pivots[k];
        }
        if d <= 0.0 || !d.is_finite() {
            return Err(());
        }
        let inv = 1.0 / d;
        for i in j + 1..m {
            let mut s = a[i * m + j];
            for k in 0..j {
                s -= a[i * m + k] * a[j * m + k] * pivots[k];
            }
            a[i * m + j] = s * inv;
        }
        // Forward substitution L y = b, row by row as L is completed. Sums accumulate in
        // locals: through `b[j]` every term would wait for the previous store.
        let mut y = b[j];
        for k in 0..j {
            y -= a[j * m + k] * b[k];
        }
        b[j] = y;
        a[j * m + j] = inv;
        pivots[j] = d;
    }
    // D z = y, then back substitution Lᵀ x = z.
    for i in (0..m).rev() {
        let mut x = b[i] * a[i * m + i];
        for k in i + 1..m {
            x -= a[k * m + i] * b[k];
        }
        b[i] = x;
    }
    Ok(())
}
