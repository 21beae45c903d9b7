//! `jointwear check SCENE`: validates a scene, prints what it describes and the pose it
//! assembles to, noting bodies that may have closed on another branch of their loop.

use crate::failure::{CliResult, Failure};
use jointwear::scene::SceneFile;
use jointwear::simulation::Scene;
use std::path::Path;

/// `check`: reads and builds the scene at `path` and prints its bodies, joints, driver, run
/// settings, degrees of freedom and assembled pose.
pub fn check(path: &Path) -> CliResult<()> {
    let file = SceneFile::read(path).map_err(|e| Failure::input(path, e))?;
    let scene = file.build().map_err(|e| Failure::from(path, e))?;
    let m = &scene.mechanism;
    println!("{}: {}", path.display(), scene.title);
    println!("bodies:");
    for b in &file.bodies {
        println!(
            "  {:12} mass {} kg, inertia {} kg m², points {}",
            b.name,
            b.mass_kg,
            b.inertia_kg_m2,
            b.points_mm.keys().cloned().collect::<Vec<_>>().join(", ")
        );
    }
    println!("ideal joints:");
    for r in &file.revolute {
        println!("  revolute       {} - {}", r.a, r.b);
    }
    for t in &file.translational {
        println!(
            "  translational  {} along {} at {} deg",
            t.a, t.b, t.axis_deg
        );
    }
    let d = &file.driver;
    println!(
        "driver: {} at {} r/min from {} deg",
        d.body, d.speed_rpm, d.angle_deg
    );
    println!("clearance joints:");
    for c in &file.clearance {
        println!(
            "  {}: journal {} in bearing {}, R = {} mm, c = {} mm, {} on {}",
            c.name,
            c.journal,
            c.bearing,
            c.bearing_radius_mm,
            c.clearance_mm,
            c.journal_material,
            c.bearing_material
        );
        let k = &c.contact;
        println!(
            "    contact {:?}, restitution {}, exponent {}; friction {:?}",
            k.model, k.restitution, k.exponent, c.friction
        );
        match &c.wear {
            Some(w) => println!(
                "    wear: k/H = {:e} 1/Pa, {:?} pressure, L = {} mm, {} sectors",
                w.k_over_h_per_pa, w.pressure, w.length_mm, w.sectors
            ),
            None => println!("    no wear"),
        }
    }
    let r = &file.run;
    println!(
        "run: {} rotations ({} recorded every {} s), {:?}, rtol {:e}, atol {:e}, max step {:e} s",
        r.rotations,
        r.record_rotations,
        r.record_interval_s,
        r.method,
        r.rtol,
        r.atol,
        r.max_step_s
    );
    let dof = m.coordinates() as i64 - m.constraint_count() as i64;
    println!(
        "degrees of freedom: {dof} (2 per clearance joint; {} with the clearance joints ideal)",
        dof - 2 * m.clearance_joints.len() as i64
    );
    print_assembly(path, &scene)
}

/// Turn (deg) between a body's guessed and assembled angle beyond which `check` says the
/// loop may have closed on another branch than the guess meant.
const BRANCH_TURN_DEG: f64 = 30.0;

/// Assembles `scene` at t = 0 as a run does and prints every body's pose, noting bodies
/// assembled far from their guessed angle (another branch of the loop, e.g. elbow down).
fn print_assembly(path: &Path, scene: &Scene) -> CliResult<()> {
    let y = (scene.mechanism.assemble(&scene.guess)).map_err(|e| Failure::from(path, e))?;
    println!("assembled pose at t = 0 (clearance joints centred):");
    for (i, b) in scene.mechanism.bodies().iter().enumerate() {
        let (x, y, angle) = (y[3 * i], y[3 * i + 1], y[3 * i + 2].to_degrees());
        println!(
            "  {:12} x {:10.4} mm, y {:10.4} mm, angle {:9.3} deg",
            b.name,
            x * 1e3,
            y * 1e3,
            angle
        );
        let turn = (angle - scene.guess[3 * i + 2].to_degrees() + 180.0).rem_euclid(360.0) - 180.0;
        if turn.abs() > BRANCH_TURN_DEG {
            println!(
                "    note: {turn:.1} deg from its guessed angle: the loop may have closed on \
                 another branch (elbow up/down) than the guess meant"
            );
        }
    }
    Ok(())
}
