//! Events inside an accepted step: sign changes of event functions located on the step's
//! dense output (contact onsets are the zeros of the gap, eq. 1).
//!
//! A change from negative to non-negative is found where the function's values at the step's
//! ends differ in sign, and also where they agree in sign but its rate does not: the function
//! then has one extremum inside the step (a journal that lifts off by a few nanometres and
//! lands again within one step of a contact, or grazes the bearing within one step of free
//! flight). The extremum is located as the zero of the rate, and when the function changes
//! sign there the crossing beside it is located. Without that search such an onset is not
//! seen, and eq. 3 keeps the previous contact's onset velocity.
//!
//! The search runs only when the tangents at the step's ends meet across zero
//! (`tangents_meet`), so that most of a contact's vibrations, micrometres deep, cost nothing.
//! That screen is a bound for a convex dip (it lies above its tangents) and a concave bump, not
//! in general: a gap pressed deeper than its static penetration bends towards zero between the
//! ends, and a dip that does so across zero could pass the screen unseen. Measured on
//! 2026-11-26: the default-tolerance rule's 128 members at its ten settings
//! (`work_precision --rule`) give the same onset counts, largest orbit errors and median
//! ratios with the screen as without it, and without it the standard scene's 40 rotations at
//! rtol 1.5e-7 searched 3 882 steps and found no landing. Two extrema in one step (a rate of the same
//! sign at both ends) are not searched for.

use super::Integrator;

/// The earliest event of an accepted step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    /// Which event function changed sign.
    pub index: usize,
    /// Where (the upper end of the located bracket, so the function has changed sign there).
    pub t: f64,
}

/// An event function's value and its rate of change with time, at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EventValue {
    /// The value; an event is a change from negative to non-negative.
    pub value: f64,
    /// Its time derivative (per s).
    pub rate: f64,
}

impl Integrator {
    /// The earliest change from negative to non-negative of the event functions `g(i, t, y)`,
    /// `i < g_prev.len()`, inside the last accepted step, located on its dense output to
    /// `1e-12·max(t, 1)` (see the module documentation for the crossings found between ends
    /// of equal sign). `g_prev` holds their values and rates at the step start and is updated
    /// to those at the step end, `g_end` (known to the caller from the right-hand side's
    /// evaluation there); `scratch` (the state's length) receives interpolated states.
    pub fn earliest_event(
        &self,
        g_prev: &mut [EventValue],
        g_end: &[EventValue],
        mut g: impl FnMut(usize, f64, &[f64]) -> EventValue,
        scratch: &mut [f64],
    ) -> Option<Event> {
        let (ta, tb) = (self.t_prev(), self.t());
        let tol = 1e-12 * tb.max(1.0);
        let mut earliest: Option<Event> = None;
        for (index, (start, &end)) in g_prev.iter_mut().zip(g_end).enumerate() {
            let mut on_dense = |t| {
                self.dense(t, scratch);
                g(index, t, scratch)
            };
            let (a, b) = (*start, end);
            let free = a.value < 0.0;
            // Across zero from where the step starts.
            let across = |v: f64| if free { v >= 0.0 } else { v < 0.0 };
            // Ends on one side of zero and a rate turning back towards it there: up from
            // negative and back down (a graze if the maximum is non-negative), or down from
            // non-negative and back up (a landing if the minimum is negative).
            let turns = if free {
                a.rate >= 0.0 && b.rate < 0.0
            } else {
                a.rate < 0.0 && b.rate >= 0.0
            };
            // The bracket [t0, t1] of a crossing from negative to non-negative, with the values
            // at its ends: between the ends, or beside an extremum when both lie on one side
            // (a contact that ends within the step has neither).
            let bracket = if free && b.value >= 0.0 {
                Some((ta, a.value, tb, b.value))
            } else if !across(b.value) {
                (turns && across(tangents_meet(ta, a, tb, b)))
                    .then(|| {
                        let t_ext = locate_root(|t| on_dense(t).rate, ta, a.rate, tb, b.rate, tol);
                        (t_ext, on_dense(t_ext).value)
                    })
                    .filter(|&(_, ext)| across(ext))
                    // The crossing from negative to non-negative: before a maximum, after a
                    // minimum.
                    .map(|(t_ext, ext)| {
                        if free {
                            (ta, a.value, t_ext, ext)
                        } else {
                            (t_ext, ext, tb, b.value)
                        }
                    })
            } else {
                None
            };
            if let Some((t0, g0, t1, g1)) = bracket {
                let t = locate_root(|t| on_dense(t).value, t0, g0, t1, g1, tol);
                if earliest.is_none_or(|e| t < e.t) {
                    earliest = Some(Event { index, t });
                }
            }
            *start = end;
        }
        earliest
    }
}

impl Integrator {
    /// The largest value of an event function inside the last accepted step, where its rate
    /// turns from positive at the start (`a`, value and rate) to negative at the end (`b`),
    /// when the ends' tangents meet above `above` (the screen of [`Integrator::earliest_event`],
    /// a bound for a concave bump): the zero of the rate located on the dense output to
    /// `1e-12·max(t, 1)`, and the function there. `None` when neither holds: the largest value
    /// is then at an end, or not above `above` (for a concave bump). `g` and `scratch` as in
    /// `earliest_event`. Returns the peak's time and value.
    pub fn peak_inside(
        &self,
        a: EventValue,
        b: EventValue,
        above: f64,
        mut g: impl FnMut(f64, &[f64]) -> EventValue,
        scratch: &mut [f64],
    ) -> Option<(f64, f64)> {
        let (ta, tb) = (self.t_prev(), self.t());
        if !(a.rate > 0.0 && b.rate < 0.0 && tangents_meet(ta, a, tb, b) > above) {
            return None;
        }
        let mut on_dense = |t| {
            self.dense(t, scratch);
            g(t, scratch)
        };
        let tol = 1e-12 * tb.max(1.0);
        let t = locate_root(|t| on_dense(t).rate, ta, a.rate, tb, b.rate, tol);
        Some((t, on_dense(t).value))
    }
}

/// Where the tangents of an event function at the ends of a step `[ta, tb]` (values and rates
/// `a`, `b`, the rates of opposite signs or one zero) meet, clamped to the step: a bound on its
/// extremum when it is convex over the step (a minimum: the function lies above both tangents)
/// or concave (a maximum: below them).
pub(super) fn tangents_meet(ta: f64, a: EventValue, tb: f64, b: EventValue) -> f64 {
    let h = tb - ta;
    let s = ((b.value - a.value - b.rate * h) / (a.rate - b.rate)).clamp(0.0, h);
    let (on_a, on_b) = (a.value + a.rate * s, b.value + b.rate * (s - h));
    if a.rate < b.rate {
        on_a.max(on_b)
    } else {
        on_a.min(on_b)
    }
}

/// Locate a sign change of a continuous scalar function g on [ta, tb] (g(ta) and g(tb) of
/// opposite sign, or either zero) by the Illinois variant of regula falsi; returns t with
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
