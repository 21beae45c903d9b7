//! Pictures of a scene's mechanism: a pose, or the frames of a recorded run, as the plain
//! geometry in millimetres that [`crate::io::plot::render_mechanism`] and
//! [`crate::io::plot::render_animation`] draw.
//!
//! This is the one place that knows both the mechanism's types and the picture's: a body is
//! drawn through the points its joints use (the named points of a scene are the points its
//! joints name), as a line for two points, a closed outline around their centroid for more, and
//! a block (a slider) when they coincide.

use nalgebra::{Rotation2, Vector2};

use super::{Recording, Scene};
use crate::io::plot::{BodyShape, ClearanceShape, Guide, MechanismPicture, Point};
use crate::mechanism::{BodyPoint, Mechanism};

/// Two points of a body closer than this (m) are one point.
const SAME_POINT: f64 = 1e-9;
/// Half-length of a one-point body's block, as a fraction of the longest body.
const BLOCK_FRACTION: f64 = 0.05;
/// Half-length of a one-point body's block around a clearance bearing, in bearing radii.
const BLOCK_BEARINGS: f64 = 1.5;

/// World position (mm) of `p` at coordinates `q` (m, rad).
fn world(m: &Mechanism, q: &[f64], p: &BodyPoint) -> Point {
    let (r, phi) = m.pose(q, p.body);
    let w = (r + Rotation2::new(phi) * p.local) * 1e3;
    (w.x, w.y)
}

/// Every body point the joints use, with the clearance joints' bearing radius (0 elsewhere).
fn joint_points(m: &Mechanism) -> Vec<(&BodyPoint, f64)> {
    let revolutes = m.revolutes.iter().flat_map(|j| [(&j.a, 0.0), (&j.b, 0.0)]);
    let sliders = m
        .translationals
        .iter()
        .flat_map(|j| [(&j.a, 0.0), (&j.b, 0.0)]);
    let clearance = m
        .clearance_joints
        .iter()
        .flat_map(|j| [(&j.journal, j.r_bearing), (&j.bearing, j.r_bearing)]);
    revolutes.chain(sliders).chain(clearance).collect()
}

/// The distinct local points (m) of body `i` among `joints` ([`joint_points`]), and the
/// largest bearing radius among them.
fn body_points(joints: &[(&BodyPoint, f64)], i: usize) -> (Vec<Vector2<f64>>, f64) {
    let mut points: Vec<Vector2<f64>> = Vec::new();
    let mut radius = 0f64;
    for (p, r) in joints.iter().filter(|(p, _)| p.body == Some(i)) {
        radius = radius.max(*r);
        if points.iter().all(|q| (q - p.local).norm() > SAME_POINT) {
            points.push(p.local);
        }
    }
    (points, radius)
}

/// The local outline (m) of a body through its distinct `points`, with the largest bearing
/// `radius` among them: a line, a closed polygon, or a block (module doc).
fn local_outline(mut points: Vec<Vector2<f64>>, radius: f64, longest: f64) -> Vec<Vector2<f64>> {
    match points.len() {
        0 => Vec::new(),
        1 => {
            let half = (BLOCK_BEARINGS * radius).max(BLOCK_FRACTION * longest);
            let c = points[0];
            [
                (-1.0, -0.6),
                (1.0, -0.6),
                (1.0, 0.6),
                (-1.0, 0.6),
                (-1.0, -0.6),
            ]
            .map(|(u, v)| c + Vector2::new(u, v) * half)
            .to_vec()
        }
        2 => points,
        n => {
            let centre = points.iter().sum::<Vector2<f64>>() / n as f64;
            let angle = |p: &Vector2<f64>| (p.y - centre.y).atan2(p.x - centre.x);
            points.sort_by(|a, b| angle(a).total_cmp(&angle(b)));
            points.push(points[0]);
            points
        }
    }
}

/// What a picture of a mechanism keeps from pose to pose: each body's local outline (m) and
/// legend entry, built once for all the frames of an animation.
struct Outlines {
    local: Vec<Vec<Vector2<f64>>>,
    labels: Vec<String>,
}

impl Outlines {
    fn of(m: &Mechanism) -> Outlines {
        let joints = joint_points(m);
        let n = m.bodies().len();
        let points: Vec<(Vec<Vector2<f64>>, f64)> =
            (0..n).map(|i| body_points(&joints, i)).collect();
        let longest = (points.iter())
            .flat_map(|(p, _)| {
                p.iter()
                    .flat_map(move |a| p.iter().map(move |b| (a - b).norm()))
            })
            .fold(0f64, f64::max);
        Outlines {
            local: (points.into_iter())
                .map(|(p, radius)| local_outline(p, radius, longest))
                .collect(),
            labels: (0..n).map(|i| body_label(m, i)).collect(),
        }
    }
}

/// The legend entry of body `i`: its name, and for the driven body its speed and sense.
fn body_label(m: &Mechanism, i: usize) -> String {
    let name = &m.bodies()[i].name;
    if m.driver.body != i {
        return name.clone();
    }
    let rpm = m.driver.speed_rpm;
    let sense = if rpm < 0.0 { "cw" } else { "ccw" };
    format!("{name} (driver, {} r/min {sense})", rpm.abs())
}

/// The picture of the mechanism at coordinates `q` (m, rad), without title or note; clearance
/// joints carry no orbit.
pub fn pose_picture(m: &Mechanism, q: &[f64]) -> MechanismPicture {
    posed(&Outlines::of(m), m, q)
}

/// [`pose_picture`] with the mechanism's `outlines` built beforehand.
fn posed(outlines: &Outlines, m: &Mechanism, q: &[f64]) -> MechanismPicture {
    let bodies = (outlines.local.iter().zip(&outlines.labels).enumerate())
        .map(|(i, (local, label))| {
            let (r, phi) = m.pose(q, Some(i));
            let outline = local
                .iter()
                .map(|p| (r + Rotation2::new(phi) * p) * 1e3)
                .map(|w| (w.x, w.y))
                .collect();
            BodyShape {
                label: label.clone(),
                outline,
            }
        })
        .collect();
    let ground = joint_points(m)
        .into_iter()
        .filter(|(p, _)| p.body.is_none())
        .map(|(p, _)| world(m, q, p))
        .fold(Vec::new(), |mut v: Vec<Point>, p| {
            if !v.contains(&p) {
                v.push(p);
            }
            v
        });
    let guides = m
        .translationals
        .iter()
        .map(|t| {
            let (_, phi) = m.pose(q, t.b.body);
            let d = Rotation2::new(phi) * Vector2::new(-t.normal.y, t.normal.x);
            Guide {
                through: world(m, q, &t.b),
                direction: (d.x, d.y),
            }
        })
        .collect();
    let clearance = m
        .clearance_joints
        .iter()
        .map(|j| ClearanceShape {
            name: j.name.clone(),
            bearing: world(m, q, &j.bearing),
            journal: world(m, q, &j.journal),
            r_bearing: j.r_bearing * 1e3,
            r_journal: j.r_journal * 1e3,
            orbit: Vec::new(),
        })
        .collect();
    MechanismPicture {
        bodies,
        ground,
        pins: m.revolutes.iter().map(|r| world(m, q, &r.a)).collect(),
        guides,
        clearance,
        ..Default::default()
    }
}

/// `frames` pictures evenly spaced over the samples of `rec` (a recording of `scene`), each
/// titled with the scene's title and noting its time and driver angle, every clearance joint
/// with its orbit from the first sample up to the frame's.
pub fn animation_frames(scene: &Scene, rec: &Recording, frames: usize) -> Vec<MechanismPicture> {
    let m = &scene.mechanism;
    let outlines = Outlines::of(m);
    let samples = rec.time.len();
    let frames = frames.min(samples);
    (0..frames)
        .map(|f| {
            let k = f * samples / frames;
            let q: Vec<f64> = rec
                .positions
                .iter()
                .flat_map(|body| [body[0][k], body[1][k], body[2][k]])
                .collect();
            let mut picture = posed(&outlines, m, &q);
            for (shape, trace) in picture.clearance.iter_mut().zip(&rec.joints) {
                shape.orbit = (0..=k)
                    .map(|s| (trace.ex[s] * 1e3, trace.ey[s] * 1e3))
                    .collect();
            }
            picture.title = scene.title.clone();
            picture.note = format!(
                "t = {:.2} ms, {} at {:.0}°",
                rec.time[k] * 1e3,
                m.bodies()[m.driver.body].name,
                rec.driver_angle[k].to_degrees().rem_euclid(360.0)
            );
            picture
        })
        .collect()
}
