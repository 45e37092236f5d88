//! Time integration and the floor (physics.md, "Time integration" and step 3); the GLSL
//! twins, same names, are in glsl/physics/integrate.glsl.

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

/// Floor contact (physics.md, second edition, "Contact without false restitution"): the floor
/// `y = 0` as a one-sided constraint `C = y >= 0` on one node, solved exactly in the implicit
/// framework, so no position is ever projected and no correction turns into velocity.
///
/// `y` [m] and `vy` [m/s] are the node's height and vertical velocity at the start of the
/// step, `fy_other` [N] every other vertical force on it (gravity, springs, constraints), `w`
/// its inverse mass [1/kg] and `dt` the step [s]. Returns the floor's normal force [N]: the
/// smallest `n >= 0` with `y + dt (vy + dt w (fy_other + n)) >= 0`, i.e. the node ends the
/// step on or above the floor and a node at rest on it keeps zero normal velocity. Pinned
/// nodes (`w = 0`) get none.
#[inline]
pub fn floor_force<R: Real>(y: R, vy: R, fy_other: R, w: R, dt: R) -> R {
    if w <= R::ZERO {
        return R::ZERO;
    }
    let needed = -(y + dt * vy) / (dt * dt * w) - fy_other;
    needed.max(R::ZERO)
}

/// Re-solves a node's floor force against its total force `f` [N], which already holds the
/// floor force `n` found so far (as part of `f.y`): returns the updated `(f, n)`. Every
/// backend calls this after each constraint sweep and before integrating (`floor_solve` in
/// glsl/physics/integrate.glsl).
#[inline]
pub fn floor_solve<V: Vector>(
    f: V,
    n: V::Real,
    y: V::Real,
    vy: V::Real,
    w: V::Real,
    dt: V::Real,
) -> (V, V::Real) {
    let other = f.y() - n;
    let n1 = floor_force(y, vy, other, w, dt);
    (f + V::UNIT_Y * (n1 - n), n1)
}

/// Friction bounded by Coulomb's law with `mu = friction`, on a velocity `relative` to the
/// surface: its part tangential to `normal` (unit) loses `friction` of itself, but never
/// more than `friction * pressed`, where `pressed` [m/s] is the velocity the contact's force
/// gave the node along the normal in the step (`n w dt`). Pressed harder than it slides, a
/// node keeps `1 - friction` of its sliding; barely touching, it slides almost freely; no
/// push, no friction. The normal part is kept.
#[inline]
pub fn coulomb_friction<V: Vector>(
    relative: V,
    normal: V,
    friction: V::Real,
    pressed: V::Real,
) -> V {
    let normal_part = normal * relative.dot(normal);
    let sliding = relative - normal_part;
    let speed = sliding.length();
    let removed = match speed > pressed {
        true => friction * pressed / speed,
        false => friction,
    };
    normal_part + sliding * (V::Real::ONE - removed)
}

/// Friction of a node on the floor: [`coulomb_friction`] about the up direction, `pressed`
/// the velocity its floor force `n` gave it in the step (`n w dt`; 0 off the floor).
#[inline]
pub fn floor_friction<V: Vector>(v: V, friction: V::Real, pressed: V::Real) -> V {
    coulomb_friction(v, V::UNIT_Y, friction, pressed)
}

/// Symplectic Euler with floor friction (`integrate_node` in glsl/physics/integrate.glsl):
/// `v' = v + dt w F`; a node on the floor (floor force `n > 0`) gets [`floor_friction`] with
/// `pressed = n w dt`; then `x' = x + dt v'`. Returns `(x', v')`.
#[inline]
pub fn integrate_node<V: Vector>(
    x: V,
    v: V,
    f: V,
    w: V::Real,
    dt: V::Real,
    n: V::Real,
    friction: V::Real,
) -> (V, V) {
    let mut v1 = v + f * (w * dt);
    if n > V::Real::ZERO {
        v1 = floor_friction(v1, friction, n * w * dt);
    }
    (x + v1 * dt, v1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3A};

    #[test]
    fn floor_force_lands_the_node_on_the_floor() {
        let (dt, w) = (1e-3, 0.5);
        // Falling at 2 m/s from 1 mm: it would end at -1 mm - dt^2 w 10; the floor stops it at 0.
        let n: f64 = floor_force(1e-3, -2.0, -10.0, w, dt);
        assert!(n > 0.0);
        let vy = -2.0 + dt * w * (-10.0 + n);
        assert!((1e-3 + dt * vy).abs() < 1e-15, "ends at {}", 1e-3 + dt * vy);
        // Resting on the floor under gravity: the floor carries exactly the weight.
        let n: f64 = floor_force(0.0, 0.0, -9.81 / w, w, dt);
        assert!((n - 9.81 / w).abs() < 1e-9);
        // Moving up or high above: no force; pinned: no force.
        assert_eq!(floor_force(0.0, 1.0, -1.0, w, dt), 0.0);
        assert_eq!(floor_force(1.0, -1.0, -1.0, w, dt), 0.0);
        assert_eq!(floor_force(-1.0, -1.0, -1.0, 0.0, dt), 0.0);
    }

    #[test]
    fn friction_scales_tangential_velocity_of_nodes_in_contact() {
        // Pressed harder than it slides: `friction` of the sliding goes.
        let v = floor_friction(DVec3::new(2.0, -3.0, -4.0), 0.25, 10.0);
        assert_eq!(v, DVec3::new(1.5, -3.0, -3.0));
        // Pressed by 1 m/s while sliding at sqrt(20): at most 0.25 m/s goes (Coulomb).
        let slid = floor_friction(DVec3::new(2.0, -3.0, -4.0), 0.25, 1.0);
        let kept = 1.0 - 0.25 / 20f64.sqrt();
        assert!((slid - DVec3::new(2.0 * kept, -3.0, -4.0 * kept)).length() < 1e-15);
        // Held by a floor force of 4 N (w 1, dt 0.5: pressed 2 m/s): stops.
        let (x, v) = integrate_node(
            Vec3A::ZERO,
            Vec3A::new(2.0, 0.0, 0.0),
            Vec3A::ZERO,
            1.0,
            0.5,
            4.0,
            1.0,
        );
        assert_eq!((x, v), (Vec3A::ZERO, Vec3A::ZERO));
        // A floor force of 1 N (pressed 0.5 m/s) takes only 0.5 of the 2 m/s.
        let (_, v) = integrate_node(
            Vec3A::ZERO,
            Vec3A::new(2.0, 0.0, 0.0),
            Vec3A::ZERO,
            1.0,
            0.5,
            1.0,
            1.0,
        );
        assert_eq!(v, Vec3A::new(1.5, 0.0, 0.0));
        let (x, _) = integrate_node(
            Vec3A::ZERO,
            Vec3A::new(2.0, 0.0, 0.0),
            Vec3A::ZERO,
            1.0,
            0.5,
            0.0,
            1.0,
        );
        assert_eq!(x, Vec3A::new(1.0, 0.0, 0.0));
    }

    #[test]
    fn euler_updates_velocity_first() {
        let (x, v) = symplectic_euler(DVec3::ZERO, DVec3::X, DVec3::new(0.0, -2.0, 0.0), 0.5, 0.1);
        assert!((v - DVec3::new(1.0, -0.1, 0.0)).length() < 1e-15);
        assert!((x - DVec3::new(0.1, -0.01, 0.0)).length() < 1e-15);
    }
}
