//! Tests that would fail on a wrong model: analytic identities, limits, invariants and an
//! independent minimal-coordinate formulation as an oracle.

use approx::assert_relative_eq;
use jointwear::contact::{ContactLaw, NormalForceModel};
use jointwear::friction::FrictionModel;
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::simulate;
use ode_solvers::{Dopri5, System, Vector4};

/// The shipped standard scene, to be varied by each test.
fn standard() -> SceneFile {
    SceneFile::read(scene_path("standard")).expect("standard scene")
}

/// A short run without wear, recording every rotation.
fn short(mut f: SceneFile, rotations: u32) -> SceneFile {
    f.run.rotations = rotations;
    f.run.record_rotations = rotations;
    f.run.wear_snapshots.clear();
    f.clearance[0].wear = None;
    f
}

#[test]
fn constraint_jacobian_and_gamma_match_finite_differences() {
    let scene = standard().build().unwrap();
    let mut m = scene.mechanism.clone();
    let y = m.assemble(&scene.guess).unwrap();
    let n = m.coordinates();
    // A perturbed, non-assembled state exercises every term.
    let q: Vec<f64> = y[..n]
        .iter()
        .enumerate()
        .map(|(i, x)| x + 1e-3 * (i as f64 + 1.0).sin())
        .collect();
    let v: Vec<f64> = y[n..2 * n]
        .iter()
        .enumerate()
        .map(|(i, x)| x + (i as f64).cos())
        .collect();
    let (jac, gamma) = m.jacobian(&q, &v);
    let rows = m.constraint_count();
    let h = 1e-7;
    for k in 0..n {
        let (mut qp, mut qm) = (q.clone(), q.clone());
        qp[k] += h;
        qm[k] -= h;
        let (pp, pm) = (
            m.constraint_vector(0.01, &qp),
            m.constraint_vector(0.01, &qm),
        );
        for i in 0..rows {
            assert_relative_eq!(jac[i * n + k], (pp[i] - pm[i]) / (2.0 * h), epsilon = 1e-7);
        }
    }
    // γ = −(d/dt Φ_q) q̇: differentiate Φ_q q̇ along q̇.
    let jv = |m: &mut jointwear::mechanism::Mechanism, s: f64| {
        let qs: Vec<f64> = q.iter().zip(&v).map(|(a, b)| a + s * b).collect();
        let (j, _) = m.jacobian(&qs, &v);
        (0..rows)
            .map(|i| (0..n).map(|k| j[i * n + k] * v[k]).sum::<f64>())
            .collect::<Vec<_>>()
    };
    let (jp, jm) = (jv(&mut m, h), jv(&mut m, -h));
    for i in 0..rows {
        assert_relative_eq!(
            gamma[i],
            -(jp[i] - jm[i]) / (2.0 * h),
            epsilon = 1e-5,
            max_relative = 1e-6
        );
    }
}

#[test]
fn zero_clearance_follows_ideal_slider_crank_kinematics() {
    let mut f = short(standard(), 2);
    f.clearance[0].clearance_mm = 0.0;
    f.clearance[0].friction = FrictionModel::None;
    let out = simulate(&f.build().unwrap()).unwrap();
    let rec = &out.recording;
    let (r, l) = (0.05, 0.12);
    let slider_x = &rec.positions[2][0];
    let mut worst: f64 = 0.0;
    for (th, x) in rec.driver_angle.iter().zip(slider_x) {
        let ideal = r * th.cos() + (l * l - (r * th.sin()).powi(2)).sqrt();
        worst = worst.max((x - ideal).abs());
    }
    // Without clearance only the contact compliance separates journal and bearing: a few
    // micrometres at the standard load, against a 100 mm stroke.
    assert!(
        worst < 1e-5,
        "slider deviates {worst:e} m from the ideal joint"
    );
    assert!(out.max_penetration[0] < 1e-5);
    // two whole rotations, in either sense
    assert_relative_eq!(
        rec.driver_angle.last().unwrap().abs(),
        2.0 * std::f64::consts::TAU,
        max_relative = 1e-9
    );
}

/// Independent oracle: the slider-crank with a clearance joint in minimal coordinates
/// (rod angle β and slider position x; the crank angle is prescribed), derived by hand from
/// Lagrange's equations and integrated with the `ode_solvers` crate.
struct MinimalSliderCrank {
    law: ContactLaw,
    friction: FrictionModel,
    omega: f64,
    c: f64,
    r_journal: f64,
}

const R: f64 = 0.05;
const L: f64 = 0.12;
const M_ROD: f64 = 0.21;
const J_ROD: f64 = 0.001;
const M_SLIDER: f64 = 0.14;
const G: f64 = 9.81;

impl MinimalSliderCrank {
    /// Journal centre minus bearing centre and its rate.
    fn eccentricity(&self, t: f64, y: &Vector4<f64>) -> ([f64; 2], [f64; 2]) {
        let (th, w) = (self.omega * t, self.omega);
        let (b, x, bd, xd) = (y[0], y[1], y[2], y[3]);
        let e = [R * th.cos() + L * b.cos() - x, R * th.sin() + L * b.sin()];
        let ed = [
            -R * w * th.sin() - L * bd * b.sin() - xd,
            R * w * th.cos() + L * bd * b.cos(),
        ];
        (e, ed)
    }
}

impl System<f64, Vector4<f64>> for MinimalSliderCrank {
    fn system(&self, t: f64, y: &Vector4<f64>, dy: &mut Vector4<f64>) {
        let (th, w) = (self.omega * t, self.omega);
        let (b, bd) = (y[0], y[2]);
        let (e, ed) = self.eccentricity(t, y);
        let dist = e[0].hypot(e[1]);
        let n = [e[0] / dist, e[1] / dist];
        let tg = [-n[1], n[0]];
        let delta = dist - self.c;
        let mut force = [0.0, 0.0];
        let mut arm = [0.0, 0.0];
        if delta >= 0.0 {
            let delta_dot = n[0] * ed[0] + n[1] * ed[1];
            let f_n = self.law.force(delta, delta_dot, 0.0, self.c);
            let v_t = tg[0] * ed[0] + tg[1] * ed[1] + bd * self.r_journal;
            let f_t = self.friction.force(f_n, v_t);
            force = [-f_n * n[0] + f_t * tg[0], -f_n * n[1] + f_t * tg[1]];
            // contact point relative to the crank pin, a material point of the rod
            arm = [
                L * b.cos() + self.r_journal * n[0],
                L * b.sin() + self.r_journal * n[1],
            ];
        }
        let q_beta = -arm[1] * force[0] + arm[0] * force[1];
        let acc_pin = [-R * w * w * th.cos(), -R * w * w * th.sin()];
        let u_perp = [-b.sin(), b.cos()];
        let inertia = M_ROD * L * L / 4.0 + J_ROD;
        let pin_term = M_ROD * L / 2.0 * (acc_pin[0] * u_perp[0] + acc_pin[1] * u_perp[1]);
        dy[0] = bd;
        dy[1] = y[3];
        dy[2] = (q_beta - pin_term - M_ROD * G * L / 2.0 * b.cos()) / inertia;
        dy[3] = -force[0] / M_SLIDER;
    }
}

#[test]
fn general_solver_agrees_with_minimal_coordinate_oracle() {
    let mut f = short(standard(), 1);
    // Damped impacts settle into contact (undamped impacting orbits are chaotic and cannot be
    // compared over a rotation). A grazing floor above every impact velocity makes the damping
    // independent of the captured onset velocity, which the oracle does not track.
    f.clearance[0].contact.restitution = 0.5;
    f.clearance[0].contact.grazing_velocity_m_s = 2.0;
    f.run.rtol = 1e-11;
    f.run.atol = 1e-13;
    f.run.record_interval_s = 1e-4;
    let scene = f.build().unwrap();
    let cj = &scene.mechanism.clearance_joints[0];
    let oracle = MinimalSliderCrank {
        law: ContactLaw::new(
            NormalForceModel::Hybrid,
            207e9 / (2.0 * 0.91),
            0.01,
            0.00998,
            1.5,
            0.5,
            2.0,
        ),
        friction: cj.friction,
        omega: scene.mechanism.driver.omega,
        c: 2e-5,
        r_journal: cj.r_journal,
    };
    let period = std::f64::consts::TAU / oracle.omega.abs();
    let y0 = Vector4::new(0.0, R + L, -R * oracle.omega / L, 0.0);
    let mut solver = Dopri5::from_param(
        oracle,
        0.0,
        period,
        1e-4,
        y0,
        1e-11,
        1e-13,
        0.9,
        0.04,
        0.2,
        10.0,
        1e-5,
        0.0,
        10_000_000,
        1000,
        ode_solvers::OutputType::Dense,
    );
    solver.integrate().expect("oracle integrates");
    let out = simulate(&scene).unwrap();
    let rec = &out.recording.joints[0];
    // ode_solvers appends its end state after the dense grid; compare on the grid only.
    let (ts, ys) = (&solver.x_out()[..solver.x_out().len() - 1], solver.y_out());
    let probe = MinimalSliderCrank {
        law: cj.contact,
        friction: cj.friction,
        omega: scene.mechanism.driver.omega,
        c: 2e-5,
        r_journal: cj.r_journal,
    };
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    for (i, &t) in out.recording.time.iter().enumerate() {
        let k = ts.iter().position(|&x| (x - t).abs() < 1e-9);
        if let Some(k) = k {
            let (e, _) = probe.eccentricity(t, &ys[k]);
            worst = worst.max((e[0] - rec.ex[i]).hypot(e[1] - rec.ey[i]));
            compared += 1;
        }
    }
    assert!(compared > 250, "compared {compared} samples");
    eprintln!("largest orbit difference {worst:e} m");
    // 0.005% of the clearance over a full rotation of impacts and sliding: both sides are
    // integrated at rtol 1e-11, so what remains is the Baumgarte-stabilised constraint drift.
    assert!(worst < 1e-9, "largest orbit difference {worst:e} m");
}

#[test]
fn conservative_joint_conserves_energy() {
    let mut f = short(standard(), 3);
    f.clearance[0].contact.restitution = 1.0;
    f.clearance[0].friction = FrictionModel::None;
    f.run.energy_accounting = true;
    f.run.rtol = 1e-10;
    f.run.atol = 1e-12;
    let out = simulate(&f.build().unwrap()).unwrap();
    let e = out.energy.unwrap();
    // Driver work equals the change of kinetic + potential + elastic energy; contact forces
    // lose nothing. The bound is the integrator tolerance times the energy exchanged.
    assert!(
        e.damping_loss().abs() < 1e-6 * e.driver_work.abs().max(1.0),
        "{e:?}"
    );
    assert!(e.residual().abs() < 1e-5, "{e:?}");
    assert_eq!(e.friction_work, 0.0);
}

#[test]
fn dissipative_joint_balances_driver_work() {
    let mut f = short(standard(), 3);
    f.run.energy_accounting = true;
    f.run.rtol = 1e-10;
    f.run.atol = 1e-12;
    let out = simulate(&f.build().unwrap()).unwrap();
    let e = out.energy.unwrap();
    assert!(e.damping_loss() > 0.0 && e.friction_work < 0.0, "{e:?}");
    assert!(e.residual().abs() < 1e-5, "{e:?}");
}

#[test]
fn zero_wear_coefficient_leaves_profile_and_dynamics_unchanged() {
    let mut with = standard();
    with.run.rotations = 2;
    with.run.record_rotations = 1;
    with.run.wear_snapshots = vec![1, 2];
    with.clearance[0].wear.as_mut().unwrap().k_over_h_per_pa = 0.0;
    let mut without = with.clone();
    without.clearance[0].wear = None;
    let a = simulate(&with.build().unwrap()).unwrap();
    let b = simulate(&without.build().unwrap()).unwrap();
    assert!(a.final_wear[0].iter().all(|&d| d == 0.0));
    assert_eq!(a.final_state, b.final_state);
}

#[test]
fn wear_grows_where_the_journal_presses() {
    let mut f = standard();
    f.run.rotations = 2;
    f.run.record_rotations = 1;
    f.run.wear_snapshots = vec![1, 2];
    let out = simulate(&f.build().unwrap()).unwrap();
    let (w1, w2) = (
        &out.wear_snapshots[0].depths[0],
        &out.wear_snapshots[1].depths[0],
    );
    assert!(
        w1.iter().zip(w2).all(|(a, b)| b >= a),
        "wear never decreases"
    );
    assert!(w2.iter().cloned().fold(0.0, f64::max) > 0.0);
}

/// The right-hand side solves some constraint equations for one coordinate each and only the
/// rest as a linear system; the full dense system `[M Φ_qᵀ; Φ_q 0] [q̈; λ] = [F; γ̂]` must give
/// the same accelerations and driver power, for every shipped mechanism.
#[test]
fn reduced_constraint_solve_matches_the_dense_system() {
    use nalgebra::{DMatrix, DVector};
    for name in ["standard", "fourbar", "two_clearance"] {
        let mut f = SceneFile::read(scene_path(name)).unwrap();
        f.run.energy_accounting = true;
        let scene = f.build().unwrap();
        let mut m = scene.mechanism.clone();
        let y0 = m.assemble(&scene.guess).unwrap();
        let (n, t) = (m.coordinates(), 0.004);
        // Off the constraint manifold (Baumgarte terms active), journals still clear of contact.
        let mut y = y0.clone();
        for (i, x) in y[..2 * n].iter_mut().enumerate() {
            *x += if i < n { 1e-7 } else { 1e-2 } * (i as f64 + 1.0).sin();
        }
        let (q, v) = (&y[..n], &y[n..2 * n]);
        for k in 0..m.clearance_joints.len() {
            assert_eq!(
                m.contact_state(k, q, v).f_n,
                0.0,
                "{name}: joint {k} in contact"
            );
        }
        let mut dy = vec![0.0; y.len()];
        m.rhs(t, &y, &mut dy).unwrap();

        let rows = m.constraint_count();
        let (jac, gamma) = m.jacobian(q, v);
        let phi = m.constraint_vector(t, q);
        let h = 1e-3;
        let phi_t: Vec<f64> = (m.constraint_vector(t + h, q).iter().zip(&phi))
            .map(|(a, b)| (a - b) / h)
            .collect();
        let (alpha, beta) = m.baumgarte;
        let size = n + rows;
        let mut a = DMatrix::<f64>::zeros(size, size);
        let mut b = DVector::<f64>::zeros(size);
        for (i, body) in m.bodies().iter().enumerate() {
            for (k, mass) in [body.mass, body.mass, body.inertia].into_iter().enumerate() {
                a[(3 * i + k, 3 * i + k)] = mass;
            }
            b[3 * i] = body.mass * m.gravity.x;
            b[3 * i + 1] = body.mass * m.gravity.y;
        }
        for r in 0..rows {
            let row = &jac[r * n..(r + 1) * n];
            for (c, &x) in row.iter().enumerate() {
                a[(n + r, c)] = x;
                a[(c, n + r)] = x;
            }
            let phi_dot = row.iter().zip(v).map(|(j, v)| j * v).sum::<f64>() + phi_t[r];
            b[n + r] = gamma[r] - 2.0 * alpha * phi_dot - beta * beta * phi[r];
        }
        let x = a.lu().solve(&b).unwrap();
        for c in 0..n {
            assert_relative_eq!(dy[n + c], x[c], epsilon = 1e-8, max_relative = 1e-9);
        }
        // The driver's equation is the only one with ∂Φ/∂t ≠ 0; its power is −λ_d φ̇.
        let d = (0..rows).find(|&r| phi_t[r] != 0.0).unwrap();
        let driven = 3 * m.driver.body + 2;
        assert_relative_eq!(dy[2 * n], -x[n + d] * v[driven], max_relative = 1e-8);
    }
}
