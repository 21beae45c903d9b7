//! Scene files: a mechanism, its joints, materials, driver and run settings as TOML data.
//!
//! Scene files use engineering units, spelled in each key (`_mm`, `_deg`, `_rpm`, `_gpa`,
//! `_kg`, `_s`, `_m_s`, `_per_pa`); [`crate::simulation::Scene::load`] converts them once to SI and validates
//! every value: a bad scene is an [`crate::Error`] naming the field, the value and the valid range.
//! Unknown keys are rejected. Angles are counter-clockwise from +x; point coordinates are in
//! the body frame, whose origin is the body's centre of mass. The shipped scenes in
//! `data/scenes/` document every key.
//!
//! A scene may extend another: `extends = "standard.toml"` (relative to the file) takes the
//! base scene, replaces its top-level keys by the ones given (e.g. `title`), then applies the
//! `[overrides]` table, whose keys are dotted paths into the base document with array indices
//! as numbers, e.g. `"clearance.0.clearance_mm" = 0.2`. A path that does not exist in the base
//! is an error, so a typo cannot silently leave the base value in place.

mod build;
mod layering;
mod validation;
pub mod variant;

pub use build::{MAX_ROTATIONS, MAX_SETTLING_ROTATIONS};
pub use layering::{reversal_note, scene_path, set_dotted};
pub use validation::{
    Limit, ABSOLUTE_TOLERANCE, ATOL_PER_CLEARANCE, BEARING_LENGTH_MM, BEARING_RADIUS_MM,
    BODY_ANGLE_DEG, COORDINATE_MM, GRAVITY_M_S2, GRAZING_VELOCITY_M_S, INERTIA_KG_M2, MASS_KG,
    MAX_CLEARANCE_RATIO, MAX_GYRATION_PER_SIZE, MAX_K_OVER_H_PER_PA, MAX_NAME_BYTES, MAX_RUN_STEPS,
    MAX_SCENE_BYTES, MAX_STEP_S, MAX_TITLE_BYTES, MIN_HERTZ_CLEARANCE_RATIO,
    MIN_RECORD_SAMPLES_PER_ROTATION, MIN_SPEED_RPM, PENETRATION_PER_RADIUS, RECORD_BUDGET_BYTES,
    RESTITUTION, YOUNGS_MODULUS_GPA,
};

use crate::laws::contact::{DissipationLaw, NormalForceModel, StiffnessLaw};
use crate::laws::friction::FrictionModel;
use crate::laws::wear::PressureModel;
use crate::ode::{Filter, StepControl};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// `value` (a law, a method, a table of a scene file) as a scene file writes it: its TOML
/// value, an inline table with its `model` key first, each number as
/// [`crate::io::format::exact`] writes it: `{ model = "modified", mu_d = 0.01, mu_s = 0.015,
/// v_d = 0.001, v_s = 0.0001 }`, `"dopri5"`. What `check` prints, so that a person reads the
/// scene's own words.
pub fn spelling(value: &impl Serialize) -> String {
    match toml::Value::try_from(value) {
        Ok(v) => toml_text(&v),
        Err(e) => format!("<{e}>"),
    }
}

/// [`spelling`] of a TOML value.
fn toml_text(v: &toml::Value) -> String {
    use toml::Value;
    let list = |items: Vec<String>| items.join(", ");
    match v {
        Value::Float(x) => crate::io::format::exact(*x),
        Value::Integer(i) => i.to_string(),
        Value::String(s) => Value::String(s.clone()).to_string(),
        Value::Boolean(b) => b.to_string(),
        Value::Datetime(d) => d.to_string(),
        Value::Array(a) => format!("[{}]", list(a.iter().map(toml_text).collect())),
        Value::Table(t) => {
            let mut keys: Vec<&String> = t.keys().collect();
            keys.sort_by_key(|k| *k != "model");
            let pairs = keys.iter().map(|k| format!("{k} = {}", toml_text(&t[*k])));
            format!("{{ {} }}", list(pairs.collect()))
        }
    }
}

/// A scene file as written (engineering units).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Free text shown on figures and summaries.
    pub title: String,
    /// Gravitational acceleration (m/s²), e.g. `[0.0, -9.81]`.
    pub gravity_m_s2: [f64; 2],
    /// Named materials used by clearance joints.
    pub materials: BTreeMap<String, MaterialSpec>,
    /// Named points fixed to the ground (mm).
    pub ground: GroundSpec,
    /// The moving bodies; each has 3 coordinates (x, y, φ).
    pub bodies: Vec<BodySpec>,
    #[serde(default)]
    /// Ideal revolute joints.
    pub revolute: Vec<RevoluteSpec>,
    #[serde(default)]
    /// Ideal translational joints.
    pub translational: Vec<TranslationalSpec>,
    /// The one driver.
    pub driver: DriverSpec,
    #[serde(default)]
    /// Clearance revolute joints, where contact, friction and wear act.
    pub clearance: Vec<ClearanceSpec>,
    /// How to run the scene.
    pub run: RunSpec,
}

/// Elastic constants of a material (eq. 2).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Young's modulus (GPa), [0.1, 10000] ([`YOUNGS_MODULUS_GPA`]).
    pub youngs_modulus_gpa: f64,
    /// Poisson's ratio, [0, 0.5).
    pub poisson_ratio: f64,
}

/// The ground (fixed frame).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundSpec {
    /// Named points fixed to the ground (mm).
    pub points_mm: BTreeMap<String, [f64; 2]>,
}

/// A rigid body.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name, as joints refer to it (`"name.point"`).
    pub name: String,
    /// Mass (kg), [1e-6, 1000000] ([`MASS_KG`]).
    pub mass_kg: f64,
    /// Moment of inertia about the centre of mass (kg m²), [1e-12, 1000000] ([`INERTIA_KG_M2`]),
    /// with a radius of gyration √(I/m) of at most [`MAX_GYRATION_PER_SIZE`] times the
    /// mechanism's size.
    pub inertia_kg_m2: f64,
    /// Initial guess of the centre of mass (mm); assembled exactly at load.
    pub position_mm: [f64; 2],
    /// Initial guess of the body angle (deg), [-36000, 36000] ([`BODY_ANGLE_DEG`]).
    pub angle_deg: f64,
    /// Named points in the body frame (mm).
    pub points_mm: BTreeMap<String, [f64; 2]>,
}

/// Ideal revolute joint between two points, written `"body.point"` (`"ground.O"`).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RevoluteSpec {
    /// The first point, `"body.point"`.
    pub a: String,
    /// The second point, `"body.point"`.
    pub b: String,
}

/// Ideal translational joint: point `a` slides along the line through point `b` whose
/// direction is `axis_deg` in `b`'s body frame; the bodies keep their relative angle.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TranslationalSpec {
    /// The sliding point, `"body.point"`.
    pub a: String,
    /// The point on the guide line, `"body.point"`.
    pub b: String,
    /// Direction of the guide line in `b`'s body frame (deg).
    pub axis_deg: f64,
}

/// Constant-speed driver of one body's absolute angle.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriverSpec {
    /// The driven body.
    pub body: String,
    /// Speed (r/min), [`MIN_SPEED_RPM`] ≤ |speed| ≤ 100000; positive is counter-clockwise.
    pub speed_rpm: f64,
    /// Angle at t = 0 (deg).
    pub angle_deg: f64,
}

/// A clearance revolute joint: a journal in a bearing with a radial clearance (eq. 1-9).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClearanceSpec {
    /// Name, for messages and output files.
    pub name: String,
    /// Journal centre, `"body.point"`.
    pub journal: String,
    /// Bearing centre, `"body.point"`; the bearing is the part that wears.
    pub bearing: String,
    /// Unworn bearing radius R_i (mm), [0.1, 10000] ([`BEARING_RADIUS_MM`]).
    pub bearing_radius_mm: f64,
    /// Radial clearance c = R_i − R_j (mm), [0, [`MAX_CLEARANCE_RATIO`] R_i], leaving a journal
    /// radius R_j of at least 0.1 mm; at least [`MIN_HERTZ_CLEARANCE_RATIO`] R_i with a
    /// Hertz-based contact or pressure law.
    pub clearance_mm: f64,
    /// The journal's material, a key of `materials`.
    pub journal_material: String,
    /// The bearing's material, a key of `materials`.
    pub bearing_material: String,
    /// Normal contact law (eq. 1-3).
    pub contact: ContactSpec,
    /// Friction law (velocities in m/s); `{ model = "none" }` computes no friction.
    pub friction: FrictionModel,
    /// Absent: the scene computes no wear.
    pub wear: Option<WearSpec>,
}

/// The normal contact law of a clearance joint (eq. 1-3): either `model` (the paper's two
/// laws by name) or `stiffness` and `dissipation` (any of the catalogue's elastic laws with any
/// of its hysteresis-damping laws, [`crate::laws::stiffness`], [`crate::laws::dissipation`]).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// The paper's law (`"hybrid"`) or Lankarani-Nikravesh (`"lankarani-nikravesh"`).
    pub model: Option<NormalForceModel>,
    /// Elastic force-penetration law, instead of `model`.
    pub stiffness: Option<StiffnessLaw>,
    /// Hysteresis-damping law, instead of `model`.
    pub dissipation: Option<DissipationLaw>,
    /// Coefficient of restitution c_e, [0.1, 1] ([`RESTITUTION`]).
    pub restitution: f64,
    /// Exponent n of the power laws (`hybrid`, `hertz`): 1.5, the paper's, which their K are
    /// derived for. The other elastic laws have their own shape and take none.
    pub exponent: Option<f64>,
    /// Bearing length L (mm) for the elastic laws written per length (`liu`, `johnson`,
    /// `radzimovsky`, `esdu-78035`, `pereira`); absent: `wear.length_mm`.
    pub length_mm: Option<f64>,
    /// Floor of the captured impact velocity (m/s), [1e-9, 10] ([`GRAZING_VELOCITY_M_S`]).
    pub grazing_velocity_m_s: f64,
}

impl ContactSpec {
    /// The laws as the scene spells them, e.g. `model = "hybrid"` or
    /// `stiffness = "johnson", dissipation = "flores"`.
    pub fn spelling(&self) -> String {
        let mut parts = Vec::new();
        if let Some(m) = self.model {
            parts.push(format!("model = \"{}\"", m.name()));
        }
        if let Some(s) = self.stiffness {
            parts.push(format!("stiffness = \"{}\"", s.name()));
        }
        if let Some(d) = self.dissipation {
            parts.push(format!("dissipation = \"{}\"", d.name()));
        }
        parts.join(", ")
    }
}

/// Archard wear of a clearance joint's bearing (eq. 5-9).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WearSpec {
    /// Archard coefficient over hardness k/H (1/Pa), [0, 1e-6].
    pub k_over_h_per_pa: f64,
    /// Contact pressure model for eq. 9.
    pub pressure: PressureModel,
    /// Bearing length L (mm), [0.1, 10000] ([`BEARING_LENGTH_MM`]).
    pub length_mm: f64,
    /// Number of sectors of the bearing profile, [8, 36000].
    pub sectors: usize,
}

/// Integration method of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MethodSpec {
    /// Dormand-Prince 5(4), adaptive (the default).
    Dopri5,
    /// Hairer's DOP853, adaptive.
    Dop853,
    /// Classical Runge-Kutta with `run.fixed_step_s`.
    Rk4,
}

/// Step-size controller of an adaptive method (`run.step_control`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StepControlSpec {
    /// The I controller, the default of a scene that names none (the standard scene names
    /// PI.4.2, at the default-tolerance rule's pick for it).
    #[default]
    I,
    /// Söderlind's PI.4.2 digital filter ([`Filter::pi42`]).
    Pi42,
}

impl StepControlSpec {
    /// The choice's name in a scene file (`run.step_control`) and in the outputs.
    pub fn name(self) -> &'static str {
        match self {
            StepControlSpec::I => "i",
            StepControlSpec::Pi42 => "pi42",
        }
    }

    /// The integrator's step control of this choice.
    pub fn control(self) -> StepControl {
        match self {
            StepControlSpec::I => StepControl::default(),
            StepControlSpec::Pi42 => StepControl {
                filter: Some(Filter::pi42()),
                ..StepControl::default()
            },
        }
    }
}

/// Run settings (units in the key names).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Driver rotations to simulate, [1, 1000000].
    pub rotations: u32,
    /// How many of the last rotations to record as time series, [0, rotations].
    pub record_rotations: u32,
    /// Recording grid spacing (s), (0, 1] and at most the driver period over
    /// [`MIN_RECORD_SAMPLES_PER_ROTATION`] when rotations are recorded.
    pub record_interval_s: f64,
    /// Rotation counts after which the wear profile is saved, each in [1, rotations].
    #[serde(default)]
    pub wear_snapshots: Vec<u32>,
    /// Integration method.
    pub method: MethodSpec,
    /// Step-size controller of `dopri5` and `dop853` (`rk4` takes fixed steps), `"i"` by
    /// default.
    #[serde(default)]
    pub step_control: StepControlSpec,
    /// Relative tolerance, [1e-13, 1].
    pub rtol: f64,
    /// Absolute tolerance, [1e-20, 1] ([`ABSOLUTE_TOLERANCE`]), and for an adaptive method at
    /// most [`ATOL_PER_CLEARANCE`] of the smallest clearance (or, where larger, penetration,
    /// [`PENETRATION_PER_RADIUS`] of the bearing radius).
    pub atol: f64,
    /// Largest step (s), (0, 1].
    pub max_step_s: f64,
    /// Step of `rk4` (s), required by it, (0, 1].
    pub fixed_step_s: Option<f64>,
    /// Baumgarte stabilisation α = β (1/s), [0, 1000000].
    pub baumgarte_per_s: f64,
    /// Integrate the energy balance (driver, contact and friction work).
    #[serde(default)]
    pub energy_accounting: bool,
    /// Settle to the steady state of `steady_state` before simulating `rotations` more.
    #[serde(default)]
    pub settle: bool,
    /// Required when `settle` is true.
    pub steady_state: Option<SteadyStateSpec>,
    /// Wear profiles saved per rotation for the wear history (0: none), [0, 3600].
    #[serde(default)]
    pub profile_history_per_rotation: u32,
    /// Accepted steps after which the run fails with an error, [1, 1e10].
    #[serde(default = "default_max_steps")]
    pub max_steps: u64,
}

fn default_max_steps() -> u64 {
    20_000_000
}

impl RunSpec {
    /// What shortening the run to `rotations` changes on the user's behalf, as the program's
    /// `--rotations` and Python's `set("run.rotations", n)` do: the wear snapshots past it are
    /// dropped and the recorded rotations cut to it, except a key (`run.wear_snapshots`,
    /// `run.record_rotations`) for which `user_set` is true. Applies the cuts and returns each
    /// changed key with its new value.
    pub fn cut_to(
        &mut self,
        rotations: u32,
        user_set: impl Fn(&str) -> bool,
    ) -> Vec<(String, toml::Value)> {
        let mut cuts = Vec::new();
        if !user_set("run.wear_snapshots") && self.wear_snapshots.iter().any(|&s| s > rotations) {
            self.wear_snapshots.retain(|&s| s <= rotations);
            let kept = self.wear_snapshots.iter().map(|&s| i64::from(s).into());
            cuts.push((
                "run.wear_snapshots".to_string(),
                toml::Value::Array(kept.collect()),
            ));
        }
        if !user_set("run.record_rotations") && self.record_rotations > rotations {
            self.record_rotations = rotations;
            cuts.push((
                "run.record_rotations".to_string(),
                i64::from(rotations).into(),
            ));
        }
        cuts
    }
}

/// Steady state: the journal orbit repeats from one rotation to the next.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SteadyStateSpec {
    /// Largest RMS change of the journal orbit between rotations over the clearance, (0, 1].
    pub orbit_tolerance: f64,
    /// Rotations after which settling gives up (chaotic motion), [2, 10000].
    pub max_rotations: u32,
}
