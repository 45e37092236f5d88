//! Finite elements on linear tets (physics.md, fourth edition): stable Neo-Hookean (Smith, de
//! Goes, Kim 2018) and its per-node Newton step (Vertex Block Descent, Chen, Macklin, Yuksel
//! 2024), as pure functions generic over precision. The GLSL twin is
//! `glsl/physics/elastic.glsl`.
//!
//! A tet's rest shape gives its shape gradients `g_a` (rows of `Dm^-1` for corners 1..3,
//! corner 0 their negative sum), so `F = sum_a x_a g_a^T` and the energy's gradient at
//! corner `a` is `V0 P(F) g_a`. The energy
//! `Psi = mu_s/2 (I_C - 3) + lambda_s/2 (J - alpha)^2 - mu_s/2 log(I_C + 1)` with
//! `mu_s = 4/3 mu`, `lambda_s = lambda + 5/6 mu`, `alpha = 1 + mu / lambda_s` is stress free
//! at rest and linear elasticity's `(mu, lambda)` in small strain ([`stable_neo_hookean`];
//! the unit tests check both by finite differences). It is finite for flat and inverted tets
//! (`J <= 0`), where `dJ/dF` (the cofactor matrix) pushes the tet back.
//!
//! The Hessian block of one corner, `d^2 Psi / dx_a^2`, is positive semi-definite for every
//! `F`: the term `(J - alpha) d^2 J` that makes Neo-Hookean's Hessian indefinite vanishes in
//! a rank-one direction `delta g_a^T` (J is linear in each column), so the per-node Newton
//! step needs no eigenvalue projection.

use super::stiffness::volume_term;
use super::{Real, Vector};

/// Lame's parameters `(mu, lambda)` [Pa] of Young's modulus `e` [Pa] and Poisson's ratio
/// `nu` (`nu < 0.5`).
pub fn lame(e: f64, nu: f64) -> (f64, f64) {
    (
        e / (2.0 * (1.0 + nu)),
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
    )
}

/// Stable Neo-Hookean's constants `(mu_s, lambda_s, alpha)` for Lame's `(mu, lambda)`: the
/// energy's small-strain limit is linear elasticity with `(mu, lambda)` and its rest state
/// is stress free (Smith, de Goes, Kim 2018, section 3.4).
pub fn stable_neo_hookean(mu: f64, lambda: f64) -> (f64, f64, f64) {
    let mu_s = 4.0 / 3.0 * mu;
    let lambda_s = lambda + 5.0 / 6.0 * mu;
    (mu_s, lambda_s, 1.0 + mu / lambda_s)
}

/// One tet's element constants: its rest volume, shape gradients and material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticTet<R> {
    /// `g_a` of corners 1..3 (rows of `Dm^-1`) [1/m]; corner 0's is their negative sum.
    pub shape: [[R; 3]; 3],
    /// Rest volume [m^3].
    pub volume: R,
    /// `mu_s` [Pa].
    pub mu: R,
    /// `lambda_s` [Pa].
    pub lambda: R,
    /// `alpha` (the rest value of `J` the volume term pulls to).
    pub alpha: R,
}

/// The shape gradients of a tet at rest `p` (`None` for a flat one), in double precision.
pub fn shape_gradients(p: [glam::DVec3; 4]) -> Option<[[f64; 3]; 3]> {
    let dm = glam::DMat3::from_cols(p[1] - p[0], p[2] - p[0], p[3] - p[0]);
    let det = dm.determinant();
    if !(det.abs() > 0.0 && det.is_finite()) {
        return None;
    }
    // Row k of Dm^-1 is column k of its transpose.
    let inv_t = dm.inverse().transpose();
    Some([0, 1, 2].map(|k| inv_t.col(k).to_array()))
}

impl<R: Real> ElasticTet<R> {
    /// The gradient `g_a` of corner `a` (0..4) as components.
    #[inline]
    pub fn gradient(&self, a: usize) -> [R; 3] {
        match a {
            0 => {
                [0, 1, 2].map(|k| R::ZERO - self.shape[0][k] - self.shape[1][k] - self.shape[2][k])
            }
            _ => self.shape[a - 1],
        }
    }
}

/// A symmetric 3x3 matrix `[xx, yy, zz, xy, xz, yz]`.
pub type Sym3<R> = [R; 6];

/// `s I + c u u^T` added to `h`.
#[inline]
fn add_outer<V: Vector>(h: &mut Sym3<V::Real>, c: V::Real, u: V) {
    let [x, y, z] = components(u);
    h[0] += c * x * x;
    h[1] += c * y * y;
    h[2] += c * z * z;
    h[3] += c * x * y;
    h[4] += c * x * z;
    h[5] += c * y * z;
}

/// The components of `v`.
#[inline]
pub fn components<V: Vector>(v: V) -> [V::Real; 3] {
    let d = v.to_dvec3();
    // Exact: a vector of R converts to f64 and back without rounding.
    [d.x, d.y, d.z].map(V::Real::from_f64)
}

/// The vector with components `c`.
#[inline]
pub fn vector<V: Vector>(c: [V::Real; 3]) -> V {
    V::from_dvec3(glam::DVec3::new(
        c[0].to_f64(),
        c[1].to_f64(),
        c[2].to_f64(),
    ))
}

/// The columns of `sum_a p_a g_a^T` for corner values `p` of tet `t`: `F` of positions,
/// `dF` of displacements or velocities.
#[inline]
pub(super) fn columns<V: Vector>(t: &ElasticTet<V::Real>, p: [V; 4]) -> [V; 3] {
    let e = [p[1] - p[0], p[2] - p[0], p[3] - p[0]];
    [0, 1, 2].map(|k| e[0] * t.shape[0][k] + e[1] * t.shape[1][k] + e[2] * t.shape[2][k])
}

/// Corner `a` of tet `t` at positions `p`: the energy's gradient `dE/dx_a = V0 P(F) g_a` [N]
/// and its Hessian block `d^2 E / dx_a^2` [N/m] (positive semi-definite; module doc).
#[inline]
pub fn elastic_corner<V: Vector>(
    t: &ElasticTet<V::Real>,
    p: [V; 4],
    a: usize,
) -> (V, Sym3<V::Real>) {
    let one = V::Real::ONE;
    let zero = V::Real::ZERO;
    let e = [p[1] - p[0], p[2] - p[0], p[3] - p[0]];
    // Columns of F = sum_b (x_b - x_0) g_b^T, b = 1..3.
    let f: [V; 3] =
        [0, 1, 2].map(|k| e[0] * t.shape[0][k] + e[1] * t.shape[1][k] + e[2] * t.shape[2][k]);
    let cof = [f[1].cross(f[2]), f[2].cross(f[0]), f[0].cross(f[1])];
    let j = f[0].dot(cof[0]);
    let ic = f[0].dot(f[0]) + f[1].dot(f[1]) + f[2].dot(f[2]);
    let g = t.gradient(a);
    let u = f[0] * g[0] + f[1] * g[1] + f[2] * g[2];
    let w = cof[0] * g[0] + cof[1] * g[1] + cof[2] * g[2];
    let s = one / (ic + one);
    let shear = t.mu * (one - s);
    let grad = (u * shear + w * (t.lambda * (j - t.alpha))) * t.volume;
    let gg = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    let d = t.volume * shear * gg;
    let mut h = [d, d, d, zero, zero, zero];
    let two = one + one;
    add_outer(&mut h, t.volume * two * t.mu * s * s, u);
    add_outer(&mut h, t.volume * t.lambda, w);
    (grad, h)
}

/// Corner `a`'s share of the tet's stiffness-proportional damping force before its factor
/// `-beta`: `V0 dP(F)[dF] g_a`, the energy's Hessian applied to the nodes' velocities `u`
/// (`dF = sum_b u_b g_b^T`), so that the Rayleigh force `-beta K u` damps strain rates only,
/// never a rigid motion; the Hessian as the solve keeps it (positive semi-definite,
/// `volume_term`), so that damping never feeds a mode.
#[inline]
pub fn elastic_rate<V: Vector>(t: &ElasticTet<V::Real>, p: [V; 4], u: [V; 4], a: usize) -> V {
    let one = V::Real::ONE;
    let (f, df) = (columns(t, p), columns(t, u));
    let cof = [f[1].cross(f[2]), f[2].cross(f[0]), f[0].cross(f[1])];
    let dcof = [
        df[1].cross(f[2]) + f[1].cross(df[2]),
        df[2].cross(f[0]) + f[2].cross(df[0]),
        df[0].cross(f[1]) + f[0].cross(df[1]),
    ];
    let j = f[0].dot(cof[0]);
    let ic = f[0].dot(f[0]) + f[1].dot(f[1]) + f[2].dot(f[2]);
    let f_df = f[0].dot(df[0]) + f[1].dot(df[1]) + f[2].dot(df[2]);
    let cof_df = cof[0].dot(df[0]) + cof[1].dot(df[1]) + cof[2].dot(df[2]);
    let s = one / (ic + one);
    let g = t.gradient(a);
    let apply = |m: &[V; 3]| m[0] * g[0] + m[1] * g[1] + m[2] * g[2];
    let two = one + one;
    (apply(&df) * (t.mu * (one - s))
        + apply(&f) * (two * t.mu * s * s * f_df)
        + apply(&cof) * (t.lambda * cof_df)
        + apply(&dcof) * volume_term(t, &f, j, s))
        * t.volume
}

/// The tet's energy `V0 Psi(F)` [J] at positions `p`.
pub fn elastic_energy<V: Vector>(t: &ElasticTet<V::Real>, p: [V; 4]) -> V::Real {
    let one = V::Real::ONE;
    let f = columns(t, p);
    let j = f[0].dot(f[1].cross(f[2]));
    let ic = f[0].dot(f[0]) + f[1].dot(f[1]) + f[2].dot(f[2]);
    let half = one / (one + one);
    let three = one + one + one;
    let log = V::Real::from_f64((ic + one).to_f64().ln());
    t.volume
        * (half * t.mu * (ic - three) + half * t.lambda * (j - t.alpha) * (j - t.alpha)
            - half * t.mu * log)
}

/// One node's Newton step of Vertex Block Descent in the engine's force form (measured
/// against the global Newton step in docs/PHYSICS.md, "Finite elements"): the force
/// increment `m dx / dt^2` [N] for a node of mass `m` whose accumulated elastic force so
/// far is `phi`, given the sums over its tets of the energy's gradient `grad` and Hessian
/// block `hessian` at the step's end positions, its stiffness-proportional damping `rate`
/// (the sum of [`elastic_rate`] at the nodes' velocities over the step, `(end - start) /
/// dt`) with damping time `beta` [s]. Solves `(m/dt^2 + (1 + beta/dt) H) dx = -grad - beta
/// rate - phi`; `None` when the system is singular.
#[inline]
pub fn elastic_step<V: Vector>(
    mass: V::Real,
    dt: V::Real,
    beta: V::Real,
    phi: V,
    grad: V,
    hessian: Sym3<V::Real>,
    rate: V,
) -> Option<V> {
    let inertia = mass / (dt * dt);
    let block = node_block(mass, dt, beta, hessian);
    let dx = sym3_apply(sym3_inverse(block)?, -(grad + rate * beta + phi));
    Some(dx * inertia)
}

/// A node's block of the step's Newton matrix, `m/dt^2 I + (1 + beta/dt) H`, for its mass
/// `mass`, damping time `beta` and the energy's Hessian block `hessian` at the node.
#[inline]
pub fn node_block<R: Real>(mass: R, dt: R, beta: R, hessian: Sym3<R>) -> Sym3<R> {
    let inertia = mass / (dt * dt);
    let damp = R::ONE + beta / dt;
    let h = hessian;
    [0, 1, 2, 3, 4, 5].map(|k| h[k] * damp + if k < 3 { inertia } else { R::ZERO })
}

/// The inverse of a symmetric 3x3 matrix (its adjugate over its determinant); `None` when
/// it is not positive definite enough to invert (determinant not positive or not finite).
#[inline]
pub fn sym3_inverse<R: Real>(m: Sym3<R>) -> Option<Sym3<R>> {
    let (a, b, c, d, e, f) = (m[0], m[1], m[2], m[3], m[4], m[5]);
    let c00 = b * c - f * f;
    let c01 = e * f - d * c;
    let c02 = d * f - b * e;
    let det = a * c00 + d * c01 + e * c02;
    if !(det > R::ZERO && det.is_finite()) {
        return None;
    }
    let c11 = a * c - e * e;
    let c12 = d * e - a * f;
    let c22 = a * b - d * d;
    let inv = R::ONE / det;
    Some([c00, c11, c22, c01, c02, c12].map(|c| c * inv))
}

/// The symmetric 3x3 matrix `m` times `v`.
#[inline]
pub fn sym3_apply<V: Vector>(m: Sym3<V::Real>, v: V) -> V {
    let [x, y, z] = components(v);
    vector::<V>([
        m[0] * x + m[3] * y + m[4] * z,
        m[3] * x + m[1] * y + m[5] * z,
        m[4] * x + m[5] * y + m[2] * z,
    ])
}

/// Where a node's next step starts, as the elastic force to begin it with: Vertex Block
/// Descent's adaptive initialisation (Chen et al. 2024, section 3.5) in the engine's force
/// form. A node whose total force this step was `total` (mass `mass`, gravity vector
/// `gravity`) starts the next with the acceleration `a~ = g_hat clamp(a . g_hat, 0, |g|)`,
/// `a = total / mass`: only what it fell along gravity, never faster than free fall. The
/// returned force `mass (a~ - gravity)` is added to gravity's: a node at rest (a = 0) starts
/// where it is, so rest is the solve's fixed point at any iteration count; a falling one
/// starts where inertia takes it; sideways or upward accelerations, which a full
/// extrapolation would repeat (and which an unconverged solve then amplifies), are dropped.
#[inline]
pub fn elastic_start<V: Vector>(total: V, mass: V::Real, gravity: V) -> V {
    let g = gravity.length();
    if !(g > V::Real::ZERO && mass > V::Real::ZERO) {
        return V::ZERO;
    }
    let down = gravity * (V::Real::ONE / g);
    let along = (total.dot(down) * (V::Real::ONE / mass)).max(V::Real::ZERO);
    let along = if along > g { g } else { along };
    (down * along - gravity) * mass
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::stiffness::{
        elastic_linearise, elastic_product, elastic_product_strain, elastic_relinearise,
    };
    use glam::DVec3;

    fn rest() -> [DVec3; 4] {
        [
            DVec3::new(0.1, -0.2, 0.05),
            DVec3::new(1.1, 0.1, 0.0),
            DVec3::new(0.2, 0.9, 0.1),
            DVec3::new(0.0, 0.3, 1.2),
        ]
    }

    fn tet(mu: f64, lambda: f64) -> ElasticTet<f64> {
        let p = rest();
        let (mu_s, lambda_s, alpha) = stable_neo_hookean(mu, lambda);
        ElasticTet {
            shape: shape_gradients(p).unwrap(),
            volume: tetmesh::geometry::tet_volume(p),
            mu: mu_s,
            lambda: lambda_s,
            alpha,
        }
    }

    fn deformed(scale: f64) -> [DVec3; 4] {
        let mut p = rest();
        p[1] += DVec3::new(0.3, -0.1, 0.2) * scale;
        p[2] += DVec3::new(-0.2, 0.25, 0.05) * scale;
        p[3] += DVec3::new(0.1, 0.1, -0.4) * scale;
        p
    }

    #[test]
    fn a_later_linearisation_keeps_the_stiffness_of_a_tet_that_barely_moved() {
        let t = tet(1e5, 4e5);
        let kept = elastic_linearise(&t, deformed(0.5));
        // F changes by 1e-4 of the rest shape's: kept as it was.
        let mut near = deformed(0.5);
        near[1] += DVec3::X * 1e-4;
        assert_eq!(elastic_relinearise(&t, near, &kept), kept);
        // By a tenth: taken anew.
        let far = deformed(0.6);
        assert_eq!(
            elastic_relinearise(&t, far, &kept),
            elastic_linearise(&t, far)
        );
        assert_ne!(elastic_linearise(&t, far), kept);
    }

    #[test]
    fn the_product_and_its_strain_share_one_df() {
        let t = tet(1e5, 4e5);
        let linear = elastic_linearise(&t, deformed(0.5));
        // A uniform stretch by 1e-3 of the rest tet: dF = 1e-3 I, its norm 1e-3 sqrt(3).
        let d = rest().map(|x| x * 1e-3);
        let (product, strain) = elastic_product_strain(&t, &linear, d);
        assert_eq!(product, elastic_product(&t, &linear, d));
        assert!((strain - 1e-3 * 3f64.sqrt()).abs() < 1e-15, "{strain}");
        // A translation changes no strain.
        assert_eq!(elastic_product_strain(&t, &linear, [DVec3::Y; 4]).1, 0.0);
    }

    #[test]
    fn rest_state_is_stress_free() {
        let t = tet(1e5, 4e5);
        for a in 0..4 {
            let (g, _) = elastic_corner(&t, rest(), a);
            assert!(g.length() < 1e-9 * 1e5, "corner {a}: {g}");
        }
    }

    #[test]
    fn gradient_and_hessian_match_finite_differences_even_inverted() {
        let t = tet(1e5, 4e5);
        // 0.5: stretched and sheared; 4: the tet is turned inside out.
        for scale in [0.5, 4.0] {
            let p = deformed(scale);
            for a in 0..4 {
                let (g, h) = elastic_corner(&t, p, a);
                let eps = 1e-6;
                for k in 0..3 {
                    let mut plus = p;
                    let mut minus = p;
                    let dir = [DVec3::X, DVec3::Y, DVec3::Z][k];
                    plus[a] += dir * eps;
                    minus[a] -= dir * eps;
                    let fd = (elastic_energy(&t, plus) - elastic_energy(&t, minus)) / (2.0 * eps);
                    assert!(
                        (fd - g[k]).abs() < 1e-5 * g.length().max(1.0),
                        "scale {scale} corner {a} axis {k}: {fd} vs {}",
                        g[k]
                    );
                    let (gp, _) = elastic_corner(&t, plus, a);
                    let (gm, _) = elastic_corner(&t, minus, a);
                    let column = (gp - gm) / (2.0 * eps);
                    let idx = [[0, 3, 4], [3, 1, 5], [4, 5, 2]];
                    for r in 0..3 {
                        let hv = h[idx[r][k]];
                        assert!(
                            (column[r] - hv).abs() < 1e-4 * h[0].abs().max(1.0),
                            "scale {scale} corner {a} H[{r}][{k}]: {} vs {hv}",
                            column[r]
                        );
                    }
                }
                // Positive semi-definite: the smallest principal minors are >= 0.
                assert!(h[0] >= 0.0 && h[0] * h[1] - h[3] * h[3] >= -1e-9 * h[0] * h[1]);
            }
        }
    }

    /// In small strain the stress is linear elasticity's `mu (H + H^T) + lambda tr(H) I`
    /// for a displacement gradient `H`: the force at each corner matches it to first order.
    #[test]
    fn small_strain_limit_is_linear_elasticity() {
        let (mu, lambda) = lame(1e7, 0.3);
        let t = tet(mu, lambda);
        let hgrad =
            glam::DMat3::from_cols_array(&[0.3, -0.1, 0.2, 0.05, -0.2, 0.1, 0.15, 0.0, 0.25]);
        let eps = 1e-6;
        let p = rest().map(|x| x + hgrad * x * eps);
        let sigma = (hgrad + hgrad.transpose()) * mu
            + glam::DMat3::IDENTITY * (lambda * (hgrad.x_axis.x + hgrad.y_axis.y + hgrad.z_axis.z));
        for a in 0..4 {
            let (g, _) = elastic_corner(&t, p, a);
            let ga = DVec3::from_array(t.gradient(a));
            let linear = sigma * ga * (t.volume * eps);
            assert!(
                (g - linear).length() < 1e-4 * linear.length(),
                "corner {a}: {g} vs {linear}"
            );
        }
    }

    #[test]
    fn damping_rate_is_the_hessian_applied_to_the_velocities_and_ignores_rigid_motion() {
        let t = tet(1e5, 4e5);
        let p = deformed(0.5);
        let u = [
            DVec3::new(0.1, 0.2, -0.1),
            DVec3::new(-0.3, 0.1, 0.2),
            DVec3::new(0.0, -0.2, 0.1),
            DVec3::new(0.2, 0.05, 0.3),
        ];
        let eps = 1e-6;
        for a in 0..4 {
            let plus: Vec<DVec3> = (0..4).map(|b| p[b] + u[b] * eps).collect();
            let minus: Vec<DVec3> = (0..4).map(|b| p[b] - u[b] * eps).collect();
            let (gp, _) = elastic_corner(&t, [plus[0], plus[1], plus[2], plus[3]], a);
            let (gm, _) = elastic_corner(&t, [minus[0], minus[1], minus[2], minus[3]], a);
            let fd = (gp - gm) / (2.0 * eps);
            let rate = elastic_rate(&t, p, u, a);
            assert!(
                (fd - rate).length() < 1e-5 * fd.length(),
                "corner {a}: {fd} vs {rate}"
            );
            let rigid = elastic_rate(&t, p, [DVec3::new(0.3, -0.2, 0.1); 4], a);
            assert!(rigid.length() < 1e-9 * fd.length(), "corner {a}: {rigid}");
        }
    }

    #[test]
    fn the_kept_stiffness_gives_the_same_products_as_the_rate() {
        let t = tet(1e5, 4e5);
        for (p, d) in [(deformed(0.5), 0.3), (deformed(-1.6), -0.7)] {
            let u = [
                DVec3::new(0.1, 0.2, -0.1),
                DVec3::new(-0.3, 0.1, 0.2),
                DVec3::new(0.0, -0.2, 0.1),
                DVec3::new(0.2, 0.05, 0.3),
            ]
            .map(|u| u * d);
            let kept = elastic_product(&t, &elastic_linearise(&t, p), u);
            for (a, kept) in kept.iter().enumerate() {
                let rate = elastic_rate(&t, p, u, a);
                assert!(
                    (*kept - rate).length() < 1e-12 * rate.length(),
                    "corner {a}: {kept} vs {rate}"
                );
            }
        }
    }

    #[test]
    fn a_step_starts_at_rest_where_the_node_is_and_falling_where_inertia_takes_it() {
        let (m, g) = (2.0, DVec3::new(0.0, -9.81, 0.0));
        // At rest (no net force) the start cancels gravity: the node starts where it is.
        let rest = elastic_start(DVec3::ZERO, m, g);
        assert!((rest + g * m).length() < 1e-12, "{rest}");
        // Falling freely (net force m g): no elastic force to start with.
        assert!(elastic_start(g * m, m, g).length() < 1e-12);
        // Sideways or upward accelerations are dropped; faster than free fall is clamped.
        let sideways = elastic_start(DVec3::new(5.0, 0.0, 0.0), m, g);
        assert!((sideways + g * m).length() < 1e-12, "{sideways}");
        assert!(elastic_start(g * (3.0 * m), m, g).length() < 1e-12);
        assert_eq!(elastic_start(g * m, m, DVec3::ZERO), DVec3::ZERO);
    }

    #[test]
    fn lame_parameters_of_e_and_nu() {
        let (mu, lambda) = lame(2.6, 0.3);
        assert!((mu - 1.0).abs() < 1e-12);
        assert!((lambda - 1.5).abs() < 1e-12);
    }

    #[test]
    fn newton_step_solves_its_block() {
        let h = [4.0, 5.0, 6.0, 1.0, 0.5, -0.3];
        let (m, dt, beta) = (2.0, 0.1, 0.0);
        let grad = DVec3::new(1.0, -2.0, 0.5);
        let dx_force = elastic_step(m, dt, beta, DVec3::ZERO, grad, h, DVec3::ZERO).unwrap();
        let dx = dx_force * (dt * dt / m);
        let mat = glam::DMat3::from_cols(
            DVec3::new(h[0], h[3], h[4]),
            DVec3::new(h[3], h[1], h[5]),
            DVec3::new(h[4], h[5], h[2]),
        ) + glam::DMat3::IDENTITY * (m / (dt * dt));
        assert!((mat * dx + grad).length() < 1e-12);
    }
}
