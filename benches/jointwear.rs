//! Criterion benches of the hot paths, all on the shipped standard scene:
//! contact force per normal-force model, friction per law, one right-hand side, one crank
//! rotation, the 40-rotation coupled wear run of figure 6, its 16-member ensemble, and the
//! whole `jointwear run` process of that run (start-up, outputs and PNGs included).
//!
//! `cargo bench`, then `cargo run --release --bin bench_summary` writes `data/benchmarks.csv`.

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode};
use jointwear::io::progress::Silent;
use jointwear::laws::contact::NormalForceModel;
use jointwear::laws::friction::FrictionModel;
use jointwear::scene::{scene_path, SceneFile};
use jointwear::simulation::ensemble::{run, EnsembleSettings};
use jointwear::simulation::simulate;
use jointwear::simulation::Scene;
use std::hint::black_box;
use std::time::Duration;

fn standard() -> SceneFile {
    SceneFile::read(scene_path("standard")).expect("standard scene")
}

fn build(file: &SceneFile) -> Scene {
    file.build().expect("valid scene")
}

/// The standard scene as figure 6 runs it (no time series), over `rotations` rotations.
fn wear_run(rotations: u32) -> Scene {
    let mut f = standard();
    f.run.rotations = rotations;
    f.run.record_rotations = 0;
    f.run.wear_snapshots.retain(|&r| r <= rotations);
    build(&f)
}

/// A typical contact of the standard joint: 1 µm penetration, closing at 1 cm/s.
const DELTA: f64 = 1e-6;
const DELTA_DOT: f64 = 1e-2;
const IMPACT_VELOCITY: f64 = 0.1;

fn contact_force(c: &mut Criterion) {
    let mut group = c.benchmark_group("contact_force");
    for (name, model) in [
        ("hybrid", NormalForceModel::Hybrid),
        ("lankarani-nikravesh", NormalForceModel::LankaraniNikravesh),
    ] {
        let mut f = standard();
        f.clearance[0].contact.model = Some(model);
        let scene = build(&f);
        let cj = &scene.mechanism.clearance_joints[0];
        let (law, dr) = (cj.contact, cj.r_bearing - cj.r_journal);
        group.bench_function(name, |b| {
            b.iter(|| {
                law.force(
                    black_box(DELTA),
                    black_box(DELTA_DOT),
                    black_box(IMPACT_VELOCITY),
                    black_box(dr),
                )
            })
        });
    }
    group.finish();
}

fn friction(c: &mut Criterion) {
    let scene = build(&standard());
    let modified = scene.mechanism.clearance_joints[0].friction;
    let FrictionModel::Modified { mu_d, v_s, v_d, .. } = modified else {
        panic!("the standard scene uses the modified friction law");
    };
    let mut group = c.benchmark_group("friction");
    // Between V_s and V_d: the branch with the cosine, the dearest one.
    let v = 0.5 * (v_s + v_d);
    for (name, law) in [
        ("modified", modified),
        ("coulomb", FrictionModel::Coulomb { mu: mu_d }),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| black_box(law).force(black_box(40.0), black_box(v)))
        });
    }
    group.finish();
}

fn rhs(c: &mut Criterion) {
    // The state at the end of the first whole rotation where the journal presses on the
    // bearing, so the evaluation includes the contact and friction forces.
    let (scene, out) = (1..=20)
        .map(|rotations| {
            let scene = wear_run(rotations);
            let out = simulate(&scene).expect("rotations of the standard scene");
            (scene, out)
        })
        .find(|(scene, out)| {
            let (m, y) = (&scene.mechanism, &out.final_state);
            let n = m.coordinates();
            m.contact_state(&m.initial_state(), 0, &y[..n], &y[n..2 * n])
                .f_n
                > 0.0
        })
        .expect("the journal touches the bearing at the end of some rotation");
    let mechanism = &scene.mechanism;
    let (state, mut ws) = (mechanism.initial_state(), mechanism.workspace());
    let y = out.final_state;
    let mut dy = vec![0.0; y.len()];
    let t = out.period;
    // What a run integrates (joint coordinates: the scene is a tree), and the absolute
    // formulation at the same state.
    let z = mechanism.ode_state(&y);
    let mut dz = vec![0.0; z.len()];
    let mut group = c.benchmark_group("rhs");
    group.bench_function("standard", |b| {
        b.iter(|| {
            mechanism
                .ode_rhs(&state, &mut ws, black_box(t), black_box(&z), &mut dz)
                .expect("rhs");
            black_box(&dz);
        })
    });
    group.bench_function("standard_absolute", |b| {
        b.iter(|| {
            mechanism
                .rhs(&state, &mut ws, black_box(t), black_box(&y), &mut dy)
                .expect("rhs");
            black_box(&dy);
        })
    });
    group.finish();
}

/// Whole runs take milliseconds to a second: flat sampling (the same iteration count in
/// every sample) keeps the 40-rotation bench near `samples` runs instead of 55 of them.
fn runs(c: &mut Criterion) {
    for (group, name, rotations, samples) in [
        ("rotation", "standard", 1, 20),
        ("wear_run", "standard_40", 40, 10),
    ] {
        let scene = wear_run(rotations);
        let mut group = c.benchmark_group(group);
        group
            .sampling_mode(SamplingMode::Flat)
            .sample_size(samples)
            .measurement_time(Duration::from_secs(10));
        group.bench_function(name, |b| {
            b.iter(|| simulate(black_box(&scene)).expect("run"))
        });
        group.finish();
    }
    // 16 members of the 40-rotation run in parallel on every core.
    let scene = wear_run(40);
    let settings = EnsembleSettings {
        members: 16,
        seed: 1,
        ..EnsembleSettings::default()
    };
    let mut group = c.benchmark_group("ensemble");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .measurement_time(Duration::from_secs(20));
    group.bench_function("standard_40x16", |b| {
        b.iter(|| {
            run(black_box(&scene), &settings, |_, o| o.final_wear, &Silent).expect("ensemble")
        })
    });
    group.finish();
}

fn quick() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(30)
}

/// The whole program as a user starts it: `jointwear run` of the standard scene without a
/// time series (the wear CSVs, README.txt, summary.json and two PNGs are written), the
/// process started and waited for in every iteration. Cargo builds the program for benches.
fn process(c: &mut Criterion) {
    let out = std::env::temp_dir().join(format!("jointwear-bench-{}", std::process::id()));
    let scene = scene_path("standard");
    let mut group = c.benchmark_group("process");
    group
        .sampling_mode(SamplingMode::Flat)
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    group.bench_function("run_standard_40", |b| {
        b.iter(|| {
            let status = std::process::Command::new(env!("CARGO_BIN_EXE_jointwear"))
                .arg("run")
                .arg(&scene)
                .args(["--set", "run.record_rotations=0", "--out"])
                .arg(&out)
                .stdout(std::process::Stdio::null())
                .status()
                .expect("jointwear starts");
            assert!(status.success(), "jointwear run failed: {status}");
        })
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&out);
}

criterion_group! {
    name = benches;
    config = quick();
    targets = contact_force, friction, rhs, runs, process
}
criterion_main!(benches);
