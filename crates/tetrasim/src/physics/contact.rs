//! Contact with kinematic colliders (physics.md, third edition, "Kinematic colliders"): the
//! one-sided constraint `phi(x) - r >= 0` on one node, solved like the floor's (exactly for
//! a plane, linearised along the normal for curved shapes, re-solved every iteration). The
//! GLSL twins, same names, are in glsl/physics/contact.glsl.

use super::integrate::coulomb_friction;
use super::{Real, Vector};

/// Which of a time step's solves runs (physics.md, "Contact that does not bounce back"): the
/// full one, whose forces give the new positions (and, with combined contact, the new
/// velocities too), or split contact's velocity solve, whose forces give the new velocities:
/// it asks every hard constraint for no change of its value (`C = 0`) and every one-sided
/// constraint (floor, colliders, contacts between bodies) to close its gap but not to undo
/// the penetration it starts the step with. Its GLSL twin is the push constant `phase`
/// (`PHASE_FULL`, `PHASE_VELOCITY`) with the same two functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Solve {
    /// Every constraint as it is.
    #[default]
    Full,
    /// Position errors left out: only velocities are solved for.
    Velocity,
}

impl Solve {
    /// The value [`compliant_multiplier`](super::compliant_multiplier) is given for a hard
    /// constraint of value `c`: `c`, or 0 in the velocity solve. Compliant constraints are
    /// elastic forces and keep their value in both.
    #[inline]
    pub fn hard<R: Real>(self, c: R) -> R {
        match self {
            Solve::Full => c,
            Solve::Velocity => R::ZERO,
        }
    }

    /// What a one-sided constraint (`C >= 0`) whose value at the step's start is `c_start`
    /// adds to its value: 0, or in the velocity solve the penetration it starts with
    /// (`max(-c_start, 0)`), so that the velocities stop the node going deeper without
    /// pushing it out.
    #[inline]
    pub fn slack<R: Real>(self, c_start: R) -> R {
        match self {
            Solve::Full => R::ZERO,
            Solve::Velocity => (R::ZERO - c_start).max(R::ZERO),
        }
    }
}

/// Where a node at `x` [m] with velocity `v` [m/s], total force `f` [N] and inverse mass `w`
/// [1/kg] ends the step of `dt` [s] by symplectic Euler: `x + dt (v + dt w f)`.
#[inline]
pub fn end_position<V: Vector>(x: V, v: V, f: V, w: V::Real, dt: V::Real) -> V {
    x + (v + f * (w * dt)) * dt
}

/// The normal force [N] that moves a node whose end-of-step position is at signed distance
/// `phi` [m] from a collider out to distance `thickness` along the normal:
/// `(thickness - phi) / (dt^2 w)`, and 0 when it is already there or pinned (`w = 0`).
#[inline]
pub fn contact_push<R: Real>(phi: R, thickness: R, w: R, dt: R) -> R {
    if w <= R::ZERO || phi >= thickness {
        return R::ZERO;
    }
    (thickness - phi) / (dt * dt * w)
}

/// Friction of a node in contact with a moving surface: [`coulomb_friction`] of its velocity
/// `v` [m/s] relative to the surface's `surface` [m/s], about `normal` (unit), with
/// `pressed = push w dt` the velocity the contact's push ([`contact_push`]) gave it along
/// the normal in the step: the friction fades to nothing as the push does.
#[inline]
pub fn surface_friction<V: Vector>(
    v: V,
    surface: V,
    normal: V,
    friction: V::Real,
    pressed: V::Real,
) -> V {
    surface + coulomb_friction(v - surface, normal, friction, pressed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn the_push_lands_the_node_on_the_surface() {
        let (x, v, w, dt) = (
            DVec3::new(0.0, 0.001, 0.0),
            DVec3::new(0.0, -2.0, 0.0),
            0.5,
            1e-3,
        );
        let f = DVec3::new(0.0, -10.0, 0.0);
        let end = end_position(x, v, f, w, dt);
        let push = contact_push(end.y, 0.0, w, dt);
        let landed = end_position(x, v, f + DVec3::Y * push, w, dt);
        assert!(landed.y.abs() < 1e-15, "ends on the plane: {}", landed.y);
        assert_eq!(contact_push(0.01, 0.0, w, dt), 0.0, "no pull");
        assert_eq!(contact_push(-0.01, 0.0, 0.0, dt), 0.0, "pinned");
    }

    #[test]
    fn friction_acts_on_the_relative_tangential_velocity() {
        let surface = DVec3::new(1.0, 0.0, 0.0);
        let v = DVec3::new(3.0, -1.0, 0.0);
        // Pressed harder than it slides: `friction` of the sliding goes.
        let held = surface_friction(v, surface, DVec3::Y, 1.0, 5.0);
        assert_eq!(held, DVec3::new(1.0, -1.0, 0.0));
        assert_eq!(surface_friction(v, surface, DVec3::Y, 0.0, 5.0), v);
        let kept = surface_friction(v, surface, DVec3::Y, 0.5, 5.0);
        assert_eq!(kept, DVec3::new(2.0, -1.0, 0.0));
    }

    #[test]
    fn friction_is_bounded_by_the_push_and_fades_with_it() {
        let (surface, v) = (DVec3::ZERO, DVec3::new(2.0, -1.0, 0.0));
        // Sliding at 2 m/s, pressed by 0.5 m/s: at most 0.8 * 0.5 = 0.4 m/s goes.
        let slid = surface_friction(v, surface, DVec3::Y, 0.8, 0.5);
        assert!(
            (slid - DVec3::new(1.6, -1.0, 0.0)).length() < 1e-15,
            "{slid}"
        );
        // No push, no friction; a vanishing push, a vanishing friction (no jump at 0).
        assert_eq!(surface_friction(v, surface, DVec3::Y, 0.8, 0.0), v);
        let grazing = surface_friction(v, surface, DVec3::Y, 0.8, 1e-9);
        assert!((grazing - v).length() < 1e-8, "{grazing}");
    }
}
