//! A tet's stiffness kept for the finite elements' Newton step (docs/PHYSICS.md, "Finite
//! elements"): taken at a linearisation ([`elastic_linearise`], made positive
//! semi-definite by [`definite_volume_term`]), kept for a later one within the step where
//! the tet barely moved ([`elastic_relinearise`]), and applied to corner moves by the
//! conjugate gradients' products ([`elastic_product`], [`elastic_product_strain`]).

use super::elastic::columns;
use super::{definite_volume_term, ElasticTet, Real, Vector};

/// The factor `lambda_s (J - alpha)` of the determinant's Hessian in the tet's stiffness at
/// `F` (columns `f`, `J`, `s = 1 / (I_C + 1)`), scaled back where it would make the Hessian
/// indefinite ([`definite_volume_term`]): the stiffness the solve and the damping use is
/// positive semi-definite (projected Newton).
#[inline]
pub(super) fn volume_term<V: Vector>(
    t: &ElasticTet<V::Real>,
    f: &[V; 3],
    j: V::Real,
    s: V::Real,
) -> V::Real {
    let one = V::Real::ONE;
    let d = t.lambda * (j - t.alpha);
    let a = t.mu * (one - s);
    let b = (one + one) * t.mu * s * s;
    let columns = f.map(|c| c.to_dvec3());
    let kept = definite_volume_term(
        a.to_f64(),
        b.to_f64(),
        t.lambda.to_f64(),
        d.to_f64(),
        columns,
    );
    if kept == d.to_f64() {
        d
    } else {
        V::Real::from_f64(kept)
    }
}

/// How far (the Frobenius norm of the change of `F`) a tet may have moved since its
/// stiffness was taken for a later linearisation within the same step to keep it
/// ([`elastic_relinearise`]): the conjugate gradients' trust (`TRUSTED_STRAIN`).
pub const KEPT_STIFFNESS_STRAIN: f64 = 0.01;

/// The tet's stiffness at positions `p` for a later linearisation within a step:
/// `kept` (taken earlier in the step) where `F` moved by at most [`KEPT_STIFFNESS_STRAIN`]
/// since, else [`elastic_linearise`] anew. The residual is always taken at `p`; the
/// stiffness only shapes the search directions, and most of a body's tets barely move
/// between two linearisations of a step (the slivers that end the model's trust do).
#[inline]
pub fn elastic_relinearise<V: Vector>(
    t: &ElasticTet<V::Real>,
    p: [V; 4],
    kept: &ElasticLinear<V>,
) -> ElasticLinear<V> {
    let f = columns(t, p);
    let moved = [0, 1, 2].map(|k| f[k] - kept.f[k]);
    if frobenius(&moved) <= V::Real::from_f64(KEPT_STIFFNESS_STRAIN) {
        *kept
    } else {
        elastic_linearise(t, p)
    }
}

/// A tet's stiffness at one configuration, kept for products with it ([`elastic_product`]):
/// the columns of `F` and of its cofactor matrix, and the factors of `V0 dP[dF]`, the last
/// scaled back where the energy's Hessian is indefinite (`volume_term`), so that the Newton
/// step's matrix stays positive definite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticLinear<V: Vector> {
    f: [V; 3],
    cof: [V; 3],
    /// `V0 mu_s (1 - s)`, `V0 2 mu_s s^2`, `V0 lambda_s`, `V0 lambda_s (J - alpha)` (the
    /// last as `volume_term` keeps it), with `s = 1 / (I_C + 1)`.
    k: [V::Real; 4],
}

impl<V: Vector> Default for ElasticLinear<V> {
    fn default() -> Self {
        ElasticLinear {
            f: [V::ZERO; 3],
            cof: [V::ZERO; 3],
            k: [V::Real::ZERO; 4],
        }
    }
}

impl<V: Vector> ElasticLinear<V> {
    /// `V0 lambda_s (J - alpha)` as the Newton step uses it: scaled back where the Hessian
    /// would be indefinite ([`definite_volume_term`]).
    pub fn volume_factor(&self) -> V::Real {
        self.k[3]
    }
}

/// Tet `t`'s stiffness at positions `p`.
#[inline]
pub fn elastic_linearise<V: Vector>(t: &ElasticTet<V::Real>, p: [V; 4]) -> ElasticLinear<V> {
    let one = V::Real::ONE;
    let f = columns(t, p);
    let cof = [f[1].cross(f[2]), f[2].cross(f[0]), f[0].cross(f[1])];
    let j = f[0].dot(cof[0]);
    let ic = f[0].dot(f[0]) + f[1].dot(f[1]) + f[2].dot(f[2]);
    let s = one / (ic + one);
    let v = t.volume;
    ElasticLinear {
        f,
        cof,
        k: [
            v * t.mu * (one - s),
            v * (one + one) * t.mu * s * s,
            v * t.lambda,
            v * volume_term(t, &f, j, s),
        ],
    }
}

/// The tet's stiffness `lin` ([`elastic_linearise`]) times the corner displacements `d`:
/// `V0 dP(F)[dF] g_a` at each corner `a` (the four [`super::elastic_rate`]s at once, `dF` formed
/// once).
#[inline]
pub fn elastic_product<V: Vector>(
    t: &ElasticTet<V::Real>,
    lin: &ElasticLinear<V>,
    d: [V; 4],
) -> [V; 4] {
    product_of(t, lin, columns(t, d))
}

/// [`elastic_product`] of the corner displacements `d` and how much they change the tet's
/// deformation gradient, the Frobenius norm of `dF = sum_a d_a g_a^T` (the strain a
/// conjugate-gradient step makes in the tet, its trust measure; a rigid translation makes
/// none), `dF` formed once.
#[inline]
pub fn elastic_product_strain<V: Vector>(
    t: &ElasticTet<V::Real>,
    lin: &ElasticLinear<V>,
    d: [V; 4],
) -> ([V; 4], V::Real) {
    let df = columns(t, d);
    (product_of(t, lin, df), frobenius(&df))
}

/// [`elastic_product`] of the deformation gradient's change `df`.
#[inline]
fn product_of<V: Vector>(t: &ElasticTet<V::Real>, lin: &ElasticLinear<V>, df: [V; 3]) -> [V; 4] {
    let (f, cof) = (&lin.f, &lin.cof);
    let dcof = [
        df[1].cross(f[2]) + f[1].cross(df[2]),
        df[2].cross(f[0]) + f[2].cross(df[0]),
        df[0].cross(f[1]) + f[0].cross(df[1]),
    ];
    let f_df = f[0].dot(df[0]) + f[1].dot(df[1]) + f[2].dot(df[2]);
    let cof_df = cof[0].dot(df[0]) + cof[1].dot(df[1]) + cof[2].dot(df[2]);
    let [shear, outer, lambda, j_term] = lin.k;
    // Columns of V0 dP[dF].
    let dp: [V; 3] = [0, 1, 2].map(|k| {
        df[k] * shear + f[k] * (outer * f_df) + cof[k] * (lambda * cof_df) + dcof[k] * j_term
    });
    let corner = |g: [V::Real; 3]| dp[0] * g[0] + dp[1] * g[1] + dp[2] * g[2];
    let (a, b, c) = (corner(t.shape[0]), corner(t.shape[1]), corner(t.shape[2]));
    [-(a + b + c), a, b, c]
}

/// The Frobenius norm of a matrix given by its columns.
#[inline]
fn frobenius<V: Vector>(m: &[V; 3]) -> V::Real {
    (m[0].dot(m[0]) + m[1].dot(m[1]) + m[2].dot(m[2])).sqrt()
}
