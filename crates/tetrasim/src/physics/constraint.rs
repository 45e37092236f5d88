//! Implicit constraint enforcement (physics.md, paper Eqs. 6, 9, 10, 13-17): constraint values
//! and gradients, and the first-order implicit multiplier.

use super::{Real, Vector};

/// Distance constraint of the spring `(i, j)` with rest length `rest` [m], squared form:
/// returns `C = |x_i - x_j|^2 - L^2` [m^2] and the gradients `[grad_i C, grad_j C]` [m].
#[inline]
pub fn distance_constraint<V: Vector>(xi: V, xj: V, rest: V::Real) -> (V::Real, [V; 2]) {
    let d = xi - xj;
    let two = V::Real::from_f64(2.0);
    (d.dot(d) - rest * rest, [d * two, d * -two])
}

/// An implicit spring's constraint (physics.md, "Compliant (implicit) springs"): the spring
/// `(i, j)` with rest length `rest` [m] gives `C = |x_i - x_j| - L` [m] and the gradients
/// `[n, -n]` with `n = (x_i - x_j) / |x_i - x_j|` (zero for a spring of zero length, which is
/// then skipped, as its `A` is 0).
#[inline]
pub fn spring_constraint<V: Vector>(xi: V, xj: V, rest: V::Real) -> (V::Real, [V; 2]) {
    let d = xi - xj;
    let l = d.length();
    if l <= V::Real::ZERO {
        return (-rest, [V::ZERO, V::ZERO]);
    }
    let n = d * (V::Real::ONE / l);
    (l - rest, [n, V::ZERO - n])
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

/// The inversion floor of a tet with rest volume `rest` [m^3] (docs/PHYSICS.md, "Inversion
/// floor"): at the positions `p` its nodes reach at the step's end ([`end_position`]
/// (super::end_position)), the one-sided hard constraint `C = V(p) - floor V0 >= 0`. Returns
/// `C` [m^3] and its gradients at `p` [m^2] while the tet is below the floor (`C < 0`), `None`
/// at or above it. Unlike [`volume_constraint`] it is measured where the step ends, not
/// linearized at `x(t)`, so one sweep is one Newton step on the true volume; its multiplier is
/// [`implicit_multiplier`] with `b = 0` (the end positions already hold `v` and `F`).
#[inline]
pub fn inversion_floor<V: Vector>(
    p: [V; 4],
    rest: V::Real,
    floor: V::Real,
) -> Option<(V::Real, [V; 4])> {
    let (c, grad) = volume_constraint(p, rest * floor);
    (c < V::Real::ZERO).then_some((c, grad))
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

/// The direction a node's contacts hold it along: `+Y` where the floor pushes it
/// (`floor_pushes`: its floor force is positive), else the direction of the kinematic
/// colliders' force on it (`collider_force`, zero where none pushes it), else zero. MINRES
/// holds its nodes along the same direction ([`crate::physics::Mobility::held_by`];
/// `held_direction` in glsl/physics/implicit.glsl).
#[inline]
pub fn held_direction<V: Vector>(floor_pushes: bool, collider_force: V) -> V {
    if floor_pushes {
        V::UNIT_Y
    } else if collider_force != V::ZERO {
        collider_force * (V::Real::ONE / collider_force.length())
    } else {
        V::ZERO
    }
}

/// The part of a global volume constraint's `A` that a contact takes from a surface node it
/// holds along `held` ([`held_direction`]; physics.md, "One global volume constraint"):
/// `w (g . held)^2` where the gradient points into the contact (`g . held < 0`), else 0.
/// When the constraint pushes outward, such a node is pushed into the floor or the
/// collider, which takes that share of the push back. On the floor it is `w g_y^2` for a
/// node facing down (`contact_held` in glsl/physics/implicit.glsl).
#[inline]
pub fn contact_held<V: Vector>(grad: V, w: V::Real, held: V) -> V::Real {
    let along = grad.dot(held);
    if along < V::Real::ZERO {
        w * along * along
    } else {
        V::Real::ZERO
    }
}

/// The multiplier of a global volume constraint from its value `c`, its `A`, the sum part
/// of its `B` and the contacts' terms `held` (the sum of [`contact_held`] over its surface
/// nodes): [`implicit_multiplier`] with `A - held` when the push is outward
/// (`c / dt^2 + b < 0`, volume to gain), which presses the held nodes into their contacts, and
/// with `A` otherwise (`global_multiplier` in glsl/physics/implicit.glsl).
#[inline]
pub fn global_multiplier<R: Real>(c: R, a: R, b: R, held: R, dt: R, epsilon: R) -> Option<R> {
    let a = match c / (dt * dt) + b < R::ZERO {
        true => a - held,
        false => a,
    };
    implicit_multiplier(c, a, b, dt, epsilon)
}

/// The multiplier from a constraint's value `c` and its accumulated `A` and sum part of `B`
/// ([`implicit_accumulate`]): `(c / dt^2 + b) / a`, `None` when `a <= epsilon` or not
/// finite. The hard constraint: [`compliant_multiplier`] with softness 0.
#[inline]
pub fn implicit_multiplier<R: Real>(c: R, a: R, b: R, dt: R, epsilon: R) -> Option<R> {
    compliant_multiplier(c, a, b, dt, R::ZERO, R::ZERO, epsilon)
}

/// The multiplier of a compliant, damped constraint (physics.md, "Compliant (implicit)
/// springs"): the force `-lambda grad C` with `lambda = k C(t + dt) + kd dC/dt(t + dt)`, both
/// to first order in the step's new velocities, is
///
/// ```text
/// lambda = (B - kd s C / dt) / (A + s),   B = C / dt^2 + b
/// ```
///
/// with the softness `s` of [`spring_softness`] or [`volume_softness`] and the damping `kd`
/// (0 for a volume constraint). `s = 0` is the hard constraint, `B / A`. `None` (skip) when
/// `a <= epsilon` or `a` is not finite, as for [`implicit_multiplier`].
#[inline]
pub fn compliant_multiplier<R: Real>(
    c: R,
    a: R,
    b: R,
    dt: R,
    softness: R,
    damping: R,
    epsilon: R,
) -> Option<R> {
    if a > epsilon && a.is_finite() {
        Some(super::compliant_residual(c, b, dt, softness, damping) / (a + softness))
    } else {
        None
    }
}

/// The softness `s = 1 / (k dt^2 + kd dt)` [1/kg] of a spring of stiffness `k` [N/m] and
/// damping `kd` [N s/m] solved as a compliant constraint (compliance `1 / k`); infinite, and
/// the spring skipped by a non-finite multiplier, only when both are 0 (refused by the
/// parameters).
#[inline]
pub fn spring_softness<R: Real>(stiffness: R, damping: R, dt: R) -> R {
    R::ONE / (stiffness * dt * dt + damping * dt)
}

/// The softness `s = alpha / dt^2` of a volume constraint of compliance `alpha` [m^3/Pa]
/// (0: hard).
#[inline]
pub fn volume_softness<R: Real>(compliance: R, dt: R) -> R {
    compliance / (dt * dt)
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
    use crate::physics::tet_volume;
    use glam::DVec3;

    fn tet() -> [DVec3; 4] {
        [
            DVec3::ZERO,
            DVec3::new(1.0, 0.1, 0.0),
            DVec3::new(0.2, 1.0, 0.1),
            DVec3::new(0.1, 0.3, 1.2),
        ]
    }

    /// One pass of a global constraint over four surface nodes, one of them resting on the
    /// floor and facing down, then the floor solved again: with the floor's terms the
    /// linearised condition `C + dt sum_k g_k . v_k(t + dt) = 0` holds after the floor took
    /// its share; with the whole `A` (`implicit_multiplier`) it does not.
    #[test]
    fn the_global_multiplier_restores_the_volume_past_the_floor() {
        use crate::physics::floor_solve;
        let dt = 1e-3;
        let grad = [
            DVec3::new(0.1, -1.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(-1.1, 0.0, 0.2),
        ];
        let w = [1.0, 0.5, 2.0, 1.0];
        let c = -1e-6;
        // Every node at rest with no net force; node 0 on the floor (y = 0) under 10 N of
        // weight, which a floor force of 10 N holds (its total force holds both).
        let floor_force = [10.0, 0.0, 0.0, 0.0];
        // `C + dt sum_k g_k . v_k(t + dt)` after the push and the floor's solve of node 0.
        let left = |lambda: f64| -> f64 {
            let mut sum = 0.0;
            for k in 0..4 {
                let mut f = grad[k] * -lambda;
                if k == 0 {
                    f = floor_solve(f, floor_force[0], 0.0, 0.0, w[0], dt).0;
                }
                sum += grad[k].dot(dt * w[k] * f);
            }
            c + dt * sum
        };
        let (mut a, mut b, mut held) = (0.0, 0.0, 0.0);
        for k in 0..4 {
            implicit_accumulate(
                &mut a,
                &mut b,
                grad[k],
                w[k],
                1.0,
                DVec3::ZERO,
                DVec3::ZERO,
                dt,
            );
            held += contact_held(
                grad[k],
                w[k],
                held_direction(floor_force[k] > 0.0, DVec3::ZERO),
            );
        }
        assert_eq!(held, 1.0);
        let with = global_multiplier(c, a, b, held, dt, 1e-20).unwrap();
        let without = implicit_multiplier(c, a, b, dt, 1e-20).unwrap();
        assert!(
            left(with).abs() < 1e-15,
            "with the floor's terms: {:e}",
            left(with)
        );
        assert!(left(without).abs() > 1e-7, "without: {:e}", left(without));
        // Pushing inward lifts the node off the floor: A stays whole.
        assert_eq!(
            global_multiplier(-c, a, b, held, dt, 1e-20),
            implicit_multiplier(-c, a, b, dt, 1e-20)
        );
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
    fn the_inversion_floor_lifts_an_inverted_tet_and_leaves_the_others() {
        let p = tet();
        let rest = tet_volume(p);
        assert!(inversion_floor(p, rest, 0.1).is_none(), "at rest");
        // Node 3 pushed through the opposite face: the tet is inside out.
        let mut q = p;
        q[3].z = -0.4;
        assert!(tet_volume(q) < 0.0);
        let (c, _) = inversion_floor(q, rest, 0.1).expect("below the floor");
        assert!((c - (tet_volume(q) - 0.1 * rest)).abs() < 1e-15);
        // The hard multiplier with b = 0 (unit masses, dt 1), step after step along
        // -lambda grad C: the volume is cubic in the positions, so each step is one Newton
        // step; it rises every step and reaches the floor within a few.
        let mut at = q;
        let mut volumes = vec![tet_volume(q)];
        while let Some((c, grad)) = inversion_floor(at, rest, 0.1) {
            assert!(volumes.len() <= 4, "still below the floor: {volumes:?}");
            let a: f64 = grad.iter().map(|g| g.length_squared()).sum();
            let lambda = implicit_multiplier(c, a, 0.0, 1.0, 1e-12).unwrap();
            at = std::array::from_fn(|k| at[k] - grad[k] * lambda);
            volumes.push(tet_volume(at));
        }
        assert!(volumes.windows(2).all(|w| w[1] > w[0]), "{volumes:?}");
        assert!(
            *volumes.last().unwrap() >= 0.1 * rest && volumes.len() > 2,
            "{volumes:?}"
        );
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
    fn spring_constraint_gradient_matches_finite_differences() {
        let (xi, xj) = (DVec3::new(0.3, -0.2, 0.5), DVec3::new(1.0, 0.4, -0.1));
        let (c0, grad) = spring_constraint(xi, xj, 0.7);
        assert!((c0 - (xi.distance(xj) - 0.7)).abs() < 1e-15);
        let h = 1e-7;
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            let (c1, _) = spring_constraint(xi + axis * h, xj, 0.7);
            assert!(((c1 - c0) / h - grad[0].dot(axis)).abs() < 1e-6);
            let (c2, _) = spring_constraint(xi, xj + axis * h, 0.7);
            assert!(((c2 - c0) / h - grad[1].dot(axis)).abs() < 1e-6);
        }
    }

    /// One spring between a pinned node and a free one, at rest: the compliant multiplier
    /// is the backward-Euler force `k C(t + dt) + kd dC/dt(t + dt)` (checked by computing the
    /// new state), from a very soft spring to a stiff one, which tends to the hard
    /// constraint.
    #[test]
    fn compliant_multiplier_is_the_implicit_spring_force() {
        let (m, dt, rest) = (2.0, 1e-2, 1.0);
        let xi = DVec3::new(1.3, 0.0, 0.0);
        let vi = DVec3::new(0.5, 0.0, 0.0);
        let (c, grad) = spring_constraint(xi, DVec3::ZERO, rest);
        let lambda_for = |k: f64, kd: f64| {
            let (mut a, mut b) = (0.0, 0.0);
            implicit_accumulate(&mut a, &mut b, grad[0], 1.0 / m, 1.0, vi, DVec3::ZERO, dt);
            let s = spring_softness(k, kd, dt);
            compliant_multiplier(c, a, b, dt, s, kd, 0.0).unwrap()
        };
        for (k, kd) in [(1e-3, 0.0), (100.0, 0.0), (100.0, 3.0), (1e9, 0.0)] {
            let lambda = lambda_for(k, kd);
            let v1 = vi + grad[0] * (-lambda / m * dt);
            let x1 = xi + v1 * dt;
            let implicit = k * (x1.length() - rest) + kd * v1.x;
            // First order: exact for motion along the spring up to the length's curvature
            // (none here, the motion is along the spring).
            assert!(
                (lambda - implicit).abs() < 1e-9 * implicit.abs().max(1.0),
                "k {k} kd {kd}: {lambda} vs {implicit}"
            );
        }
        let hard = implicit_multiplier(c, 0.5, vi.x / dt, dt, 0.0).unwrap();
        assert!((lambda_for(1e12, 0.0) - hard).abs() < 1e-6 * hard);
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
