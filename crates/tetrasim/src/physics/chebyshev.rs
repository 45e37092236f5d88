//! The Chebyshev semi-iteration's weights (Wang 2015) and the spectral radius estimate they
//! use: at most [`chebyshev_rho_limit`] of the iteration count, so that a step's
//! extrapolation cannot feed a mode back into the next step with a growing amplitude
//! (docs/PHYSICS.md, "Chebyshev semi-iteration"). Host-side only: every backend takes the
//! weights from [`chebyshev_weights`] (the shaders as a push constant), so all follow the
//! same ones.

/// The largest share of a constraint mode's predicted violation that one step's
/// `iterations` Chebyshev iterations may leave with its sign reversed.
///
/// After `K` iterations a mode of the Jacobi sweep with eigenvalue `l` keeps the share
/// `p = T_K(l / rho) / T_K(1 / rho)` of its violation (`T_K` the Chebyshev polynomial),
/// which swings between `+-1 / T_K(1 / rho)` over `[-rho, rho]`. The violation a step leaves
/// returns in the next step as a velocity (symplectic Euler), so a mode's violations obey
/// `c_(n+1) = p (2 c_n - c_(n-1))`, which grows from step to step when `p < -1/3` (its
/// larger root is `|p| + sqrt(p^2 + |p|)`). Keeping `1 / T_K(1 / rho)` at or below this
/// bound leaves a margin to `1/3` (a decay of about 8 % per step without damping) for
/// what the linear picture leaves out; springs and their damping only help.
pub const CHEBYSHEV_MAX_REVERSAL: f64 = 0.3;

/// The largest spectral radius estimate `iterations` Chebyshev iterations use: the `rho`
/// at which `1 / T_K(1 / rho)` is [`CHEBYSHEV_MAX_REVERSAL`],
/// `1 / cosh(acosh(1 / bound) / K)`; 1 for one iteration, whose weight does not depend on
/// `rho`. About 0.679 for 2 iterations, 0.832 for 3, 0.899 for 4, 0.934 for 5, 0.953 for
/// 6, 0.983 for 10 and 0.996 for 20.
pub fn chebyshev_rho_limit(iterations: u32) -> f64 {
    match iterations {
        0 | 1 => 1.0,
        k => 1.0 / ((1.0 / CHEBYSHEV_MAX_REVERSAL).acosh() / f64::from(k)).cosh(),
    }
}

/// The spectral radius estimate the weights of `iterations` iterations use for the asked
/// `rho`: `rho`, or [`chebyshev_rho_limit`] when that is lower (too few iterations for
/// `rho`).
pub fn chebyshev_rho(rho: f64, iterations: u32) -> f64 {
    rho.min(chebyshev_rho_limit(iterations))
}

/// The Chebyshev weights of iterations `1..=iterations` for the spectral radius estimate
/// `rho`, used as [`chebyshev_rho`] (`rho` at most [`chebyshev_rho_limit`]): `w_1 = 1`,
/// `w_2 = 2 / (2 - rho^2)`, `w_(k+1) = 4 / (4 - rho^2 w_k)`. Every backend uses this
/// function.
pub fn chebyshev_weights(rho: f64, iterations: u32) -> Vec<f64> {
    let rho = chebyshev_rho(rho, iterations);
    let r2 = rho * rho;
    let mut out: Vec<f64> = Vec::with_capacity(iterations as usize);
    for k in 0..iterations as usize {
        let w = match k {
            0 => 1.0,
            1 => 2.0 / (2.0 - r2),
            _ => 4.0 / (4.0 - r2 * out[k - 1]),
        };
        out.push(w);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `T_k(x)` for `x >= 1`.
    fn chebyshev_t(k: u32, x: f64) -> f64 {
        (f64::from(k) * x.acosh()).cosh()
    }

    /// The share of a mode with Jacobi eigenvalue `l` that the weights `w` leave: the
    /// iteration `x_k = w_k (l x_(k-1) - x_(k-2)) + x_(k-2)` from `x_0 = x_(-1) = 1`.
    fn residual(l: f64, w: &[f64]) -> f64 {
        let (mut before, mut now) = (1.0, 1.0);
        for &wk in w {
            (before, now) = (now, wk * (l * now - before) + before);
        }
        now
    }

    #[test]
    fn chebyshev_weights_follow_the_recurrence_down_to_the_optimal_limit() {
        let rho: f64 = 0.95;
        let w = chebyshev_weights(rho, 60);
        assert_eq!(w[0], 1.0);
        assert!((w[1] - 2.0 / (2.0 - rho * rho)).abs() < 1e-15);
        assert!((w[2] - 4.0 / (4.0 - rho * rho * w[1])).abs() < 1e-15);
        // From w_2 on the weights fall to the optimal SOR-like limit
        // 2 / (1 + sqrt(1 - rho^2)), staying above it.
        let limit = 2.0 / (1.0 + (1.0 - rho * rho).sqrt());
        assert!(w[1..].windows(2).all(|p| p[1] <= p[0] && p[1] >= limit));
        assert!((w[59] - limit).abs() < 1e-9, "{} vs {limit}", w[59]);
    }

    #[test]
    fn the_weights_leave_the_chebyshev_polynomial_of_the_effective_rho() {
        for (rho, k) in [(0.95, 5), (0.95, 10), (0.99, 10), (0.5, 3)] {
            let w = chebyshev_weights(rho, k);
            let used = chebyshev_rho(rho, k);
            for i in 0..=200 {
                let l = -used + 2.0 * used * f64::from(i) / 200.0;
                let t = (f64::from(k) * (l / used).acos()).cos();
                let p = t / chebyshev_t(k, 1.0 / used);
                assert!(
                    (residual(l, &w) - p).abs() < 1e-12,
                    "rho {rho}, {k} it, l {l}"
                );
            }
        }
    }

    #[test]
    fn too_few_iterations_for_rho_lower_it_to_the_limit() {
        // The default 0.95 is kept from 6 iterations on and lowered below.
        assert_eq!(chebyshev_rho(0.95, 6), 0.95);
        assert_eq!(chebyshev_rho(0.95, 10), 0.95);
        assert!((chebyshev_rho(0.95, 5) - 0.9337).abs() < 1e-4);
        assert!((chebyshev_rho(0.99, 10) - 0.9827).abs() < 1e-4);
        assert_eq!(chebyshev_rho(0.95, 1), 0.95);
        assert_eq!(chebyshev_weights(0.95, 1), vec![1.0]);
        assert_eq!(
            chebyshev_weights(0.95, 5),
            chebyshev_weights(chebyshev_rho_limit(5), 5)
        );
        for k in 2..=64 {
            let limit = chebyshev_rho_limit(k);
            assert!(k == 2 || limit > chebyshev_rho_limit(k - 1), "{k}");
            assert!(limit < 1.0, "{k}");
            // Whatever rho is asked, no mode with an eigenvalue in [-rho, 1] (rho as used)
            // is left reversed by more than the bound.
            for rho in [0.5, 0.9, 0.95, 0.99, 0.999] {
                let (w, used) = (chebyshev_weights(rho, k), chebyshev_rho(rho, k));
                let worst = (0..=400)
                    .map(|i| -used + (1.0 + used) * f64::from(i) / 400.0)
                    .map(|l| residual(l, &w))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    worst >= -CHEBYSHEV_MAX_REVERSAL - 1e-9,
                    "rho {rho}, {k} it: {worst}"
                );
            }
        }
    }
}
