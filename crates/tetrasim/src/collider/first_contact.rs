//! When a body falling freely from its start state first touches a fixed collider: what a
//! run record's `contact_time_s` adds to the floor's closed form
//! ([`crate::model::Model::contact_time`]), so that a run that ends before a body lands on a
//! collider says so as it does for the floor.

use glam::DVec3;
use rayon::prelude::*;

use super::{clearance, Collider, ColliderAt, Motion};

/// How far ahead the search looks [s]: a body that has not touched a collider after a
/// minute of free fall is taken never to.
pub const HORIZON_S: f64 = 60.0;

/// A node this close to a collider's contact surface [m] touches it.
const TOUCH_M: f64 = 1e-9;

/// Most steps of one node's search: the clearance at least halves with every step towards
/// a collider, so a node heading for one needs a few dozen.
const MAX_STEPS: usize = 2000;

/// When the first of `nodes` (start position and velocity of each free node) would come
/// within its contact thickness of one of the fixed `colliders`, each node falling freely
/// under `gravity` [m/s^2] [s]: 0 if one starts in contact, `None` if none does
/// within [`HORIZON_S`] or no collider is fixed. Moving colliders are left out (where they
/// are is not a question of the body's fall).
///
/// Conservative advancement along each node's parabola: a node that moves less than its
/// [`clearance`] in a stretch of time cannot touch a collider in it, and the stretch is
/// the longest for which the fall's speed bound keeps it so.
pub fn free_fall_contact_time(
    colliders: &[Collider],
    nodes: &[(DVec3, DVec3)],
    gravity: DVec3,
) -> Option<f64> {
    let fixed: Vec<ColliderAt<'_>> = colliders
        .iter()
        .filter(|c| c.motion == Motion::Fixed)
        .map(|c| ColliderAt::new(c, 0.0, 0.0))
        .collect();
    if fixed.is_empty() {
        return None;
    }
    nodes
        .par_iter()
        .filter_map(|&(x, v)| node_contact_time(&fixed, x, v, gravity))
        .min_by(f64::total_cmp)
}

/// [`free_fall_contact_time`] of one node starting at `x0` with velocity `v0`.
fn node_contact_time(fixed: &[ColliderAt<'_>], x0: DVec3, v0: DVec3, a: DVec3) -> Option<f64> {
    let mut t = 0.0;
    for _ in 0..MAX_STEPS {
        let x = x0 + v0 * t + 0.5 * a * t * t;
        let clear = clearance(fixed, x);
        if clear <= TOUCH_M {
            return Some(t);
        }
        let speed = (v0 + a * t).length();
        t += stretch(speed, a.length(), clear)?;
        if t > HORIZON_S {
            return None;
        }
    }
    None
}

/// The longest time a point moving at `speed` and accelerated by at most `accel` stays
/// within `distance` of where it starts (`speed h + accel h^2 / 2 = distance`); `None` for
/// a point that never moves.
fn stretch(speed: f64, accel: f64, distance: f64) -> Option<f64> {
    if accel > 0.0 {
        // The root written without the cancellation of -speed + sqrt(...).
        Some(2.0 * distance / (speed + (speed * speed + 2.0 * accel * distance).sqrt()))
    } else if speed > 0.0 {
        Some(distance / speed)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Pose;

    const G: f64 = 9.81;
    const DOWN: DVec3 = DVec3::new(0.0, -G, 0.0);

    #[test]
    fn a_node_dropped_on_a_plane_lands_when_the_closed_form_says() {
        // The half-space y <= -0.5: from y = 0.3 at rest the fall is 0.8 m.
        let plane = Collider::plane(DVec3::Y, -0.5).unwrap();
        let t = free_fall_contact_time(&[plane], &[(DVec3::new(0.0, 0.3, 0.0), DVec3::ZERO)], DOWN)
            .unwrap();
        assert!((t - (2.0 * 0.8 / G).sqrt()).abs() < 1e-8, "{t}");
    }

    #[test]
    fn a_thrown_node_meets_a_sphere_and_the_earliest_node_counts() {
        // A ball of radius 0.2 at the origin with a contact thickness of 0.05; one node
        // 1 m above it at rest lands at |y| = 0.25, another thrown down at 2 m/s from 0.5 m
        // lands first (2 t + g t^2 / 2 = 0.25).
        let mut ball = Collider::sphere(DVec3::ZERO, 0.2);
        ball.thickness = 0.05;
        let resting = (DVec3::new(0.0, 1.0, 0.0), DVec3::ZERO);
        let thrown = (DVec3::new(0.0, 0.5, 0.0), DVec3::new(0.0, -2.0, 0.0));
        let t = free_fall_contact_time(&[ball.clone()], &[resting, thrown], DOWN).unwrap();
        let expected = (-2.0 + (4.0 + 2.0 * G * 0.25f64).sqrt()) / G;
        assert!((t - expected).abs() < 1e-8, "{t} vs {expected}");
        let t = free_fall_contact_time(&[ball], &[resting], DOWN).unwrap();
        assert!((t - (2.0 * 0.75 / G).sqrt()).abs() < 1e-8, "{t}");
    }

    #[test]
    fn a_node_beside_a_collider_or_a_moving_collider_gives_none() {
        let ball = Collider::sphere(DVec3::ZERO, 0.2);
        let beside = (DVec3::new(1.0, 1.0, 0.0), DVec3::ZERO);
        assert_eq!(
            free_fall_contact_time(&[ball.clone()], &[beside], DOWN),
            None
        );
        let above = (DVec3::new(0.0, 1.0, 0.0), DVec3::ZERO);
        let moving = ball.moving(Motion::Velocity {
            linear: DVec3::X,
            angular: DVec3::ZERO,
        });
        assert_eq!(free_fall_contact_time(&[moving], &[above], DOWN), None);
    }

    #[test]
    fn a_node_inside_a_turned_box_touches_at_once() {
        let tilted = Collider::new(
            crate::collider::Shape::Cuboid {
                half_extents: DVec3::splat(0.5),
            },
            Pose {
                position: DVec3::ZERO,
                rotation: glam::DQuat::from_rotation_z(0.3),
            },
        );
        let t =
            free_fall_contact_time(&[tilted], &[(DVec3::new(0.1, 0.1, 0.0), DVec3::ZERO)], DOWN);
        assert_eq!(t, Some(0.0));
    }
}
