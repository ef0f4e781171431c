//! Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, Solving ODEs I, §II.5): the tableau, one
//! trial step and its 4th-order continuous extension.

use super::{Dense, Integrator, OdeSystem, Trial};

// Dormand–Prince 5(4) tableau.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (Hairer's DOPRI5 `contd5`).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

impl<const N: usize> Integrator<N> {
    /// One Dormand–Prince 5(4) step of size h from the current point; stages in `self.k[..7]`.
    pub(super) fn trial_dp54<S: OdeSystem<N>>(&mut self, sys: &S, h: f64) -> Trial<N> {
        let t = self.t;
        let y = self.y;
        let k1 = self.f;
        let mut k2 = [0.0; N];
        let mut k3 = [0.0; N];
        let mut k4 = [0.0; N];
        let mut k5 = [0.0; N];
        let mut k6 = [0.0; N];
        let mut k7 = [0.0; N];
        // Each stage sum adds its newest stage last, to the older ones' sum (ready earlier):
        // the stage then waits one multiply and one add on the newest right-hand side.
        let s: [f64; N] = std::array::from_fn(|i| y[i] + h * A21 * k1[i]);
        sys.rhs(t + C2 * h, &s, &mut k2);
        let s: [f64; N] = std::array::from_fn(|i| (y[i] + h * (A31 * k1[i])) + h * A32 * k2[i]);
        sys.rhs(t + C3 * h, &s, &mut k3);
        let s: [f64; N] =
            std::array::from_fn(|i| (y[i] + h * (A41 * k1[i] + A42 * k2[i])) + h * A43 * k3[i]);
        sys.rhs(t + C4 * h, &s, &mut k4);
        let s: [f64; N] = std::array::from_fn(|i| {
            (y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i])) + h * A54 * k4[i]
        });
        sys.rhs(t + C5 * h, &s, &mut k5);
        let s: [f64; N] = std::array::from_fn(|i| {
            (y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i])) + h * A65 * k5[i]
        });
        sys.rhs(t + h, &s, &mut k6);
        let y1: [f64; N] = std::array::from_fn(|i| {
            (y[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i])) + h * B6 * k6[i]
        });
        sys.rhs(t + h, &y1, &mut k7);
        self.stats.rhs_evals += 6;
        // k7 last again: the error, and through it the next step's size, waits on it.
        let e: [f64; N] = std::array::from_fn(|i| {
            h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i]) + h * E7 * k7[i]
        });
        let err2 = self.norm_squared(&e, &y, &y1);
        self.k[..7].copy_from_slice(&[k1, k2, k3, k4, k5, k6, k7]);
        Trial { y1, f1: k7, err2 }
    }

    pub(super) fn dense_dp54(&self, h: f64, y1: &[f64; N]) -> Dense<N> {
        let y0 = &self.y;
        let k = &self.k;
        let mut r = [[0.0; N]; 8];
        for i in 0..N {
            let ydiff = y1[i] - y0[i];
            let bspl = h * k[0][i] - ydiff;
            r[0][i] = y0[i];
            r[1][i] = ydiff;
            r[2][i] = bspl;
            r[3][i] = ydiff - h * k[6][i] - bspl;
            r[4][i] = h
                * (D1 * k[0][i]
                    + D3 * k[2][i]
                    + D4 * k[3][i]
                    + D5 * k[4][i]
                    + D6 * k[5][i]
                    + D7 * k[6][i]);
        }
        Dense {
            t0: self.t,
            h,
            r,
            top: 4,
        }
    }
}
