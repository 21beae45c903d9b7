//! Events inside an accepted step: sign changes of event functions located on the step's
//! dense output (contact onsets are the zeros of the gap, eq. 1).

use super::Integrator;

/// The earliest event of an accepted step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    /// Which event function changed sign.
    pub index: usize,
    /// Where (the upper end of the located bracket, so the function has changed sign there).
    pub t: f64,
}

impl Integrator {
    /// The earliest change from negative to non-negative of the event functions `g(i, t, y)`,
    /// `i < g_prev.len()`, inside the last accepted step, located on its dense output to
    /// `1e-12·max(t, 1)`. `g_prev` holds their values at the step start and is updated to
    /// their values at the step end, `g_end` (known to the caller from the right-hand side's
    /// evaluation there); `scratch` (the state's length) receives interpolated states.
    pub fn earliest_event(
        &self,
        g_prev: &mut [f64],
        g_end: &[f64],
        mut g: impl FnMut(usize, f64, &[f64]) -> f64,
        scratch: &mut [f64],
    ) -> Option<Event> {
        let (ta, tb) = (self.t_prev(), self.t());
        let mut earliest: Option<Event> = None;
        for (index, (g_start, &g_end)) in g_prev.iter_mut().zip(g_end).enumerate() {
            if *g_start < 0.0 && g_end >= 0.0 {
                let on_dense = |t| {
                    self.dense(t, scratch);
                    g(index, t, scratch)
                };
                let t = locate_root(on_dense, ta, *g_start, tb, g_end, 1e-12 * tb.max(1.0));
                if earliest.is_none_or(|e| t < e.t) {
                    earliest = Some(Event { index, t });
                }
            }
            *g_start = g_end;
        }
        earliest
    }
}

/// Locate a sign change of a continuous scalar function g on [ta, tb] (g(ta) and g(tb) of
/// opposite sign or g(tb) == 0) by the Illinois variant of regula falsi; returns t with
/// |bracket| < tol. The returned t is the upper end of the final bracket, so g has already
/// changed sign there (or is zero): a driver that restarts at t is past the event.
pub fn locate_root(
    mut g: impl FnMut(f64) -> f64,
    mut ta: f64,
    mut ga: f64,
    mut tb: f64,
    mut gb: f64,
    tol: f64,
) -> f64 {
    debug_assert!(
        ga * gb <= 0.0,
        "locate_root needs a bracket: g({ta}) = {ga}, g({tb}) = {gb}"
    );
    // +1 when the last iterate replaced tb, -1 when it replaced ta.
    let mut side = 0;
    while gb != 0.0 && tb - ta > tol {
        let mut t = tb - gb * (tb - ta) / (gb - ga);
        if !(t > ta && t < tb) {
            t = 0.5 * (ta + tb);
            if !(t > ta && t < tb) {
                break; // the bracket is down to adjacent floating-point numbers
            }
        }
        let gt = g(t);
        if gt == 0.0 {
            return t;
        }
        if (gt > 0.0) == (gb > 0.0) {
            tb = t;
            gb = gt;
            // Illinois: halve the value at the end that stays, so it moves next time.
            if side == 1 {
                ga *= 0.5;
            }
            side = 1;
        } else {
            ta = t;
            ga = gt;
            if side == -1 {
                gb *= 0.5;
            }
            side = -1;
        }
    }
    tb
}
