//! Time integration and the floor (physics.md, "Time integration" and step 3).

use super::{Real, Vector};

/// Symplectic Euler (paper Eqs. 2, 3): `v' = v + dt w F`, `x' = x + dt v'`.
///
/// `f` is the total force [N] on the node, gravity included (as `m g`), `w` the inverse mass
/// [1/kg] (0 pins the node) and `dt` the step [s]. Returns `(x', v')`.
#[inline]
pub fn symplectic_euler<V: Vector>(x: V, v: V, f: V, w: V::Real, dt: V::Real) -> (V, V) {
    let v1 = v + f * (w * dt);
    (x + v1 * dt, v1)
}

/// The floor plane `y = 0`: a node strictly below it is put back on it, its normal (Y)
/// velocity is clamped to be non-negative and its tangential velocity is scaled by
/// `1 - friction`. Nodes on or above the floor are returned unchanged. Returns `(x', v')`.
#[inline]
pub fn resolve_floor<V: Vector>(x: V, v: V, friction: V::Real) -> (V, V) {
    let height = x.y();
    let below = height < V::Real::ZERO;
    if !below {
        return (x, v);
    }
    let up = V::UNIT_Y;
    let vn = v.dot(up);
    let tangential = v - up * vn;
    (
        x - up * height,
        tangential * (V::Real::ONE - friction) + up * vn.max(V::Real::ZERO),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3A};

    #[test]
    fn floor_projects_position_and_clamps_velocity() {
        let (x, v) = resolve_floor(
            DVec3::new(0.5, -0.01, 2.0),
            DVec3::new(2.0, -3.0, -4.0),
            0.25,
        );
        assert_eq!(x, DVec3::new(0.5, 0.0, 2.0));
        assert_eq!(v, DVec3::new(1.5, 0.0, -3.0));
        let (x, v) = resolve_floor(Vec3A::new(0.0, -1.0, 0.0), Vec3A::new(0.0, 2.0, 1.0), 1.0);
        assert_eq!((x, v), (Vec3A::ZERO, Vec3A::new(0.0, 2.0, 0.0)));
    }

    #[test]
    fn nodes_above_floor_are_untouched() {
        let (x, v) = resolve_floor(DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, -1.0, 0.0), 0.5);
        assert_eq!((x, v), (DVec3::ZERO, DVec3::new(1.0, -1.0, 0.0)));
    }

    #[test]
    fn euler_updates_velocity_first() {
        let (x, v) = symplectic_euler(DVec3::ZERO, DVec3::X, DVec3::new(0.0, -2.0, 0.0), 0.5, 0.1);
        assert!((v - DVec3::new(1.0, -0.1, 0.0)).length() < 1e-15);
        assert!((x - DVec3::new(0.1, -0.01, 0.0)).length() < 1e-15);
    }
}
