//! DOP853: the explicit Runge–Kutta pair 8(5,3) of Dormand & Prince with
//! its 7th-order dense output (Hairer, Nørsett & Wanner, Solving ODEs I, §II.10). Transcribed
//! from scipy's `scipy/integrate/_ivp/dop853_coefficients.py`, itself taken from Hairer's
//! `dop853.f` (<http://www.unige.ch/~hairer/software.html>); the indices are scipy's: stages
//! 0–11 make the step, stage 12 is f(t + h, y1) (first-same-as-last), stages 13–15 exist only
//! for the dense output. The coefficients, then one trial step and the dense output.

// Transcribed digit for digit.
#![allow(clippy::excessive_precision)]

use super::{Dense, Integrator, OdeSystem, Step, Trial};

pub const STAGES: usize = 12;
pub const STAGES_EXTENDED: usize = 16;

pub const C: [f64; STAGES_EXTENDED] = [
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
    1.0,
    0.1,
    0.2,
    0.777777777777777777777777777778,
];

/// Row i holds a[i][0..i]; zeros elsewhere.
pub const A: [[f64; STAGES_EXTENDED]; STAGES_EXTENDED] = {
    let mut a = [[0.0; STAGES_EXTENDED]; STAGES_EXTENDED];
    a[1][0] = 5.26001519587677318785587544488e-2;

    a[2][0] = 1.97250569845378994544595329183e-2;
    a[2][1] = 5.91751709536136983633785987549e-2;

    a[3][0] = 2.95875854768068491816892993775e-2;
    a[3][2] = 8.87627564304205475450678981324e-2;

    a[4][0] = 2.41365134159266685502369798665e-1;
    a[4][2] = -8.84549479328286085344864962717e-1;
    a[4][3] = 9.24834003261792003115737966543e-1;

    a[5][0] = 3.7037037037037037037037037037e-2;
    a[5][3] = 1.70828608729473871279604482173e-1;
    a[5][4] = 1.25467687566822425016691814123e-1;

    a[6][0] = 3.7109375e-2;
    a[6][3] = 1.70252211019544039314978060272e-1;
    a[6][4] = 6.02165389804559606850219397283e-2;
    a[6][5] = -1.7578125e-2;

    a[7][0] = 3.70920001185047927108779319836e-2;
    a[7][3] = 1.70383925712239993810214054705e-1;
    a[7][4] = 1.07262030446373284651809199168e-1;
    a[7][5] = -1.53194377486244017527936158236e-2;
    a[7][6] = 8.27378916381402288758473766002e-3;

    a[8][0] = 6.24110958716075717114429577812e-1;
    a[8][3] = -3.36089262944694129406857109825;
    a[8][4] = -8.68219346841726006818189891453e-1;
    a[8][5] = 2.75920996994467083049415600797e1;
    a[8][6] = 2.01540675504778934086186788979e1;
    a[8][7] = -4.34898841810699588477366255144e1;

    a[9][0] = 4.77662536438264365890433908527e-1;
    a[9][3] = -2.48811461997166764192642586468;
    a[9][4] = -5.90290826836842996371446475743e-1;
    a[9][5] = 2.12300514481811942347288949897e1;
    a[9][6] = 1.52792336328824235832596922938e1;
    a[9][7] = -3.32882109689848629194453265587e1;
    a[9][8] = -2.03312017085086261358222928593e-2;

    a[10][0] = -9.3714243008598732571704021658e-1;
    a[10][3] = 5.18637242884406370830023853209;
    a[10][4] = 1.09143734899672957818500254654;
    a[10][5] = -8.14978701074692612513997267357;
    a[10][6] = -1.85200656599969598641566180701e1;
    a[10][7] = 2.27394870993505042818970056734e1;
    a[10][8] = 2.49360555267965238987089396762;
    a[10][9] = -3.0467644718982195003823669022;

    a[11][0] = 2.27331014751653820792359768449;
    a[11][3] = -1.05344954667372501984066689879e1;
    a[11][4] = -2.00087205822486249909675718444;
    a[11][5] = -1.79589318631187989172765950534e1;
    a[11][6] = 2.79488845294199600508499808837e1;
    a[11][7] = -2.85899827713502369474065508674;
    a[11][8] = -8.87285693353062954433549289258;
    a[11][9] = 1.23605671757943030647266201528e1;
    a[11][10] = 6.43392746015763530355970484046e-1;

    // Row 12 is the weights b of the 8th-order solution.
    a[12][0] = 5.42937341165687622380535766363e-2;
    a[12][5] = 4.45031289275240888144113950566;
    a[12][6] = 1.89151789931450038304281599044;
    a[12][7] = -5.8012039600105847814672114227;
    a[12][8] = 3.1116436695781989440891606237e-1;
    a[12][9] = -1.52160949662516078556178806805e-1;
    a[12][10] = 2.01365400804030348374776537501e-1;
    a[12][11] = 4.47106157277725905176885569043e-2;

    a[13][0] = 5.61675022830479523392909219681e-2;
    a[13][6] = 2.53500210216624811088794765333e-1;
    a[13][7] = -2.46239037470802489917441475441e-1;
    a[13][8] = -1.24191423263816360469010140626e-1;
    a[13][9] = 1.5329179827876569731206322685e-1;
    a[13][10] = 8.20105229563468988491666602057e-3;
    a[13][11] = 7.56789766054569976138603589584e-3;
    a[13][12] = -8.298e-3;

    a[14][0] = 3.18346481635021405060768473261e-2;
    a[14][5] = 2.83009096723667755288322961402e-2;
    a[14][6] = 5.35419883074385676223797384372e-2;
    a[14][7] = -5.49237485713909884646569340306e-2;
    a[14][10] = -1.08347328697249322858509316994e-4;
    a[14][11] = 3.82571090835658412954920192323e-4;
    a[14][12] = -3.40465008687404560802977114492e-4;
    a[14][13] = 1.41312443674632500278074618366e-1;

    a[15][0] = -4.28896301583791923408573538692e-1;
    a[15][5] = -4.69762141536116384314449447206;
    a[15][6] = 7.68342119606259904184240953878;
    a[15][7] = 4.06898981839711007970213554331;
    a[15][8] = 3.56727187455281109270669543021e-1;
    a[15][12] = -1.39902416515901462129418009734e-3;
    a[15][13] = 2.9475147891527723389556272149;
    a[15][14] = -9.15095847217987001081870187138;
    a
};

/// Weights of the 8th-order solution.
pub const B: [f64; STAGES] = {
    let mut b = [0.0; STAGES];
    let mut i = 0;
    while i < STAGES {
        b[i] = A[12][i];
        i += 1;
    }
    b
};

/// 3rd-order error weights (b − b̂₃), as in Hairer's `er`/`bhh` pair.
pub const E3: [f64; STAGES] = {
    let mut e = B;
    e[0] -= 0.244094488188976377952755905512;
    e[8] -= 0.733846688281611857341361741547;
    e[11] -= 0.220588235294117647058823529412e-1;
    e
};

/// 5th-order error weights.
pub const E5: [f64; STAGES] = {
    let mut e = [0.0; STAGES];
    e[0] = 0.1312004499419488073250102996e-1;
    e[5] = -0.1225156446376204440720569753e1;
    e[6] = -0.4957589496572501915214079952;
    e[7] = 0.1664377182454986536961530415e1;
    e[8] = -0.3503288487499736816886487290;
    e[9] = 0.3341791187130174790297318841;
    e[10] = 0.8192320648511571246570742613e-1;
    e[11] = -0.2235530786388629525884427845e-1;
    e
};

/// Dense-output weights of the four highest coefficients (the first three come from the end
/// values and derivatives).
pub const D: [[f64; STAGES_EXTENDED]; 4] = {
    let mut d = [[0.0; STAGES_EXTENDED]; 4];
    d[0][0] = -0.84289382761090128651353491142e1;
    d[0][5] = 0.56671495351937776962531783590;
    d[0][6] = -0.30689499459498916912797304727e1;
    d[0][7] = 0.23846676565120698287728149680e1;
    d[0][8] = 0.21170345824450282767155149946e1;
    d[0][9] = -0.87139158377797299206789907490;
    d[0][10] = 0.22404374302607882758541771650e1;
    d[0][11] = 0.63157877876946881815570249290;
    d[0][12] = -0.88990336451333310820698117400e-1;
    d[0][13] = 0.18148505520854727256656404962e2;
    d[0][14] = -0.91946323924783554000451984436e1;
    d[0][15] = -0.44360363875948939664310572000e1;

    d[1][0] = 0.10427508642579134603413151009e2;
    d[1][5] = 0.24228349177525818288430175319e3;
    d[1][6] = 0.16520045171727028198505394887e3;
    d[1][7] = -0.37454675472269020279518312152e3;
    d[1][8] = -0.22113666853125306036270938578e2;
    d[1][9] = 0.77334326684722638389603898808e1;
    d[1][10] = -0.30674084731089398182061213626e2;
    d[1][11] = -0.93321305264302278729567221706e1;
    d[1][12] = 0.15697238121770843886131091075e2;
    d[1][13] = -0.31139403219565177677282850411e2;
    d[1][14] = -0.93529243588444783865713862664e1;
    d[1][15] = 0.35816841486394083752465898540e2;

    d[2][0] = 0.19985053242002433820987653617e2;
    d[2][5] = -0.38703730874935176555105901742e3;
    d[2][6] = -0.18917813819516756882830838328e3;
    d[2][7] = 0.52780815920542364900561016686e3;
    d[2][8] = -0.11573902539959630126141871134e2;
    d[2][9] = 0.68812326946963000169666922661e1;
    d[2][10] = -0.10006050966910838403183860980e1;
    d[2][11] = 0.77771377980534432092869265740;
    d[2][12] = -0.27782057523535084065932004339e1;
    d[2][13] = -0.60196695231264120758267380846e2;
    d[2][14] = 0.84320405506677161018159903784e2;
    d[2][15] = 0.11992291136182789328035130030e2;

    d[3][0] = -0.25693933462703749003312586129e2;
    d[3][5] = -0.15418974869023643374053993627e3;
    d[3][6] = -0.23152937917604549567536039109e3;
    d[3][7] = 0.35763911791061412378285349910e3;
    d[3][8] = 0.93405324183624310003907691704e2;
    d[3][9] = -0.37458323136451633156875139351e2;
    d[3][10] = 0.10409964950896230045147246184e3;
    d[3][11] = 0.29840293426660503123344363579e2;
    d[3][12] = -0.43533456590011143754432175058e2;
    d[3][13] = 0.96324553959188282948394950600e2;
    d[3][14] = -0.39177261675615439165231486172e2;
    d[3][15] = -0.14972683625798562581422125276e3;
    d
};

/// Σ_j c_j k_j componentwise, j ascending from 0.0 (the order of the scalar loops this
/// replaced, so results are bit-identical). Row by row: the inner loop runs over the N
/// components of one stage, contiguous and of constant length, which the compiler unrolls and
/// vectorises; summed column by column (one component over all stages) it cost ~370
/// instructions per stage on the bare block (N = 6), more than the right-hand side itself.
/// The tableau's zero coefficients (a quarter of DOP853's a_sj below the diagonal, and of its
/// weights) are skipped: adding 0·k changes no sum, and with the row a constant (the stages
/// are written out one by one) the test folds away.
#[inline(always)]
fn combine<const N: usize>(c: &[f64], k: &[[f64; N]]) -> [f64; N] {
    let mut acc = [0.0; N];
    for (cj, kj) in c.iter().zip(k) {
        if *cj != 0.0 {
            for i in 0..N {
                acc[i] += cj * kj[i];
            }
        }
    }
    acc
}

/// y0 + h Σ_j c_j k_j with the newest stage's term added last, to the rest's sum: the stage
/// then waits on the newest right-hand side for one multiply and one add, not four (the
/// older stages' sum is ready before it arrives). The sum differs from the plain one by
/// roundoff only.
#[inline(always)]
fn newest_last<const N: usize>(y0: &[f64; N], h: f64, c: &[f64], k: &[[f64; N]]) -> [f64; N] {
    let (newest, older) = c.split_last().expect("a stage reads at least one stage");
    let acc = combine(older, &k[..older.len()]);
    let base: [f64; N] = std::array::from_fn(|i| y0[i] + h * acc[i]);
    let hc = h * newest;
    std::array::from_fn(|i| base[i] + hc * k[older.len()][i])
}

/// The stages `$s…` one by one, each with its row of the tableau a constant.
macro_rules! stages {
    ($integ:expr, $sys:expr, $start:expr, $h:expr; $($s:literal)*) => {
        $( $integ.dop853_stage($sys, $start, $h, $s); )*
    };
}

impl<const N: usize> Integrator<N> {
    /// Stage `s` of the extended DOP853 tableau, for the step of size h from (t0, y0), into
    /// `self.k[s]`.
    #[inline(always)]
    fn dop853_stage<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        (t0, y0): (f64, &[f64; N]),
        h: f64,
        s: usize,
    ) {
        let ys = newest_last(y0, h, &A[s][..s], &self.k[..s]);
        let mut ks = [0.0; N];
        sys.rhs(t0 + C[s] * h, &ys, &mut ks);
        self.k[s] = ks;
    }

    /// One DOP853 step of size h; stages in `self.k[..13]` (k[12] = f(t + h, y1)). The error
    /// is Hairer's: the 5th-order estimate, damped where the 3rd-order one is much smaller,
    /// err = |h|·‖e5‖² / √(‖e5‖² + 0.01‖e3‖²), per norm group (returned squared).
    pub(super) fn trial_dop853<S: OdeSystem<N>>(&mut self, sys: &S, h: f64) -> Trial<N> {
        self.k[0] = self.f;
        let y = self.y;
        stages!(self, sys, (self.t, &y), h; 1 2 3 4 5 6 7 8 9 10 11);
        let y1 = newest_last(&y, h, &B, &self.k[..B.len()]);
        let mut f1 = [0.0; N];
        sys.rhs(self.t + h, &y1, &mut f1);
        self.k[12] = f1;
        self.stats.rhs_evals += 12;
        let e5 = combine(&E5[..STAGES], &self.k);
        let e3 = combine(&E3[..STAGES], &self.k);
        // Squared, err² = h²·‖e5‖⁴ / (‖e5‖² + 0.01‖e3‖²): no square root before the step
        // control (see `norm_squared`).
        let mut err2: f64 = 0.0;
        for range in self.groups() {
            let (mut e5sum, mut e3sum, mut n) = (0.0, 0.0, 0);
            for i in range {
                if !self.opts.atol[i].is_finite() {
                    continue;
                }
                let inv_sc = 1.0 / self.error_scale(i, y[i], y1[i]);
                e5sum += (e5[i] * inv_sc) * (e5[i] * inv_sc);
                e3sum += (e3[i] * inv_sc) * (e3[i] * inv_sc);
                n += 1;
            }
            if n > 0 && (e5sum > 0.0 || e3sum > 0.0) {
                let denominator = (e5sum + 0.01 * e3sum) * n as f64;
                // Squared, a finite error beyond ~1e154 would overflow where the norm did not:
                // capped, it is rejected as a large error, not taken for a non-finite one.
                let squared = h * h * e5sum * (e5sum / denominator);
                err2 = err2.max(if e5sum.is_finite() {
                    squared.min(f64::MAX)
                } else {
                    squared
                });
            }
        }
        Trial { y1, f1, err2 }
    }

    /// DOP853's 7th-order dense output of the step `step` (its start and size, and its end
    /// y1) whose stages are in `self.k`: three more stages, then the coefficients.
    pub(super) fn dense_dop853<S: OdeSystem<N>>(&mut self, sys: &S, step: &Step<N>) -> Dense<N> {
        let (y0, h, y1) = (&step.y0, step.h, &step.y1);
        stages!(self, sys, (step.t0, y0), h; 13 14 15);
        self.stats.rhs_evals += 3;
        let k = &self.k;
        let mut r = [[0.0; N]; 8];
        for (row, d) in D.iter().enumerate() {
            let acc = combine(d, k);
            r[4 + row] = std::array::from_fn(|i| h * acc[i]);
        }
        for i in 0..N {
            let dy = y1[i] - y0[i];
            r[0][i] = y0[i];
            r[1][i] = dy;
            r[2][i] = h * k[0][i] - dy;
            r[3][i] = 2.0 * dy - h * (k[12][i] + k[0][i]);
        }
        Dense {
            t0: step.t0,
            h,
            r,
            top: 7,
        }
    }
}
