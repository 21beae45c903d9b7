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
//! penetration is `δ = |e| − c − h(θ)` with `h` the bearing's wear depth ([`crate::laws::wear`]).
//! The normal force is [`crate::laws::contact`]'s law; friction ([`crate::laws::friction`]) acts along the
//! tangent `t = (−n_y, n_x)` against the relative velocity of the material points in contact,
//! `v_t = ė·t + φ̇_J R_J − φ̇_B R_B`.
//!
//! The module keeps apart what a mechanism *is* ([`Mechanism`], immutable once built), what a
//! run *changes* ([`RunState`]: wear profiles and onset velocities; `q`, `q̇` live in the
//! integrator's state vector) and the *scratch* space of an evaluation ([`Workspace`]).
//! Files: `kinematics` (clearance-joint geometry and forces), `constraints` (Φ, Φ_q, γ and
//! the accelerations), `workspace` (layout of the solve and LDLᵀ), `dynamics` (the
//! right-hand side), `assembly` (initial state), `energy`, `tree` (joint coordinates).
//!
//! # What a run integrates ([`Formulation`])
//!
//! A mechanism whose ideal joints form a tree rooted at the ground (its loops close only
//! through clearance joints, as in the slider-crank) is integrated in joint coordinates
//! (`tree`): one coordinate per ideal-joint freedom, no constraints, no drift; a body held only
//! by clearance joints (the rod of `two_clearance`) floats, its position and angle three of
//! them. Otherwise (a closed loop of ideal joints, more than `MAX_TREE_FREEDOMS` freedoms or
//! four bodies, a slide on the driven body) the run integrates the absolute coordinates above. Everything outside the integrator's state (events, wear, recording, outputs) sees
//! the absolute coordinates: [`Mechanism::absolute_state`] maps one to the other.

mod assembly;
mod constraints;
mod dynamics;
mod energy;
mod kinematics;
mod tree;
mod workspace;

pub use assembly::{Lock, SWEEP_RESOLUTION_DEG, SWEEP_STEP_DEG};
pub use dynamics::{eigenvalues_by_modulus, JACOBIAN_STEP};
pub use kinematics::{cephes, ContactState};
pub use tree::MAX_TREE_FREEDOMS;
pub use workspace::Workspace;

use crate::laws::contact::ContactLaw;
use crate::laws::friction::FrictionModel;
use crate::laws::wear::{WearLaw, WearProfile};
use crate::Result;
use nalgebra::Vector2;

/// A body's coordinate index, or `None` for the ground (fixed, at the origin, angle 0).
pub type BodyIndex = Option<usize>;

/// Rigid body: mass (kg) and moment of inertia about its centre of mass (kg m²).
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name, as the scene writes it.
    pub name: String,
    /// Mass (kg).
    pub mass: f64,
    /// Moment of inertia about the centre of mass (kg m²).
    pub inertia: f64,
}

/// A point fixed in a body: body index and local coordinates (m) from its centre of mass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPoint {
    /// The body (`None`: ground).
    pub body: BodyIndex,
    /// Coordinates in the body frame from the centre of mass (m).
    pub local: Vector2<f64>,
}

/// Ideal revolute joint: two body points coincide (2 equations).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Revolute {
    /// The first point.
    pub a: BodyPoint,
    /// The second point.
    pub b: BodyPoint,
}

/// Ideal translational joint: body `a` keeps its angle relative to `b`, and point `a` stays
/// on the line through point `b` whose unit normal is `normal` in `b`'s frame (2 equations).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Translational {
    /// The sliding point.
    pub a: BodyPoint,
    /// A point of the guide line.
    pub b: BodyPoint,
    /// Unit normal of the guide line in `b`'s frame.
    pub normal: Vector2<f64>,
    /// φ_a − φ_b held constant (rad).
    pub relative_angle: f64,
}

/// Constant-speed driver: `φ_body = angle0 + ω t` (1 equation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Driver {
    /// The driven body.
    pub body: usize,
    /// Angular speed ω (rad/s), positive counter-clockwise.
    pub omega: f64,
    /// The speed as the scene gives it (r/min, signed): what reports echo, since ω converted
    /// back reads -1999.9999999999998 for -2000.
    pub speed_rpm: f64,
    /// Angle at t = 0 (rad).
    pub angle0: f64,
}

/// A clearance revolute joint with its contact, friction and (optional) wear models.
#[derive(Clone, Debug, PartialEq)]
pub struct ClearanceJoint {
    /// Name, as the scene writes it.
    pub name: String,
    /// Journal centre.
    pub journal: BodyPoint,
    /// Bearing centre.
    pub bearing: BodyPoint,
    /// Journal radius R_j (m).
    pub r_journal: f64,
    /// Unworn bearing radius R_i (m).
    pub r_bearing: f64,
    /// The radial clearance as the scene gives it, in m ([`crate::io::format::shift_decimal`]:
    /// 0.02 mm reads 2e-5 m): what reports echo. The model's is R_i − R_j
    /// ([`ClearanceJoint::clearance`]), 1.9999999999999185e-5 m for that joint.
    pub given_clearance: f64,
    /// Normal contact law (eq. 1-3).
    pub contact: ContactLaw,
    /// Friction law (eq. 4).
    pub friction: FrictionModel,
    /// `None`: the scene computes no wear.
    pub wear: Option<WearLaw>,
    /// The bearing's profile at the start of a run: its sectors and any initial wear. The
    /// profile a run wears is in its [`RunState`].
    pub initial_profile: WearProfile,
}

impl ClearanceJoint {
    /// Radial clearance `c = R_i − R_j` of the unworn joint (m).
    pub fn clearance(&self) -> f64 {
        self.r_bearing - self.r_journal
    }

    /// Deepest penetration (m) the contact laws describe in this joint: at most
    /// [`MAX_PENETRATION_CLEARANCES`] radial clearances, at least
    /// [`MIN_PENETRATION_LIMIT_RATIO`] and at most [`MAX_PENETRATION_RATIO`] of the journal
    /// radius. A run stops beyond it.
    pub fn penetration_limit(&self) -> f64 {
        (MAX_PENETRATION_CLEARANCES * self.clearance())
            .max(MIN_PENETRATION_LIMIT_RATIO * self.r_journal)
            .min(MAX_PENETRATION_RATIO * self.r_journal)
    }
}

/// What a clearance joint carries from one instant of a run to the next besides the
/// coordinates: its worn profile and eq. 3's memory of the onset velocity.
#[derive(Clone, Debug, PartialEq)]
pub struct JointState {
    /// The bearing's worn profile h(θ) (eq. 5-9).
    pub wear: WearProfile,
    /// Normal velocity δ̇⁻ captured at the onset of the current contact (m/s), eq. 3.
    pub onset_velocity: f64,
}

/// The state of a run that is not in the integrator's state vector `y = (q, q̇, energies)`:
/// one [`JointState`] per clearance joint. The mechanism is immutable; this is what a run
/// changes (by wear and contact onsets) between steps.
#[derive(Clone, Debug, PartialEq)]
pub struct RunState {
    /// Per clearance joint, in the mechanism's order.
    pub joints: Vec<JointState>,
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

/// Largest penetration of a clearance joint, in radial clearances, that the contact laws
/// describe ([`ClearanceJoint::penetration_limit`]). Pressed `δ` into a bore `c` wider than
/// it, the journal overlaps the bore over a half-angle `acos(c / (c + δ))` on either side of
/// the contact normal: 87.3 deg at 20 c, so the contact covers 175 deg, almost the whole half
/// of the bore. The laws and pressure models describe a contact patch on one side with the
/// force along the eccentricity; deeper, the bore as a whole would have to deform. Shipped
/// scenes reach at most 7.1 c (a 1 GPa bearing material; the standard scene 0.51 c).
pub const MAX_PENETRATION_CLEARANCES: f64 = 20.0;

/// Floor of the penetration limit as a fraction of the journal radius, for clearances so
/// small that [`MAX_PENETRATION_CLEARANCES`] says nothing (at zero clearance any contact
/// covers the half bore).
pub const MIN_PENETRATION_LIMIT_RATIO: f64 = 1e-2;

/// A planar mechanism: bodies, ideal joints, one driver, clearance joints, gravity.
#[derive(Clone, Debug)]
pub struct Mechanism {
    /// Ideal revolute joints.
    pub revolutes: Vec<Revolute>,
    /// Ideal translational joints.
    pub translationals: Vec<Translational>,
    /// The driver.
    pub driver: Driver,
    /// Clearance joints, as force elements.
    pub clearance_joints: Vec<ClearanceJoint>,
    /// Gravitational acceleration (m/s²); fixed at construction, as the weights derive from it.
    gravity: Vector2<f64>,
    /// Baumgarte parameters α, β (1/s).
    pub baumgarte: (f64, f64),
    /// Integrate driver work, normal-contact work and friction work as extra states.
    pub energy_accounting: bool,
    /// Fixed at construction: the inverse masses and the equations solved for one coordinate
    /// derive from them.
    bodies: Vec<Body>,
    /// Each body's weight (m g_x, m g_y, 0) in N, N, N m: the start of its generalised force
    /// at every evaluation, multiplied once here.
    weights: Vec<[f64; 3]>,
    /// The layout of the constraint solve with buffers sized, derived once from the joints:
    /// the template of every run's [`Workspace`], never written to.
    layout: Workspace,
    /// The ideal joints as a tree in joint coordinates, if they form one ([`Formulation`]).
    tree: Option<tree::Tree>,
}

/// The coordinates a run integrates, chosen when the mechanism is built (module
/// documentation, "What a run integrates").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formulation {
    /// Three absolute coordinates per body, the ideal joints as constraints with Baumgarte
    /// stabilisation (eq. 10).
    Absolute,
    /// One coordinate per ideal-joint freedom of a tree-shaped linkage (at most
    /// [`MAX_TREE_FREEDOMS`]), three for a body held by clearance joints only, the driver
    /// prescribed.
    JointCoordinates {
        /// Ideal-joint freedoms (coordinates), a floating body's three included.
        freedoms: usize,
        /// Bodies held by clearance joints only, floating on three coordinates each.
        floating: usize,
    },
}

impl std::fmt::Display for Formulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Formulation::Absolute => write!(
                f,
                "absolute coordinates (3 per body), ideal joints as Baumgarte-stabilised \
                 constraints"
            ),
            Formulation::JointCoordinates {
                freedoms,
                floating: 0,
            } => write!(
                f,
                "joint coordinates ({freedoms} for the tree of ideal joints, the driver \
                 prescribed)"
            ),
            Formulation::JointCoordinates { freedoms, floating } => write!(
                f,
                "joint coordinates ({freedoms} for the tree of ideal joints, {} of them the \
                 position and angle of the {floating} {} held by clearance joints only, the \
                 driver prescribed)",
                3 * floating,
                if *floating == 1 { "body" } else { "bodies" }
            ),
        }
    }
}

impl Mechanism {
    /// Builds a mechanism and lays out its constraint solve; errors on redundant joints.
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
        let weights = bodies
            .iter()
            .map(|b| [b.mass * gravity.x, b.mass * gravity.y, 0.0])
            .collect();
        let mut m = Mechanism {
            bodies,
            weights,
            revolutes,
            translationals,
            driver,
            clearance_joints,
            gravity,
            baumgarte,
            energy_accounting,
            layout: Workspace::default(),
            tree: None,
        };
        // Laid out here, so that redundant joints are refused when the mechanism is built.
        m.layout = Workspace::new(&m)?;
        m.tree = tree::Tree::of(&m);
        Ok(m)
    }

    /// The bodies, in coordinate order.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The bodies of clearance joint `k`'s journal and bearing.
    #[inline(always)]
    pub(super) fn clearance_ends(&self, k: usize) -> (BodyIndex, BodyIndex) {
        let cj = &self.clearance_joints[k];
        (cj.journal.body, cj.bearing.body)
    }

    /// Gravitational acceleration (m/s²).
    pub fn gravity(&self) -> Vector2<f64> {
        self.gravity
    }

    /// Number of generalised coordinates, 3 per body.
    pub fn coordinates(&self) -> usize {
        3 * self.bodies.len()
    }

    /// Number of constraint equations.
    pub fn constraint_count(&self) -> usize {
        2 * self.revolutes.len() + 2 * self.translationals.len() + 1
    }

    /// Degrees of freedom: coordinates minus constraint equations (negative when
    /// over-constrained; 2 per clearance joint in a driven single loop).
    pub fn degrees_of_freedom(&self) -> i64 {
        self.coordinates() as i64 - self.constraint_count() as i64
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

    /// The coordinates a run of this mechanism integrates.
    pub fn formulation(&self) -> Formulation {
        self.tree
            .as_ref()
            .map_or(Formulation::Absolute, |t| Formulation::JointCoordinates {
                freedoms: t.freedoms(),
                floating: t.floating(),
            })
    }

    /// Length of the integrator's state in the [`Formulation`]: its coordinates and rates
    /// (the first [`Mechanism::ode_controlled`] components, under error control), then the
    /// energy quadratures if on.
    pub fn ode_len(&self) -> usize {
        self.state_len() - 2 * self.coordinates() + self.ode_controlled()
    }

    /// Coordinates and rates of the integrator's state.
    pub fn ode_controlled(&self) -> usize {
        2 * self
            .tree
            .as_ref()
            .map_or(self.coordinates(), |t| t.freedoms())
    }

    /// The integrator's state (of [`Mechanism::ode_len`]) of an absolute state `y` (of
    /// [`Mechanism::state_len`]) that satisfies the ideal joints.
    pub fn ode_state(&self, y: &[f64]) -> Vec<f64> {
        self.tree
            .as_ref()
            .map_or_else(|| y.to_vec(), |tree| tree.coordinates(self, y))
    }

    /// Writes the absolute state (of [`Mechanism::state_len`]) of the integrator's state `z`
    /// at time `t` into `y`.
    pub fn absolute_state(&self, t: f64, z: &[f64], y: &mut [f64]) {
        match &self.tree {
            Some(tree) => tree.absolute(self, t, z, y),
            None => y.copy_from_slice(z),
        }
    }

    /// [`Mechanism::contact_state`] of every clearance joint that wears, at the absolute
    /// state of the integrator's state `z` at time `t`, into `out` (one entry per clearance
    /// joint; the others are left as they are): the same bits, from the bodies' frames
    /// without writing that state out and taking its angles' sines and cosines again.
    pub fn wearing_contact_states(
        &self,
        state: &RunState,
        t: f64,
        z: &[f64],
        out: &mut [ContactState],
    ) {
        assert_eq!(
            out.len(),
            self.clearance_joints.len(),
            "one state per clearance joint"
        );
        match &self.tree {
            Some(tree) => {
                let frames = tree.frames(self, t, z);
                let frame = |b| frames[tree::slot(b)];
                self.each_wearing(out, |k| {
                    let cs = self.contact_geometry(state, k, frame).0;
                    self.with_forces(state, k, cs)
                })
            }
            None => {
                let (q, v) = z[..2 * self.coordinates()].split_at(self.coordinates());
                self.each_wearing(out, |k| self.contact_state(state, k, q, v))
            }
        }
    }

    /// Sets `out[k]` to `contact(k)` for every clearance joint `k` that wears.
    #[inline(always)]
    fn each_wearing(&self, out: &mut [ContactState], contact: impl Fn(usize) -> ContactState) {
        for (k, cj) in self.clearance_joints.iter().enumerate() {
            if cj.wear.is_some() {
                out[k] = contact(k);
            }
        }
    }

    /// The right-hand side of the integrator's state: [`Mechanism::rhs`], or Lagrange's
    /// equations in joint coordinates (`ws` keeps only the penetrations and their rates,
    /// [`Workspace::last_gaps`]).
    #[inline(always)]
    pub fn ode_rhs(
        &self,
        state: &RunState,
        ws: &mut Workspace,
        t: f64,
        z: &[f64],
        dz: &mut [f64],
    ) -> Result<()> {
        match &self.tree {
            Some(tree) => tree.rhs(self, state, t, z, dz, &mut ws.gaps),
            None => self.rhs(state, ws, t, z, dz),
        }
    }

    /// A fresh workspace for the right-hand side of this mechanism (a copy of the layout
    /// made once in [`Mechanism::new`]).
    pub fn workspace(&self) -> Workspace {
        self.layout.clone()
    }

    /// The run state at the start: every joint with its initial profile and no contact.
    pub fn initial_state(&self) -> RunState {
        RunState {
            joints: (self.clearance_joints.iter())
                .map(|cj| JointState {
                    wear: cj.initial_profile.clone(),
                    onset_velocity: 0.0,
                })
                .collect(),
        }
    }

    /// Position (m) and angle (rad) of body `b` at coordinates `q` (ground: origin, 0).
    pub fn pose(&self, q: &[f64], b: BodyIndex) -> (Vector2<f64>, f64) {
        b.map_or((Vector2::zeros(), 0.0), |i| {
            (Vector2::new(q[3 * i], q[3 * i + 1]), q[3 * i + 2])
        })
    }
}
