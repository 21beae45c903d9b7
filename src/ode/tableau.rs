//! Butcher tableaux of the explicit Runge-Kutta methods, as data: a method is its
//! coefficients plus how it estimates its error and interpolates; one stepping routine in
//! [`super::Integrator`] runs them all.

use super::Method;
use nalgebra::Complex;

/// How a method estimates its local error.
pub(super) enum Estimate {
    /// No estimate: fixed step.
    None,
    /// `err_i = h Σ_j e_j k_j` over the stages and, last, f at the new point
    /// (first-same-as-last): the difference of the embedded pair's weights.
    Embedded(&'static [f64]),
    /// Hairer's DOP853 blend of the 5th-order difference `er` and the 3rd-order estimate with
    /// weights `bhh` on stages 1, 9 and 12:
    /// `err = |h| E5² / sqrt(n (E5² + 0.01 E3²))`.
    Blended {
        /// Weights of the 5th-order error estimate.
        er: &'static [f64],
        /// Weights of the 3rd-order estimate on stages 1, 9 and 12.
        bhh: [f64; 3],
    },
}

/// How a method interpolates inside an accepted step.
pub(super) enum Dense {
    /// Cubic Hermite interpolation of (y, f) at both ends (3rd order).
    Hermite,
    /// Shampine's 4th-order extension: the Hermite cubic plus `r5 = h Σ_j d_j k_j` (stages,
    /// then f at the new point).
    Shampine(&'static [f64]),
}

/// An explicit Runge-Kutta method.
pub(super) struct Tableau {
    /// Rows of the Butcher matrix, one per stage (the first is empty).
    pub a: &'static [&'static [f64]],
    /// Stage times as fractions of the step.
    pub c: &'static [f64],
    /// Weights of the solution that advances.
    pub b: &'static [f64],
    /// f at the new point is a stage of the error estimate (first-same-as-last), evaluated
    /// with every attempt; otherwise it is evaluated once the step is accepted.
    pub fsal: bool,
    /// Error estimate.
    pub estimate: Estimate,
    /// Dense output.
    pub dense: Dense,
    /// Order of the error estimate, for the step-size controller and the first step.
    pub order: f64,
}

impl Method {
    /// The method's tableau.
    pub(super) fn tableau(&self) -> &'static Tableau {
        match self {
            Method::Dopri5 => &DOPRI5,
            Method::Dop853 => &DOP853,
            Method::Rk4 { .. } => &RK4,
        }
    }

    /// Where the method turns unstable along a ray of the complex plane of `z = hλ`: the
    /// smallest `r > 0` with `|R(r e^{iθ})| = 1`, `θ = angle` (rad from the positive real
    /// axis), where `R(z) = 1 + z bᵀ(I − zA)⁻¹ 1` is the stability function (the step's
    /// amplification of `y' = λy`). A step `h` on an eigenvalue `λ` at that angle is stable
    /// while `h|λ|` is below it: for the classical RK4, 2.785 on the negative real axis and
    /// 2√2 on the imaginary one. 0 on a ray where `|R|` exceeds 1 from the start (into the
    /// right half-plane, where the exact solution grows too); `None` if `|R|` stays within 1
    /// up to `|z| = 50`.
    pub fn stability_boundary(&self, angle: f64) -> Option<f64> {
        let tab = self.tableau();
        let direction = Complex::from_polar(1.0, angle);
        // The stage values, cleared and refilled for each r.
        let mut k: Vec<Complex<f64>> = Vec::with_capacity(tab.c.len());
        let mut amplification = |r: f64| {
            let z = direction * r;
            k.clear();
            for row in tab.a {
                let sum: Complex<f64> = row.iter().zip(&k).map(|(a, k)| k * *a).sum();
                k.push(Complex::new(1.0, 0.0) + z * sum);
            }
            let sum: Complex<f64> = tab.b.iter().zip(&k).map(|(b, k)| k * *b).sum();
            (Complex::new(1.0, 0.0) + z * sum).norm()
        };
        // Scan outwards for the first |R| > 1, then bisect the crossing.
        const DR: f64 = 1e-3;
        let first = (1..=50_000)
            .map(|i| i as f64 * DR)
            .find(|&r| amplification(r) > 1.0)?;
        if first == DR {
            return Some(0.0);
        }
        let (mut lo, mut hi) = (first - DR, first);
        while hi - lo > 1e-12 * hi {
            let mid = 0.5 * (lo + hi);
            if amplification(mid) > 1.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }
}

/// Most stages of a method (DOP853's).
pub(super) const MAX_STAGES: usize = 12;

/// Dormand-Prince 5(4) with Shampine's dense output.
pub(super) const DOPRI5: Tableau = Tableau {
    a: DP5_A.split_at(6).0,
    c: DP5_C.split_at(6).0,
    b: DP5_A[6],
    fsal: true,
    estimate: Estimate::Embedded(&DP5_E),
    dense: Dense::Shampine(&DP5_D),
    order: 5.0,
};

/// Hairer's DOP853.
const DOP853: Tableau = Tableau {
    a: &DOP853_A,
    c: &DOP853_C,
    b: &DOP853_B,
    fsal: false,
    estimate: Estimate::Blended {
        er: &DOP853_ER,
        bhh: DOP853_BHH,
    },
    dense: Dense::Hermite,
    order: 8.0,
};

/// The classical 4th-order method (fixed step).
const RK4: Tableau = Tableau {
    a: &RK4_A,
    c: &RK4_C,
    b: &RK4_B,
    fsal: false,
    estimate: Estimate::None,
    dense: Dense::Hermite,
    order: 4.0,
};

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
