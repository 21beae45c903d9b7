//! One-step ODE integrators for y' = f(t, y) with a state of any length (fixed at construction).
//!
//! # Methods
//!
//! Every method is an explicit Runge-Kutta tableau held as data (`tableau.rs`); one stepping
//! routine runs them all.
//!
//! * [`Method::Dopri5`]: the explicit Dormand-Prince pair 5(4) (7 stages, first-same-as-last, so
//!   6 evaluations per attempted step), advancing with the 5th-order solution. Dense output is
//!   Shampine's 4th-order continuous extension (Hairer's coefficients `d1..d7`), written in
//!   Hairer's nested form
//!   `y(t_prev + θh) = y0 + θ(Δ + (1-θ)(hf0 - Δ + θ(Δ - hf1 - (hf0 - Δ) + (1-θ) r5)))`,
//!   `Δ = y1 - y0`, which is the cubic Hermite interpolant plus one extra term `r5`.
//! * [`Method::Dop853`]: Hairer's explicit 8(5,3) pair (12 stages, 11 evaluations per attempt
//!   plus 1 per accepted step for f at the new point). Its error estimate blends the 5th- and
//!   3rd-order embedded differences as in Hairer's DOP853:
//!   `err = |h| E5² / sqrt(n (E5² + 0.01 E3²))`. Dense output is the cubic Hermite interpolant
//!   of (y, f) at both ends, which is only 3rd-order accurate: the 7th-order extension would cost
//!   3 more evaluations per step and nothing here needs it.
//! * [`Method::Rk4`]: the classical 4th-order Runge-Kutta method with a fixed step (the last step
//!   shortened to land on `t_limit`), no error control; cubic Hermite dense output.
//!
//! # Error control
//!
//! The error norm is the RMS over the controlled components (index `< n_controlled`) of
//! `err_i / (atol + rtol * max(|y_i|, |y_new_i|))`; later components (energy-accounting
//! quadratures) are integrated but never shrink the step. A step is accepted when the norm is
//! `<= 1`. With `q` the order of the error estimate (5, 8) the next step is
//! `h * clamp(safety * err^-(1/q - 0.75 β) * err_prev^β, fac_min, fac_max)` where `β = 0` is the
//! plain (I) controller and `β ≈ 0.04` Hairer's PI controller ([`StepControl`]); `fac_max` is
//! replaced by 1 for the step that follows a rejection, and `|h|` never exceeds `max_step`.
//! Opt-in, a digital filter of Söderlind's ([`Filter`], e.g. PI.4.2) takes the place of that
//! formula after an accepted step, with the same limits.
//! After a rejection the step shrinks by `max(fac_min, safety * err^(-1/q))`; `err^(-1/q)` is
//! taken by Newton's method (`root.rs`, within 2 ulp of the exact root), not libm's `pow`.
//! A trial whose right-hand side fails ([`OdeSystem::rhs`] returns an error, e.g. a contact
//! far outside the model's validity) or overflows is rejected and retried `fac_min` times
//! smaller; only when the step size underflows is it an error, and then the first such
//! failure is reported.
//!
//! # Events
//!
//! [`Integrator::earliest_event`] finds the first sign change from negative to non-negative
//! of a set of event functions inside the last accepted step, on its dense output, with
//! [`locate_root`]: between the step's ends, or beside an extremum inside the step where the
//! function's rate ([`EventValue`]) changes sign; the driver decides what the event does and
//! restarts with [`Integrator::reset`].
//!
//! # Why our own integrator
//!
//! Crates like `ode_solvers` integrate over a whole interval and own the loop. The simulation
//! needs a hook after every accepted step (wear update, energy bookkeeping), root finding for
//! contact events on the dense output of the last step, restarts after discontinuities, a
//! checkpoint of the exact stepping state ([`IntegratorState`]) and a hot loop that never
//! allocates: every buffer is sized once in [`Integrator::new`]. ARCHITECTURE.md records the
//! comparison with the `diffsol` and `differential-equations` crates.

mod events;
mod root;
mod tableau;
#[cfg(test)]
mod tests;

pub use events::{locate_root, Event, EventValue};

use crate::{Error, Result};
use root::inverse_root;
use tableau::{Dense, Estimate, Tableau, DOPRI5};

/// The right-hand side y' = f(t, y). `&mut self` because systems keep scratch buffers.
pub trait OdeSystem {
    /// Length of the state vector.
    fn dim(&self) -> usize;
    /// Writes f(t, y) into `dy`, or fails where f is not defined (the integrator retries a
    /// smaller step and reports the failure if none succeeds).
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<()>;
}

/// Accuracy requirements of an adaptive run.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Upper bound on the step size (`f64::INFINITY` for none).
    pub max_step: f64,
    /// First step size; 0 selects it automatically (Hairer's heuristic).
    pub initial_step: f64,
}

/// Step-size controller parameters (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepControl {
    /// Safety factor applied to the optimal step.
    pub safety: f64,
    /// Smallest ratio between successive steps.
    pub fac_min: f64,
    /// Largest ratio between successive steps.
    pub fac_max: f64,
    /// PI gain on the previous error; 0 gives the classical I controller.
    pub beta: f64,
    /// A digital filter in place of the I/PI formula after an accepted step (`None`, the
    /// default: the I/PI controller).
    pub filter: Option<Filter>,
}

/// Söderlind's two-step digital filter for the step size (G. Söderlind, "Digital filters in
/// adaptive time-stepping", ACM TOMS 29, 2003), of the PI kind (no gain on the last step
/// ratio: the filters with one, H211b and H211PI, lost accuracy as the tolerance loosened and
/// were not kept, paper.md section 7). After an accepted step `h_n` with error norm `r_n` the
/// next step is `h_n ρ`, limited as the I controller's (to `[fac_min, fac_max]`, `fac_max`
/// replaced by 1 after a rejection, at most `max_step`), with
/// `ρ = (ε/r_n)^(β1/k) (ε/r_{n-1})^(β2/k)`, `k` the order of the error estimate (5 for
/// Dopri5), `r_n` floored at 1e-10, and `r_{n-1}` the error norm (floored at 1e-4) of the
/// accepted step before; right after a (re)start `r_{n-1} = r_n`. Rejected attempts shrink the step as the I
/// controller's do (with [`StepControl::safety`], which the filter itself does not use). Its
/// memory is the integrator's checkpointed state ([`IntegratorState`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter {
    /// β1, the gain on the last error.
    pub beta1: f64,
    /// β2, the gain on the error of the accepted step before it.
    pub beta2: f64,
    /// ε, the error norm the filter steers to (a norm up to 1 is accepted).
    pub target: f64,
}

impl Filter {
    /// PI.4.2 (β1 = 3/5, β2 = −1/5), steering to ε = 0.9⁵, the norm at which the I
    /// controller's safety factor 0.9 keeps the step constant. The standard scene runs it at
    /// rtol 2.5e-7, the default-tolerance rule's pick for it over 512 members (the I
    /// controller's is 1.5e-7), for a median 12.5 % fewer evaluations over 40 rotations than
    /// the I controller at its pick (members 0-63 of seed 1; `paper.md` sections 5 and 7).
    pub fn pi42() -> Filter {
        Filter {
            beta1: 0.6,
            beta2: -0.2,
            target: 0.9f64.powi(5),
        }
    }
}

impl Default for StepControl {
    fn default() -> Self {
        StepControl {
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 5.0,
            beta: 0.0,
            filter: None,
        }
    }
}

/// Work counters, accumulated over the lifetime of an [`Integrator`] (restarts included).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts.
    pub rejected: u64,
    /// Evaluations of the right-hand side (Jacobian columns included).
    pub evaluations: u64,
    /// Events handled by the driver ([`Integrator::record_event`]).
    pub events: u64,
    /// The rejected attempts by what preceded them.
    #[serde(default)]
    pub rejections: Rejections,
}

/// Rejected attempts by what preceded them; they sum to [`Stats::rejected`]. Many rejections
/// right after the controller enlarged the step, few after restarts, is the signature of an
/// explicit method at its stability limit (a stiff contact), not of events or discontinuities.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Rejections {
    /// The right-hand side failed, or the trial state or error estimate was not finite.
    pub failed: u64,
    /// The first attempt after a start or restart (a contact onset): the guessed step.
    pub after_restart: u64,
    /// The first attempt after the controller enlarged the step.
    pub after_increase: u64,
    /// An attempt after a rejection within the same step.
    pub repeated: u64,
    /// The first attempt at a step no larger than the last accepted one.
    pub other: u64,
}

/// The integration method.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Method {
    /// Dormand-Prince 5(4) with 4th-order dense output.
    Dopri5,
    /// Hairer's DOP853, 8(5,3), with cubic Hermite dense output.
    Dop853,
    /// Classical Runge-Kutta with a fixed step.
    Rk4 {
        /// The fixed step (s).
        step: f64,
    },
}

/// How an accepted step ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Inside the interval, short of `t_limit`.
    Step,
    /// Exactly on `t_limit`.
    Limit,
}

/// What an [`Integrator`] carries from one accepted step to the next: restoring it continues
/// the same step sequence bit for bit.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct IntegratorState {
    t: f64,
    t_prev: f64,
    /// Proposed size of the next step.
    h: f64,
    /// Error norm of the last accepted step (memory of the PI controller).
    err_prev: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    dy: Vec<f64>,
    dy_prev: Vec<f64>,
    /// Term `r5` of the dense output; zero for the cubic Hermite methods.
    dense5: Vec<f64>,
    stats: Stats,
}

impl IntegratorState {
    /// The current time.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// The state vector at the current time.
    pub fn y(&self) -> &[f64] {
        &self.y
    }
}

/// A one-step integrator; see the module documentation.
pub struct Integrator {
    method: Method,
    tol: Tolerances,
    control: StepControl,
    n_controlled: usize,
    /// What the next steps depend on, as a checkpoint saves it.
    s: IntegratorState,
    y_new: Vec<f64>,
    dy_new: Vec<f64>,
    y_stage: Vec<f64>,
    /// Stage derivatives k2, k3, ... (k1 is `dy`, first-same-as-last), one after another,
    /// each of the state's length: [`Integrator::attempt_sized`] slices them once, not a
    /// vector per stage whose length is read again after every evaluation.
    k: Vec<f64>,
    /// Per-component error estimate of the last attempt (scratch).
    err: Vec<f64>,
}

/// Calls `$f::<N, C>` with the state's length `N` and the controlled count `C` as constants
/// for the shapes of the shipped scenes, where the loops over components then unroll: joint
/// coordinates of a two-freedom tree and of a four-freedom one (`two_clearance`), each without
/// and with the three energy integrals; `<0, 0>` (lengths read at run time) otherwise.
macro_rules! sized {
    ($self:ident . $f:ident ( $($arg:expr),* )) => {
        match ($self.s.y.len(), $self.n_controlled) {
            (4, 4) => $self.$f::<4, 4>($($arg),*),
            (7, 4) => $self.$f::<7, 4>($($arg),*),
            (8, 8) => $self.$f::<8, 8>($($arg),*),
            (11, 8) => $self.$f::<11, 8>($($arg),*),
            _ => $self.$f::<0, 0>($($arg),*),
        }
    };
}

/// `v[..N]`, or all of `v` when `N` is 0 (unknown at compile time; see `sized!`).
#[inline(always)]
fn first<const N: usize>(v: &[f64]) -> &[f64] {
    if N == 0 {
        v
    } else {
        &v[..N]
    }
}

/// [`first`] for a mutable slice.
#[inline(always)]
fn first_mut<const N: usize>(v: &mut [f64]) -> &mut [f64] {
    if N == 0 {
        v
    } else {
        &mut v[..N]
    }
}

/// `$f(out, args..)` on the first `N` components of `out` held in a local array (on all of
/// `out`, in place, when `N` is 0), then stored: as far as the compiler knows `out` may
/// overlap the stage buffers `$f` reads, so in place every pass would store and reload each
/// component, while a local array stays in registers and its passes are vectorised. The same
/// operations in the same order either way. (A macro: a closure here is not inlined.)
macro_rules! accumulate {
    ($n:ident, $f:ident($out:expr, $($arg:expr),*)) => {
        if $n == 0 {
            $f($out, $($arg),*)
        } else {
            let mut acc = [0.0; $n];
            $f(&mut acc, $($arg),*);
            $out[..$n].copy_from_slice(&acc);
        }
    };
}

/// The stage derivatives k2, k3, ... held one after another in `k`, each `d` long.
#[inline(always)]
fn stages(k: &[f64], d: usize) -> std::slice::ChunksExact<'_, f64> {
    // `max(1)`: no stages to read for an empty state, and chunks may not be empty.
    k.chunks_exact(d.max(1))
}

/// `out = y + h (row[0] k1 + Σ_{j≥1} row[j] k_{j+1})`, with k2, k3, ... the [`stages`] of
/// `k`, each `d` long, skipping the many zero coefficients; `N` as in `sized!`. Every
/// component sums its terms in stage order.
#[inline(always)]
fn combine<const N: usize>(
    out: &mut [f64],
    y: &[f64],
    k1: &[f64],
    k: (&[f64], usize),
    row: &[f64],
    h: f64,
) {
    accumulate!(N, combine_in(out, y, k1, k, row, h));
}

/// [`combine`] into all of `out`.
#[inline(always)]
fn combine_in(
    out: &mut [f64],
    y: &[f64],
    k1: &[f64],
    (k, d): (&[f64], usize),
    row: &[f64],
    h: f64,
) {
    let h0 = h * row.first().copied().unwrap_or(0.0);
    for ((o, &yi), &k1i) in out.iter_mut().zip(y).zip(k1) {
        *o = yi + h0 * k1i;
    }
    for (&a, kj) in row.iter().skip(1).zip(stages(k, d)) {
        if a != 0.0 {
            let ha = h * a;
            for (o, &kji) in out.iter_mut().zip(kj) {
                *o += ha * kji;
            }
        }
    }
}

/// `out_i = Σ_j w_j k_j,i` over the stages k1 (`k1`), k2.. (the [`stages`] of `k`, each `d`
/// long) and, last, f at the new point (`k_new`), skipping zero weights, for the first
/// `out.len()` components (`N` of them when `N` is not 0). Stage by stage, so that each pass
/// is a contiguous axpy the compiler vectorises; every component still sums its terms in
/// stage order, so the result is the same bits as a component-by-component sum.
#[inline(always)]
fn weighted<const N: usize>(
    out: &mut [f64],
    w: &[f64],
    k1: &[f64],
    k: (&[f64], usize),
    k_new: &[f64],
) {
    accumulate!(N, weighted_in(out, w, k1, k, k_new));
}

/// [`weighted`] into all of `out`.
#[inline(always)]
fn weighted_in(out: &mut [f64], w: &[f64], k1: &[f64], (k, d): (&[f64], usize), k_new: &[f64]) {
    out.fill(0.0);
    let last = w.len() - 1;
    for (j, &wj) in w.iter().enumerate() {
        if wj == 0.0 {
            continue;
        }
        let kj = match j {
            0 => k1,
            j if j == last => k_new,
            j => &k[(j - 1) * d..j * d],
        };
        for (o, &v) in out.iter_mut().zip(kj) {
            *o += wj * v;
        }
    }
}

/// Error scale of component i.
fn scale(tol: &Tolerances, y: f64, y_new: f64) -> f64 {
    tol.atol + tol.rtol * y.abs().max(y_new.abs())
}

fn integration_error(time: f64, cause: String) -> Error {
    Error::Integration { time, cause }
}

impl Integrator {
    /// Allocates every buffer for a state of length `dim`, of which the first `n_controlled`
    /// components enter the error norm.
    pub fn new(method: Method, dim: usize, n_controlled: usize, tol: Tolerances) -> Self {
        assert!(
            n_controlled <= dim,
            "n_controlled ({n_controlled}) exceeds dim ({dim})"
        );
        Integrator {
            method,
            tol,
            control: StepControl::default(),
            n_controlled,
            s: IntegratorState {
                t: 0.0,
                t_prev: 0.0,
                h: 0.0,
                err_prev: 1e-4,
                y: vec![0.0; dim],
                y_prev: vec![0.0; dim],
                dy: vec![0.0; dim],
                dy_prev: vec![0.0; dim],
                dense5: vec![0.0; dim],
                stats: Stats::default(),
            },
            y_new: vec![0.0; dim],
            dy_new: vec![0.0; dim],
            y_stage: vec![0.0; dim],
            k: vec![0.0; dim * (method.tableau().a.len() - 1)],
            err: vec![0.0; dim],
        }
    }

    /// What the next steps depend on (the stage buffers are scratch).
    pub fn state(&self) -> IntegratorState {
        self.s.clone()
    }

    /// Continues from a saved state; fails (changing nothing) with the name of the first field
    /// that no run of this integrator can have written: a vector of another length, a
    /// non-finite number, a time before the previous one, a step that is not positive.
    pub fn restore(&mut self, s: IntegratorState) -> std::result::Result<(), &'static str> {
        let n = self.s.y.len();
        let vectors = [
            ("y", &s.y),
            ("y_prev", &s.y_prev),
            ("dy", &s.dy),
            ("dy_prev", &s.dy_prev),
            ("dense5", &s.dense5),
        ];
        if let Some((name, _)) =
            (vectors.iter()).find(|(_, v)| v.len() != n || v.iter().any(|x| !x.is_finite()))
        {
            return Err(name);
        }
        let times_fit = s.t.is_finite() && s.t_prev.is_finite() && s.t_prev <= s.t;
        if !times_fit || s.t < 0.0 {
            return Err("t");
        }
        if !(s.h.is_finite() && s.h > 0.0) {
            return Err("h");
        }
        if !(s.err_prev.is_finite() && s.err_prev > 0.0) {
            return Err("err_prev");
        }
        self.s = s;
        Ok(())
    }

    /// Replaces the step-size controller parameters (e.g. to enable PI control).
    pub fn with_control(mut self, control: StepControl) -> Self {
        self.control = control;
        self
    }

    /// Start (or restart after a discontinuity) at (t, y): evaluates f(t, y) and chooses the
    /// initial step if `tol.initial_step` is 0 (Hairer's heuristic, one more evaluation).
    pub fn reset(&mut self, sys: &mut impl OdeSystem, t: f64, y: &[f64]) -> Result<()> {
        assert_eq!(
            sys.dim(),
            self.s.y.len(),
            "system dimension differs from the integrator's"
        );
        self.s.t = t;
        self.s.t_prev = t;
        self.s.y.copy_from_slice(y);
        self.s.y_prev.copy_from_slice(y);
        self.s.stats.evaluations += 1;
        sys.rhs(t, &self.s.y, &mut self.s.dy)?;
        self.s.dy_prev.copy_from_slice(&self.s.dy);
        self.s.dense5.fill(0.0);
        self.s.err_prev = 1e-4;
        self.s.h = match self.method {
            Method::Rk4 { step } => step,
            _ if self.tol.initial_step > 0.0 => self.tol.initial_step.min(self.tol.max_step),
            m => self.initial_step(sys, m.tableau().order)?,
        };
        Ok(())
    }

    /// Hairer's starting step: make the Euler step's change and its local error estimate small.
    fn initial_step(&mut self, sys: &mut impl OdeSystem, order: f64) -> Result<f64> {
        let n = self.n_controlled.max(1) as f64;
        let (mut d0, mut d1) = (0.0, 0.0);
        for i in 0..self.n_controlled {
            let sc = scale(&self.tol, self.s.y[i], self.s.y[i]);
            d0 += (self.s.y[i] / sc).powi(2);
            d1 += (self.s.dy[i] / sc).powi(2);
        }
        let (d0, d1) = ((d0 / n).sqrt(), (d1 / n).sqrt());
        let mut h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        }
        .min(self.tol.max_step);
        // The Euler probe may land where f is not defined (12 degrees of crank into a stiff
        // contact): it is retried smaller, as a failed trial step is, and only a probe that
        // fails down to the step size's underflow is the run's error.
        loop {
            combine::<0>(
                &mut self.y_stage,
                &self.s.y,
                &self.s.dy,
                (&[], 0),
                &[1.0],
                h0,
            );
            self.s.stats.evaluations += 1;
            match sys.rhs(self.s.t + h0, &self.y_stage, &mut self.dy_new) {
                Ok(()) => break,
                Err(e) => {
                    h0 *= self.control.fac_min;
                    if self.underflows(h0) {
                        return Err(e);
                    }
                }
            }
        }
        let mut d2 = 0.0;
        for i in 0..self.n_controlled {
            let sc = scale(&self.tol, self.s.y[i], self.s.y[i]);
            d2 += ((self.dy_new[i] - self.s.dy[i]) / sc).powi(2);
        }
        let d2 = (d2 / n).sqrt() / h0;
        let dmax = d1.max(d2);
        let h1 = if dmax <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / dmax).powf(1.0 / order)
        };
        Ok((100.0 * h0).min(h1).min(self.tol.max_step))
    }

    /// Take ONE accepted step (retrying rejected attempts internally), never stepping past
    /// `t_limit`; a step that ends within 1 % of a step size of `t_limit` lands on it exactly.
    ///
    /// Errors: `t_limit` not ahead of `t()`, step size below 1e-14·|t| (underflow, reported
    /// as the first failed right-hand side of the step if there was one), a failed
    /// right-hand side or non-finite values with a fixed step.
    pub fn step(&mut self, sys: &mut impl OdeSystem, t_limit: f64) -> Result<Stop> {
        if t_limit <= self.s.t || t_limit.is_nan() {
            return Err(integration_error(
                self.s.t,
                format!("step limit {t_limit:e} is not ahead of t"),
            ));
        }
        let tableau = self.method.tableau();
        if let Method::Rk4 { step } = self.method {
            if step.is_nan() || step <= 0.0 {
                return Err(integration_error(
                    self.s.t,
                    format!("Rk4 step {step:e} is not positive"),
                ));
            }
            let last = self.s.t + step * (1.0 + 1e-9) >= t_limit;
            let h = if last { t_limit - self.s.t } else { step };
            self.attempt(sys, h)?;
            self.check_finite()?;
            self.finish_step(sys, h)?;
            return Ok(self.accept(h, last, t_limit));
        }
        let mut rejected = false;
        // The last accepted step; 0 right after a (re)start.
        let h_last = self.s.t - self.s.t_prev;
        // Why the last attempt was thrown away, for the underflow message.
        let mut blow_up: Option<String> = None;
        let mut failure: Option<Error> = None;
        loop {
            if self.underflows(self.s.h) {
                if let Some(e) = failure {
                    return Err(e);
                }
                let why = blow_up.map_or(String::new(), |b| format!(" after {b}"));
                return Err(integration_error(
                    self.s.t,
                    format!("step size underflow (h = {:e}){why}", self.s.h),
                ));
            }
            let last = self.s.t + 1.01 * self.s.h >= t_limit;
            let h = if last { t_limit - self.s.t } else { self.s.h };
            // A trial whose right-hand side fails, that overflows (a step far too large for
            // stiff contact) or gives a NaN estimate is rejected and retried smaller.
            blow_up = match self.attempt(sys, h) {
                Err(e) => {
                    failure.get_or_insert(e);
                    Some("a failed right-hand side".into())
                }
                Ok(err) => match self.non_finite_component() {
                    Some(i) => Some(format!("a non-finite state component {i}")),
                    None if !err.is_finite() => Some("a non-finite error estimate".into()),
                    None if err <= 1.0 => {
                        self.control_accepted(h, err, rejected);
                        self.finish_step(sys, h)?;
                        return Ok(self.accept(h, last, t_limit));
                    }
                    None => {
                        let c = self.control;
                        self.s.h = h * (c.safety * inverse_root(err, tableau.order)).max(c.fac_min);
                        None
                    }
                },
            };
            self.s.stats.rejected += 1;
            let by = &mut self.s.stats.rejections;
            *match () {
                _ if blow_up.is_some() => &mut by.failed,
                _ if rejected => &mut by.repeated,
                _ if h_last == 0.0 => &mut by.after_restart,
                _ if h > h_last => &mut by.after_increase,
                _ => &mut by.other,
            } += 1;
            rejected = true;
            if blow_up.is_some() {
                self.s.h = h * self.control.fac_min;
            }
        }
    }

    /// The next step size after an accepted step of size `h` with error norm `err`.
    /// Whether a step of `h` from the current time is too small to advance it.
    fn underflows(&self, h: f64) -> bool {
        h <= 1e-14 * self.s.t.abs() || h < f64::MIN_POSITIVE
    }

    fn control_accepted(&mut self, h: f64, err: f64, after_rejection: bool) {
        let c = self.control;
        let order = self.method.tableau().order;
        let fac_max = if after_rejection { 1.0 } else { c.fac_max };
        if let Some(f) = c.filter {
            let r = err.max(1e-10);
            // no accepted step since the (re)start: no earlier error to filter
            let r_prev = if self.s.t > self.s.t_prev {
                self.s.err_prev
            } else {
                r
            };
            let rho =
                (f.target / r).powf(f.beta1 / order) * (f.target / r_prev).powf(f.beta2 / order);
            self.s.err_prev = err.max(1e-4);
            self.s.h = (h * rho.clamp(c.fac_min, fac_max)).min(self.tol.max_step);
            return;
        }
        // The I controller (β = 0) needs no `powf`: its exponent is −1/q and the PI factor 1.
        let fac = if c.beta == 0.0 {
            c.safety * inverse_root(err, order)
        } else {
            c.safety * err.powf(-(1.0 / order - 0.75 * c.beta)) * self.s.err_prev.powf(c.beta)
        };
        self.s.err_prev = err.max(1e-4);
        self.s.h = (h * fac.clamp(c.fac_min, fac_max)).min(self.tol.max_step);
    }

    /// One attempt of size `h`: fills `y_new` (and `dy_new` for first-same-as-last methods)
    /// and returns the error norm (0 without an estimate).
    fn attempt(&mut self, sys: &mut impl OdeSystem, h: f64) -> Result<f64> {
        match self.method {
            Method::Dopri5 => sized!(self.attempt_sized(sys, h, &DOPRI5)),
            m => sized!(self.attempt_sized(sys, h, m.tableau())),
        }
    }

    /// [`Integrator::attempt`] with tableau `tab` for a state of `N` components of which `C`
    /// are controlled (both 0: read at run time). The stages are unrolled, so that with a
    /// constant `tab` (Dormand-Prince's) every coefficient is a constant and the zeros' tests
    /// and the loops over a row drop out: the same operations in the same order.
    #[inline(always)]
    fn attempt_sized<const N: usize, const C: usize>(
        &mut self,
        sys: &mut impl OdeSystem,
        h: f64,
        tab: &Tableau,
    ) -> Result<f64> {
        // Slices taken once: their lengths are then known across the evaluations, which the
        // compiler cannot assume of the vectors' (an evaluation gets pointers into them).
        let s = &mut self.s;
        let (y, dy, t) = (first::<N>(&s.y), first::<N>(&s.dy), s.t);
        let d = y.len();
        let (y_stage, y_new) = (
            first_mut::<N>(&mut self.y_stage),
            first_mut::<N>(&mut self.y_new),
        );
        let (k, dy_new) = (&mut self.k[..], first_mut::<N>(&mut self.dy_new));
        macro_rules! stage {
            ($s:literal) => {
                if $s < tab.a.len() {
                    let (done, next) = k.split_at_mut(($s - 1) * d);
                    combine::<N>(y_stage, y, dy, (done, d), tab.a[$s], h);
                    s.stats.evaluations += 1;
                    sys.rhs(t + tab.c[$s] * h, y_stage, &mut next[..d])?;
                }
            };
        }
        stage!(1);
        stage!(2);
        stage!(3);
        stage!(4);
        stage!(5);
        stage!(6);
        stage!(7);
        stage!(8);
        stage!(9);
        stage!(10);
        stage!(11);
        const _: () = assert!(
            tableau::MAX_STAGES == 12,
            "one stage! per stage after the first"
        );
        debug_assert!(
            tab.a.len() <= tableau::MAX_STAGES,
            "a stage without its stage!"
        );
        combine::<N>(y_new, y, dy, (k, d), tab.b, h);
        if tab.fsal {
            s.stats.evaluations += 1;
            sys.rhs(t + h, y_new, dy_new)?;
        }
        Ok(match tab.estimate {
            Estimate::None => 0.0,
            Estimate::Embedded(e) => {
                let n = self.n_controlled;
                weighted::<C>(&mut self.err[..n], e, dy, (k, d), dy_new);
                self.error_norm::<C>(h)
            }
            Estimate::Blended { er, bhh } => self.blended_error(h, tab.b, er, bhh),
        })
    }

    /// Hairer's DOP853 error norm (see [`Estimate::Blended`]).
    fn blended_error(&self, h: f64, b: &[f64], er: &[f64], bhh: [f64; 3]) -> f64 {
        let (mut err5, mut err3) = (0.0, 0.0);
        for i in 0..self.n_controlled {
            let stage = |j: usize| {
                if j == 0 {
                    self.s.dy[i]
                } else {
                    self.k[(j - 1) * self.s.y.len() + i]
                }
            };
            let (mut e5, mut bi) = (0.0, 0.0);
            for j in 0..b.len() {
                e5 += er[j] * stage(j);
                bi += b[j] * stage(j);
            }
            let e3 = bi - bhh[0] * stage(0) - bhh[1] * stage(8) - bhh[2] * stage(11);
            let sc = scale(&self.tol, self.s.y[i], self.y_new[i]);
            err5 += (e5 / sc).powi(2);
            err3 += (e3 / sc).powi(2);
        }
        let deno = err5 + 0.01 * err3;
        let deno = if deno > 0.0 { deno } else { 1.0 };
        h * err5 / (self.n_controlled.max(1) as f64 * deno).sqrt()
    }

    /// What an accepted step needs before it becomes current: the dense-output term, or f at
    /// the new point for methods that do not evaluate it with every attempt.
    fn finish_step(&mut self, sys: &mut impl OdeSystem, h: f64) -> Result<()> {
        match self.method {
            Method::Dopri5 => self.finish_step_with(sys, h, &DOPRI5),
            m => self.finish_step_with(sys, h, m.tableau()),
        }
    }

    /// [`Integrator::finish_step`] with tableau `tab` (constant for Dormand-Prince's, as in
    /// [`Integrator::attempt_sized`]).
    #[inline(always)]
    fn finish_step_with(&mut self, sys: &mut impl OdeSystem, h: f64, tab: &Tableau) -> Result<()> {
        if let Dense::Shampine(d) = tab.dense {
            sized!(self.dense_term(d, h));
        }
        if !tab.fsal {
            self.s.stats.evaluations += 1;
            sys.rhs(self.s.t + h, &self.y_new, &mut self.dy_new)?;
        }
        Ok(())
    }

    /// Shampine's dense-output term `r5 = h Σ_j d_j k_j` of an accepted step of size `h`
    /// (`N` as in [`Integrator::attempt_sized`]).
    #[inline(always)]
    fn dense_term<const N: usize, const C: usize>(&mut self, d: &[f64], h: f64) {
        let k = (&self.k[..], self.s.y.len());
        weighted::<N>(&mut self.s.dense5, d, &self.s.dy, k, &self.dy_new);
        for r in first_mut::<N>(&mut self.s.dense5) {
            *r *= h;
        }
    }

    /// Index of the first non-finite component of the trial state, if any.
    fn non_finite_component(&self) -> Option<usize> {
        self.y_new.iter().position(|v| !v.is_finite())
    }

    fn check_finite(&self) -> Result<()> {
        match self.non_finite_component() {
            None => Ok(()),
            Some(i) => Err(integration_error(
                self.s.t,
                format!("non-finite state component {i}"),
            )),
        }
    }

    /// Makes `y_new`, `dy_new` the current point of a step of size `h`, landing exactly on
    /// `t_limit` if it is the `last`.
    fn accept(&mut self, h: f64, last: bool, t_limit: f64) -> Stop {
        let t_new = if last { t_limit } else { self.s.t + h };
        debug_assert!((t_new - self.s.t - h).abs() <= 1e-12 * t_new.abs().max(h));
        std::mem::swap(&mut self.s.y_prev, &mut self.s.y);
        std::mem::swap(&mut self.s.y, &mut self.y_new);
        std::mem::swap(&mut self.s.dy_prev, &mut self.s.dy);
        std::mem::swap(&mut self.s.dy, &mut self.dy_new);
        self.s.t_prev = self.s.t;
        self.s.t = t_new;
        self.s.stats.steps += 1;
        if last {
            Stop::Limit
        } else {
            Stop::Step
        }
    }

    /// RMS norm over the controlled components of `h err_i / scale_i` (`C` of them when `C`
    /// is not 0). A division per component, as `h err_i · (1 / scale_i)` would round
    /// differently.
    #[inline(always)]
    fn error_norm<const C: usize>(&self, h: f64) -> f64 {
        let n = self.n_controlled;
        let (y, y_new) = (first::<C>(&self.s.y[..n]), first::<C>(&self.y_new[..n]));
        let mut sum = 0.0;
        for ((&e, &yi), &yn) in first::<C>(&self.err[..n]).iter().zip(y).zip(y_new) {
            sum += (h * e / scale(&self.tol, yi, yn)).powi(2);
        }
        (sum / n.max(1) as f64).sqrt()
    }

    /// End of the last accepted step.
    pub fn t(&self) -> f64 {
        self.s.t
    }

    /// Start of the last accepted step.
    pub fn t_prev(&self) -> f64 {
        self.s.t_prev
    }

    /// State at [`t`](Self::t).
    pub fn y(&self) -> &[f64] {
        &self.s.y
    }

    /// State at [`t_prev`](Self::t_prev).
    pub fn y_prev(&self) -> &[f64] {
        &self.s.y_prev
    }

    /// f(t, y) at [`t`](Self::t).
    pub fn dy(&self) -> &[f64] {
        &self.s.dy
    }

    /// Dense output inside the last accepted step [t_prev, t]: writes y(t_eval) into `out`.
    /// Exact at both ends.
    pub fn dense(&self, t_eval: f64, out: &mut [f64]) {
        if t_eval == self.s.t {
            out.copy_from_slice(&self.s.y);
            return;
        }
        sized!(self.dense_sized(t_eval, out))
    }

    /// [`Integrator::dense`] inside the step (`N` as in [`Integrator::attempt_sized`]).
    #[inline(always)]
    fn dense_sized<const N: usize, const C: usize>(&self, t_eval: f64, out: &mut [f64]) {
        let s = &self.s;
        let h = s.t - s.t_prev;
        let th = (t_eval - s.t_prev) / h;
        let th1 = 1.0 - th;
        let (y, y_prev) = (first::<N>(&s.y), first::<N>(&s.y_prev));
        let (dy, dy_prev) = (first::<N>(&s.dy), first::<N>(&s.dy_prev));
        let ends = y.iter().zip(y_prev).zip(dy).zip(dy_prev);
        for (o, ((((&y, &y_prev), &dy), &dy_prev), &r5)) in first_mut::<N>(out)
            .iter_mut()
            .zip(ends.zip(first::<N>(&s.dense5)))
        {
            let d = y - y_prev;
            let b = h * dy_prev - d;
            let c = d - h * dy - b;
            *o = y_prev + th * (d + th1 * (b + th * (c + th1 * r5)));
        }
    }

    /// Work counters.
    pub fn stats(&self) -> Stats {
        self.s.stats
    }

    /// Counts an event handled by the driver, so that [`stats`](Self::stats) tells the whole story.
    pub fn record_event(&mut self) {
        self.s.stats.events += 1;
    }

    /// Currently proposed size of the next step.
    pub fn step_size(&self) -> f64 {
        self.s.h
    }
}
