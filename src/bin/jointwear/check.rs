//! `jointwear check SCENE`: validates a scene, prints what it describes and the pose it
//! assembles to, noting bodies that may have closed on another branch of their loop, turns
//! the driver through one rotation to find where the loop cannot close (bad input, which every
//! command that simulates refuses too: `Simulation::new`), and
//! draws the assembled pose (`mechanism_<scene>.png`).

use crate::failure::{CliResult, Failure};
use crate::{checked_out_dir, claim_out, scene_stem};
use jointwear::io::format::{exact as given, turn_deg};
use jointwear::io::plot::render_mechanism;
use jointwear::mechanism::SWEEP_STEP_DEG;
use jointwear::scene::{spelling, ContactSpec, SceneFile};
use jointwear::simulation::picture::pose_picture;
use jointwear::simulation::Scene;
use std::path::{Path, PathBuf};

/// `check`: reads and builds the scene at `path`, prints its bodies, joints, driver, run
/// settings, degrees of freedom and assembled pose, draws the pose into `out`
/// ([`checked_out_dir`], claimed while `check` runs: [`claim_out`]), and fails (bad input) if the driver cannot turn a whole rotation
/// ([`jointwear::mechanism::Mechanism::check_rotation`]).
pub fn check(path: &Path, out: Option<PathBuf>) -> CliResult<()> {
    let file = SceneFile::read(path).map_err(|e| Failure::input(path, e))?;
    let scene = file.build().map_err(|e| Failure::from(path, e))?;
    let dir = checked_out_dir(path, "check", out)?;
    // Another check of the same scene may draw into this folder: claimed as runs claim theirs.
    let _claim = claim_out(path, &dir)?;
    let m = &scene.mechanism;
    println!("{}: {}", path.display(), scene.title);
    // The scene's own values and words, each number as the file gives it.
    println!("bodies:");
    for b in &file.bodies {
        println!(
            "  {:12} mass {} kg, inertia {} kg m², points {}",
            b.name,
            given(b.mass_kg),
            given(b.inertia_kg_m2),
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
            t.a,
            t.b,
            given(t.axis_deg)
        );
    }
    let d = &file.driver;
    println!(
        "driver: {} at {} r/min from {} deg",
        d.body,
        given(d.speed_rpm),
        given(d.angle_deg)
    );
    println!("clearance joints:");
    for c in &file.clearance {
        println!(
            "  {}: journal {} in bearing {}, R = {} mm, c = {} mm, {} on {}",
            c.name,
            c.journal,
            c.bearing,
            given(c.bearing_radius_mm),
            given(c.clearance_mm),
            c.journal_material,
            c.bearing_material
        );
        println!(
            "    contact = {}{}",
            spelling(&c.contact),
            model_laws(&c.contact)
        );
        println!("    friction = {}", spelling(&c.friction));
        match &c.wear {
            Some(w) => println!("    wear = {}", spelling(w)),
            None => println!("    no wear"),
        }
    }
    let r = &file.run;
    // A settling run simulates its settling rotations first (they wear too).
    let settling = scene.run.settle.map_or(String::new(), |s| {
        format!(" after settling (up to {} rotations)", s.max_rotations)
    });
    println!(
        "run: {} rotations{settling} ({} recorded every {} s), method {}, rtol {}, atol {}, max \
         step {} s",
        r.rotations,
        r.record_rotations,
        given(r.record_interval_s),
        spelling(&r.method),
        given(r.rtol),
        given(r.atol),
        given(r.max_step_s)
    );
    let dof = m.degrees_of_freedom();
    println!(
        "degrees of freedom: {dof} (2 per clearance joint; {} with the clearance joints ideal)",
        dof - 2 * m.clearance_joints.len() as i64
    );
    println!("integrated in {}", m.formulation());
    let (q, far) = print_assembly(path, &scene)?;
    let lock = m
        .check_rotation(0.0, &q)
        .map_err(|e| Failure::from(path, e))?;
    if lock.is_none() {
        println!(
            "one driver rotation: the ideal loop closes at every driver angle (every \
             {SWEEP_STEP_DEG} deg)"
        );
    }
    let mut picture = pose_picture(m, &q);
    picture.title = scene.title.clone();
    // the branch on a line of its own: a note of several bodies is long
    picture.note = format!("t = 0, clearance joints centred\n{}", branch_note(&far));
    let png = dir.join(format!("mechanism_{}.png", scene_stem(path)));
    render_mechanism(&png, &picture).map_err(|e| Failure::from(path, e))?;
    println!(
        "drew {}: {}",
        png.display(),
        picture.note.replace('\n', "; ")
    );
    // Drawn first: the pose at the start shows which links cannot reach.
    match lock {
        Some(lock) => Err(Failure::from(path, lock.error())),
        None => Ok(()),
    }
}

/// The two catalogue laws a contact `model` stands for, e.g. ` (stiffness "hybrid",
/// dissipation "zhiying-qishao")`; empty for a scene that names its laws itself.
fn model_laws(k: &ContactSpec) -> String {
    k.model.map_or_else(String::new, |m| {
        let (s, d) = m.laws();
        format!(
            " (stiffness \"{}\", dissipation \"{}\")",
            s.name(),
            d.name()
        )
    })
}

/// A body assembled far from its guessed angle: its name and turn from the guess (deg).
type FarBody = (String, f64);

/// What the picture says of the branch: the bodies assembled far from their guessed angle,
/// or that there are none.
fn branch_note(far: &[FarBody]) -> String {
    let turns: Vec<String> = far
        .iter()
        .enumerate()
        .map(|(k, (name, turn))| {
            let verb = if k == 0 { " assembled" } else { "" };
            format!("{name}{verb} {:.0}°", turn.abs())
        })
        .collect();
    match far.len() {
        0 => "assembled on the guessed branch".into(),
        1 => format!("{} from its guess: other branch", turns[0]),
        _ => format!("{} from their guesses: other branch", turns.join(", ")),
    }
}

/// Turn (deg) between a body's guessed and assembled angle beyond which `check` says the
/// loop may have closed on another branch than the guess meant.
const BRANCH_TURN_DEG: f64 = 30.0;

/// Assembles `scene` at t = 0 as a run does and prints every body's pose, noting bodies
/// assembled far from their guessed angle (another branch of the loop, e.g. elbow down).
/// Returns the assembled state and those bodies with their turn from the guess (deg).
fn print_assembly(path: &Path, scene: &Scene) -> CliResult<(Vec<f64>, Vec<FarBody>)> {
    let q = (scene.mechanism.assemble(&scene.guess)).map_err(|e| Failure::from(path, e))?;
    let mut far = Vec::new();
    println!("assembled pose at t = 0 (clearance joints centred):");
    for (i, b) in scene.mechanism.bodies().iter().enumerate() {
        let (x, y, angle) = (q[3 * i], q[3 * i + 1], q[3 * i + 2].to_degrees());
        println!(
            "  {:12} x {:10.4} mm, y {:10.4} mm, angle {:9.3} deg",
            b.name,
            x * 1e3,
            y * 1e3,
            turn_deg(angle)
        );
        let turn = turn_deg(angle - scene.guess[3 * i + 2].to_degrees());
        if turn.abs() > BRANCH_TURN_DEG {
            println!(
                "    note: {turn:.1} deg from its guessed angle: the loop may have closed on \
                 another branch (elbow up/down) than the guess meant"
            );
            far.push((b.name.clone(), turn));
        }
    }
    Ok((q, far))
}
