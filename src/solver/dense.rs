//! Dense output: the continuous extension of the last accepted step, shared by both methods.

/// Dense output of the last accepted step: y(t0 + τh), τ ∈ [0, 1]. Both methods' continuous
/// extensions have Hairer's nested form
/// y = r0 + τ(r1 + (1−τ)(r2 + τ(r3 + (1−τ)(r4 + τ(r5 + (1−τ)(r6 + τ r7)))))),
/// Dormand–Prince 5(4) with r5 = r6 = r7 = 0 (`top` = 4), DOP853 with all eight (`top` = 7).
#[derive(Clone, Copy, Debug)]
pub struct Dense<const N: usize> {
    pub t0: f64,
    pub h: f64,
    pub(super) r: [[f64; N]; 8],
    pub(super) top: usize,
}

impl<const N: usize> Dense<N> {
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }

    fn tau(&self, t: f64) -> f64 {
        if self.h == 0.0 {
            0.0
        } else {
            (t - self.t0) / self.h
        }
    }

    /// State at time t (t within the step).
    pub fn state(&self, t: f64) -> [f64; N] {
        self.state_head(t, N)
    }

    /// The first `n` components of the state at time t; the rest hold the step's start values
    /// (for readers of the leading components only, [`OdeSystem::event_inputs`]).
    #[inline]
    pub fn state_head(&self, t: f64, n: usize) -> [f64; N] {
        let th = self.tau(t);
        let th1 = 1.0 - th;
        let r = &self.r;
        let mut y = r[0];
        if self.top == 4 {
            for i in 0..n.min(N) {
                y[i] += th * (r[1][i] + th1 * (r[2][i] + th * (r[3][i] + th1 * r[4][i])));
            }
        } else {
            for i in 0..n.min(N) {
                let inner = r[4][i] + th * (r[5][i] + th1 * (r[6][i] + th * r[7][i]));
                y[i] += th * (r[1][i] + th1 * (r[2][i] + th * (r[3][i] + th1 * inner)));
            }
        }
        y
    }

    /// Component `i` of the interpolant and its time derivative at t, from one pass over the
    /// nested form (each the same numbers as [`Self::state`] and [`Self::derivative`] give):
    /// what a Newton search on one component reads.
    #[inline]
    pub fn component_with_rate(&self, t: f64, i: usize) -> (f64, f64) {
        let th = self.tau(t);
        let th1 = 1.0 - th;
        let r = &self.r;
        if self.top == 4 {
            let v3 = r[3][i] + th1 * r[4][i];
            let v2 = r[2][i] + th * v3;
            let v1 = r[1][i] + th1 * v2;
            let dv1 = -v2 + th1 * (v3 - th * r[4][i]);
            let value = r[0][i] + th * (r[1][i] + th1 * (r[2][i] + th * (r[3][i] + th1 * r[4][i])));
            return (value, (v1 + th * dv1) / self.h);
        }
        debug_assert_eq!(self.top, 7);
        let inner = r[4][i] + th * (r[5][i] + th1 * (r[6][i] + th * r[7][i]));
        let value = r[0][i] + th * (r[1][i] + th1 * (r[2][i] + th * (r[3][i] + th1 * inner)));
        const TOP: usize = 7;
        let (mut v, mut dv) = (r[TOP][i], 0.0);
        for k in (0..TOP).rev() {
            let (m, dm) = if k % 2 == 0 { (th, 1.0) } else { (th1, -1.0) };
            dv = dm * v + m * dv;
            v = r[k][i] + m * v;
        }
        (value, dv / self.h)
    }

    /// No |y_i(t)| of the interpolant on the step exceeds this. In the nested form
    /// y = r0 + τ(r1 + (1−τ)(r2 + …)) every multiplier lies in [0, 1], so
    /// y = (1−τ)y(t0) + τy(t1) + τ(1−τ)Q with |Q| ≤ Σ_{k≥2}|r_k| and τ(1−τ) ≤ ¼.
    pub fn bound(&self, i: usize) -> f64 {
        let ends = self.r[0][i].abs().max((self.r[0][i] + self.r[1][i]).abs());
        ends + 0.25 * self.r[2..].iter().map(|r| r[i].abs()).sum::<f64>()
    }

    /// No |ẏ_i(t)| of the interpolant on the step exceeds this. With V_k = r_k + m_k V_(k+1)
    /// (m_k = τ or 1 − τ, |m_k| ≤ 1, |m_k'| = 1): |V_k| ≤ A_k = Σ_{j≥k}|r_j| and
    /// |V_k'| ≤ A_(k+1) + B_(k+1) =: B_k; ẏ = V_0'/h.
    pub fn rate_bound(&self, i: usize) -> f64 {
        if self.h == 0.0 {
            return f64::INFINITY;
        }
        // (A_j, B_j) from the top down, starting past the last coefficient (0, 0).
        let (mut a, mut b) = (0.0, 0.0);
        for r in self.r[1..].iter().rev() {
            b += a;
            a += r[i].abs();
        }
        (a + b) / self.h.abs()
    }

    /// Time derivative of the interpolant at t.
    pub fn derivative(&self, t: f64) -> [f64; N] {
        self.derivative_head(t, N)
    }

    /// The first `n` components of the interpolant's time derivative at t; the rest are 0.
    #[inline]
    pub fn derivative_head(&self, t: f64, n: usize) -> [f64; N] {
        let th = self.tau(t);
        let th1 = 1.0 - th;
        let r = &self.r;
        let mut d = [0.0; N];
        if self.top == 4 {
            // v3 = r3 + (1−τ)r4, v2 = r2 + τv3, v1 = r1 + (1−τ)v2, y = r0 + τv1.
            for (i, di) in d.iter_mut().enumerate().take(n) {
                let v3 = r[3][i] + th1 * r[4][i];
                let dv3 = -r[4][i];
                let v2 = r[2][i] + th * v3;
                let dv2 = v3 + th * dv3;
                let v1 = r[1][i] + th1 * v2;
                let dv1 = -v2 + th1 * dv2;
                *di = (v1 + th * dv1) / self.h;
            }
            return d;
        }
        // DOP853 (top = 7). The top as a constant lets the compiler unroll the loop and
        // resolve the parity tests (read from `self.top` it cost ~16 % of the bare block's
        // instructions at rtol 1e-6); the operations and their order are unchanged.
        debug_assert_eq!(self.top, 7);
        const TOP: usize = 7;
        for (i, di) in d.iter_mut().enumerate().take(n) {
            // Inside out: v_k = r_k + m_k v_(k+1), m_k = τ for even k, 1 − τ for odd k.
            let mut v = r[TOP][i];
            let mut dv = 0.0;
            for k in (0..TOP).rev() {
                let (m, dm) = if k % 2 == 0 { (th, 1.0) } else { (th1, -1.0) };
                dv = dm * v + m * dv;
                v = r[k][i] + m * v;
            }
            *di = dv / self.h;
        }
        d
    }
}
