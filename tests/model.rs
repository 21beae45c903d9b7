//! Tests that would catch a wrong contact, friction or wear model: each result of the library
//! is compared with an independent computation written from the paper's equations in this
//! file (a 1-D impact integrated by RK4, a closed-form free fall, the contact angles and the
//! Archard integral of a recorded run), never with the library's own laws.

use jointwear::io::progress::Silent;
use jointwear::laws::wear::PressureModel;
use jointwear::mechanism::eigenvalues_by_modulus;
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::{simulate, RunOutput, Simulation};
use std::f64::consts::{PI, TAU};
use std::path::Path;

/// Steel on steel, as the standard scene: E = 207 GPa, ν = 0.3 on both sides.
const E_STAR: f64 = 207e9 / (2.0 * (1.0 - 0.09));
/// Bearing radius and radial clearance of the free-journal scene (m).
const R_BEARING: f64 = 0.01;
const CLEARANCE: f64 = 2e-5;
/// Mass of the free journal (kg), the standard slider's.
const M_JOURNAL: f64 = 0.14;

/// The smallest mechanism with a free journal impact: a journal body with no joint at all in
/// a bearing fixed to the ground, beside a driven spinner the format requires (a driver) and
/// which does not touch the journal. `gravity` in m/s², `restitution` c_e.
fn free_journal(gravity: [f64; 2], restitution: f64) -> SceneFile {
    let text = format!(
        r#"
title = "free journal"
gravity_m_s2 = [{gx:?}, {gy:?}]
[materials.steel]
youngs_modulus_gpa = 207.0
poisson_ratio = 0.3
[ground]
points_mm = {{ O = [0.0, 0.0] }}
[[bodies]]
name = "spinner"
mass_kg = 1.0
inertia_kg_m2 = 0.001
position_mm = [0.0, 0.0]
angle_deg = 0.0
points_mm = {{ O = [0.0, 0.0] }}
[[bodies]]
name = "journal"
mass_kg = {M_JOURNAL:?}
inertia_kg_m2 = 0.0001
position_mm = [0.0, 0.0]
angle_deg = 0.0
points_mm = {{ C = [0.0, 0.0] }}
[[revolute]]
a = "ground.O"
b = "spinner.O"
[driver]
body = "spinner"
speed_rpm = 100000.0
angle_deg = 0.0
[[clearance]]
name = "free"
journal = "journal.C"
bearing = "ground.O"
bearing_radius_mm = {rb:?}
clearance_mm = {c:?}
journal_material = "steel"
bearing_material = "steel"
contact = {{ model = "hybrid", restitution = {restitution:?}, exponent = 1.5, grazing_velocity_m_s = 1e-6 }}
friction = {{ model = "none" }}
[run]
rotations = 1
record_rotations = 0
record_interval_s = 1e-6
method = "dopri5"
rtol = 1e-10
atol = 1e-14
max_step_s = 1e-5
baumgarte_per_s = 100.0
"#,
        gx = gravity[0],
        gy = gravity[1],
        rb = R_BEARING * 1e3,
        c = CLEARANCE * 1e3,
    );
    SceneFile::parse(&text, Path::new("free_journal.toml")).expect("free-journal scene")
}

/// The shipped standard scene, to be varied by each test.
fn standard() -> SceneFile {
    SceneFile::read(scene_path("standard")).expect("standard scene")
}

/// Coordinates of the journal body in the state vector: (x, y, φ) of body 1.
const JX: usize = 3;
/// Number of coordinates of the free-journal mechanism (two bodies).
const N: usize = 6;

/// Eq. 1-3 written out from the paper for the hybrid law, independently of the library:
/// `F = K δ^1.5 + D δ̇`, `K = (π/8) E* sqrt(2δ(3ΔR + 2δ)² / (ΔR + δ)³)`,
/// `D = 3K(1 − c_e²) e^{2(1 − c_e)} δ^1.5 / (4 δ̇⁻)`, and no pull (F ≥ 0).
fn paper_normal_force(delta: f64, delta_dot: f64, onset: f64, ce: f64, dr: f64) -> f64 {
    if delta < 0.0 {
        return 0.0;
    }
    let k = PI / 8.0
        * E_STAR
        * (2.0 * delta * (3.0 * dr + 2.0 * delta).powi(2) / (dr + delta).powi(3)).sqrt();
    let d = 3.0 * k * (1.0 - ce * ce) * (2.0 * (1.0 - ce)).exp() * delta.powf(1.5) / (4.0 * onset);
    (k * delta.powf(1.5) + d * delta_dot).max(0.0)
}

/// Restitution of one impact of a point mass `m` on the hybrid law, from the 1-D contact ODE
/// `m δ̈ = −F(δ, δ̇)` with δ(0) = 0, δ̇(0) = v0, integrated by classical RK4 with a fixed step
/// until δ returns to zero: `−δ̇(exit) / v0`.
fn rk4_restitution(m: f64, v0: f64, ce: f64, dr: f64) -> f64 {
    let acc = |d: f64, v: f64| -paper_normal_force(d, v, v0, ce, dr) / m;
    // Hertz-like contact time scale: the step resolves the ~10 µs contact by 1e5 steps.
    let h = 1e-10;
    let (mut d, mut v) = (0.0_f64, v0);
    loop {
        let (k1d, k1v) = (v, acc(d, v));
        let (k2d, k2v) = (v + 0.5 * h * k1v, acc(d + 0.5 * h * k1d, v + 0.5 * h * k1v));
        let (k3d, k3v) = (v + 0.5 * h * k2v, acc(d + 0.5 * h * k2d, v + 0.5 * h * k2v));
        let (k4d, k4v) = (v + h * k3v, acc(d + h * k3d, v + h * k3v));
        let dn = d + h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
        let vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if dn < 0.0 && v < 0.0 {
            // Exit inside this step: the force is ~δ² there, so the velocity is linear to
            // far below the tolerance; interpolate it at the zero of δ.
            let s = d / (d - dn);
            return -(v + s * (vn - v)) / v0;
        }
        (d, v) = (dn, vn);
    }
}

#[test]
fn single_impact_restitution_matches_the_contact_ode() {
    let v0 = 0.05;
    let dir = [30f64.to_radians().cos(), 30f64.to_radians().sin()];
    for ce in [0.3, 0.6, 0.9] {
        let scene = free_journal([0.0, 0.0], ce).build().unwrap();
        // The journal 0.25 µm from the wall, flying at v0 along `dir` (a central impact); at
        // 0.05 m/s it cannot cross the 40 µm bore and hit again within the 0.6 ms run.
        let mut y0 = scene.mechanism.assemble(&scene.guess).unwrap();
        let start = CLEARANCE - 2.5e-7;
        for k in 0..2 {
            y0[JX + k] = start * dir[k];
            y0[N + JX + k] = v0 * dir[k];
        }
        let mut sim = Simulation::new(scene.mechanism.clone(), scene.run.clone(), &y0).unwrap();
        sim.run_to_end(&Silent).unwrap();
        let out = sim.finish();
        assert_eq!(out.impacts[0], 1, "c_e = {ce}: one impact");
        // Free flight before and after: the entry normal velocity is v0, the exit one is the
        // final velocity along the normal.
        let v = &out.final_state[N + JX..N + JX + 2];
        let measured = -(v[0] * dir[0] + v[1] * dir[1]) / v0;
        let expected = rk4_restitution(M_JOURNAL, v0, ce, CLEARANCE);
        // Measured agreement ≤ 1e-8 (c_e = 0.6; 3e-10 at 0.3 and 0.9): the run's rtol of
        // 1e-10 and its onset location. 1e-6 keeps a 100-fold margin; c_e in place of c_e² in
        // eq. 3 gives 0.394 instead of 0.327 at c_e = 0.3, dropping (1 − c_e²) 0.304.
        approx::assert_relative_eq!(measured, expected, max_relative = 1e-6);
        // The hybrid law is built so that the restitution is close to c_e: the RK4 reference
        // gives 0.327, 0.577 and 0.896, within 0.03 (a wrong reference, such as an
        // undamped one, would be far off).
        assert!((expected - ce).abs() < 0.03, "c_e = {ce}: {expected}");
    }
}

/// The captured onset velocity (eq. 3's δ̇⁻) of the free-journal scene after a free fall from
/// rest at the bearing centre in the uniform field `g`, and the run's contact onsets.
fn free_fall_onset(g: [f64; 2]) -> (f64, u64) {
    let mut f = free_journal(g, 0.9);
    // 4 rotations of 0.6 ms: the journal reaches the wall at about 2 ms and rebounds for
    // longer than the rest of the run, so the captured value is the first onset's.
    f.run.rotations = 4;
    let scene = f.build().unwrap();
    let mut sim = Simulation::start(&scene).unwrap();
    sim.run_to_end(&Silent).unwrap();
    let captured = sim.state().joints[0].onset_velocity;
    (captured, sim.finish().impacts[0])
}

#[test]
fn onset_velocity_is_the_gap_rate_at_the_root_in_free_fall() {
    // From rest at the centre, the journal falls |e| = |g| t²/2 and touches the wall
    // (δ = |e| − c = 0) at t* = sqrt(2c/|g|), with gap rate δ̇ = |g| t* = sqrt(2c|g|).
    // |g| = 11 m/s²: t* = 1.907 ms falls inside a 10 µs free-flight step (with |g| = 10,
    // t* = 2 ms would coincide with a step end and hide a capture at the step's end).
    let g = [-6.6, -8.8];
    let (captured, impacts) = free_fall_onset(g);
    assert_eq!(impacts, 1);
    let expected = (2.0 * CLEARANCE * g[0].hypot(g[1])).sqrt();
    // Free flight is a quadratic in t, which Dopri5 reproduces to rounding, but the step that
    // crosses the root already feels the contact after it, so its dense output is not exactly
    // the free-flight parabola there; the root is bracketed to 1e-12 s (5e-10 of δ̇).
    // Measured: 3.5e-9; a 30-fold margin. A capture at the start or the end of the step that
    // crosses the root is off by 1.5e-5 and 7.6e-6.
    approx::assert_relative_eq!(captured, expected, max_relative = 1e-7);
}

/// Root and slope at the root of the cubic through the four points `(ts, ds)`, by Newton
/// iterations from `t0` (the cubic is monotone between the samples bracketing the root).
fn cubic_root(ts: &[f64; 4], ds: &[f64; 4], t0: f64) -> (f64, f64) {
    let eval = |x: f64| {
        let (mut v, mut dv) = (0.0, 0.0);
        for a in 0..4 {
            let (mut l, mut dl) = (1.0, 0.0);
            for b in (0..4).filter(|&b| b != a) {
                let den = ts[a] - ts[b];
                dl = dl * (x - ts[b]) / den + l / den;
                l *= (x - ts[b]) / den;
            }
            v += ds[a] * l;
            dv += ds[a] * dl;
        }
        (v, dv)
    };
    let mut x = t0;
    for _ in 0..20 {
        let (v, dv) = eval(x);
        x -= v / dv;
    }
    (x, eval(x).1)
}

#[test]
fn onset_velocity_is_the_gap_rate_at_the_recorded_root() {
    // A slider-crank whose journal flies and impacts (c = 0.5 mm: 17 onsets per rotation).
    let rotations = 3;
    let mut f = standard();
    f.run.rotations = rotations;
    f.run.record_rotations = rotations;
    f.run.record_interval_s = 1e-6;
    f.run.rtol = 1e-10;
    f.run.atol = 1e-13;
    f.run.wear_snapshots.clear();
    f.clearance[0].wear = None;
    f.clearance[0].clearance_mm = 0.5;
    let scene = f.build().unwrap();
    let mut sim = Simulation::start(&scene).unwrap();
    // The captured value is kept until the next onset: after a rotation it is the one of
    // the rotation's last onset.
    let mut captured = Vec::new();
    for _ in 0..rotations {
        sim.advance_rotation().unwrap();
        captured.push(sim.state().joints[0].onset_velocity);
    }
    let out = sim.finish();
    let (t, delta) = (&out.recording.time, &out.recording.joints[0].delta);
    // Onsets seen on the 1 µs grid: the sample before in free flight, the sample after in
    // contact. Seeing all of them means no contact hid between two samples.
    let onsets: Vec<usize> = (1..delta.len())
        .filter(|&i| delta[i - 1] < 0.0 && delta[i] >= 0.0)
        .collect();
    assert_eq!(onsets.len() as u64, out.impacts[0]);
    for (r, captured) in captured.into_iter().enumerate() {
        let end = (r + 1) as f64 * out.period;
        let i = *onsets.iter().rev().find(|&&i| t[i] <= end).unwrap();
        // δ(t) is smooth up to the root and C² across it (the hybrid force grows as δ²):
        // a cubic through the last three free-flight samples and the first in contact
        // gives the root and δ̇ there independently of the run's own root finding.
        let ts = [0, 1, 2, 3].map(|k| t[i - 3 + k] - t[i - 1]);
        let ds = [0, 1, 2, 3].map(|k| delta[i - 3 + k]);
        let (root, rate) = cubic_root(&ts, &ds, 0.0);
        assert!(root > 0.0 && root <= ts[3]);
        // Measured: ≤ 7.9e-7 relative over the three onsets (the run's dense output at rtol
        // 1e-10, sampled every 1 µs; 3.4e-6 at the standard rtol 1e-7). A capture anywhere
        // but at the root (the step's start or end, one step late) is off by δ̈·h or by the
        // contact's deceleration.
        approx::assert_relative_eq!(captured, rate, max_relative = 1e-5);
    }
}

/// Archard coefficient k/H (1/Pa), bearing length L (m) and sector count of a scene's wear.
/// The pressure model is Hertz's line contact, which the tests below write out themselves.
fn wear_of(f: &SceneFile) -> (f64, f64, usize) {
    let w = f.clearance[0].wear.as_ref().expect("a wear model");
    assert_eq!(w.pressure, PressureModel::HertzLine);
    (w.k_over_h_per_pa, w.length_mm * 1e-3, w.sectors)
}

/// Wear of one rotation of the standard joint at crank speed `rpm`, recorded every
/// `interval` s, with steps of at most `max_step` s.
fn worn_run(rpm: f64, interval: f64, max_step: f64) -> (SceneFile, RunOutput) {
    let mut f = standard();
    f.driver.speed_rpm = rpm;
    f.run.rotations = 1;
    f.run.record_rotations = 1;
    f.run.record_interval_s = interval;
    f.run.max_step_s = max_step;
    f.run.wear_snapshots.clear();
    f.run.profile_history_per_rotation = 10;
    let out = simulate(&f.build().unwrap()).unwrap();
    (f, out)
}

/// Angular distance (rad) between two angles, in [0, π].
fn angular_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

#[test]
fn wear_lies_at_the_contact_angles_where_the_journal_pressed() {
    // At 30 r/min inertia is negligible against gravity (Rω² = 0.5 m/s²): the rod's weight
    // presses the journal onto the bottom of the bearing (on the slider, which does not
    // turn), i.e. the contact angles stay around 270 deg, as the paper says (section 6.3).
    let (f, out) = worn_run(-30.0, 2e-5, 1e-4);
    let (k_over_h, length, sectors) = wear_of(&f);
    let (rec, tr) = (&out.recording, &out.recording.joints[0]);
    let depth = &out.final_wear[0];
    let width = TAU / sectors as f64;
    let r_journal = R_BEARING - CLEARANCE;
    let r_star = R_BEARING * r_journal / CLEARANCE;
    // The pressed samples: contact angle θ = atan2(e_y, e_x) of the recorded eccentricity
    // (the slider's frame is the global one), Hertz half-angle b/R_i of the arc (eq. of the
    // Hertz line contact, written here), peak pressure and sliding speed.
    struct Pressed {
        theta: f64,
        half: f64,
        peak: f64,
        speed: f64,
    }
    let pressed: Vec<Pressed> = (0..rec.time.len())
        .filter(|&i| tr.normal_force[i] > 0.0)
        .map(|i| {
            let f_n = tr.normal_force[i];
            let b = (4.0 * f_n * r_star / (PI * length * E_STAR)).sqrt();
            Pressed {
                theta: tr.ey[i].atan2(tr.ex[i]).rem_euclid(TAU),
                half: b / R_BEARING,
                peak: 2.0 * f_n / (PI * b * length),
                speed: tr.sliding_velocity[i].abs(),
            }
        })
        .collect();
    assert!(pressed.len() > rec.time.len() / 2, "mostly in contact");
    let widest = pressed.iter().map(|p| p.half).fold(0.0, f64::max);
    // Every contact angle on the lower half (measured: within 26 deg of 270 deg; rebounds
    // spread them with other restitution or friction laws, so the bound is the half), and
    // the deepest wear at the bottom (measured: the sector at 270.5 deg). A wear convention
    // 180 deg or a quarter turn off, or clockwise, would put it at 90, 0 or 180 deg.
    for p in &pressed {
        assert!(
            angular_distance(p.theta, 1.5 * PI) < 0.5 * PI,
            "contact at {} deg",
            p.theta.to_degrees()
        );
    }
    let deepest = (0..sectors)
        .max_by(|&a, &b| depth[a].total_cmp(&depth[b]))
        .unwrap();
    let deepest_angle = (deepest as f64 + 0.5) * width;
    assert!(
        angular_distance(deepest_angle, 1.5 * PI) < 15f64.to_radians(),
        "deepest wear at {} deg",
        deepest_angle.to_degrees()
    );
    // Support: sector i (centre (i + ½)·width, the convention of wear.rs) gained wear if and
    // only if a pressed contact arc reached it. A sector farther than the widest arc plus a
    // sector from every pressed contact angle has no wear at all; a sector holding a pressed
    // contact angle has wear.
    let reach = widest + width;
    let mut far = 0;
    for (i, &d) in depth.iter().enumerate() {
        let centre = (i as f64 + 0.5) * width;
        let nearest = pressed
            .iter()
            .map(|p| angular_distance(p.theta, centre))
            .fold(PI, f64::min);
        if nearest > reach {
            far += 1;
            assert_eq!(
                d, 0.0,
                "sector {i} ({centre:.3} rad) is {nearest:.3} rad from any contact but worn"
            );
        }
        if nearest < 0.5 * width {
            assert!(d > 0.0, "sector {i} held a pressed contact but has no wear");
        }
    }
    // Measured: 311 of the 360 sectors are far from every contact (the arcs are at most
    // 2.2 deg wide), 43 are worn.
    assert!(far > sectors / 2, "{far} sectors far from contact");
    // Wear never decreases: the profiles saved along the rotation grow sector by sector.
    let mut profiles: Vec<&[f64]> = out.profile_history.iter().map(|(_, p)| &p[0][..]).collect();
    profiles.push(depth);
    assert!(profiles.len() > 5);
    for pair in profiles.windows(2) {
        assert!(pair[0].iter().zip(pair[1]).all(|(a, b)| b >= a));
    }
    // Shape: the profile the recorded contacts imply, eq. 9 per sample, each sample's
    // semi-elliptic Hertz pressure integrated exactly over the sectors its arc covers.
    let dt = rec.time[1] - rec.time[0];
    let primitive = |x: f64| 0.5 * (x * (1.0 - x * x).sqrt() + x.asin());
    let mut expected = vec![0.0; sectors];
    for p in &pressed {
        let scale = k_over_h * p.peak * p.speed * dt * p.half / width;
        let first = ((p.theta - p.half) / width).floor() as isize;
        let last = ((p.theta + p.half) / width).floor() as isize;
        for k in first..=last {
            let edge = |k: isize| ((k as f64 * width - p.theta) / p.half).clamp(-1.0, 1.0);
            expected[k.rem_euclid(sectors as isize) as usize] +=
                scale * (primitive(edge(k + 1)) - primitive(edge(k)));
        }
    }
    let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
    let error = norm(&mut depth.iter().zip(&expected).map(|(a, b)| a - b));
    let size = norm(&mut expected.iter().copied());
    let shifted = norm(&mut (0..sectors).map(|i| expected[(i + 1) % sectors] - expected[i]));
    // Measured: 1.0e-3 relative (the 20 µs recording against the run's step midpoints). The
    // bound is ten times that; the same profile moved by one sector (1 deg) differs by 0.62.
    assert!(
        error < 1e-2 * size,
        "profile differs from the recorded contacts' by {:e} (one-sector shift: {:e})",
        error / size,
        shifted / size
    );
}

#[test]
fn worn_volume_balances_the_archard_integral() {
    let (f, out) = worn_run(-2000.0, 1e-6, 2e-6);
    let (k_over_h, length, sectors) = wear_of(&f);
    // Worn volume: depth × arc length R_i·2π/N × bearing length, summed over the sectors
    // (wear.rs's `area` times L). The Hertz semi-ellipse carries F/L along the arc exactly, so
    // eq. 9 conserves the Archard volume k/H · F · Δs of every step.
    let volume = out.final_wear[0].iter().sum::<f64>() * R_BEARING * TAU / sectors as f64 * length;
    // Eq. 5: V = k/H ∫ F_n |v_t| dt, by the trapezoidal rule on the recording.
    let (t, tr) = (&out.recording.time, &out.recording.joints[0]);
    let power: Vec<f64> = (0..t.len())
        .map(|i| tr.normal_force[i] * tr.sliding_velocity[i].abs())
        .collect();
    let integral: f64 = (1..t.len())
        .map(|i| 0.5 * (power[i - 1] + power[i]) * (t[i] - t[i - 1]))
        .sum();
    // Both sides are quadratures of the same run: the library adds each accepted step's wear
    // at its midpoint (second order in the step: 5.1e-4 at the standard steps, 2.5e-5 at
    // rtol 1e-10), the 1 µs trapezoid is converged (to 4e-8). Measured at steps ≤ 2 µs:
    // 1.0e-5; a tenfold margin.
    approx::assert_relative_eq!(volume, k_over_h * integral, max_relative = 1e-4);
}

/// The fastest time scale of the right-hand side (what the step-limit study reads) against
/// eq. 1-3 linearised by hand: a free journal pressed `δ` into the bottom of its bearing
/// moves normally as `m Δδ̈ = −(∂F/∂δ) Δδ − (∂F/∂δ̇) Δδ̇`, so the Jacobian's eigenvalue of
/// largest modulus is a root of `m λ² + (∂F/∂δ̇) λ + ∂F/∂δ = 0`, the derivatives taken of
/// [`paper_normal_force`], not of the library's law.
#[test]
fn fastest_eigenvalue_in_contact_is_the_linearised_contact_oscillator() {
    let scene = free_journal([0.0, -9.81], 0.9).build().unwrap();
    let m = &scene.mechanism;
    let mut state = m.initial_state();
    for (delta, onset) in [(1e-6, 0.05), (4e-6, 0.01), (2e-7, 0.2)] {
        state.joints[0].onset_velocity = onset;
        let mut y = vec![0.0; m.state_len()];
        y[JX + 1] = -(CLEARANCE + delta);
        y[N + 2] = m.driver.omega;
        let jacobian = m.rhs_jacobian(&state, &mut m.workspace(), 0.0, &y).unwrap();
        let fastest = eigenvalues_by_modulus(&jacobian).unwrap()[0];
        let dr = CLEARANCE;
        let h = 1e-6 * delta;
        let force = |d: f64, v: f64| paper_normal_force(d, v, onset, 0.9, dr);
        let stiffness = (force(delta + h, 0.0) - force(delta - h, 0.0)) / (2.0 * h);
        let damping = (force(delta, 1e-6) - force(delta, -1e-6)) / 2e-6;
        // m λ² + c λ + k = 0: the root of largest modulus (complex when underdamped).
        let (a, b) = (
            -damping / (2.0 * M_JOURNAL),
            damping.powi(2) - 4.0 * M_JOURNAL * stiffness,
        );
        let (re, im) = if b < 0.0 {
            (a, (-b).sqrt() / (2.0 * M_JOURNAL))
        } else {
            (a - b.sqrt() / (2.0 * M_JOURNAL), 0.0)
        };
        let tag = format!("δ = {delta:e} m, onset {onset} m/s: {fastest} vs {re} ± {im}i");
        assert!((fastest.re - re).abs() <= 1e-4 * fastest.norm(), "{tag}");
        assert!(
            (fastest.im.abs() - im).abs() <= 1e-4 * fastest.norm(),
            "{tag}"
        );
    }
}

/// The force the kinematics computes (the hybrid law's (ΔR + δ)^{3/2} from the centres'
/// distance |e|, `ContactLaw::force_spanning`) is [`jointwear::laws::contact::ContactLaw::force`]
/// of the same δ, δ̇ and local clearance, on a worn bearing, to rounding. Fails when the
/// kinematics passes the local clearance c + h as the span instead of |e|: tried.
#[test]
fn the_kinematics_force_is_the_contact_law_of_its_penetration() {
    let mut file = free_journal([0.0, -9.81], 0.9);
    file.clearance[0].wear = Some(jointwear::scene::WearSpec {
        k_over_h_per_pa: 1e-12,
        pressure: PressureModel::HertzLine,
        length_mm: 20.0,
        sectors: 360,
    });
    let scene = file.build().unwrap();
    let m = &scene.mechanism;
    let mut state = m.initial_state();
    state.joints[0].onset_velocity = 0.05;
    // A worn bearing: depths of 0.2-1.8 µm varying round it.
    let sectors = state.joints[0].wear.depths().len();
    let depths: Vec<f64> = (0..sectors)
        .map(|i| 1e-6 * (1.0 + 0.8 * (TAU * i as f64 / sectors as f64).sin()))
        .collect();
    assert!(state.joints[0].wear.set_depths(&depths));
    let cj = &m.clearance_joints[0];
    let mut pressed = 0;
    for k in 0..24 {
        let angle = TAU * k as f64 / 24.0;
        let mut y = vec![0.0; m.state_len()];
        // 3 µm beyond the unworn clearance: in contact wherever the wear is under 3 µm.
        let r = CLEARANCE + 3e-6;
        (y[JX], y[JX + 1]) = (r * angle.cos(), r * angle.sin());
        (y[N + JX], y[N + JX + 1]) = (-0.01 * angle.sin(), 0.02 * angle.cos());
        let n = m.coordinates();
        let cs = m.contact_state(&state, 0, &y[..n], &y[n..2 * n]);
        let law = cj
            .contact
            .force(cs.delta, cs.delta_dot, 0.05, cs.local_clearance);
        approx::assert_relative_eq!(cs.f_n, law, max_relative = 1e-12);
        pressed += usize::from(cs.f_n > 0.0);
    }
    assert_eq!(pressed, 24);
}
