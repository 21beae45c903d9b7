//! Converts a scene file to SI and builds the mechanism and run settings, validating every
//! value on the way ([`SceneFile::build`]).

use super::validation::*;
use super::*;
use crate::io::format::{exact, number as terminal, shift_decimal};
use crate::laws::contact::{
    compound_modulus, ContactLaw, DissipationLaw, JointElasticity, StiffnessLaw,
};
use crate::laws::stiffness::{PEREIRA_CLEARANCE_MM, POWER_LAW_EXPONENT};
use crate::laws::wear::{PressureModel, WearLaw, WearProfile};
use crate::mechanism::{
    Body, BodyIndex, BodyPoint, ClearanceJoint, Driver, Mechanism, Revolute, Translational,
};
use crate::ode::{Method, Tolerances};
use crate::simulation::{RunSettings, Scene, SteadyState, RATIO_ROUNDING};
use crate::{Error, Result};
use nalgebra::Vector2;

const MM: f64 = 1e-3;
const GPA: f64 = 1e9;

impl SceneFile {
    /// Validates every value and converts the scene to SI.
    pub fn build(&self) -> Result<Scene> {
        self.build_for(false)
    }

    /// [`SceneFile::build`] for a command that needs recorded rotations if `always` (a
    /// sweep): its refusal of a coarse recording grid does not advise recording none
    /// ([`Scene::check_recording`]).
    pub fn build_for(&self, always: bool) -> Result<Scene> {
        self.check_sizes()?;
        // Every material and ground point is checked, used or not: a value out of its range
        // is a mistake either way, and one unused today is used by the next edit.
        for name in self.materials.keys() {
            self.material(&format!("materials.{name}"), name)?;
        }
        for (name, p) in &self.ground.points_mm {
            check_coordinates(&format!("ground.points_mm.{name}"), p)?;
        }
        if let Some(g) =
            (self.gravity_m_s2.iter()).find(|g| !(g.is_finite() && g.abs() <= GRAVITY_M_S2))
        {
            return Err(Error::invalid(
                "gravity_m_s2",
                exact(*g),
                format!(
                    "finite components within ±{} m/s² (1000 g)",
                    terminal(GRAVITY_M_S2)
                ),
            ));
        }
        if self.bodies.is_empty() {
            return Err(Error::invalid("bodies", "none", "at least one body"));
        }
        let mut bodies = Vec::new();
        let mut guess = Vec::new();
        for (i, b) in self.bodies.iter().enumerate() {
            let f = |k: &str| format!("bodies[{i}].{k}");
            if b.name == "ground" || self.bodies[..i].iter().any(|o| o.name == b.name) {
                return Err(Error::invalid(
                    f("name"),
                    &b.name,
                    "a unique name other than `ground`",
                ));
            }
            bodies.push(Body {
                name: b.name.clone(),
                mass: within(&f("mass_kg"), b.mass_kg, &MASS_KG)?,
                inertia: within(&f("inertia_kg_m2"), b.inertia_kg_m2, &INERTIA_KG_M2)?,
            });
            check_coordinates(&f("position_mm"), &b.position_mm)?;
            within(&f("angle_deg"), b.angle_deg, &BODY_ANGLE_DEG)?;
            for (name, p) in &b.points_mm {
                check_coordinates(&f(&format!("points_mm.{name}")), p)?;
            }
            guess.extend([
                b.position_mm[0] * MM,
                b.position_mm[1] * MM,
                b.angle_deg.to_radians(),
            ]);
        }
        check_gyration(self)?;
        let revolutes = self
            .revolute
            .iter()
            .enumerate()
            .map(|(i, r)| {
                Ok(Revolute {
                    a: self.point(&format!("revolute[{i}].a"), &r.a)?,
                    b: self.point(&format!("revolute[{i}].b"), &r.b)?,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let translationals = self
            .translational
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let a = self.point(&format!("translational[{i}].a"), &t.a)?;
                let b = self.point(&format!("translational[{i}].b"), &t.b)?;
                let axis = check(
                    &format!("translational[{i}].axis_deg"),
                    t.axis_deg,
                    -360.0,
                    360.0,
                )?
                .to_radians();
                let angle = |p: &BodyPoint| p.body.map_or(0.0, |k| guess[3 * k + 2]);
                Ok(Translational {
                    a,
                    b,
                    normal: Vector2::new(-axis.sin(), axis.cos()),
                    relative_angle: angle(&a) - angle(&b),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let driver_body = self
            .body_index(&self.driver.body)
            .flatten()
            .ok_or_else(|| {
                Error::invalid(
                    "driver.body",
                    &self.driver.body,
                    "the name of a body (not ground)",
                )
            })?;
        let speed = self.driver.speed_rpm;
        if !(speed.is_finite() && (MIN_SPEED_RPM..=1e5).contains(&speed.abs())) {
            return Err(Error::invalid(
                "driver.speed_rpm",
                exact(speed),
                format!(
                    "a finite speed whose magnitude is in [{}, 100000] r/min (either sign): \
                     a rotation slower than {} r/min needs more steps than the largest \
                     run.max_steps, {:e}, of the largest step, {} s; likely cause: a speed in \
                     another unit",
                    terminal(MIN_SPEED_RPM),
                    terminal(MIN_SPEED_RPM),
                    MAX_RUN_STEPS as f64,
                    terminal(MAX_STEP_S)
                ),
            ));
        }
        let driver = Driver {
            body: driver_body,
            omega: speed * std::f64::consts::TAU / 60.0,
            speed_rpm: speed,
            angle0: check("driver.angle_deg", self.driver.angle_deg, -360.0, 360.0)?.to_radians(),
        };
        guess[3 * driver_body + 2] = driver.angle0;
        let clearance_joints = self
            .clearance
            .iter()
            .enumerate()
            .map(|(i, c)| self.clearance_joint(i, c))
            .collect::<Result<Vec<_>>>()?;
        self.check_replaced_revolutes(&revolutes, &clearance_joints)?;
        let run = self.run.build()?;
        let mechanism = Mechanism::new(
            bodies,
            revolutes,
            translationals,
            driver,
            clearance_joints,
            Vector2::new(self.gravity_m_s2[0], self.gravity_m_s2[1]),
            (run.baumgarte, run.baumgarte),
            run.energy_accounting,
        )?;
        let dof = mechanism.degrees_of_freedom();
        if dof < 0 {
            return Err(Error::invalid(
                "joints",
                format!("{dof} degrees of freedom"),
                "a mechanism that is not over-constrained",
            ));
        }
        let scene = Scene {
            title: self.title.clone(),
            mechanism,
            guess,
            run,
        };
        scene.check_recording(always)?;
        scene.check_step_budget()?;
        scene.check_tolerances()?;
        Ok(scene)
    }

    /// Refuses a `[[revolute]]` left at the pin of a `[[clearance]]` joint (the same two body
    /// points, in either order): the clearance joint replaces it, and left in, it holds the
    /// journal centred, which the assembly only reports as dependent constraints.
    fn check_replaced_revolutes(
        &self,
        revolutes: &[Revolute],
        clearance_joints: &[ClearanceJoint],
    ) -> Result<()> {
        for (i, cj) in clearance_joints.iter().enumerate() {
            let pin = |r: &Revolute| {
                (r.a == cj.journal && r.b == cj.bearing) || (r.a == cj.bearing && r.b == cj.journal)
            };
            if let Some(k) = revolutes.iter().position(pin) {
                let (r, c) = (&self.revolute[k], &self.clearance[i]);
                return Err(Error::invalid(
                    format!("revolute[{k}]"),
                    format!("{} - {}", r.a, r.b),
                    format!(
                        "no ideal revolute at the pin of clearance joint `{}` (clearance[{i}], \
                         journal {} in bearing {}): the clearance joint replaces that revolute, \
                         so remove this [[revolute]] from the scene",
                        cj.name, c.journal, c.bearing
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Checks the lengths of the title and of every name ([`MAX_TITLE_BYTES`],
    /// [`MAX_NAME_BYTES`]), and that no two clearance joints write the same files.
    fn check_sizes(&self) -> Result<()> {
        if self.title.len() > MAX_TITLE_BYTES {
            return Err(Error::invalid(
                "title",
                format!("a title of {} bytes", self.title.len()),
                format!(
                    "a title of at most {MAX_TITLE_BYTES} bytes (it is drawn above every \
                     figure; likely cause: a description that belongs in a comment)"
                ),
            ));
        }
        for name in self.materials.keys() {
            check_name(&format!("materials.{name:.64}"), name)?;
        }
        for name in self.ground.points_mm.keys() {
            check_name(&format!("ground.points_mm.{name:.64}"), name)?;
        }
        for (i, b) in self.bodies.iter().enumerate() {
            check_name(&format!("bodies[{i}].name"), &b.name)?;
            for name in b.points_mm.keys() {
                check_name(&format!("bodies[{i}].points_mm.{name:.64}"), name)?;
            }
        }
        for (i, c) in self.clearance.iter().enumerate() {
            check_name(&format!("clearance[{i}].name"), &c.name)?;
        }
        let names: Vec<&str> = self.clearance.iter().map(|c| c.name.as_str()).collect();
        check_joint_file_names(&names)
    }

    /// `Some(None)` for the ground, `Some(Some(i))` for body i, `None` if unknown.
    fn body_index(&self, name: &str) -> Option<BodyIndex> {
        if name == "ground" {
            return Some(None);
        }
        self.bodies.iter().position(|b| b.name == name).map(Some)
    }

    /// Resolves `"body.point"` (local coordinates converted to m).
    fn point(&self, field: &str, spec: &str) -> Result<BodyPoint> {
        let bad = || {
            Error::invalid(
                field,
                format!("\"{spec}\""),
                "\"body.point\" naming a body (or ground) and one of its points",
            )
        };
        let (body, point) = spec.split_once('.').ok_or_else(bad)?;
        let index = self.body_index(body).ok_or_else(bad)?;
        let points = match index {
            None => &self.ground.points_mm,
            Some(i) => &self.bodies[i].points_mm,
        };
        let p = points.get(point).ok_or_else(bad)?;
        check_coordinates(field, p)?;
        Ok(BodyPoint {
            body: index,
            local: Vector2::new(p[0] * MM, p[1] * MM),
        })
    }

    fn material(&self, field: &str, name: &str) -> Result<(f64, f64)> {
        let m = self.materials.get(name).ok_or_else(|| {
            Error::invalid(
                field,
                format!("\"{name}\""),
                "the name of a [materials] entry",
            )
        })?;
        let mf = format!("materials.{name}");
        Ok((
            within(
                &format!("{mf}.youngs_modulus_gpa"),
                m.youngs_modulus_gpa,
                &YOUNGS_MODULUS_GPA,
            )? * GPA,
            check(&format!("{mf}.poisson_ratio"), m.poisson_ratio, 0.0, 0.4999)?,
        ))
    }

    fn clearance_joint(&self, i: usize, c: &ClearanceSpec) -> Result<ClearanceJoint> {
        let f = |k: &str| format!("clearance[{i}].{k}");
        let journal = self.point(&f("journal"), &c.journal)?;
        let bearing = self.point(&f("bearing"), &c.bearing)?;
        if journal.body == bearing.body {
            return Err(Error::invalid(
                f("bearing"),
                &c.bearing,
                "a point on another body than the journal's",
            ));
        }
        let r_bearing = within(
            &f("bearing_radius_mm"),
            c.bearing_radius_mm,
            &BEARING_RADIUS_MM,
        )? * MM;
        let clearance = c.clearance_mm * MM;
        if !(clearance.is_finite() && clearance >= 0.0 && clearance < r_bearing) {
            return Err(Error::invalid(
                f("clearance_mm"),
                exact(c.clearance_mm),
                format!(
                    "a finite number in [0, {}) (the journal must fit in the bearing)",
                    exact(c.bearing_radius_mm)
                ),
            ));
        }
        // mm over mm: the ratio of the numbers as written (1 µm in 10 mm is exactly 1e-4).
        let ratio = c.clearance_mm / c.bearing_radius_mm;
        let radius = || {
            format!(
                "{} = {} mm",
                f("bearing_radius_mm"),
                exact(c.bearing_radius_mm)
            )
        };
        if ratio > MAX_CLEARANCE_RATIO * RATIO_ROUNDING {
            return Err(Error::invalid(
                f("clearance_mm"),
                exact(c.clearance_mm),
                format!(
                    "at most {MAX_CLEARANCE_RATIO} x the bearing radius ({}), {} mm: the \
                     contact laws are those of a journal conforming to its bore, and the wear \
                     model holds to wear of that fraction of the radius, the depth that \
                     doubles such a clearance (longlife's default limit); a wider joint is a \
                     loose pin, not a clearance joint (likely cause: the clearance and the \
                     radius swapped, or a diameter for the radius)",
                    radius(),
                    terminal(MAX_CLEARANCE_RATIO * c.bearing_radius_mm)
                ),
            ));
        }
        let journal_mm = c.bearing_radius_mm - c.clearance_mm;
        // R − c of two decimals is rounded (0.105 − 0.005 gives 0.09999999999999999): a
        // journal within two roundings of R of the minimum has it.
        if journal_mm < BEARING_RADIUS_MM.lo - 2.0 * f64::EPSILON * c.bearing_radius_mm {
            return Err(Error::invalid(
                f("clearance_mm"),
                exact(c.clearance_mm),
                format!(
                    "a clearance that leaves a journal radius, bearing_radius_mm - \
                     clearance_mm, of at least {} mm ({}; the journal's is {} mm): {}",
                    terminal(BEARING_RADIUS_MM.lo),
                    radius(),
                    terminal(journal_mm),
                    BEARING_RADIUS_MM.why
                ),
            ));
        }
        let r_journal = r_bearing - clearance;
        let (ej, nj) = self.material(&f("journal_material"), &c.journal_material)?;
        let (eb, nb) = self.material(&f("bearing_material"), &c.bearing_material)?;
        let e_star = compound_modulus(eb, nb, ej, nj);
        let k = &c.contact;
        let (stiffness, dissipation) = contact_laws(&f, k)?;
        contact_exponent(&f, k, stiffness)?;
        let length = contact_length(&f, c, stiffness)?;
        if stiffness == StiffnessLaw::Pereira {
            let (lo, hi) = PEREIRA_CLEARANCE_MM;
            if !(lo..=hi).contains(&c.clearance_mm) {
                return Err(Error::invalid(
                    f("clearance_mm"),
                    exact(c.clearance_mm),
                    format!(
                        "a clearance in [{lo}, {hi}] mm with stiffness = \"pereira\": the \
                         range its exponent was fitted over (Pereira et al. 2011)"
                    ),
                ));
            }
        }
        let joint = JointElasticity {
            e_star,
            r_bearing,
            r_journal,
            length,
        };
        let contact = ContactLaw::from_laws(
            stiffness,
            dissipation,
            &joint,
            within(&f("contact.restitution"), k.restitution, &RESTITUTION)?,
            within(
                &f("contact.grazing_velocity_m_s"),
                k.grazing_velocity_m_s,
                &GRAZING_VELOCITY_M_S,
            )?,
        );
        validate_friction(&f("friction"), &c.friction)?;
        let (contact_key, contact_instead) = if k.model.is_some() {
            (
                "contact.model",
                "model = \"hybrid\" (the paper's law, whose elastic-foundation stiffness \
                 holds down to zero clearance)",
            )
        } else {
            (
                "contact.stiffness",
                "stiffness = \"hybrid\" or \"liu\" (elastic-foundation laws, which hold down \
                 to zero clearance)",
            )
        };
        let hertz = [
            (stiffness.hertz_based(), contact_key, contact_instead),
            (
                c.wear
                    .as_ref()
                    .is_some_and(|w| w.pressure == PressureModel::HertzLine),
                "wear.pressure",
                "pressure = \"elastic-foundation\" (the Winkler overlap model, valid for \
                 conformal contact down to tiny clearances)",
            ),
        ];
        if let Some((_, key, instead)) = hertz
            .iter()
            .find(|(hertz, _, _)| *hertz && ratio < MIN_HERTZ_CLEARANCE_RATIO)
        {
            return Err(Error::invalid(
                f("clearance_mm"),
                exact(c.clearance_mm),
                format!(
                    "at least {MIN_HERTZ_CLEARANCE_RATIO:e} x the bearing radius ({} mm) with \
                     the Hertz-based {key}: its contact half-width must stay small against the \
                     radius, and as the clearance goes to zero it is unbounded (zero pressure); \
                     use {instead}",
                    exact(MIN_HERTZ_CLEARANCE_RATIO * c.bearing_radius_mm)
                ),
            ));
        }
        let (wear, sectors) = match &c.wear {
            None => (None, 8),
            Some(w) => {
                let sectors = w.sectors;
                if !(8..=36000).contains(&sectors) {
                    return Err(Error::invalid(
                        f("wear.sectors"),
                        sectors,
                        "an integer in [8, 36000]",
                    ));
                }
                let k_over_h = check(
                    &f("wear.k_over_h_per_pa"),
                    w.k_over_h_per_pa,
                    0.0,
                    MAX_K_OVER_H_PER_PA,
                )?;
                if c.clearance_mm == 0.0 && k_over_h > 0.0 {
                    return Err(Error::invalid(
                        f("wear.k_over_h_per_pa"),
                        exact(k_over_h),
                        "0 at a radial clearance of 0: against no clearance any uneven wear is \
                         steeper than the paper's gap describes (|dh/dθ| / (c + h) = |h′|/h, \
                         above 0.3 after the first rotation whatever k/H; README, validity \
                         limits); give the joint a clearance, or no wear",
                    ));
                }
                let law = WearLaw {
                    k_over_h,
                    pressure: w.pressure,
                    length: within(&f("wear.length_mm"), w.length_mm, &BEARING_LENGTH_MM)? * MM,
                    e_star,
                    r_bearing,
                    r_journal,
                };
                (Some(law), sectors)
            }
        };
        Ok(ClearanceJoint {
            name: c.name.clone(),
            journal,
            bearing,
            r_journal,
            r_bearing,
            given_clearance: shift_decimal(c.clearance_mm, -3),
            contact,
            friction: c.friction,
            wear,
            initial_profile: WearProfile::new(sectors),
        })
    }
}

/// Largest `run.rotations`.
pub const MAX_ROTATIONS: u32 = 1_000_000;

/// Largest `run.steady_state.max_rotations`: a run simulates at most [`MAX_ROTATIONS`] plus
/// this many rotations.
pub const MAX_SETTLING_ROTATIONS: u32 = 10_000;

impl RunSpec {
    fn build(&self) -> Result<RunSettings> {
        if !(1..=MAX_ROTATIONS).contains(&self.rotations) {
            return Err(Error::invalid(
                "run.rotations",
                self.rotations,
                format!("an integer in [1, {MAX_ROTATIONS}]"),
            ));
        }
        if self.record_rotations > self.rotations {
            return Err(Error::invalid(
                "run.record_rotations",
                self.record_rotations,
                format!("an integer in [0, {}]", self.rotations),
            ));
        }
        if let Some(&s) = self
            .wear_snapshots
            .iter()
            .find(|&&s| s == 0 || s > self.rotations)
        {
            return Err(Error::invalid(
                "run.wear_snapshots",
                s,
                format!("rotation counts in [1, {}]", self.rotations),
            ));
        }
        let tolerances = Tolerances {
            rtol: check("run.rtol", self.rtol, 1e-13, 1.0)?,
            atol: within("run.atol", self.atol, &ABSOLUTE_TOLERANCE)?,
            max_step: check_open("run.max_step_s", self.max_step_s, 0.0, MAX_STEP_S)?,
            initial_step: 0.0,
        };
        let method = match self.method {
            MethodSpec::Dopri5 => Method::Dopri5,
            MethodSpec::Dop853 => Method::Dop853,
            MethodSpec::Rk4 => {
                let step = self.fixed_step_s.ok_or_else(|| {
                    Error::invalid(
                        "run.fixed_step_s",
                        "missing",
                        "a step in (0, 1] s for method rk4",
                    )
                })?;
                // A fixed step has no controller: a filter chosen for it would be named in
                // summary.json and steer nothing.
                if self.step_control != StepControlSpec::I {
                    return Err(Error::invalid(
                        "run.step_control",
                        "pi42",
                        "\"i\" (the default) with method rk4, whose step is fixed; \
                         the filter steers dopri5 and dop853; likely cause: the method changed \
                         to rk4 in a scene that names the filter (the standard scene and its \
                         variants do): set run.step_control = \"i\" as well",
                    ));
                }
                Method::Rk4 {
                    step: check_open("run.fixed_step_s", step, 0.0, MAX_STEP_S)?,
                }
            }
        };
        let mut wear_snapshots = self.wear_snapshots.clone();
        wear_snapshots.sort_unstable();
        wear_snapshots.dedup();
        Ok(RunSettings {
            rotations: self.rotations,
            record_rotations: self.record_rotations,
            record_interval: check_open("run.record_interval_s", self.record_interval_s, 0.0, 1.0)?,
            wear_snapshots,
            method,
            step_control: self.step_control,
            tolerances,
            baumgarte: check("run.baumgarte_per_s", self.baumgarte_per_s, 0.0, 1e6)?,
            energy_accounting: self.energy_accounting,
            // The criterion is checked whether the run settles or not: a bad one is a mistake
            // either way, and the next edit turns settling on.
            settle: match (
                self.settle,
                self.steady_state.as_ref().map(|s| s.build()).transpose()?,
            ) {
                (false, _) => None,
                (true, Some(criterion)) => Some(criterion),
                (true, None) => {
                    return Err(Error::invalid(
                        "run.steady_state",
                        "missing",
                        "a steady-state criterion when run.settle is true",
                    ))
                }
            },
            profile_history_per_rotation: match self.profile_history_per_rotation {
                h @ 0..=3600 => h,
                h => {
                    return Err(Error::invalid(
                        "run.profile_history_per_rotation",
                        h,
                        "an integer in [0, 3600]",
                    ))
                }
            },
            max_steps: match self.max_steps {
                m @ 1..=MAX_RUN_STEPS => m,
                m => {
                    return Err(Error::invalid(
                        "run.max_steps",
                        m,
                        "an integer in [1, 1e10]",
                    ))
                }
            },
        })
    }
}

impl SteadyStateSpec {
    fn build(&self) -> Result<SteadyState> {
        let max_rotations = self.max_rotations;
        if !(2..=MAX_SETTLING_ROTATIONS).contains(&max_rotations) {
            return Err(Error::invalid(
                "run.steady_state.max_rotations",
                max_rotations,
                format!("an integer in [2, {MAX_SETTLING_ROTATIONS}]"),
            ));
        }
        Ok(SteadyState {
            tolerance: check_open(
                "run.steady_state.orbit_tolerance",
                self.orbit_tolerance,
                0.0,
                1.0,
            )?,
            max_rotations,
        })
    }
}

/// The stiffness and dissipation laws of `contact`: its `model`, or its `stiffness` and
/// `dissipation` (one way or the other, not both).
fn contact_laws(
    f: &dyn Fn(&str) -> String,
    k: &ContactSpec,
) -> Result<(StiffnessLaw, DissipationLaw)> {
    let either = "either model = \"hybrid\" or \"lankarani-nikravesh\", or both stiffness and \
                  dissipation (README: \"Picking a contact law\")";
    match (k.model, k.stiffness, k.dissipation) {
        (Some(m), None, None) => Ok(m.laws()),
        (None, Some(s), Some(d)) => Ok((s, d)),
        (Some(_), _, _) => Err(Error::invalid(
            f("contact"),
            k.spelling(),
            format!("{either}; not both"),
        )),
        (None, None, _) => Err(Error::invalid(f("contact.stiffness"), "missing", either)),
        (None, Some(_), None) => Err(Error::invalid(f("contact.dissipation"), "missing", either)),
    }
}

/// Checks the exponent n of the contact: a power law's must be [`POWER_LAW_EXPONENT`], which
/// its K is derived for (another n with that K is another law: n = 2 let the standard joint
/// penetrate 102 µm, five clearances); the other laws take none.
fn contact_exponent(f: &dyn Fn(&str) -> String, k: &ContactSpec, s: StiffnessLaw) -> Result<()> {
    let field = f("contact.exponent");
    let power = || {
        format!(
            "{POWER_LAW_EXPONENT}: the K of stiffness \"{}\" is derived for n = \
             {POWER_LAW_EXPONENT} (N/m^{POWER_LAW_EXPONENT}), and with another n the same K is \
             not the law at all; no law takes a free exponent: for another force-penetration \
             shape choose a stiffness with its own (\"pereira\", fitted to finite elements; \
             \"liu\"; \"johnson\", \"radzimovsky\", \"esdu-78035\") and no exponent",
            s.name()
        )
    };
    match (s.uses_exponent(), k.exponent) {
        (true, Some(n)) if n == POWER_LAW_EXPONENT => Ok(()),
        (true, Some(n)) => Err(Error::invalid(field, exact(n), power())),
        (true, None) => Err(Error::invalid(field, "missing", power())),
        (false, Some(n)) => Err(Error::invalid(
            field,
            exact(n),
            format!(
                "no exponent: stiffness \"{}\" has its own shape, not K δ^n (remove it)",
                s.name()
            ),
        )),
        (false, None) => Ok(()),
    }
}

/// The bearing length (m) of a law written per length: `contact.length_mm`, else
/// `wear.length_mm`; two different lengths of one joint are an error. Other laws take none (0).
fn contact_length(f: &dyn Fn(&str) -> String, c: &ClearanceSpec, s: StiffnessLaw) -> Result<f64> {
    let field = f("contact.length_mm");
    let wear = c.wear.as_ref().map(|w| w.length_mm);
    if !s.needs_length() {
        return match c.contact.length_mm {
            Some(l) => Err(Error::invalid(
                field,
                exact(l),
                format!(
                    "no length: stiffness \"{}\" is not written per bearing length (remove it)",
                    s.name()
                ),
            )),
            None => Ok(0.0),
        };
    }
    match (c.contact.length_mm, wear) {
        (Some(l), Some(w)) if l != w => Err(Error::invalid(
            field,
            exact(l),
            format!(
                "the bearing length of wear.length_mm ({}) or no contact.length_mm: one joint \
                 has one length",
                exact(w)
            ),
        )),
        (Some(l), _) => Ok(within(&field, l, &BEARING_LENGTH_MM)? * MM),
        (None, Some(w)) => Ok(within(&f("wear.length_mm"), w, &BEARING_LENGTH_MM)? * MM),
        (None, None) => Err(Error::invalid(
            field,
            "missing",
            format!(
                "a bearing length in [{}, {}] mm: stiffness \"{}\" is a force per bearing length \
                 (or give the joint a wear model with its length_mm)",
                BEARING_LENGTH_MM.lo,
                BEARING_LENGTH_MM.hi,
                s.name()
            ),
        )),
    }
}
