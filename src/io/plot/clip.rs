//! Clipping of lines and bands to the visible ranges of a chart. Plotters maps coordinates
//! outside a chart's ranges to pixels outside its plotting area and draws them there (over
//! the tick labels, or across an inset's frame), so everything drawn is cut to the ranges
//! first: polylines into the runs that lie inside (Liang-Barsky, per segment), polygons into
//! the part inside (Sutherland-Hodgman).

/// A rectangle of data coordinates: `(x_lo, x_hi, y_lo, y_hi)`.
pub(super) type Rect = (f64, f64, f64, f64);

/// The part of segment `p`-`q` inside `r`, if any (Liang-Barsky).
fn clip_segment(p: (f64, f64), q: (f64, f64), r: Rect) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (den, num) in [
        (-dx, p.0 - r.0),
        (dx, r.1 - p.0),
        (-dy, p.1 - r.2),
        (dy, r.3 - p.1),
    ] {
        if den == 0.0 {
            if num < 0.0 {
                return None;
            }
        } else {
            let t = num / den;
            if den < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then(|| {
        let at = |t: f64| (p.0 + t * dx, p.1 + t * dy);
        (at(t0), at(t1))
    })
}

/// Whether `p` lies in `r`.
pub(super) fn inside(p: (f64, f64), r: Rect) -> bool {
    (r.0..=r.1).contains(&p.0) && (r.2..=r.3).contains(&p.1)
}

/// The runs of the polyline `points` that lie inside `r`.
pub(super) fn clip_polyline(points: &[(f64, f64)], r: Rect) -> Vec<Vec<(f64, f64)>> {
    if points.len() == 1 {
        return if inside(points[0], r) {
            vec![points.to_vec()]
        } else {
            Vec::new()
        };
    }
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    for w in points.windows(2) {
        match clip_segment(w[0], w[1], r) {
            Some((a, b)) => {
                if current.last() != Some(&a) {
                    if !current.is_empty() {
                        runs.push(std::mem::take(&mut current));
                    }
                    current.push(a);
                }
                current.push(b);
                if b != w[1] {
                    runs.push(std::mem::take(&mut current));
                }
            }
            None => {
                if !current.is_empty() {
                    runs.push(std::mem::take(&mut current));
                }
            }
        }
    }
    if !current.is_empty() {
        runs.push(current);
    }
    runs
}

/// The part of the closed polygon `points` inside `r` (Sutherland-Hodgman).
pub(super) fn clip_polygon(points: &[(f64, f64)], r: Rect) -> Vec<(f64, f64)> {
    type Edge = (
        fn((f64, f64), f64) -> bool,
        fn((f64, f64), (f64, f64), f64) -> (f64, f64),
    );
    let x_at = |p: (f64, f64), q: (f64, f64), x: f64| {
        let t = (x - p.0) / (q.0 - p.0);
        (x, p.1 + t * (q.1 - p.1))
    };
    let y_at = |p: (f64, f64), q: (f64, f64), y: f64| {
        let t = (y - p.1) / (q.1 - p.1);
        (p.0 + t * (q.0 - p.0), y)
    };
    let edges: [(Edge, f64); 4] = [
        ((|p, v| p.0 >= v, x_at), r.0),
        ((|p, v| p.0 <= v, x_at), r.1),
        ((|p, v| p.1 >= v, y_at), r.2),
        ((|p, v| p.1 <= v, y_at), r.3),
    ];
    let mut poly = points.to_vec();
    for ((keep, cut), v) in edges {
        if poly.is_empty() {
            break;
        }
        let mut out = Vec::with_capacity(poly.len() + 4);
        for i in 0..poly.len() {
            let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
            match (keep(p, v), keep(q, v)) {
                (true, true) => out.push(q),
                (true, false) => out.push(cut(p, q, v)),
                (false, true) => {
                    out.push(cut(p, q, v));
                    out.push(q);
                }
                (false, false) => {}
            }
        }
        poly = out;
    }
    poly
}

/// `points` split at every turn sharper than 120° of its path in pixels (`px` maps a point to
/// the pixel plotters draws it at), the turning point ending one piece and starting the next.
/// Plotters fills a line wider than a pixel as one polygon with mitred joins, and a joint's
/// inner corner lies half a width over sin(θ/2) from it (θ the angle the path turns back by,
/// its interior angle): unbounded as a path doubles back, so a curve that reverses (the
/// work-precision lines, whose rtol order is not their evaluation order) drew a long thin
/// sliver past its turn. At 120° or less the corner stays within a width; a cut joint shows the
/// pieces' square ends. Pixels repeated in a row count once, as plotters draws them.
pub(super) fn split_at_sharp_turns(
    points: &[(f64, f64)],
    px: impl Fn((f64, f64)) -> (i32, i32),
) -> Vec<Vec<(f64, f64)>> {
    let mut pieces = vec![Vec::new()];
    // The last two distinct pixels of the current piece.
    let (mut before, mut last) = (None::<(i32, i32)>, None::<(i32, i32)>);
    for &p in points {
        let here = px(p);
        if last == Some(here) {
            pieces.last_mut().expect("a piece").push(p);
            continue;
        }
        if let (Some(a), Some(b)) = (before, last) {
            let (u, v) = (
                (f64::from(b.0 - a.0), f64::from(b.1 - a.1)),
                (f64::from(here.0 - b.0), f64::from(here.1 - b.1)),
            );
            // cos of the turn below −1/2: sharper than 120°.
            let dot = u.0 * v.0 + u.1 * v.1;
            if 2.0 * dot < -(u.0.hypot(u.1) * v.0.hypot(v.1)) {
                let joint = *pieces.last().and_then(|p| p.last()).expect("a joint");
                pieces.push(vec![joint]);
            }
        }
        pieces.last_mut().expect("a piece").push(p);
        (before, last) = (last, Some(here));
    }
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_leaving_and_reentering_the_box_becomes_two_runs() {
        let r = (0.0, 1.0, 0.0, 1.0);
        let runs = clip_polyline(&[(0.5, 0.5), (0.5, 2.0), (0.8, 0.5)], r);
        assert_eq!(runs.len(), 2);
        assert_eq!(runs[0], vec![(0.5, 0.5), (0.5, 1.0)]);
        assert_eq!(runs[1].last(), Some(&(0.8, 0.5)));
        assert!(clip_polyline(&[(2.0, 2.0), (3.0, 3.0)], r).is_empty());
    }

    #[test]
    fn a_polygon_is_cut_at_the_box() {
        let square = [(-1.0, -1.0), (2.0, -1.0), (2.0, 2.0), (-1.0, 2.0)];
        let cut = clip_polygon(&square, (0.0, 1.0, 0.0, 1.0));
        assert_eq!(cut.len(), 4);
        assert!(cut.iter().all(|&p| inside(p, (0.0, 1.0, 0.0, 1.0))));
    }

    /// A path that doubles back is cut at the turn, a gentle bend and repeated pixels are
    /// not; the pieces share the turning point.
    #[test]
    fn a_path_is_cut_where_it_turns_back() {
        let px = |p: (f64, f64)| (p.0.round() as i32, p.1.round() as i32);
        let zigzag = [(0.0, 0.0), (10.0, 0.0), (10.2, 0.0), (0.0, 1.0), (0.0, 9.0)];
        let pieces = split_at_sharp_turns(&zigzag, px);
        assert_eq!(
            pieces,
            vec![
                vec![(0.0, 0.0), (10.0, 0.0), (10.2, 0.0)],
                vec![(10.2, 0.0), (0.0, 1.0), (0.0, 9.0)],
            ]
        );
        // 90° and 120° turns keep their joints.
        let bends = [
            (0.0, 0.0),
            (10.0, 0.0),
            (10.0, 10.0),
            (10.0 - 75f64.sqrt(), 5.0),
        ];
        assert_eq!(split_at_sharp_turns(&bends, px).len(), 1);
    }
}
