//! Anderson acceleration of a step's constraint iterations (type II, Walker and Ni 2011;
//! docs/PHYSICS.md, "Anderson acceleration"): the host-side pieces every backend shares.
//!
//! One iteration is a fixed-point map `G` of what the next iteration reads: the step's
//! forces `F` (the floor's and the colliders' included) and the compliant constraints'
//! multipliers. With `g_k = G(x_k)` and the residual `f_k = g_k - x_k` of the forces, the
//! last `m` differences `df_j = f_(j+1) - f_j`, `dg_j = g_(j+1) - g_j` give the next input
//! `x_(k+1) = g_k - sum_j gamma_j dg_j`, `gamma` minimising `|f_k - sum_j gamma_j df_j|`:
//! the normal equations `(df_i . df_j) gamma = (df_i . f_k)`. The multipliers are mixed with
//! the same `gamma` (the forces are linear in them, gradients taken at `x(t)`), which keeps
//! the two consistent: mixing the forces alone lets implicit springs' multipliers drift
//! from their forces, and the backends then part by 1e-4 of the body's size within 30
//! frames. After the mix the floor and colliders are solved again (one-sided: the mix may
//! not pull a node into them). The history lives within one step (one solve of split
//! contact).
//!
//! A backend's Anderson passes per iteration `k` ([`AndersonIteration`]): `anderson_sum`
//! stores `f_k`, `g_k` and the new history columns and sums the products [`gram_terms`]
//! over fixed chunks of nodes; `anderson_mix` adds the chunks up, solves for `gamma`
//! ([`anderson_weights`]), mixes, and solves the floor and colliders again.

/// The most history columns `anderson` may keep (the GPU's shared arrays are sized by it).
pub const ANDERSON_MAX_MEMORY: u32 = 8;

/// The Tikhonov term of the normal equations, relative to their largest diagonal entry:
/// nearly parallel history columns get small weights instead of huge opposite ones.
pub const ANDERSON_REGULARIZATION: f64 = 1e-6;

/// What Anderson's passes do in one iteration of a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AndersonIteration {
    /// Iteration 0: `g_0` is only stored as the next input (no residual yet).
    pub first: bool,
    /// The history column this iteration writes (from iteration 2 on: the ring slot of
    /// `df`, `dg` that the oldest column leaves).
    pub slot: Option<usize>,
    /// The history columns the mix uses (`min(k - 1, m)` from iteration 2 on).
    pub columns: usize,
}

impl AndersonIteration {
    /// Iteration `iteration` (0-based within the step) with memory `memory`.
    pub fn of(iteration: u32, memory: u32) -> Self {
        let (k, m) = (iteration as usize, memory.max(1) as usize);
        AndersonIteration {
            first: k == 0,
            slot: (k >= 2).then(|| (k - 2) % m),
            columns: k.saturating_sub(1).min(m),
        }
    }
}

/// The number of chunked sums of `columns` history columns: the upper triangle of the
/// products `df_i . df_j` row by row, then `df_i . f`.
pub const fn gram_terms(columns: usize) -> usize {
    columns * (columns + 1) / 2 + columns
}

/// The index of `df_i . df_j` (`i <= j`) among the [`gram_terms`] of `columns` columns;
/// `df_i . f` is at `columns * (columns + 1) / 2 + i`.
pub fn gram_index(i: usize, j: usize, columns: usize) -> usize {
    let (i, j) = (i.min(j), i.max(j));
    i * columns - i * (i.saturating_sub(1)) / 2 + (j - i)
}

/// The mixing weights `gamma` from the summed [`gram_terms`] of `columns` columns: the
/// normal equations, regularised by [`ANDERSON_REGULARIZATION`], solved by Cholesky. All
/// zeros (no mix) when there are no columns, the history vanished or the system is not
/// positive definite in floating point.
pub fn anderson_weights(sums: &[f64], columns: usize) -> [f64; ANDERSON_MAX_MEMORY as usize] {
    let mut gamma = [0.0; ANDERSON_MAX_MEMORY as usize];
    let k = columns;
    let scale = (0..k)
        .map(|i| sums[gram_index(i, i, k)])
        .fold(0.0f64, f64::max);
    if k == 0 || scale <= 0.0 || !scale.is_finite() {
        return gamma;
    }
    // Cholesky factor L (lower, row-major k x k) of the regularised matrix.
    let mut l = [0.0f64; (ANDERSON_MAX_MEMORY * ANDERSON_MAX_MEMORY) as usize];
    for i in 0..k {
        for j in 0..=i {
            let mut s = sums[gram_index(i, j, k)];
            if i == j {
                s += ANDERSON_REGULARIZATION * scale;
            }
            for p in 0..j {
                s -= l[i * k + p] * l[j * k + p];
            }
            if i == j {
                if s.is_nan() || s <= 0.0 {
                    return gamma;
                }
                l[i * k + i] = s.sqrt();
            } else {
                l[i * k + j] = s / l[j * k + j];
            }
        }
    }
    let rhs = &sums[k * (k + 1) / 2..];
    let mut y = [0.0f64; ANDERSON_MAX_MEMORY as usize];
    for i in 0..k {
        let s = rhs[i] - (0..i).map(|p| l[i * k + p] * y[p]).sum::<f64>();
        y[i] = s / l[i * k + i];
    }
    for i in (0..k).rev() {
        let s = y[i] - (i + 1..k).map(|p| l[p * k + i] * gamma[p]).sum::<f64>();
        gamma[i] = s / l[i * k + i];
    }
    if gamma.iter().any(|g| !g.is_finite()) {
        return [0.0; ANDERSON_MAX_MEMORY as usize];
    }
    gamma
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iterations_fill_the_ring_and_use_what_they_have() {
        let of = |k| AndersonIteration::of(k, 3);
        assert!(of(0).first && of(0).slot.is_none() && of(0).columns == 0);
        assert!(!of(1).first && of(1).slot.is_none() && of(1).columns == 0);
        let slots: Vec<_> = (2..9)
            .map(|k| (of(k).slot.unwrap(), of(k).columns))
            .collect();
        assert_eq!(
            slots,
            [(0, 1), (1, 2), (2, 3), (0, 3), (1, 3), (2, 3), (0, 3)]
        );
    }

    #[test]
    fn gram_indices_cover_the_upper_triangle_once() {
        for k in 1..=ANDERSON_MAX_MEMORY as usize {
            let mut seen = vec![false; gram_terms(k)];
            for i in 0..k {
                for j in i..k {
                    let at = gram_index(i, j, k);
                    assert!(!seen[at], "{k}: ({i}, {j}) twice");
                    seen[at] = true;
                    assert_eq!(at, gram_index(j, i, k));
                }
            }
            assert!(seen[..k * (k + 1) / 2].iter().all(|&s| s));
        }
    }

    /// The weights are the least-squares solution: on a small problem with a known answer.
    #[test]
    fn weights_solve_the_least_squares_problem() {
        // Columns df_0 = (1, 0, 1), df_1 = (0, 2, 1); f = 2 df_0 - 3 df_1 exactly.
        let df = [[1.0, 0.0, 1.0], [0.0, 2.0, 1.0]];
        let f: Vec<f64> = (0..3).map(|r| 2.0 * df[0][r] - 3.0 * df[1][r]).collect();
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let k = 2;
        let mut sums = vec![0.0; gram_terms(k)];
        for i in 0..k {
            for j in i..k {
                sums[gram_index(i, j, k)] = dot(&df[i], &df[j]);
            }
            sums[k * (k + 1) / 2 + i] = dot(&df[i], &f);
        }
        let gamma = anderson_weights(&sums, k);
        // Within what the regularisation (1e-6 of the largest diagonal) moves them.
        assert!((gamma[0] - 2.0).abs() < 1e-4, "{gamma:?}");
        assert!((gamma[1] + 3.0).abs() < 1e-4, "{gamma:?}");
        assert!(gamma[2..].iter().all(|&g| g == 0.0));
    }

    #[test]
    fn a_vanished_or_singular_history_does_not_mix() {
        assert_eq!(anderson_weights(&[0.0, 0.0], 1), [0.0; 8]);
        assert_eq!(anderson_weights(&[f64::NAN, 1.0], 1), [0.0; 8]);
        assert_eq!(anderson_weights(&[], 0), [0.0; 8]);
        // Two identical columns: the regularisation splits the weight between them.
        let gamma = anderson_weights(&[1.0, 1.0, 1.0, 1.0, 1.0], 2);
        assert!((gamma[0] - 0.5).abs() < 1e-4 && (gamma[1] - 0.5).abs() < 1e-4);
    }
}
