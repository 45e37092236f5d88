//! Stable Neo-Hookean's Hessian made positive semi-definite for the Newton step's
//! conjugate gradients (projected Newton; docs/PHYSICS.md, "Finite elements").
//!
//! Per unit rest volume the Hessian with respect to `F` is
//! `a I + b f f^T + c g g^T + d H_J`: `a = mu_s (1 - s)`, `b = 2 mu_s s^2`, `c = lambda_s`,
//! `d = lambda_s (J - alpha)`, `f = vec F`, `g = vec cof F`, `H_J` the determinant's
//! Hessian and `s = 1 / (I_C + 1)`. Only `d H_J` can make it indefinite. In the frame of
//! `F`'s singular value decomposition (Smith, de Goes, Kim 2019, "Analytic eigensystems for
//! isotropic distortion energies") it has six twist and flip eigenvalues `a +- d sigma_k`
//! and a 3x3 scaling block `a I + b sigma sigma^T + c gamma gamma^T + d H_s(sigma)`
//! (`gamma_i` the product of the other two singular values, `H_s` with `sigma_k` off the
//! diagonal at `(i, j)`, `k` the third index). A compression of 1 % already turns the twists
//! negative at `nu = 0.45` (their value at rest is 0: the rotations): the conjugate
//! gradients then meet a direction of negative curvature and stop.
//!
//! [`definite_volume_term`] scales `d` back just enough that every eigenvalue is at least
//! zero, and leaves it as it is wherever the Hessian already is: `|d| <= a / sigma_max`
//! for the twists and flips, and the largest share of that for which the scaling block's
//! least eigenvalue is not negative. The singular values come from `F^T F`'s eigenvalues
//! (signed: the smallest negative for an inverted tet), so no rotations are needed; the
//! products keep their matrix-free form with `d` replaced.

use glam::DVec3;

/// The factor to use for `d = lambda_s (J - alpha)` in the Hessian's products, for the
/// other factors `a`, `b`, `c` (module doc) and `F`'s columns `f`: `d` itself where the
/// Hessian is positive semi-definite, else the largest share of it (same sign) that makes it
/// so.
pub fn definite_volume_term(a: f64, b: f64, c: f64, d: f64, f: [DVec3; 3]) -> f64 {
    let sigma = singular_values(f);
    let largest = sigma.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    if !(largest > 0.0 && largest.is_finite() && a > 0.0) {
        return d;
    }
    let bound = a / largest;
    let twists = d.clamp(-bound, bound);
    // The block is `S0 + share twists H_s`, `S0` (no `d`: `a I` plus two outer products)
    // positive definite, so the largest share that keeps it semi-definite is one over the
    // largest eigenvalue of `-L^-1 (twists H_s) L^-T` (`S0 = L L^T`), where that exceeds 1.
    if cholesky(scaling_block(a, b, c, twists, sigma)).is_some() {
        return twists;
    }
    let Some(l) = cholesky(scaling_block(a, b, c, 0.0, sigma)) else {
        return twists;
    };
    let h = scaling_block(0.0, 0.0, 0.0, twists, sigma);
    let mut m = [[0.0; 3]; 3];
    let columns = [0, 1, 2].map(|j| lower_solve(&l, [h[0][j], h[1][j], h[2][j]]));
    for i in 0..3 {
        // Row i of L^-1 H, then (L^-1 H) L^-T by solving against its rows.
        let row = lower_solve(&l, [columns[0][i], columns[1][i], columns[2][i]]);
        for j in 0..3 {
            m[i][j] = -row[j];
        }
    }
    let worst = eigenvalues(symmetric(m))[0];
    if worst > 1.0 {
        twists / worst
    } else {
        twists
    }
}

/// The Cholesky factor `L` (lower) of the symmetric positive definite `m`; `None` if it is
/// not.
fn cholesky(m: [[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let mut l = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..=i {
            let sum: f64 = (0..j).map(|k| l[i][k] * l[j][k]).sum();
            if i == j {
                let pivot = m[i][i] - sum;
                if pivot.is_nan() || pivot <= 0.0 {
                    return None;
                }
                l[i][i] = pivot.sqrt();
            } else {
                l[i][j] = (m[i][j] - sum) / l[j][j];
            }
        }
    }
    Some(l)
}

/// `L^-1 v` for the lower triangular `l`.
fn lower_solve(l: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    let x0 = v[0] / l[0][0];
    let x1 = (v[1] - l[1][0] * x0) / l[1][1];
    let x2 = (v[2] - l[2][0] * x0 - l[2][1] * x1) / l[2][2];
    [x0, x1, x2]
}

/// `(m + m^T) / 2`: `m` as a symmetric matrix (rounding made it not quite).
fn symmetric(m: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| 0.5 * (m[i][j] + m[j][i])))
}

/// The scaling block `a I + b sigma sigma^T + c gamma gamma^T + d H_s(sigma)` (module doc).
fn scaling_block(a: f64, b: f64, c: f64, d: f64, sigma: [f64; 3]) -> [[f64; 3]; 3] {
    let gamma = [
        sigma[1] * sigma[2],
        sigma[0] * sigma[2],
        sigma[0] * sigma[1],
    ];
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let diagonal = if i == j { a } else { d * sigma[3 - i - j] };
            m[i][j] = diagonal + b * sigma[i] * sigma[j] + c * gamma[i] * gamma[j];
        }
    }
    m
}

/// `F`'s singular values (columns `f`) from the eigenvalues of `F^T F`, largest first; the
/// smallest is negative where `det F < 0` (the rotation-variant decomposition).
pub fn singular_values(f: [DVec3; 3]) -> [f64; 3] {
    let c = [0, 1, 2].map(|i| [0, 1, 2].map(|j| f[i].dot(f[j])));
    let e = eigenvalues(c);
    let mut sigma = e.map(|e| e.max(0.0).sqrt());
    if f[0].dot(f[1].cross(f[2])) < 0.0 {
        sigma[2] = -sigma[2];
    }
    sigma
}

/// The eigenvalues of the symmetric 3x3 `m`, largest first (the closed form of the
/// characteristic cubic's three real roots).
fn eigenvalues(m: [[f64; 3]; 3]) -> [f64; 3] {
    let off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    let q = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
    let spread = (m[0][0] - q).powi(2) + (m[1][1] - q).powi(2) + (m[2][2] - q).powi(2) + 2.0 * off;
    let p = (spread / 6.0).sqrt();
    if p.is_nan() || p <= 0.0 {
        return [q; 3];
    }
    let b = |i: usize, j: usize| (m[i][j] - if i == j { q } else { 0.0 }) / p;
    let det = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1))
        - b(0, 1) * (b(1, 0) * b(2, 2) - b(1, 2) * b(2, 0))
        + b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0));
    let phi = (det / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
    let largest = q + 2.0 * p * phi.cos();
    let least = q + 2.0 * p * (phi + 2.0 * std::f64::consts::PI / 3.0).cos();
    [largest, 3.0 * q - largest - least, least]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat3;

    /// The 9x9 Hessian `a I + b f f^T + c g g^T + d H_J` at `F` (per unit volume), with
    /// `H_J` by central differences of the cofactor (exact: it is quadratic).
    fn hessian(a: f64, b: f64, c: f64, d: f64, f: DMat3) -> [[f64; 9]; 9] {
        let cof = |m: DMat3| {
            let [c0, c1, c2] = [m.col(0), m.col(1), m.col(2)];
            DMat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1))
        };
        let fv = f.to_cols_array();
        let gv = cof(f).to_cols_array();
        let mut h = [[0.0; 9]; 9];
        for (j, column) in (0..9).map(|j| {
            let mut e = [0.0; 9];
            e[j] = 1.0;
            let de = DMat3::from_cols_array(&e);
            let hj = (cof(f + de) - cof(f - de)).to_cols_array().map(|x| x / 2.0);
            (j, hj)
        }) {
            for i in 0..9 {
                let identity = if i == j { a } else { 0.0 };
                h[i][j] = identity + b * fv[i] * fv[j] + c * gv[i] * gv[j] + d * column[i];
            }
        }
        h
    }

    /// The least eigenvalue of a symmetric 9x9 matrix (cyclic Jacobi rotations).
    fn least(mut m: [[f64; 9]; 9]) -> f64 {
        for _ in 0..50 {
            for p in 0..9 {
                for q in p + 1..9 {
                    if m[p][q].abs() < 1e-300 {
                        continue;
                    }
                    let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
                    let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                    let cs = 1.0 / (t * t + 1.0).sqrt();
                    let sn = t * cs;
                    for k in 0..9 {
                        let (mkp, mkq) = (m[k][p], m[k][q]);
                        m[k][p] = cs * mkp - sn * mkq;
                        m[k][q] = sn * mkp + cs * mkq;
                    }
                    for k in 0..9 {
                        let (mpk, mqk) = (m[p][k], m[q][k]);
                        m[p][k] = cs * mpk - sn * mqk;
                        m[q][k] = sn * mpk + cs * mqk;
                    }
                }
            }
        }
        (0..9).map(|i| m[i][i]).fold(f64::INFINITY, f64::min)
    }

    /// Stable Neo-Hookean's factors at `F` for `mu`, `lambda` (Lame's, nu from them).
    fn factors(mu: f64, lambda: f64, f: DMat3) -> (f64, f64, f64, f64) {
        let (mu_s, lambda_s, alpha) = crate::physics::stable_neo_hookean(mu, lambda);
        let ic = f.to_cols_array().iter().map(|x| x * x).sum::<f64>();
        let s = 1.0 / (ic + 1.0);
        let j = f.determinant();
        (
            mu_s * (1.0 - s),
            2.0 * mu_s * s * s,
            lambda_s,
            lambda_s * (j - alpha),
        )
    }

    fn columns(f: DMat3) -> [DVec3; 3] {
        [f.col(0), f.col(1), f.col(2)]
    }

    fn deformations() -> Vec<DMat3> {
        let turn = DMat3::from_quat(glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1));
        let shear = DMat3::from_cols_array(&[1.0, 0.2, -0.1, 0.05, 1.0, 0.3, 0.1, -0.2, 1.0]);
        vec![
            DMat3::IDENTITY,
            turn,
            DMat3::from_diagonal(DVec3::splat(0.99)),
            turn * DMat3::from_diagonal(DVec3::new(0.7, 0.9, 0.95)),
            turn * DMat3::from_diagonal(DVec3::new(1.6, 0.8, 0.8)),
            shear * 0.5,
            turn * shear * 2.0,
            // Inverted: one reflected axis, and a tet flattened to almost nothing.
            turn * DMat3::from_diagonal(DVec3::new(1.0, 0.9, -0.4)),
            DMat3::from_diagonal(DVec3::new(1.0, 1.0, 1e-3)),
        ]
    }

    #[test]
    fn singular_values_are_those_of_f_with_the_sign_of_its_determinant() {
        let turn = DMat3::from_quat(glam::DQuat::from_rotation_y(0.8));
        let sigma = singular_values(columns(
            turn * DMat3::from_diagonal(DVec3::new(0.5, 2.0, -1.5)),
        ));
        for (s, want) in sigma.iter().zip([2.0, 1.5, -0.5]) {
            assert!((s - want).abs() < 1e-12, "{sigma:?}");
        }
    }

    #[test]
    fn the_projected_hessian_has_no_negative_eigenvalue_and_is_exact_where_definite() {
        for nu in [0.0, 0.3, 0.45, 0.49] {
            let (mu, lambda) = crate::physics::lame(1.0, nu);
            for f in deformations() {
                let (a, b, c, d) = factors(mu, lambda, f);
                let exact = least(hessian(a, b, c, d, f));
                let kept = definite_volume_term(a, b, c, d, columns(f));
                let projected = least(hessian(a, b, c, kept, f));
                let scale = a + b + c;
                assert!(projected >= -1e-9 * scale, "nu {nu} F {f}: {projected}");
                assert!(kept * d >= 0.0 && kept.abs() <= d.abs() * (1.0 + 1e-12));
                if exact >= 1e-9 * scale {
                    assert!(
                        (kept - d).abs() <= 1e-12 * d.abs(),
                        "nu {nu} F {f}: {kept} {d}"
                    );
                } else {
                    // Scaled back no further than it must be: a little more is indefinite.
                    let more = kept + (d - kept) * 1e-3 + d * 1e-6;
                    assert!(
                        least(hessian(a, b, c, more, f)) < 1e-9 * scale,
                        "nu {nu} F {f}"
                    );
                }
            }
        }
    }

    #[test]
    fn at_rest_and_turned_the_hessian_is_kept() {
        let (mu, lambda) = crate::physics::lame(1.0, 0.45);
        for f in deformations().into_iter().take(2) {
            let (a, b, c, d) = factors(mu, lambda, f);
            let kept = definite_volume_term(a, b, c, d, columns(f));
            assert!((kept - d).abs() < 1e-12, "{kept} {d}");
        }
        // Compressed by 1 %: the twists are negative, and the term is scaled back.
        let f = DMat3::from_diagonal(DVec3::splat(0.99));
        let (a, b, c, d) = factors(mu, lambda, f);
        assert!(least(hessian(a, b, c, d, f)) < -0.2 * mu);
        assert!(definite_volume_term(a, b, c, d, columns(f)).abs() < 0.8 * d.abs());
    }
}
