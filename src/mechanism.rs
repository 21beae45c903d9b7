//! Planar multibody dynamics with clearance joints as force elements (paper eq. 10-12).
//!
//! ```text
//! M q̈ + Φ_qᵀ λ = F + F_c,     Φ(q, t) = 0                                   (10)
//! F_c = u(δ) (F_n + F_t),      u(δ) = 1 for δ ≥ 0, 0 otherwise              (11, 12)
//! ```
//! Each body has absolute coordinates `(x, y, φ)` of its centre of mass; M is diagonal
//! (`m, m, J` per body), so the multipliers come from the small SPD system
//! `(Φ_q M⁻¹ Φ_qᵀ) λ = Φ_q M⁻¹ F − γ̂` and `q̈ = M⁻¹ (F − Φ_qᵀ λ)`; no n×n matrix is ever formed.
//! A constraint equation whose only non-zero column outside the coordinates already fixed is
//! a constant one (the driver; a revolute pin to the ground of a driven body; the angle lock
//! of a translational joint on the ground) fixes that coordinate's acceleration by itself: it
//! is solved for it directly, in order, and leaves the system. For the slider-crank the
//! system shrinks from 7×7 to 2×2 (the crank-rod pin).
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

/// Smallest LDLᵀ pivot of the constraint system relative to its diagonal entry before
/// elimination: the squared sine of the angle between a constraint row and the span of the
/// earlier ones (in the M⁻¹ metric). Below it the rows are dependent to 1e-5 rad, the
/// linkage is at a lock (dead-centre) position or has redundant joints, and the reactions
/// grow without bound: the run stops there, naming the joints, instead of crawling into the
/// step limit.
pub const MIN_RELATIVE_PIVOT: f64 = 1e-10;

/// Largest penetration of a clearance joint, as a fraction of its journal radius, that the
/// contact laws describe: they are linear-elastic small-strain laws, and a tenth of the
/// radius is a strain of order 10 %. A run goes past it only when the linkage forces the
/// joint apart (links that cannot reach lock the mechanism against the contact) or a material
/// is far too soft; it stops there instead of crawling on with meganewton forces.
pub const MAX_PENETRATION_RATIO: f64 = 0.1;

/// Rows of the constraint system found linearly dependent by the LDLᵀ solve: the row whose
/// pivot vanished, then the earlier rows it combines.
#[derive(Debug)]
struct Dependent(Vec<usize>);

/// A planar mechanism: bodies, ideal joints, one driver, clearance joints, gravity.
#[derive(Clone, Debug)]
pub struct Mechanism {
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
    /// Fixed at construction: the inverse masses and the equations solved for one coordinate
    /// derive from them.
    bodies: Vec<Body>,
    ws: Workspace,
}

/// A constraint equation solved for one coordinate: `coef · q̈_coord + Σ_other (Φ_q)_c q̈_c =
/// γ̂`, with every other column on a coordinate solved before.
#[derive(Clone, Copy, Debug, Default)]
struct Solved {
    row: Row,
    coord: usize,
    /// 1 / (∂Φ/∂q_coord), the same at every state: a multiplication, not a division, on the
    /// chain from one solved coordinate to the next.
    inv_coef: f64,
    gamma: f64,
    phi: f64,
    /// ∂Φ/∂t.
    phi_t: f64,
}

/// Where `constraints` stores an equation.
#[derive(Clone, Copy, Debug)]
enum Slot {
    Row(usize),
    Solved(usize),
}

/// Stores the equations of one `constraints` call, in order, at their slots.
struct Sink<'a> {
    rows: &'a mut [Row],
    gamma: &'a mut [f64],
    solved: &'a mut [Solved],
    slot: &'a [Slot],
    phi: Option<&'a mut [f64]>,
    e: usize,
}

impl Sink<'_> {
    /// The next equation: its two blocks of Φ_q, γ, Φ and ∂Φ/∂t.
    #[inline(always)]
    fn set(&mut self, blocks: [(BodyIndex, [f64; 3]); 2], g: f64, value: f64, phi_t: f64) {
        match self.slot[self.e] {
            Slot::Row(i) => {
                self.rows[i].set(blocks);
                self.gamma[i] = g;
                if let Some(phi) = self.phi.as_deref_mut() {
                    phi[i] = value;
                }
            }
            Slot::Solved(j) => {
                let s = &mut self.solved[j];
                s.row.set(blocks);
                (s.gamma, s.phi, s.phi_t) = (g, value, phi_t);
            }
        }
        self.e += 1;
    }
}

/// Scratch buffers sized once, so that a right-hand side allocates nothing.
#[derive(Clone, Debug, Default)]
struct Workspace {
    /// `(sin φ, cos φ)` of every body: one `sin_cos` per body and evaluation, not per point.
    rot: Vec<(f64, f64)>,
    /// Whether a body's rotation matters: it has a point off its centre of mass or carries a
    /// translational joint's axis. The others skip their `sin_cos` (a tenth of the
    /// right-hand side), as their rotation multiplies only zero vectors.
    rotates: Vec<bool>,
    /// Diagonal of M per coordinate.
    mass: Vec<f64>,
    /// Diagonal of M⁻¹ per coordinate, zero for the solved ones.
    inv_mass: Vec<f64>,
    /// Applied forces F.
    force: Vec<f64>,
    /// Storage of each equation, in the order `constraints` visits them.
    slot: Vec<Slot>,
    /// The equations solved for one coordinate, in the order they are solved (driver first).
    solved: Vec<Solved>,
    /// Φ_q without the solved equations, sparse: every row touches at most two bodies.
    rows: Vec<Row>,
    /// The non-zero entries of the lower triangle of Φ_q M⁻¹ Φ_qᵀ: the pairs of row blocks of
    /// the same body. Fixed by the joints, so found once, in `resize_workspace`.
    pairs: Vec<Pair>,
    gamma: Vec<f64>,
    /// J W Jᵀ, then its LDLᵀ factors (row-major m×m, lower triangle).
    schur: Vec<f64>,
    /// The pivots D of the LDLᵀ factorisation.
    pivots: Vec<f64>,
    lambda: Vec<f64>,
    /// Φ_qᵀ λ, for the driver's torque.
    reaction: Vec<f64>,
}

/// One row of Φ_q: the three columns of each of (at most) two bodies, and the same columns
/// times M⁻¹. A `None` body (ground) has zero columns and comes second.
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
    /// Sets the blocks in place (a `Row` returned by value would be copied by `memcpy`).
    #[inline]
    fn set(&mut self, mut blocks: [(BodyIndex, [f64; 3]); 2]) {
        // A ground block goes second, where `dot` skips it.
        if blocks[0].0.is_none() {
            blocks.swap(0, 1);
        }
        for (s, (body, col)) in blocks.into_iter().enumerate() {
            self.body[s] = body;
            (self.at[s], self.col[s]) = match body {
                Some(i) => (3 * i, col),
                None => (0, [0.0; 3]),
            };
        }
    }

    /// Σ columns · x over the row's bodies (x: 3 entries per body).
    #[inline]
    fn dot(&self, x: &[f64]) -> f64 {
        let [a, b] = self.at;
        let first = dot3(&self.col[0], &x[a..a + 3]);
        // Most rows of one body are pins and locks to the ground: skip its zero block.
        match self.body[1] {
            Some(_) => first + dot3(&self.col[1], &x[b..b + 3]),
            None => first,
        }
    }

    /// The coordinates and values of the non-zero columns.
    fn entries(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        (0..2)
            .filter(|&s| self.body[s].is_some())
            .flat_map(move |s| (0..3).map(move |k| (self.at[s] + k, self.col[s][k])))
            .filter(|&(_, c)| c != 0.0)
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
    ) -> Result<Self> {
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
        m.resize_workspace()?;
        Ok(m)
    }

    /// The bodies, in coordinate order.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Orders the equations solved for one coordinate and sizes the workspace for the others.
    fn resize_workspace(&mut self) -> Result<()> {
        let n = self.coordinates();
        let equations = self.constraint_count();
        let mass: Vec<f64> = (self.bodies.iter())
            .flat_map(|b| [b.mass, b.mass, b.inertia])
            .collect();
        let mut rotates = vec![false; self.bodies.len()];
        let points = (self.revolutes.iter().flat_map(|j| [j.a, j.b]))
            .chain(self.translationals.iter().flat_map(|j| [j.a, j.b]))
            .chain(
                self.clearance_joints
                    .iter()
                    .flat_map(|j| [j.journal, j.bearing]),
            );
        for p in points {
            if let Some(i) = p.body.filter(|_| p.local != Vector2::zeros()) {
                rotates[i] = true;
            }
        }
        for i in self.translationals.iter().filter_map(|j| j.b.body) {
            rotates[i] = true;
        }
        self.ws = Workspace {
            rot: vec![(0.0, 1.0); self.bodies.len()],
            rotates,
            inv_mass: mass.iter().map(|m| 1.0 / m).collect(),
            mass,
            force: vec![0.0; n],
            slot: (0..equations).map(Slot::Row).collect(),
            rows: vec![Row::default(); equations],
            gamma: vec![0.0; equations],
            reaction: vec![0.0; n],
            ..Default::default()
        };
        // The pattern at two unremarkable states: a column non-zero at either is non-zero,
        // and a coefficient that differs between them is not constant.
        let pattern = |m: &mut Self, phase: f64| {
            let q: Vec<f64> = (0..n).map(|i| (phase + i as f64).sin()).collect();
            m.constraints(0.0, &q, &q, None);
            m.ws.rows.clone()
        };
        let (p1, p2) = (pattern(self, 0.3), pattern(self, 1.1));
        let mut fixed = vec![false; n];
        let mut order = Vec::new();
        // The driver (the last equation) first, then sweeps until no equation qualifies.
        let candidates: Vec<usize> = std::iter::once(equations - 1)
            .chain(0..equations - 1)
            .collect();
        let mut progress = true;
        while progress {
            progress = false;
            for &e in &candidates {
                if order.iter().any(|&(o, _, _)| o == e) {
                    continue;
                }
                let free: Vec<(usize, f64)> = (p1[e].entries().chain(p2[e].entries()))
                    .filter(|&(k, _)| !fixed[k])
                    .collect();
                let coord = free.first().map(|f| f.0);
                if let Some(k) = coord.filter(|&k| free.iter().all(|f| f.0 == k)) {
                    let coefs = |p: &[Row]| p[e].entries().find(|f| f.0 == k).map(|f| f.1);
                    if let (Some(c), Some(c2)) = (coefs(&p1), coefs(&p2)) {
                        if c == c2 {
                            fixed[k] = true;
                            order.push((e, k, c));
                            progress = true;
                        }
                    }
                } else if free.is_empty() {
                    let (r, t) = (2 * self.revolutes.len(), 2 * self.translationals.len());
                    let joint = match e {
                        e if e < r => format!("revolute[{}]", e / 2),
                        e if e < r + t => format!("translational[{}]", (e - r) / 2),
                        _ => "driver".into(),
                    };
                    return Err(Error::invalid(
                        "joints",
                        format!("{joint} constrains coordinates already fixed by the others"),
                        "independent joints (no locked or redundant joint)",
                    ));
                }
            }
        }
        let rows = equations - order.len();
        let ws = &mut self.ws;
        let mut next_row = 0;
        for (e, slot) in ws.slot.iter_mut().enumerate() {
            *slot = match order.iter().position(|&(o, _, _)| o == e) {
                Some(j) => Slot::Solved(j),
                None => {
                    next_row += 1;
                    Slot::Row(next_row - 1)
                }
            };
        }
        ws.solved = (order.iter())
            .map(|&(_, coord, coef)| Solved {
                coord,
                inv_coef: 1.0 / coef,
                ..Default::default()
            })
            .collect();
        for s in &ws.solved {
            ws.inv_mass[s.coord] = 0.0;
        }
        ws.rows.truncate(rows);
        ws.gamma.truncate(rows);
        ws.schur = vec![0.0; rows * rows];
        ws.pivots = vec![0.0; rows];
        ws.lambda = vec![0.0; rows];
        // The rows' bodies do not depend on the state: any state reveals the pattern.
        let zeros = vec![0.0; n];
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
        Ok(())
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

    /// Fills the body rotations of the workspace and, for every equation, Φ_q and
    /// γ = −(Φ_q q̇)_q q̇ (with M⁻¹ Φ_qᵀ for the rows), and Φ (of the rows into `phi` if given).
    fn constraints(&mut self, t: f64, q: &[f64], v: &[f64], phi: Option<&mut [f64]>) {
        let ws = &mut self.ws;
        for (i, (rot, _)) in (ws.rot.iter_mut().zip(&ws.rotates))
            .enumerate()
            .filter(|(_, (_, &r))| r)
        {
            *rot = q[3 * i + 2].sin_cos();
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

    /// Moves x onto `J x = b` along `W Jᵀ` (W = M⁻¹ without the prescribed coordinates,
    /// which stay as they are): with b in `ws.lambda` on entry, solves `(J W Jᵀ) λ = J x − b`
    /// by LDLᵀ, leaving λ there, and sets `x −= W Jᵀ λ`.
    /// Only the blocks of bodies two rows share contribute ([`Workspace::pairs`]).
    fn project(&mut self, x: &mut [f64]) -> std::result::Result<(), Dependent> {
        let ws = &mut self.ws;
        for (b, row) in ws.lambda.iter_mut().zip(&ws.rows) {
            *b = row.dot(x) - *b;
        }
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
        if let Err(j) = unrolled!(1 2 3 4 5 6 7 8 9 10) {
            // Row j of L (complete when column j fails) holds the rows it combines.
            let coupled = (0..j).filter(|&k| ws.schur[j * m + k].abs() > 1e-6);
            return Err(Dependent(std::iter::once(j).chain(coupled).collect()));
        }
        for (r, l) in ws.rows.iter().zip(&ws.lambda) {
            for s in 0..2 {
                // A ground block would chain the stores to x[0..3] for nothing.
                if r.body[s].is_some() {
                    let at = r.at[s];
                    for (x, wc) in x[at..at + 3].iter_mut().zip(&r.wcol[s]) {
                        *x -= l * wc;
                    }
                }
            }
        }
        Ok(())
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
            n,
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
    /// Returns (normal-force power, friction power) into the system, or the clearance joint
    /// and penetration beyond [`MAX_PENETRATION_RATIO`] of its journal radius.
    fn applied_forces(
        &mut self,
        q: &[f64],
        v: &[f64],
    ) -> std::result::Result<(f64, f64), (usize, f64)> {
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
            let cj = &self.clearance_joints[k];
            if cs.delta > MAX_PENETRATION_RATIO * cj.r_journal {
                self.ws.force = force;
                return Err((k, cs.delta));
            }
            if cs.f_n == 0.0 {
                continue;
            }
            let (n, t) = (cs.n, perp(cs.n));
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
        Ok((p_normal, p_friction))
    }

    /// The error of clearance joint `k` penetrating `delta` beyond the contact laws at `t`.
    fn overload(&self, t: f64, k: usize, delta: f64) -> Error {
        let cj = &self.clearance_joints[k];
        Error::Integration {
            time: t,
            cause: format!(
                "clearance joint `{}` (journal on {}, bearing on {}) penetrates {delta:.3e} m at \
                 driver angle {}, beyond {} % of its journal radius ({:.3e} m) where the \
                 small-strain contact laws hold: the linkage forces the joint apart (links \
                 that cannot reach at this angle lock the mechanism) or a material is far too \
                 soft",
                cj.name,
                self.body_name(cj.journal.body),
                self.body_name(cj.bearing.body),
                self.driver_angle_text(t),
                100.0 * MAX_PENETRATION_RATIO,
                MAX_PENETRATION_RATIO * cj.r_journal
            ),
        }
    }

    /// The right-hand side y' = f(t, y) of eq. 10 with Baumgarte stabilisation.
    pub fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        let n = self.coordinates();
        let (q, v) = (&y[..n], &y[n..2 * n]);
        let mut phi = std::mem::take(&mut self.ws.lambda);
        self.constraints(t, q, v, Some(&mut phi));
        self.ws.lambda = phi;
        let (p_normal, p_friction) = self
            .applied_forces(q, v)
            .map_err(|(k, delta)| self.overload(t, k, delta))?;
        self.accelerations(t, v, &mut dy[n..2 * n])?;
        dy[..n].copy_from_slice(v);
        if self.energy_accounting {
            let driven = 3 * self.driver.body + 2;
            dy[2 * n] = self.driver_torque(&dy[n..2 * n]) * v[driven];
            dy[2 * n + 1] = p_normal;
            dy[2 * n + 2] = p_friction;
        }
        Ok(())
    }

    /// The driver's torque −λ_d, from the equations of motion of the solved coordinates,
    /// `m_k q̈_k = F_k − (Φ_qᵀ λ)_k`, taken in reverse order: each gives the multiplier of
    /// the equation solved for it, as only equations solved later (and the rows) touch it.
    fn driver_torque(&mut self, acc: &[f64]) -> f64 {
        let ws = &mut self.ws;
        ws.reaction.fill(0.0);
        let add = |reaction: &mut [f64], r: &Row, l: f64| {
            for (k, c) in r.entries() {
                reaction[k] += c * l;
            }
        };
        for (r, &l) in ws.rows.iter().zip(&ws.lambda) {
            add(&mut ws.reaction, r, l);
        }
        let mut lambda = 0.0;
        for s in ws.solved.iter().rev() {
            let k = s.coord;
            lambda = (ws.force[k] - ws.mass[k] * acc[k] - ws.reaction[k]) * s.inv_coef;
            add(&mut ws.reaction, &s.row, lambda);
        }
        // The driver's equation is solved first, so its multiplier comes last.
        -lambda
    }

    /// Sets each solved coordinate of x from its equation, `coef · x_k = b − Σ_other Φ_q x`
    /// (b from `target`), in order; x must be zero there on entry.
    fn solve_fixed(&self, x: &mut [f64], target: impl Fn(&Solved) -> f64) {
        for s in &self.ws.solved {
            x[s.coord] = (target(s) - s.row.dot(x)) * s.inv_coef;
        }
    }

    /// q̈ = M⁻¹ (F − Φ_qᵀ λ) for the constraints, Φ (in `ws.lambda`) and applied forces in
    /// the workspace, the solved coordinates first; leaves the rows' λ in the workspace.
    fn accelerations(&mut self, t: f64, v: &[f64], acc: &mut [f64]) -> Result<()> {
        let (alpha, beta) = self.baumgarte;
        let ws = &mut self.ws;
        for (a, (f, w)) in acc.iter_mut().zip(ws.force.iter().zip(&ws.inv_mass)) {
            *a = f * w;
        }
        for ((b, row), g) in ws.lambda.iter_mut().zip(&ws.rows).zip(&ws.gamma) {
            *b = g - 2.0 * alpha * row.dot(v) - beta * beta * *b;
        }
        self.solve_fixed(acc, |s| {
            s.gamma - 2.0 * alpha * (s.row.dot(v) + s.phi_t) - beta * beta * s.phi
        });
        let dependent = match self.project(acc) {
            Ok(()) => return Ok(()),
            Err(d) => d,
        };
        // A blown-up state also breaks the solve; only a finite one means bad joints.
        let cause = if v.iter().chain(&self.ws.force).all(|x| x.is_finite()) {
            format!(
                "the linkage locks at driver angle {}: the constraints of {} are dependent \
                 (a dead-centre position, links that cannot reach, or redundant joints)",
                self.driver_angle_text(t),
                self.joints_of_rows(&dependent.0, &[]).join(", ")
            )
        } else {
            "non-finite state: the step is too large for the contact stiffness".into()
        };
        Err(Error::Integration { time: t, cause })
    }

    /// Name of body `b` as the scene writes it (`ground` for the ground).
    fn body_name(&self, b: BodyIndex) -> &str {
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

    /// The constraint equation at index `i` of [`Mechanism::constraint_vector`] (the rows of
    /// the constraint system, then the equations solved for one coordinate).
    fn vector_equation(&self, i: usize) -> usize {
        let rows = self.ws.rows.len();
        let wanted = |slot: &Slot| match *slot {
            Slot::Row(r) => i < rows && r == i,
            Slot::Solved(j) => i >= rows && j == i - rows,
        };
        self.ws.slot.iter().position(wanted).unwrap_or(0)
    }

    /// The joints of rows of the constraint system, in order, without repeats.
    fn joints_of_rows(&self, rows: &[usize], held: &[ClearanceJoint]) -> Vec<String> {
        let mut joints: Vec<String> = Vec::new();
        for &row in rows {
            let joint = self.equation_joint(self.vector_equation(row), held);
            if !joints.contains(&joint) {
                joints.push(joint);
            }
        }
        joints
    }

    /// The driver's prescribed angle at time `t`, for messages (deg in [0, 360)).
    fn driver_angle_text(&self, t: f64) -> String {
        let d = &self.driver;
        format!(
            "{:.1} deg",
            (d.angle0 + d.omega * t).to_degrees().rem_euclid(360.0)
        )
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
        ideal.resize_workspace()?;
        let held = &self.clearance_joints;
        let n = self.coordinates();
        let zeros = vec![0.0; n];
        let mut q = guess.to_vec();
        for iteration in 0.. {
            let phi = ideal.constraint_vector(0.0, &q);
            let residual = phi.iter().fold(0.0f64, |a, p| a.max(p.abs()));
            if residual < 1e-13 {
                break;
            }
            if iteration == 50 || !residual.is_finite() {
                return Err(ideal.unclosed(&phi, iteration, held));
            }
            // Newton step Δq with Φ_q Δq = −Φ (the rows' part of Φ first).
            for (b, p) in ideal.ws.lambda.iter_mut().zip(&phi) {
                *b = -p;
            }
            for (q, dq) in q.iter_mut().zip(ideal.min_norm_step(|s| -s.phi, held)?) {
                *q += dq;
            }
        }
        // Velocities: Φ_q q̇ = −Φ_t.
        ideal.constraints(0.0, &q, &zeros, None);
        ideal.ws.lambda.fill(0.0);
        let v = ideal.min_norm_step(|s| -s.phi_t, held)?;
        let mut y = vec![0.0; self.state_len()];
        y[..n].copy_from_slice(&q);
        y[n..2 * n].copy_from_slice(&v);
        Ok(y)
    }

    /// The mass-weighted minimum-norm x with `J x = b` (the rows' b in `ws.lambda`, the
    /// solved equations' from `target`), for the state of the last `constraints` call.
    /// `held`: the clearance joints held ideal, for messages ([`Mechanism::equation_joint`]).
    fn min_norm_step(
        &mut self,
        target: impl Fn(&Solved) -> f64,
        held: &[ClearanceJoint],
    ) -> Result<Vec<f64>> {
        let mut x = vec![0.0; self.coordinates()];
        self.solve_fixed(&mut x, target);
        self.project(&mut x).map_err(|Dependent(rows)| {
            Error::invalid(
                "joints (assembly)",
                format!(
                    "the constraints of {} are dependent at a pose the assembly reached",
                    self.joints_of_rows(&rows, held).join(", ")
                ),
                "independent joints away from a dead-centre position (no locked or redundant \
                 joint; a driver angle at a dead centre needs another one)",
            )
        })?;
        Ok(x)
    }

    /// The error of an assembly whose Newton iterations did not close the constraints `phi`
    /// (in [`Mechanism::constraint_vector`] order): the joints with the largest residuals.
    fn unclosed(&self, phi: &[f64], iterations: usize, held: &[ClearanceJoint]) -> Error {
        let mut order: Vec<usize> = (0..phi.len()).collect();
        order.sort_by(|&a, &b| phi[b].abs().total_cmp(&phi[a].abs()));
        let largest = phi[order[0]].abs();
        let mut joints: Vec<(String, f64)> = Vec::new();
        // The joints whose residual is of the order of the largest: where the loop breaks.
        let near_largest = |i: &&usize| phi[**i].abs() >= 0.1 * largest || phi[**i].is_nan();
        for &i in order.iter().take_while(near_largest) {
            let joint = self.equation_joint(self.vector_equation(i), held);
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

    /// Dense copy of the constraint Jacobian and γ at (q, v), for tests and diagnostics: the
    /// rows of [`Mechanism::constraint_vector`].
    pub fn jacobian(&mut self, q: &[f64], v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        self.constraints(0.0, q, v, None);
        let n = self.coordinates();
        let ws = &self.ws;
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
    pub fn constraint_vector(&mut self, t: f64, q: &[f64]) -> Vec<f64> {
        let rows = self.ws.rows.len();
        let mut phi = vec![0.0; rows];
        let zeros = vec![0.0; q.len()];
        self.constraints(t, q, &zeros, Some(&mut phi));
        phi.extend(self.ws.solved.iter().map(|s| s.phi));
        phi
    }
}

/// In-place LDLᵀ factorisation and solve of the SPD `m×m` matrix `a` (row-major, lower
/// triangle used), overwriting `b` with the solution. Errors with the column whose pivot is
/// not above [`MIN_RELATIVE_PIVOT`] times its diagonal entry (`a` singular or nearly so).
/// On exit the strict lower triangle holds L, the diagonal 1/D and `pivots` D. No square
/// roots and one division per column: the solve is bound by latency, not by its flops.
#[inline(always)]
fn ldl_solve(
    a: &mut [f64],
    pivots: &mut [f64],
    b: &mut [f64],
    m: usize,
) -> std::result::Result<(), usize> {
    let (a, pivots, b) = (&mut a[..m * m], &mut pivots[..m], &mut b[..m]);
    for j in 0..m {
        let diagonal = a[j * m + j];
        let mut d = diagonal;
        for k in 0..j {
            d -= a[j * m + k] * a[j * m + k] * pivots[k];
        }
        // Also refuses NaN (no comparison holds) and a non-finite pivot.
        let regular = d > MIN_RELATIVE_PIVOT * diagonal && d.is_finite();
        if !regular {
            return Err(j);
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
