//! Implicit constraint enforcement (physics.md, paper Eqs. 6, 9, 10, 13-17): constraint values
//! and gradients, and the first-order implicit multiplier.

use super::{Real, Vector};

/// Signed volume [m^3] of the tetrahedron `p`: `(e1 x e2) . e3 / 6` with `e_k = p_k - p_0`.
#[inline]
pub fn tet_volume<V: Vector>(p: [V; 4]) -> V::Real {
    let (e1, e2, e3) = (p[1] - p[0], p[2] - p[0], p[3] - p[0]);
    e1.cross(e2).dot(e3) * V::Real::from_f64(1.0 / 6.0)
}

/// Distance constraint of the spring `(i, j)` with rest length `rest` [m], squared form:
/// returns `C = |x_i - x_j|^2 - L^2` [m^2] and the gradients `[grad_i C, grad_j C]` [m].
#[inline]
pub fn distance_constraint<V: Vector>(xi: V, xj: V, rest: V::Real) -> (V::Real, [V; 2]) {
    let d = xi - xj;
    let two = V::Real::from_f64(2.0);
    (d.dot(d) - rest * rest, [d * two, d * -two])
}

/// Volume constraint of the tetrahedron `p` with rest volume `rest` [m^3]: returns
/// `C = V(p) - V0` [m^3] and the gradients `grad_k C` [m^2] for the four nodes.
#[inline]
pub fn volume_constraint<V: Vector>(p: [V; 4], rest: V::Real) -> (V::Real, [V; 4]) {
    let (e1, e2, e3) = (p[1] - p[0], p[2] - p[0], p[3] - p[0]);
    let sixth = V::Real::from_f64(1.0 / 6.0);
    let g2 = e2.cross(e3) * sixth;
    let g3 = e3.cross(e1) * sixth;
    let g4 = e1.cross(e2) * sixth;
    let c = g4.dot(e3) - rest;
    (c, [-(g2 + g3 + g4), g2, g3, g4])
}

/// The first-order implicit multiplier of one constraint (physics.md, "Implicit constraint
/// enforcement" with the second edition's "Momentum-conserving scaling"):
///
/// ```text
/// A = sum_k s_k w_k |grad_k C|^2
/// B = C / dt^2 + sum_k grad_k C . (v_k / dt + w_k F_k)
/// lambda = B / A
/// ```
///
/// `c` is the constraint value, `grad`, `w` [1/kg], `v` [m/s] and `f` [N] the gradient, inverse
/// mass, velocity and current total force of each node it touches, `s` each node's scale of
/// its inverse mass in `A` (`d_k`, its constraint count, for the momentum-conserving
/// scaling; 1 for the paper's plain form; see
/// [`ConstraintCombine::node_factors`](crate::params::ConstraintCombine::node_factors)),
/// `dt` the time step [s]. Returns `None` (skip the constraint) when `A <= epsilon` or `A`
/// is not finite. The force on node `k` is then `-lambda grad_k C`.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn implicit_lambda<V: Vector, const K: usize>(
    c: V::Real,
    grad: &[V; K],
    w: &[V::Real; K],
    s: &[V::Real; K],
    v: &[V; K],
    f: &[V; K],
    dt: V::Real,
    epsilon: V::Real,
) -> Option<V::Real> {
    let (mut a, mut b) = (V::Real::ZERO, V::Real::ZERO);
    for k in 0..K {
        implicit_accumulate(&mut a, &mut b, grad[k], w[k], s[k], v[k], f[k], dt);
    }
    implicit_multiplier(c, a, b, dt, epsilon)
}

/// Adds one node's terms to a constraint's `A` and to the sum part of its `B` (the terms of
/// [`implicit_lambda`], for constraints with many nodes; `implicit_accumulate` in
/// glsl/physics/implicit.glsl).
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn implicit_accumulate<V: Vector>(
    a: &mut V::Real,
    b: &mut V::Real,
    grad: V,
    w: V::Real,
    s: V::Real,
    v: V,
    f: V,
    dt: V::Real,
) {
    *a += s * w * grad.dot(grad);
    *b += grad.dot(v * (V::Real::ONE / dt) + f * w);
}

/// The multiplier from a constraint's value `c` and its accumulated `A` and sum part of `B`
/// ([`implicit_accumulate`]): `(c / dt^2 + b) / a`, `None` when `a <= epsilon` or not
/// finite.
#[inline]
pub fn implicit_multiplier<R: Real>(c: R, a: R, b: R, dt: R, epsilon: R) -> Option<R> {
    if a > epsilon && a.is_finite() {
        Some((c / (dt * dt) + b) / a)
    } else {
        None
    }
}

/// One boundary face's share of the volume a closed surface encloses, measured from the
/// reference point `o`: `(x_a - o) . ((x_b - o) x (x_c - o)) / 6` [m^3] (the signed volume of
/// the tet `o, a, b, c`), and its gradients with respect to `x_a`, `x_b`, `x_c` [m^2]. Summed
/// over the outward faces of a tet mesh's boundary this is the sum of its tets' signed
/// volumes, for any `o` (physics.md, "One global volume constraint").
#[inline]
pub fn face_volume<V: Vector>(p: [V; 3], o: V) -> (V::Real, [V; 3]) {
    let sixth = V::Real::from_f64(1.0 / 6.0);
    let [a, b, c] = p.map(|x| x - o);
    let ga = b.cross(c) * sixth;
    (a.dot(ga), [ga, c.cross(a) * sixth, a.cross(b) * sixth])
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn tet() -> [DVec3; 4] {
        [
            DVec3::ZERO,
            DVec3::new(1.0, 0.1, 0.0),
            DVec3::new(0.2, 1.0, 0.1),
            DVec3::new(0.1, 0.3, 1.2),
        ]
    }

    #[test]
    fn volume_gradient_matches_finite_differences() {
        let p = tet();
        let (c0, grad) = volume_constraint(p, 0.1);
        assert!((c0 - (tet_volume(p) - 0.1)).abs() < 1e-15);
        let h = 1e-6;
        for k in 0..4 {
            for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                let mut q = p;
                q[k] += axis * h;
                let (c1, _) = volume_constraint(q, 0.1);
                assert!(
                    ((c1 - c0) / h - grad[k].dot(axis)).abs() < 1e-5,
                    "node {k} axis {axis}"
                );
            }
        }
    }

    #[test]
    fn distance_gradient_matches_finite_differences() {
        let (xi, xj) = (DVec3::new(0.3, -0.2, 0.5), DVec3::new(1.0, 0.4, -0.1));
        let (c0, grad) = distance_constraint(xi, xj, 0.7);
        assert!((c0 - (xi.distance_squared(xj) - 0.49)).abs() < 1e-15);
        let h = 1e-7;
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            let (c1, _) = distance_constraint(xi + axis * h, xj, 0.7);
            assert!(((c1 - c0) / h - grad[0].dot(axis)).abs() < 1e-5);
            let (c2, _) = distance_constraint(xi, xj + axis * h, 0.7);
            assert!(((c2 - c0) / h - grad[1].dot(axis)).abs() < 1e-5);
        }
    }

    #[test]
    fn face_volumes_of_a_tets_boundary_sum_to_its_volume() {
        let p = tet();
        let faces = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
        let o = DVec3::new(5.0, -3.0, 2.0);
        let mut volume = 0.0;
        let mut grad = [DVec3::ZERO; 4];
        for f in faces {
            let (v, g) = face_volume(f.map(|i| p[i]), o);
            volume += v;
            for k in 0..3 {
                grad[f[k]] += g[k];
            }
        }
        let (c, want) = volume_constraint(p, 0.0);
        assert!((volume - c).abs() < 1e-12, "{volume} vs {c}");
        for k in 0..4 {
            assert!(grad[k].distance(want[k]) < 1e-12, "node {k}");
        }
    }

    #[test]
    fn degenerate_constraint_is_skipped() {
        let p = [DVec3::ZERO; 4];
        let (c, grad) = volume_constraint(p, 0.1);
        let lambda = implicit_lambda(
            c,
            &grad,
            &[1.0; 4],
            &[1.0; 4],
            &[DVec3::ZERO; 4],
            &[DVec3::ZERO; 4],
            1e-3,
            1e-20,
        );
        assert_eq!(lambda, None);
    }
}
