//! What the accepted steps of a standard 40-rotation run look like, per 10 rotations:
//! `cargo run --release --example step_anatomy [-- MEMBER SEED]` (no arguments: the
//! unperturbed default trajectory; else ensemble member MEMBER of seed SEED, as
//! `jointwear run --member MEMBER --seed SEED` runs it).
//!
//! At every accepted step's end it reads the journal's contact (angle θ in the bearing's frame,
//! penetration δ, sliding speed v_t, normal force F_n), the attempts rejected before the step,
//! and the normal velocity δ̇⁻ of the last contact onset, which eq. 3's damping divides by for
//! as long as that contact lasts (floored by the scene's grazing velocity). The wear profile is
//! a Catmull-Rom spline through the sector centres, C¹ only: its second derivative jumps at
//! every centre, so a step over which θ crosses a centre integrates a kink. The table says how
//! often steps cross one, how many rejections such steps and the others see, and how long the
//! steps are; the last line gives the final profile's roughness on the sector scale, the median
//! of |h_(i−1) − 2h_i + h_(i+1)|.

mod common;

use jointwear::analysis::statistics::Distribution;
use jointwear::laws::friction::FrictionModel;
use jointwear::scene::{scene_path, SceneFile};
use std::f64::consts::TAU;

/// Rotations per row of the table.
const WINDOW: usize = 10;

/// What the steps of one window measured.
#[derive(Default)]
struct Window {
    steps: Vec<f64>,
    rejected: u64,
    crossing_steps: u64,
    crossing_rejected: u64,
    angle_moves: Vec<f64>,
    penetrations: Vec<f64>,
    forces: Vec<f64>,
    sticking: u64,
    /// δ̇⁻ held at the window's end (m/s).
    onset_velocity: f64,
    /// Contact onsets of the run up to the window's end.
    onsets: u64,
}

fn median(v: &[f64]) -> f64 {
    Distribution::of(v.iter().copied()).median()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut file = SceneFile::read(scene_path("standard"))?;
    // Eq. 4's stiction velocity: a contact sliding slower is in the law's steep branch.
    let v_s = match file.clearance[0].friction {
        FrictionModel::Modified { v_s, .. } => v_s,
        _ => 0.0,
    };
    file.run.record_rotations = 0;
    let scene = file.build()?;
    let mut sim = common::named_trajectory(&scene)?;
    let m = sim.mechanism().clone();
    let (n, period) = (m.coordinates(), scene.period());
    let width = TAU / sim.state().joints[0].wear.depths().len() as f64;
    let mut y = vec![0.0; m.state_len()];
    let mut windows: Vec<Window> = Vec::new();
    // The contact angle at the last step's end, unwrapped, in sector widths less a half, so
    // that its floor changes where θ crosses a sector centre.
    let mut last: Option<f64> = None;
    // Each contact onset: its number, the driver rotation it fell in, its δ̇⁻.
    let mut onsets: Vec<(u64, usize, f64)> = Vec::new();
    while !sim.is_finished() {
        let (t0, rejected) = (sim.time(), sim.stats().rejected);
        sim.advance_step()?;
        sim.y_into(&mut y);
        let c = m.contact_state(sim.state(), 0, &y[..n], &y[n..2 * n]);
        let k = (t0 / period) as usize / WINDOW;
        if windows.len() <= k {
            windows.resize_with(k + 1, Window::default);
        }
        let w = &mut windows[k];
        let rejected = sim.stats().rejected - rejected;
        w.steps.push(sim.time() - t0);
        w.rejected += rejected;
        let u = c.theta / width - 0.5;
        if let Some(prev) = last {
            // θ wraps at 2π: the move is the shorter way round.
            let turn = TAU / width;
            let du = (u - prev + 0.5 * turn).rem_euclid(turn) - 0.5 * turn;
            if (prev + du).floor() != prev.floor() {
                w.crossing_steps += 1;
                w.crossing_rejected += rejected;
            }
            w.angle_moves.push(du.abs() * width.to_degrees());
        }
        last = Some(u);
        w.penetrations.push(c.delta);
        w.forces.push(c.f_n);
        w.sticking += u64::from(c.in_contact() && c.v_t.abs() < v_s);
        w.onset_velocity = sim.state().joints[0].onset_velocity;
        w.onsets = sim.contact_onsets()[0];
        if onsets.last().map_or(0, |o| o.0) != w.onsets {
            let rotation = (sim.time() / period) as usize + 1;
            onsets.push((w.onsets, rotation, w.onset_velocity));
        }
    }
    let stats = sim.stats();
    println!(
        "{} steps, {} rejected, {} evaluations",
        stats.steps, stats.rejected, stats.evaluations
    );
    println!(
        "rotations | steps | median step (us) | rejected/attempts | steps crossing a centre | \
         rejections per crossing step | per other step | median |dtheta| (deg) | median delta (um) | \
         median F_n (N) | steps in contact below v_s | onset velocity held at the end (mm/s) | onsets so far"
    );
    for (k, w) in windows.iter_mut().enumerate() {
        let steps = w.steps.len() as u64;
        let other = steps - w.crossing_steps;
        println!(
            "{:>3}-{:<3} | {steps:>6} | {:>6.2} | {:.3} | {:.2} | {:.3} | {:.3} | {:.3} | {:.3} | {:.0} | {} | {:.3} | {}",
            k * WINDOW,
            (k + 1) * WINDOW,
            median(&w.steps) * 1e6,
            w.rejected as f64 / (steps + w.rejected) as f64,
            w.crossing_steps as f64 / steps as f64,
            w.crossing_rejected as f64 / w.crossing_steps.max(1) as f64,
            (w.rejected - w.crossing_rejected) as f64 / other.max(1) as f64,
            median(&w.angle_moves),
            median(&w.penetrations) * 1e6,
            median(&w.forces),
            w.sticking,
            w.onset_velocity * 1e3,
            w.onsets,
        );
    }
    for (n, rotation, v) in onsets {
        println!(
            "onset {n} in rotation {rotation}: onset velocity {:.3} mm/s",
            v * 1e3
        );
    }
    let h = sim.state().joints[0].wear.depths();
    let second: Vec<f64> = (0..h.len())
        .map(|i| {
            let at = |j: usize| h[(j + h.len()) % h.len()];
            (at(i + h.len() - 1) - 2.0 * h[i] + at(i + 1)).abs()
        })
        .collect();
    println!(
        "final profile: deepest {:.4} um, median |second difference| {:.3} nm",
        sim.state().joints[0].wear.deepest() * 1e6,
        median(&second) * 1e9
    );
    Ok(())
}
