//! `jointwear animate SCENE`: simulates rotations of a scene from its assembled start and
//! draws them as a looping GIF (`mechanism_<scene>.gif`), the clearance joint's journal orbit
//! magnified in an inset.

use crate::failure::{CliResult, Failure};
use crate::{claim_out, load_variant, scene_stem};
use jointwear::io::plot::render_animation;
use jointwear::simulation::picture::animation_frames;
use jointwear::simulation::simulate;
use jointwear::Error;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Time a frame is shown (ms): 20 frames per second, so 72 frames loop in 3.6 s.
const FRAME_DELAY_MS: u32 = 50;
/// Most frames an animation may have: beyond it the GIF grows past tens of megabytes.
const MAX_FRAMES: usize = 1000;

/// `animate`: `rotations` rotations of the scene at `path` from its assembled start (no
/// settling, no wear snapshots), recorded on the scene's interval and drawn as `frames`
/// evenly spaced frames into `out` (checked and claimed as `run` checks and claims it).
pub fn animate(path: &Path, out: Option<PathBuf>, rotations: u32, frames: usize) -> CliResult<()> {
    // `--rotations` is checked with the scene, as `run.rotations`
    if !(2..=MAX_FRAMES).contains(&frames) {
        let expected = format!("2 to {MAX_FRAMES} frames");
        let e = Error::invalid("--frames", frames, expected);
        return Err(Failure::input(path, e));
    }
    let variant = load_variant(path, &[], Some(rotations), ("animate", out))?;
    let (mut scene, dir) = (variant.scene, variant.dir);
    let _claim = claim_out(path, &dir)?;
    // The animation starts where `check` draws the mechanism: settling would only add
    // rotations nobody sees, and wear snapshots are not drawn.
    scene.run.settle = None;
    scene.run.record_rotations = rotations;
    scene.run.wear_snapshots.clear();
    // Every rotation is recorded here: the scene's own check counted its record_rotations.
    scene
        .check_recording(true)
        .map_err(|e| Failure::input(path, e))?;
    let started = Instant::now();
    let run = simulate(&scene).map_err(|e| Failure::from(path, e))?;
    let simulated = started.elapsed().as_secs_f64();
    let pictures = animation_frames(&scene, &run.recording, frames);
    let gif = dir.join(format!("mechanism_{}.gif", scene_stem(path)));
    render_animation(&gif, &pictures, FRAME_DELAY_MS).map_err(|e| Failure::from(path, e))?;
    println!(
        "wrote {} ({} frames; simulated in {simulated:.1} s, drawn in {:.1} s)",
        gif.display(),
        pictures.len(),
        started.elapsed().as_secs_f64() - simulated
    );
    Ok(())
}
