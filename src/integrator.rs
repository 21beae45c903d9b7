//! One-step ODE integrators for y' = f(t, y) with a dynamic-length state.
//!
//! # Methods
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
//! * [`Method::Rosenbrock`]: RODAS3 (Sandu et al. 1997), a stiffly accurate, L-stable linearly
//!   implicit method of order 3 with an embedded order-2 solution; 4 stages, 2 new evaluations
//!   per attempt. The Jacobian and ∂f/∂t come from forward differences once per step; each
//!   attempt factorises `I/(γh) - J` by dense LU. It exists for work-precision studies, so its
//!   per-step LU allocation is accepted. Cubic Hermite dense output.
//!
//! # Error control
//!
//! The error norm is the RMS over the controlled components (index `< n_controlled`) of
//! `err_i / (atol + rtol * max(|y_i|, |y_new_i|))`; later components (energy-accounting
//! quadratures) are integrated but never shrink the step. A step is accepted when the norm is
//! `<= 1`. With `q` the order of the error estimate (5, 8, 3) the next step is
//! `h * clamp(safety * err^-(1/q - 0.75 β) * err_prev^β, fac_min, fac_max)` where `β = 0` is the
//! plain (I) controller and `β ≈ 0.04` Hairer's PI controller ([`StepControl`]); `fac_max` is
//! replaced by 1 for the step that follows a rejection, and `|h|` never exceeds `max_step`.
//! After a rejection the step shrinks by `max(fac_min, safety * err^(-1/q))`.
//!
//! # Why our own integrator
//!
//! Crates like `ode_solvers` integrate over a whole interval and own the loop. The simulation
//! needs a hook after every accepted step (wear update, energy bookkeeping), root finding for
//! contact events on the dense output of the last step ([`Integrator::dense`] with
//! [`locate_root`]), restarts after discontinuities ([`Integrator::reset`]), and a hot loop that
//! never allocates: every buffer is sized once in [`Integrator::new`].

use crate::{Error, Result};
use nalgebra::{DMatrix, DVectorViewMut};

/// The right-hand side y' = f(t, y). `&mut self` because systems keep scratch buffers.
pub trait OdeSystem {
    /// Length of the state vector.
    fn dim(&self) -> usize;
    /// Writes f(t, y) into `dy`.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]);
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
}

impl Default for StepControl {
    fn default() -> Self {
        StepControl {
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 5.0,
            beta: 0.0,
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
    /// RODAS3, a stiff L-stable Rosenbrock 3(2) method.
    Rosenbrock,
}

// Dormand-Prince 5(4): rows of the Butcher matrix; the last row holds the 5th-order weights.
const DP5_A: [&[f64]; 7] = [
    &[],
    &[1.0 / 5.0],
    &[3.0 / 40.0, 9.0 / 40.0],
    &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
    &[
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
    ],
    &[
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
    ],
    &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
const DP5_C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
// Difference between the 5th- and 4th-order weights.
const DP5_E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
// Shampine's dense output coefficients.
const DP5_D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

// DOP853 (Hairer, Nørsett & Wanner, Solving ODEs I, and the Fortran code DOP853).
#[allow(clippy::excessive_precision)]
const DOP853_A: [&[f64]; 12] = [
    &[],
    &[5.26001519587677318785587544488e-2],
    &[
        1.97250569845378994544595329183e-2,
        5.91751709536136983633785987549e-2,
    ],
    &[
        2.95875854768068491816892993775e-2,
        0.0,
        8.87627564304205475450678981324e-2,
    ],
    &[
        2.41365134159266685502369798665e-1,
        0.0,
        -8.84549479328286085344864962717e-1,
        9.24834003261792003115737966543e-1,
    ],
    &[
        3.7037037037037037037037037037e-2,
        0.0,
        0.0,
        1.70828608729473871279604482173e-1,
        1.25467687566822425016691814123e-1,
    ],
    &[
        3.7109375e-2,
        0.0,
        0.0,
        1.70252211019544039314978060272e-1,
        6.02165389804559606850219397283e-2,
        -1.7578125e-2,
    ],
    &[
        3.70920001185047927108779319836e-2,
        0.0,
        0.0,
        1.70383925712239993810214054705e-1,
        1.07262030446373284651809199168e-1,
        -1.53194377486244017527936158236e-2,
        8.27378916381402288758473766002e-3,
    ],
    &[
        6.24110958716075717114429577812e-1,
        0.0,
        0.0,
        -3.36089262944694129406857109825e0,
        -8.68219346841726006818189891453e-1,
        2.75920996994467083049415600797e1,
        2.01540675504778934086186788979e1,
        -4.34898841810699588477366255144e1,
    ],
    &[
        4.77662536438264365890433908527e-1,
        0.0,
        0.0,
        -2.48811461997166764192642586468e0,
        -5.90290826836842996371446475743e-1,
        2.12300514481811942347288949897e1,
        1.52792336328824235832596922938e1,
        -3.32882109689848629194453265587e1,
        -2.03312017085086261358222928593e-2,
    ],
    &[
        -9.3714243008598732571704021658e-1,
        0.0,
        0.0,
        5.18637242884406370830023853209e0,
        1.09143734899672957818500254654e0,
        -8.14978701074692612513997267357e0,
        -1.85200656599969598641566180701e1,
        2.27394870993505042818970056734e1,
        2.49360555267965238987089396762e0,
        -3.0467644718982195003823669022e0,
    ],
    &[
        2.27331014751653820792359768449e0,
        0.0,
        0.0,
        -1.05344954667372501984066689879e1,
        -2.00087205822486249909675718444e0,
        -1.79589318631187989172765950534e1,
        2.79488845294199600508499808837e1,
        -2.85899827713502369474065508674e0,
        -8.87285693353062954433549289258e0,
        1.23605671757943030647266201528e1,
        6.43392746015763530355970484046e-1,
    ],
];
#[allow(clippy::excessive_precision)]
const DOP853_C: [f64; 12] = [
    0.0,
    0.526001519587677318785587544488e-1,
    0.789002279381515978178381316732e-1,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    1.0 / 3.0,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
];
#[allow(clippy::excessive_precision)]
const DOP853_B: [f64; 12] = [
    5.42937341165687622380535766363e-2,
    0.0,
    0.0,
    0.0,
    0.0,
    4.45031289275240888144113950566e0,
    1.89151789931450038304281599044e0,
    -5.8012039600105847814672114227e0,
    3.1116436695781989440891606237e-1,
    -1.52160949662516078556178806805e-1,
    2.01365400804030348374776537501e-1,
    4.47106157277725905176885569043e-2,
];
// Weights of the 3rd-order estimate on stages 1, 9 and 12.
#[allow(clippy::excessive_precision)]
const DOP853_BHH: [f64; 3] = [
    0.244094488188976377952755905512,
    0.733846688281611857341361741547,
    0.220588235294117647058823529412e-1,
];
// Weights of the 5th-order error estimate.
#[allow(clippy::excessive_precision)]
const DOP853_ER: [f64; 12] = [
    0.1312004499419488073250102996e-1,
    0.0,
    0.0,
    0.0,
    0.0,
    -0.1225156446376204440720569753e1,
    -0.4957589496572501915214079952,
    0.1664377182454986536961530415e1,
    -0.3503288487499736816886487290,
    0.3341791187130174790297318841,
    0.8192320648511571246570742613e-1,
    -0.2235530786388629525884427845e-1,
];

const RK4_A: [&[f64]; 4] = [&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]];
const RK4_C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
const RK4_B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];

// RODAS3 in the form of Hairer & Wanner / KPP: (I/(γh) - J) K_i = f(t + α_i h, y + Σ a_ij K_j)
// + Σ (c_ij/h) K_j + h γ_i ∂f/∂t, y_new = y + 2K1 + K3 + K4, error estimate K4.
// The a_ij (a31 = a41 = 2, a43 = 1, others 0) and α = (0, 0, 1, 1) are written out in the code.
const ROS_GAMMA: f64 = 0.5;
const ROS_GAMMA1: f64 = 0.5;
const ROS_GAMMA2: f64 = 1.5;
const ROS_C21: f64 = 4.0;
const ROS_C31: f64 = 1.0;
const ROS_C32: f64 = -1.0;
const ROS_C41: f64 = 1.0;
const ROS_C42: f64 = -1.0;
const ROS_C43: f64 = -8.0 / 3.0;

/// Numerical Jacobian and ∂f/∂t of the Rosenbrock method, computed once per step.
struct RosenbrockWork {
    jac: DMatrix<f64>,
    dfdt: Vec<f64>,
}

/// What an [`Integrator`] carries from one accepted step to the next: restoring it continues
/// the same step sequence bit for bit.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct IntegratorState {
    t: f64,
    t_prev: f64,
    h: f64,
    err_prev: f64,
    y: Vec<f64>,
    y_prev: Vec<f64>,
    dy: Vec<f64>,
    dy_prev: Vec<f64>,
    dense5: Vec<f64>,
    stats: Stats,
}

impl IntegratorState {
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
    y_new: Vec<f64>,
    dy_new: Vec<f64>,
    y_stage: Vec<f64>,
    /// Stage derivatives k2, k3, ... (k1 is `dy`, first-same-as-last); K1..K4 for Rosenbrock.
    k: Vec<Vec<f64>>,
    /// Term `r5` of the dense output; zero for the cubic Hermite methods.
    dense5: Vec<f64>,
    ros: Option<RosenbrockWork>,
    stats: Stats,
}

/// `out = y + h (row[0] k1 + Σ_{j≥1} row[j] k[j-1])`, skipping the many zero coefficients.
fn combine(out: &mut [f64], y: &[f64], k1: &[f64], k: &[Vec<f64>], row: &[f64], h: f64) {
    let h0 = h * row.first().copied().unwrap_or(0.0);
    for ((o, &yi), &k1i) in out.iter_mut().zip(y).zip(k1) {
        *o = yi + h0 * k1i;
    }
    for (&a, kj) in row.iter().skip(1).zip(k) {
        if a != 0.0 {
            let ha = h * a;
            for (o, &kji) in out.iter_mut().zip(kj) {
                *o += ha * kji;
            }
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
        let n_stages = match method {
            Method::Dopri5 => 5,
            Method::Dop853 => 11,
            Method::Rk4 { .. } => 3,
            Method::Rosenbrock => 4,
        };
        let ros = matches!(method, Method::Rosenbrock).then(|| RosenbrockWork {
            jac: DMatrix::zeros(dim, dim),
            dfdt: vec![0.0; dim],
        });
        Integrator {
            method,
            tol,
            control: StepControl::default(),
            n_controlled,
            t: 0.0,
            t_prev: 0.0,
            h: 0.0,
            err_prev: 1e-4,
            y: vec![0.0; dim],
            y_prev: vec![0.0; dim],
            dy: vec![0.0; dim],
            dy_prev: vec![0.0; dim],
            y_new: vec![0.0; dim],
            dy_new: vec![0.0; dim],
            y_stage: vec![0.0; dim],
            k: vec![vec![0.0; dim]; n_stages],
            dense5: vec![0.0; dim],
            ros,
            stats: Stats::default(),
        }
    }

    /// What the next steps depend on (the stage buffers are scratch).
    pub fn state(&self) -> IntegratorState {
        IntegratorState {
            t: self.t,
            t_prev: self.t_prev,
            h: self.h,
            err_prev: self.err_prev,
            y: self.y.clone(),
            y_prev: self.y_prev.clone(),
            dy: self.dy.clone(),
            dy_prev: self.dy_prev.clone(),
            dense5: self.dense5.clone(),
            stats: self.stats,
        }
    }

    /// Continues from a saved state; fails (changing nothing) if its vectors do not have this
    /// integrator's length.
    pub fn restore(&mut self, s: IntegratorState) -> Result<()> {
        let n = self.y.len();
        if [&s.y, &s.y_prev, &s.dy, &s.dy_prev, &s.dense5]
            .iter()
            .any(|v| v.len() != n)
        {
            return Err(integration_error(
                s.t,
                "saved state of another length".into(),
            ));
        }
        (self.t, self.t_prev, self.h, self.err_prev) = (s.t, s.t_prev, s.h, s.err_prev);
        (self.y, self.y_prev, self.dy, self.dy_prev) = (s.y, s.y_prev, s.dy, s.dy_prev);
        self.dense5 = s.dense5;
        self.stats = s.stats;
        Ok(())
    }

    /// Replaces the step-size controller parameters (e.g. to enable PI control).
    pub fn with_control(mut self, control: StepControl) -> Self {
        self.control = control;
        self
    }

    /// Start (or restart after a discontinuity) at (t, y): evaluates f(t, y) and chooses the
    /// initial step if `tol.initial_step` is 0 (Hairer's heuristic, one more evaluation).
    pub fn reset(&mut self, sys: &mut impl OdeSystem, t: f64, y: &[f64]) {
        assert_eq!(
            sys.dim(),
            self.y.len(),
            "system dimension differs from the integrator's"
        );
        self.t = t;
        self.t_prev = t;
        self.y.copy_from_slice(y);
        self.y_prev.copy_from_slice(y);
        sys.rhs(t, &self.y, &mut self.dy);
        self.dy_prev.copy_from_slice(&self.dy);
        self.dense5.fill(0.0);
        self.stats.evaluations += 1;
        self.err_prev = 1e-4;
        self.h = match self.method {
            Method::Rk4 { step } => step,
            _ if self.tol.initial_step > 0.0 => self.tol.initial_step.min(self.tol.max_step),
            Method::Dopri5 => self.initial_step(sys, 5),
            Method::Dop853 => self.initial_step(sys, 8),
            Method::Rosenbrock => self.initial_step(sys, 3),
        };
    }

    /// Hairer's starting step: make the Euler step's change and its local error estimate small.
    fn initial_step(&mut self, sys: &mut impl OdeSystem, order: i32) -> f64 {
        let n = self.n_controlled.max(1) as f64;
        let (mut d0, mut d1) = (0.0, 0.0);
        for i in 0..self.n_controlled {
            let sc = scale(&self.tol, self.y[i], self.y[i]);
            d0 += (self.y[i] / sc).powi(2);
            d1 += (self.dy[i] / sc).powi(2);
        }
        let (d0, d1) = ((d0 / n).sqrt(), (d1 / n).sqrt());
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        }
        .min(self.tol.max_step);
        combine(&mut self.y_stage, &self.y, &self.dy, &[], &[1.0], h0);
        sys.rhs(self.t + h0, &self.y_stage, &mut self.dy_new);
        self.stats.evaluations += 1;
        let mut d2 = 0.0;
        for i in 0..self.n_controlled {
            let sc = scale(&self.tol, self.y[i], self.y[i]);
            d2 += ((self.dy_new[i] - self.dy[i]) / sc).powi(2);
        }
        let d2 = (d2 / n).sqrt() / h0;
        let dmax = d1.max(d2);
        let h1 = if dmax <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / dmax).powf(1.0 / order as f64)
        };
        (100.0 * h0).min(h1).min(self.tol.max_step)
    }

    /// Take ONE accepted step (retrying rejected attempts internally), never stepping past
    /// `t_limit`; a step that ends within 1 % of a step size of `t_limit` lands on it exactly.
    ///
    /// Errors: `t_limit` not ahead of `t()`, step size below 1e-14·|t| (underflow), non-finite
    /// values in the new state.
    pub fn step(&mut self, sys: &mut impl OdeSystem, t_limit: f64) -> Result<()> {
        if t_limit <= self.t || t_limit.is_nan() {
            return Err(integration_error(
                self.t,
                format!("step limit {t_limit:e} is not ahead of t"),
            ));
        }
        if let Method::Rk4 { step } = self.method {
            if step.is_nan() || step <= 0.0 {
                return Err(integration_error(
                    self.t,
                    format!("Rk4 step {step:e} is not positive"),
                ));
            }
            let last = self.t + step * (1.0 + 1e-9) >= t_limit;
            let h = if last { t_limit - self.t } else { step };
            self.attempt_rk4(sys, h);
            self.check_finite()?;
            self.accept(h, if last { t_limit } else { self.t + h });
            return Ok(());
        }
        let order = match self.method {
            Method::Dop853 => 8.0,
            Method::Rosenbrock => {
                self.jacobian(sys);
                3.0
            }
            _ => 5.0,
        };
        let mut rejected = false;
        // Why the last attempt was thrown away, for the underflow message.
        let mut blow_up: Option<String> = None;
        loop {
            if self.h <= 1e-14 * self.t.abs() || self.h < f64::MIN_POSITIVE {
                let why = blow_up.map_or(String::new(), |b| format!(" after {b}"));
                return Err(integration_error(
                    self.t,
                    format!("step size underflow (h = {:e}){why}", self.h),
                ));
            }
            let last = self.t + 1.01 * self.h >= t_limit;
            let h = if last { t_limit - self.t } else { self.h };
            let err = match self.method {
                Method::Dopri5 => self.attempt_dopri5(sys, h),
                Method::Dop853 => self.attempt_dop853(sys, h),
                _ => self.attempt_rosenbrock(sys, h),
            };
            // A trial that overflows (a step far too large for stiff contact), a NaN estimate or
            // a singular iteration matrix (infinite norm) is rejected and retried smaller; only
            // when the step size underflows is it an error.
            blow_up = match self.non_finite_component() {
                Some(i) => Some(format!("a non-finite state component {i}")),
                None if !err.is_finite() => Some("a non-finite error estimate".into()),
                None => None,
            };
            if blow_up.is_some() {
                self.stats.rejected += 1;
                rejected = true;
                self.h = h * self.control.fac_min;
                continue;
            }
            let c = self.control;
            if err <= 1.0 {
                let fac_max = if rejected { 1.0 } else { c.fac_max };
                let fac = c.safety
                    * err.powf(-(1.0 / order - 0.75 * c.beta))
                    * self.err_prev.powf(c.beta);
                self.err_prev = err.max(1e-4);
                self.h = (h * fac.clamp(c.fac_min, fac_max)).min(self.tol.max_step);
                match self.method {
                    Method::Dopri5 => self.dense_dopri5(h),
                    _ => {
                        // Dop853 and Rosenbrock need f at the new point (FSAL for the next step).
                        sys.rhs(self.t + h, &self.y_new, &mut self.dy_new);
                        self.stats.evaluations += 1;
                    }
                }
                self.accept(h, if last { t_limit } else { self.t + h });
                return Ok(());
            }
            self.stats.rejected += 1;
            rejected = true;
            self.h = h * (c.safety * err.powf(-1.0 / order)).max(c.fac_min);
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
                self.t,
                format!("non-finite state component {i}"),
            )),
        }
    }

    /// Makes `y_new`, `dy_new` the current point of a step of size `h` ending at `t_new`.
    fn accept(&mut self, h: f64, t_new: f64) {
        debug_assert!((t_new - self.t - h).abs() <= 1e-12 * t_new.abs().max(h));
        std::mem::swap(&mut self.y_prev, &mut self.y);
        std::mem::swap(&mut self.y, &mut self.y_new);
        std::mem::swap(&mut self.dy_prev, &mut self.dy);
        std::mem::swap(&mut self.dy, &mut self.dy_new);
        self.t_prev = self.t;
        self.t = t_new;
        self.stats.steps += 1;
    }

    /// RMS norm over the controlled components of `e_i(i) / scale_i`.
    fn error_norm(&self, e_i: impl Fn(usize) -> f64) -> f64 {
        let mut sum = 0.0;
        for i in 0..self.n_controlled {
            sum += (e_i(i) / scale(&self.tol, self.y[i], self.y_new[i])).powi(2);
        }
        (sum / self.n_controlled.max(1) as f64).sqrt()
    }

    fn attempt_rk4(&mut self, sys: &mut impl OdeSystem, h: f64) {
        for s in 1..4 {
            combine(&mut self.y_stage, &self.y, &self.dy, &self.k, RK4_A[s], h);
            sys.rhs(self.t + RK4_C[s] * h, &self.y_stage, &mut self.k[s - 1]);
        }
        combine(&mut self.y_new, &self.y, &self.dy, &self.k, &RK4_B, h);
        sys.rhs(self.t + h, &self.y_new, &mut self.dy_new);
        self.stats.evaluations += 4;
    }

    /// One Dormand-Prince attempt: fills `y_new`, `dy_new` (= k7) and returns the error norm.
    fn attempt_dopri5(&mut self, sys: &mut impl OdeSystem, h: f64) -> f64 {
        for s in 1..6 {
            combine(&mut self.y_stage, &self.y, &self.dy, &self.k, DP5_A[s], h);
            sys.rhs(self.t + DP5_C[s] * h, &self.y_stage, &mut self.k[s - 1]);
        }
        combine(&mut self.y_new, &self.y, &self.dy, &self.k, DP5_A[6], h);
        sys.rhs(self.t + h, &self.y_new, &mut self.dy_new);
        self.stats.evaluations += 6;
        let (k, k1, k7) = (&self.k, &self.dy, &self.dy_new);
        self.error_norm(|i| {
            h * (DP5_E[0] * k1[i]
                + DP5_E[2] * k[1][i]
                + DP5_E[3] * k[2][i]
                + DP5_E[4] * k[3][i]
                + DP5_E[5] * k[4][i]
                + DP5_E[6] * k7[i])
        })
    }

    /// Shampine's `r5 = h Σ d_j k_j` of the accepted Dormand-Prince step (before `accept`).
    fn dense_dopri5(&mut self, h: f64) {
        let (k, k1, k7) = (&self.k, &self.dy, &self.dy_new);
        for (i, r) in self.dense5.iter_mut().enumerate() {
            *r = h
                * (DP5_D[0] * k1[i]
                    + DP5_D[2] * k[1][i]
                    + DP5_D[3] * k[2][i]
                    + DP5_D[4] * k[3][i]
                    + DP5_D[5] * k[4][i]
                    + DP5_D[6] * k7[i]);
        }
    }

    /// One DOP853 attempt: fills `y_new` and returns Hairer's blended error norm.
    fn attempt_dop853(&mut self, sys: &mut impl OdeSystem, h: f64) -> f64 {
        for s in 1..12 {
            combine(
                &mut self.y_stage,
                &self.y,
                &self.dy,
                &self.k,
                DOP853_A[s],
                h,
            );
            sys.rhs(self.t + DOP853_C[s] * h, &self.y_stage, &mut self.k[s - 1]);
        }
        combine(&mut self.y_new, &self.y, &self.dy, &self.k, &DOP853_B, h);
        self.stats.evaluations += 11;
        let (mut err5, mut err3) = (0.0, 0.0);
        for i in 0..self.n_controlled {
            let stage = |j: usize| if j == 0 { self.dy[i] } else { self.k[j - 1][i] };
            let (mut e5, mut b) = (0.0, 0.0);
            for j in 0..12 {
                e5 += DOP853_ER[j] * stage(j);
                b += DOP853_B[j] * stage(j);
            }
            let e3 =
                b - DOP853_BHH[0] * stage(0) - DOP853_BHH[1] * stage(8) - DOP853_BHH[2] * stage(11);
            let sc = scale(&self.tol, self.y[i], self.y_new[i]);
            err5 += (e5 / sc).powi(2);
            err3 += (e3 / sc).powi(2);
        }
        let deno = err5 + 0.01 * err3;
        let deno = if deno > 0.0 { deno } else { 1.0 };
        h * err5 / (self.n_controlled.max(1) as f64 * deno).sqrt()
    }

    /// Forward-difference Jacobian and ∂f/∂t at (t, y); perturbations as in Hairer's RADAU5,
    /// `sqrt(eps · max(|y_j|, 1e-5))`, so that small components are not swamped by round-off.
    fn jacobian(&mut self, sys: &mut impl OdeSystem) {
        let Some(ros) = self.ros.as_mut() else { return };
        let n = self.y.len();
        self.y_stage.copy_from_slice(&self.y);
        for j in 0..n {
            let yj = self.y[j];
            self.y_stage[j] = yj + (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
            let delta = self.y_stage[j] - yj;
            sys.rhs(self.t, &self.y_stage, &mut self.dy_new);
            for (jac, (&f1, &f0)) in ros
                .jac
                .column_mut(j)
                .iter_mut()
                .zip(self.dy_new.iter().zip(&self.dy))
            {
                *jac = (f1 - f0) / delta;
            }
            self.y_stage[j] = yj;
        }
        let t1 = self.t + (f64::EPSILON * self.t.abs().max(1e-5)).sqrt();
        let delta = t1 - self.t;
        sys.rhs(t1, &self.y, &mut self.dy_new);
        for ((d, &f1), &f0) in ros.dfdt.iter_mut().zip(&self.dy_new).zip(&self.dy) {
            *d = (f1 - f0) / delta;
        }
        self.stats.evaluations += n as u64 + 1;
    }

    /// One RODAS3 attempt: fills `y_new`; returns the error norm, or infinity if the iteration
    /// matrix is singular.
    // Indexed loops keep the stage formulas readable side by side with the method's tableau.
    #[allow(clippy::needless_range_loop)]
    fn attempt_rosenbrock(&mut self, sys: &mut impl OdeSystem, h: f64) -> f64 {
        let (Some(ros), [k1, k2, k3, k4]) = (self.ros.as_ref(), &mut self.k[..]) else {
            unreachable!("Rosenbrock buffers are allocated in new")
        };
        let n = self.y.len();
        // LU on a fresh matrix per attempt: accepted for this method (work-precision studies only).
        let mut g = -ros.jac.clone();
        for i in 0..n {
            g[(i, i)] += 1.0 / (ROS_GAMMA * h);
        }
        let lu = g.lu();
        let solve = |k: &mut Vec<f64>| lu.solve_mut(&mut DVectorViewMut::from_slice(k, n));
        // Stages 1 and 2 share f(t, y).
        for i in 0..n {
            k1[i] = self.dy[i] + h * ROS_GAMMA1 * ros.dfdt[i];
        }
        let mut ok = solve(k1);
        for i in 0..n {
            k2[i] = self.dy[i] + ROS_C21 / h * k1[i] + h * ROS_GAMMA2 * ros.dfdt[i];
        }
        ok &= solve(k2);
        for i in 0..n {
            self.y_stage[i] = self.y[i] + 2.0 * k1[i];
        }
        sys.rhs(self.t + h, &self.y_stage, &mut self.dy_new);
        for i in 0..n {
            k3[i] = self.dy_new[i] + (ROS_C31 * k1[i] + ROS_C32 * k2[i]) / h;
        }
        ok &= solve(k3);
        for i in 0..n {
            self.y_stage[i] = self.y[i] + 2.0 * k1[i] + k3[i];
        }
        sys.rhs(self.t + h, &self.y_stage, &mut self.dy_new);
        for i in 0..n {
            k4[i] = self.dy_new[i] + (ROS_C41 * k1[i] + ROS_C42 * k2[i] + ROS_C43 * k3[i]) / h;
        }
        ok &= solve(k4);
        self.stats.evaluations += 2;
        if !ok {
            return f64::INFINITY;
        }
        for i in 0..n {
            self.y_new[i] = self.y_stage[i] + k4[i];
        }
        let k4 = &self.k[3];
        self.error_norm(|i| k4[i])
    }

    /// End of the last accepted step.
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Start of the last accepted step.
    pub fn t_prev(&self) -> f64 {
        self.t_prev
    }

    /// State at [`t`](Self::t).
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// State at [`t_prev`](Self::t_prev).
    pub fn y_prev(&self) -> &[f64] {
        &self.y_prev
    }

    /// f(t, y) at [`t`](Self::t).
    pub fn dy(&self) -> &[f64] {
        &self.dy
    }

    /// Dense output inside the last accepted step [t_prev, t]: writes y(t_eval) into `out`.
    /// Exact at both ends.
    pub fn dense(&self, t_eval: f64, out: &mut [f64]) {
        if t_eval == self.t {
            out.copy_from_slice(&self.y);
            return;
        }
        let h = self.t - self.t_prev;
        let th = (t_eval - self.t_prev) / h;
        let th1 = 1.0 - th;
        for (i, o) in out.iter_mut().enumerate() {
            let d = self.y[i] - self.y_prev[i];
            let b = h * self.dy_prev[i] - d;
            let c = d - h * self.dy[i] - b;
            *o = self.y_prev[i] + th * (d + th1 * (b + th * (c + th1 * self.dense5[i])));
        }
    }

    /// Work counters.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Counts an event handled by the driver, so that [`stats`](Self::stats) tells the whole story.
    pub fn record_event(&mut self) {
        self.stats.events += 1;
    }

    /// Currently proposed size of the next step.
    pub fn step_size(&self) -> f64 {
        self.h
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

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use ode_solvers::{SVector, System};
    use std::f64::consts::PI;

    /// A system from a closure.
    struct Sys<F>(usize, F);

    impl<F: FnMut(f64, &[f64], &mut [f64])> OdeSystem for Sys<F> {
        fn dim(&self) -> usize {
            self.0
        }
        fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
            (self.1)(t, y, dy)
        }
    }

    const ALL: [Method; 4] = [
        Method::Dopri5,
        Method::Dop853,
        Method::Rk4 { step: 0.01 },
        Method::Rosenbrock,
    ];

    fn tol(rtol: f64, atol: f64) -> Tolerances {
        Tolerances {
            rtol,
            atol,
            max_step: f64::INFINITY,
            initial_step: 0.0,
        }
    }

    /// Tolerances so loose that every step is accepted at exactly `h`.
    fn fixed(h: f64) -> Tolerances {
        Tolerances {
            rtol: 1e10,
            atol: 1e10,
            max_step: h,
            initial_step: h,
        }
    }

    /// Integrates from (t0, y0) to t_end; the last step must land on t_end exactly.
    fn run(
        method: Method,
        tol: Tolerances,
        n_controlled: usize,
        sys: &mut impl OdeSystem,
        t0: f64,
        y0: &[f64],
        t_end: f64,
    ) -> Integrator {
        let mut int = Integrator::new(method, y0.len(), n_controlled, tol);
        int.reset(sys, t0, y0);
        while int.t() < t_end {
            int.step(sys, t_end).unwrap();
            assert!(int.t() <= t_end);
        }
        assert_eq!(int.t(), t_end);
        int
    }

    /// Rotation q' = p, p' = -q together with the non-autonomous z' = -z + sin t.
    fn rotation_forced() -> Sys<impl FnMut(f64, &[f64], &mut [f64])> {
        Sys(3, |t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -y[0];
            dy[2] = -y[2] + t.sin();
        })
    }

    fn rotation_forced_exact(t: f64) -> [f64; 3] {
        [
            t.cos(),
            -t.sin(),
            1.5 * (-t).exp() + 0.5 * (t.sin() - t.cos()),
        ]
    }

    fn global_error(method: Method, h: f64) -> f64 {
        let t_end = 4.0;
        let int = run(
            method,
            fixed(h),
            3,
            &mut rotation_forced(),
            0.0,
            &[1.0, 0.0, 1.0],
            t_end,
        );
        let exact = rotation_forced_exact(t_end);
        int.y()
            .iter()
            .zip(exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn integrator_convergence_orders() {
        // (method, coarse step, expected order)
        let cases = [
            (Method::Dopri5, 0.2, 5),
            (Method::Dop853, 0.4, 8),
            (Method::Rosenbrock, 0.05, 3),
        ];
        for (method, h, order) in cases {
            let ratio = global_error(method, h) / global_error(method, h / 2.0);
            let ideal = 2f64.powi(order);
            assert!(
                ratio > 0.75 * ideal && ratio < 1.3 * ideal,
                "{method:?}: ratio {ratio}, ideal {ideal}"
            );
        }
        let rk4 = |h| global_error(Method::Rk4 { step: h }, 1.0);
        let ratio = rk4(0.1) / rk4(0.05);
        assert!(ratio > 14.0 && ratio < 18.0, "Rk4: ratio {ratio}");
        // Same step, much higher order.
        assert!(global_error(Method::Dop853, 0.2) < 1e-3 * global_error(Method::Dopri5, 0.2));
    }

    /// Van der Pol with mu = 5.
    fn van_der_pol(y: &[f64], dy: &mut [f64]) {
        dy[0] = y[1];
        dy[1] = 5.0 * (1.0 - y[0] * y[0]) * y[1] - y[0];
    }

    /// Kepler problem (mu = 1).
    fn kepler(y: &[f64], dy: &mut [f64]) {
        let r3 = (y[0] * y[0] + y[1] * y[1]).powf(1.5);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = -y[0] / r3;
        dy[3] = -y[1] / r3;
    }

    /// An autonomous right-hand side seen by the oracle crate.
    struct Oracle(fn(&[f64], &mut [f64]));

    impl<const D: usize> System<f64, SVector<f64, D>> for Oracle {
        fn system(&self, _t: f64, y: &SVector<f64, D>, dy: &mut SVector<f64, D>) {
            (self.0)(y.as_slice(), dy.as_mut_slice());
        }
    }

    /// Final states and accepted steps of ours and the oracle: (ours, theirs, our steps, their steps).
    type Comparison = (Vec<f64>, Vec<f64>, u64, u64);

    /// Our Dopri5 and ode_solvers' on the same problem.
    fn against_oracle<const D: usize>(
        rhs: fn(&[f64], &mut [f64]),
        y0: [f64; D],
        t_end: f64,
        rtol: f64,
    ) -> Comparison {
        let mut sys = Sys(D, |_t: f64, y: &[f64], dy: &mut [f64]| rhs(y, dy));
        let ours = run(
            Method::Dopri5,
            tol(rtol, rtol),
            D,
            &mut sys,
            0.0,
            &y0,
            t_end,
        );
        let mut theirs = ode_solvers::Dopri5::new(
            Oracle(rhs),
            0.0,
            t_end,
            t_end,
            SVector::from(y0),
            rtol,
            rtol,
        );
        theirs.set_output(ode_solvers::OutputType::Sparse);
        let stats = theirs.integrate().unwrap();
        let last = theirs.y_out().last().unwrap().as_slice().to_vec();
        (
            ours.y().to_vec(),
            last,
            ours.stats().steps,
            stats.accepted_steps as u64,
        )
    }

    /// Kepler orbit of eccentricity 0.5 over three periods.
    fn kepler_case(rtol: f64) -> Comparison {
        let e: f64 = 0.5;
        let y0 = [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()];
        against_oracle(kepler, y0, 3.0 * 2.0 * PI, rtol)
    }

    #[test]
    fn integrator_dopri5_matches_ode_solvers() {
        for problem in ["vdp", "kepler"] {
            let case = |rtol| match problem {
                "vdp" => against_oracle(van_der_pol, [2.0, 0.0], 30.0, rtol),
                _ => kepler_case(rtol),
            };
            let (ours, theirs, _, _) = case(1e-10);
            let size = theirs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in ours.iter().zip(&theirs) {
                assert!(
                    (a - b).abs() < 1e-7 * size,
                    "{problem}: {ours:?} vs {theirs:?}"
                );
            }
            let (_, _, our_steps, their_steps) = case(1e-6);
            let rel = (our_steps as f64 - their_steps as f64).abs() / their_steps as f64;
            assert!(rel < 0.2, "{problem}: {our_steps} steps vs {their_steps}");
        }
        // The Kepler orbit also returns to its start after whole periods.
        let (ours, _, _, _) = kepler_case(1e-10);
        let e: f64 = 0.5;
        assert_relative_eq!(ours[0], 1.0 - e, epsilon = 1e-7);
        assert_relative_eq!(ours[3], ((1.0 + e) / (1.0 - e)).sqrt(), epsilon = 1e-7);
    }

    #[test]
    fn integrator_pi_control_matches_i_control() {
        let e: f64 = 0.5;
        let y0 = [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()];
        let t_end = 2.0 * PI;
        let orbit = |control| {
            let mut sys = Sys(4, |_t: f64, y: &[f64], dy: &mut [f64]| kepler(y, dy));
            let mut int =
                Integrator::new(Method::Dopri5, 4, 4, tol(1e-8, 1e-8)).with_control(control);
            int.reset(&mut sys, 0.0, &y0);
            while int.t() < t_end {
                int.step(&mut sys, t_end).unwrap();
            }
            let error = int
                .y()
                .iter()
                .zip(y0)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            (error, int.stats().steps)
        };
        let (i_error, i_steps) = orbit(StepControl::default());
        let (pi_error, pi_steps) = orbit(StepControl {
            beta: 0.04,
            fac_max: 10.0,
            ..StepControl::default()
        });
        assert!(
            i_error < 1e-5 && pi_error < 1e-5,
            "errors {i_error}, {pi_error}"
        );
        assert!(
            pi_steps.abs_diff(i_steps) * 5 < i_steps,
            "steps {pi_steps} vs {i_steps}"
        );
    }

    #[test]
    fn integrator_dense_output() {
        let mid_error = |method: Method, h: f64| {
            let mut sys = Sys(1, |t: f64, _y: &[f64], dy: &mut [f64]| dy[0] = t.cos());
            let t0 = 0.3;
            let tol = if let Method::Rk4 { .. } = method {
                fixed(1.0)
            } else {
                fixed(h)
            };
            let mut int = Integrator::new(method, 1, 1, tol);
            int.reset(&mut sys, t0, &[t0.sin()]);
            int.step(&mut sys, t0 + h).unwrap();
            let mut out = [0.0];
            // Exact at both ends.
            int.dense(int.t_prev(), &mut out);
            assert_eq!(out, int.y_prev());
            int.dense(int.t(), &mut out);
            assert_eq!(out, int.y());
            let tm = t0 + 0.37 * h;
            int.dense(tm, &mut out);
            (out[0] - tm.sin()).abs()
        };
        // Dopri5's continuous extension is 4th order: local error O(h^5).
        let (coarse, fine) = (
            mid_error(Method::Dopri5, 0.4),
            mid_error(Method::Dopri5, 0.2),
        );
        assert!(coarse / fine > 24.0, "Dopri5 dense ratio {}", coarse / fine);
        assert!(fine < 1e-6 * 0.2, "Dopri5 dense error {fine}");
        // Cubic Hermite: local error O(h^4).
        for method in [
            Method::Dop853,
            Method::Rk4 { step: 1.0 },
            Method::Rosenbrock,
        ] {
            let ratio = mid_error(method, 0.4) / mid_error(method, 0.2);
            assert!(
                ratio > 12.0 && ratio < 24.0,
                "{method:?} dense ratio {ratio}"
            );
        }
        // Hermite is exact on cubics, Shampine's extension is not needed for that.
        let mut sys = Sys(1, |t: f64, _y: &[f64], dy: &mut [f64]| dy[0] = 3.0 * t * t);
        let mut int = Integrator::new(Method::Dop853, 1, 1, fixed(1.0));
        int.reset(&mut sys, 0.0, &[0.0]);
        int.step(&mut sys, 1.0).unwrap();
        let mut out = [0.0];
        int.dense(0.5, &mut out);
        assert_relative_eq!(out[0], 0.125, epsilon = 1e-14);
    }

    #[test]
    fn integrator_dopri5_energy_drift() {
        let mut sys = Sys(2, |_t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -y[0];
        });
        let t_end = 10.0 * 2.0 * PI;
        let mut int = Integrator::new(Method::Dopri5, 2, 2, tol(1e-10, 1e-10));
        int.reset(&mut sys, 0.0, &[1.0, 0.0]);
        let mut drift: f64 = 0.0;
        while int.t() < t_end {
            int.step(&mut sys, t_end).unwrap();
            let y = int.y();
            drift = drift.max((0.5 * (y[0] * y[0] + y[1] * y[1]) - 0.5).abs());
        }
        assert!(drift < 1e-8, "energy drift {drift}");
        assert!(drift > 0.0);
    }

    #[test]
    fn integrator_rosenbrock_is_efficient_on_stiff_problems() {
        let lambda = 1e4;
        let exact = |t: f64| {
            let l2 = lambda * lambda + 1.0;
            lambda / l2 * (lambda * t.cos() + t.sin()) - lambda * lambda / l2 * (-lambda * t).exp()
        };
        let t_end = 2.0;
        let steps = |method| {
            let mut sys = Sys(1, |t: f64, y: &[f64], dy: &mut [f64]| {
                dy[0] = -lambda * (y[0] - t.cos())
            });
            let int = run(method, tol(1e-6, 1e-8), 1, &mut sys, 0.0, &[0.0], t_end);
            assert_relative_eq!(int.y()[0], exact(t_end), max_relative = 1e-5);
            int.stats().steps
        };
        let (ros, dopri) = (steps(Method::Rosenbrock), steps(Method::Dopri5));
        assert!(dopri > 20 * ros, "Dopri5 {dopri} steps, Rosenbrock {ros}");

        // Robertson's chemical kinetics; reference values at t = 40 from Hairer & Wanner.
        let mut sys = Sys(3, |_t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
            dy[2] = 3e7 * y[1] * y[1];
            dy[1] = -dy[0] - dy[2];
        });
        let int = run(
            Method::Rosenbrock,
            tol(1e-6, 1e-10),
            3,
            &mut sys,
            0.0,
            &[1.0, 0.0, 0.0],
            40.0,
        );
        assert_relative_eq!(int.y()[0], 0.7158270687, max_relative = 1e-4);
        assert_relative_eq!(int.y()[1], 9.185534764e-6, max_relative = 1e-3);
        assert_relative_eq!(int.y()[2], 0.2841637457, max_relative = 1e-4);
        assert!(int.stats().steps < 300, "{:?}", int.stats());
    }

    #[test]
    fn integrator_locate_root() {
        let t = locate_root(f64::cos, 1.0, 1f64.cos(), 2.0, 2f64.cos(), 1e-12);
        assert!((t - PI / 2.0).abs() < 1e-12, "root {t}");
        // Superlinear on a curved g: plain regula falsi, stuck at one end, needs far more.
        let mut evaluations = 0;
        let g = |t: f64| {
            evaluations += 1;
            t.exp() - 2.0
        };
        let t = locate_root(g, 0.0, -1.0, 3.0, 3f64.exp() - 2.0, 1e-12);
        assert!((t - 2f64.ln()).abs() < 1e-12, "root {t}");
        assert!(evaluations <= 15, "{evaluations} evaluations");
        assert!(
            t.exp() - 2.0 >= 0.0,
            "the root is returned from the far side of the sign change"
        );
        // g(tb) == 0 returns tb without evaluating g.
        let t = locate_root(
            |_| panic!("no evaluation needed"),
            1.0,
            -1.0,
            2.0,
            0.0,
            1e-12,
        );
        assert_eq!(t, 2.0);
        // A root at ta is approached from above.
        let t = locate_root(|t| t - 1.0, 1.0, 0.0, 3.0, 2.0, 1e-10);
        assert!((t - 1.0).abs() < 1e-10, "root {t}");
    }

    #[test]
    fn integrator_reports_non_finite_state() {
        for method in ALL {
            let mut sys = Sys(2, |t: f64, _y: &[f64], dy: &mut [f64]| {
                dy[0] = 1.0;
                dy[1] = if t > 0.5 { f64::NAN } else { 0.0 };
            });
            let mut int = Integrator::new(method, 2, 1, tol(1e-6, 1e-6));
            int.reset(&mut sys, 0.0, &[0.0, 0.0]);
            let result = (0..10_000)
                .map(|_| int.step(&mut sys, 1.0))
                .find(Result::is_err);
            match result {
                Some(Err(Error::Integration { time, cause })) => {
                    assert!((0.0..=0.5).contains(&time), "{method:?}: {time} {cause}");
                    assert!(cause.contains("non-finite"), "{method:?}: {cause}");
                }
                other => panic!("{method:?}: expected an integration error, got {other:?}"),
            }
        }
        // A step limit behind t is an error too.
        let mut sys = Sys(1, |_t: f64, _y: &[f64], dy: &mut [f64]| dy[0] = 1.0);
        let mut int = Integrator::new(Method::Dopri5, 1, 1, tol(1e-6, 1e-6));
        int.reset(&mut sys, 1.0, &[0.0]);
        assert!(matches!(
            int.step(&mut sys, 0.5),
            Err(Error::Integration { .. })
        ));
    }

    #[test]
    fn integrator_uncontrolled_components_do_not_limit_the_step() {
        let make = || {
            Sys(3, |t: f64, y: &[f64], dy: &mut [f64]| {
                dy[0] = y[1];
                dy[1] = -y[0];
                dy[2] = 1e12 * (40.0 * t).sin(); // a wildly varying quadrature
            })
        };
        let steps = |n_controlled| {
            let int = run(
                Method::Dopri5,
                tol(1e-8, 1e-8),
                n_controlled,
                &mut make(),
                0.0,
                &[1.0, 0.0, 0.0],
                10.0,
            );
            int.stats().steps
        };
        let mut plain = Sys(2, |_t: f64, y: &[f64], dy: &mut [f64]| {
            dy[0] = y[1];
            dy[1] = -y[0];
        });
        let reference = run(
            Method::Dopri5,
            tol(1e-8, 1e-8),
            2,
            &mut plain,
            0.0,
            &[1.0, 0.0],
            10.0,
        )
        .stats()
        .steps;
        assert_eq!(steps(2), reference);
        assert!(steps(3) > 2 * reference, "{} vs {reference}", steps(3));
    }

    #[test]
    fn integrator_counts_evaluations() {
        let vdp = || Sys(2, |_t: f64, y: &[f64], dy: &mut [f64]| van_der_pol(y, dy));
        let y0 = [2.0, 0.0];
        // A deliberately large first step provokes rejections.
        let given = Tolerances {
            initial_step: 0.5,
            ..tol(1e-6, 1e-6)
        };

        let s = run(Method::Dopri5, given, 2, &mut vdp(), 0.0, &y0, 5.0).stats();
        assert!(s.rejected > 0);
        assert_eq!(s.evaluations, 1 + 6 * (s.steps + s.rejected));
        let s = run(
            Method::Dopri5,
            tol(1e-6, 1e-6),
            2,
            &mut vdp(),
            0.0,
            &y0,
            5.0,
        )
        .stats();
        assert_eq!(
            s.evaluations,
            2 + 6 * (s.steps + s.rejected),
            "automatic initial step costs one"
        );

        let s = run(Method::Dop853, given, 2, &mut vdp(), 0.0, &y0, 5.0).stats();
        assert!(s.rejected > 0);
        assert_eq!(s.evaluations, 1 + 11 * (s.steps + s.rejected) + s.steps);

        let s = run(
            Method::Rk4 { step: 0.01 },
            given,
            2,
            &mut vdp(),
            0.0,
            &y0,
            5.0,
        )
        .stats();
        assert_eq!((s.steps, s.rejected), (500, 0));
        assert_eq!(s.evaluations, 1 + 4 * s.steps);

        // Per step: Jacobian (dim) + df/dt + f at the new point; 2 per attempt.
        let s = run(Method::Rosenbrock, given, 2, &mut vdp(), 0.0, &y0, 5.0).stats();
        assert!(s.rejected > 0);
        assert_eq!(
            s.evaluations,
            1 + (2 + 2) * s.steps + 2 * (s.steps + s.rejected)
        );

        let mut int = Integrator::new(Method::Dopri5, 2, 2, given);
        int.record_event();
        assert_eq!(int.stats().events, 1);
    }

    #[test]
    fn integrator_reset_restarts_at_a_discontinuity() {
        let mut sys = Sys(1, |_t: f64, _y: &[f64], dy: &mut [f64]| dy[0] = 1.0);
        let mut int = Integrator::new(Method::Dopri5, 1, 1, tol(1e-8, 1e-8));
        int.reset(&mut sys, 0.0, &[0.0]);
        int.step(&mut sys, 1.0).unwrap();
        int.reset(&mut sys, 2.0, &[5.0]);
        assert_eq!(
            (int.t(), int.t_prev(), int.y(), int.y_prev(), int.dy()),
            (2.0, 2.0, &[5.0][..], &[5.0][..], &[1.0][..])
        );
        int.step(&mut sys, 3.0).unwrap();
        assert!(int.t() > 2.0 && int.t() <= 3.0 && int.step_size() > 0.0);
        assert_relative_eq!(int.y()[0], 5.0 + int.t() - 2.0, epsilon = 1e-12);
    }
}
