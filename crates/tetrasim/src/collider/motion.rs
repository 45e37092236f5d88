//! How a kinematic collider (or a clamp) moves: a rigid displacement of its declared pose as a
//! function of time, either with constant linear and angular velocity or along keyframes
//! (positions linear, rotations slerped, held after the last key). physics.md, "Kinematic
//! colliders".

use glam::{DQuat, DVec3};

use crate::error::{Error, Result};

/// A rigid placement: `world = position + rotation * local`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Where the local origin is [m].
    pub position: DVec3,
    /// The local frame's orientation (unit quaternion).
    pub rotation: DQuat,
}

impl Pose {
    /// The identity placement.
    pub const IDENTITY: Pose = Pose {
        position: DVec3::ZERO,
        rotation: DQuat::IDENTITY,
    };

    /// A local point in the world.
    pub fn apply(&self, local: DVec3) -> DVec3 {
        self.position + self.rotation * local
    }

    /// A world point in the local frame.
    pub fn invert(&self, world: DVec3) -> DVec3 {
        self.rotation.inverse() * (world - self.position)
    }
}

/// One key of a keyframed motion: at time `t` [s] the collider is displaced by `position` [m]
/// and turned by `rotation` about its declared centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Keyframe {
    /// Time [s].
    pub t: f64,
    /// Displacement of the declared centre [m].
    pub position: DVec3,
    /// Rotation about the declared centre (unit quaternion).
    pub rotation: DQuat,
}

/// A rigid motion of a collider or a clamp, relative to its declared pose: at time `t` the
/// declared shape is turned by `rotation(t)` about its declared centre, then moved by
/// `position(t)`.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Motion {
    /// It does not move.
    #[default]
    Fixed,
    /// Constant linear velocity [m/s] and angular velocity [rad/s] (about the centre).
    Velocity {
        /// Linear velocity [m/s].
        linear: DVec3,
        /// Angular velocity [rad/s], its direction the axis.
        angular: DVec3,
    },
    /// Keyframes in increasing time: before the first key its displacement, after the last
    /// key the last one's; between two keys the position is interpolated linearly and the
    /// rotation by slerp.
    Keyframes(Vec<Keyframe>),
}

impl Motion {
    /// The displacement at time `t` [s]: `(translation, rotation about the centre)`.
    pub fn displacement(&self, t: f64) -> (DVec3, DQuat) {
        match self {
            Motion::Fixed => (DVec3::ZERO, DQuat::IDENTITY),
            Motion::Velocity { linear, angular } => {
                (*linear * t, DQuat::from_scaled_axis(*angular * t))
            }
            Motion::Keyframes(keys) => {
                let after = keys.partition_point(|k| k.t <= t);
                match (after.checked_sub(1).map(|i| &keys[i]), keys.get(after)) {
                    (Some(a), Some(b)) => {
                        let s = (t - a.t) / (b.t - a.t);
                        (
                            a.position.lerp(b.position, s),
                            a.rotation.slerp(b.rotation, s).normalize(),
                        )
                    }
                    (Some(k), None) | (None, Some(k)) => (k.position, k.rotation),
                    (None, None) => (DVec3::ZERO, DQuat::IDENTITY),
                }
            }
        }
    }

    /// Whether it ever moves.
    pub fn is_moving(&self) -> bool {
        match self {
            Motion::Fixed => false,
            Motion::Velocity { linear, angular } => {
                *linear != DVec3::ZERO || *angular != DVec3::ZERO
            }
            Motion::Keyframes(keys) => keys
                .windows(2)
                .any(|w| w[0].position != w[1].position || w[0].rotation != w[1].rotation),
        }
    }

    /// Checks finiteness, unit quaternions and keyframe order; `key` names the motion in
    /// messages (e.g. `collider[0].motion`).
    pub fn validate(&self, key: &str) -> Result<()> {
        match self {
            Motion::Fixed => Ok(()),
            Motion::Velocity { linear, angular } => {
                finite_vector(&format!("{key}.velocity"), *linear)?;
                finite_vector(&format!("{key}.angular_velocity"), *angular)
            }
            Motion::Keyframes(keys) => {
                if keys.is_empty() {
                    return Err(param(
                        &format!("{key}.keyframes"),
                        "needs at least one keyframe",
                    ));
                }
                for (i, k) in keys.iter().enumerate() {
                    let at = format!("{key}.keyframes[{i}]");
                    if !k.t.is_finite() {
                        return Err(param(
                            &format!("{at}.t"),
                            format!("must be finite, got {}", k.t),
                        ));
                    }
                    finite_vector(&format!("{at}.position"), k.position)?;
                    unit_quaternion(&format!("{at}.rotation"), k.rotation)?;
                    if i > 0 && k.t <= keys[i - 1].t {
                        return Err(param(
                            &format!("{at}.t"),
                            format!(
                                "keyframes must be in increasing time: {} follows {}",
                                k.t,
                                keys[i - 1].t
                            ),
                        ));
                    }
                }
                Ok(())
            }
        }
    }
}

/// A parameter error for `key`.
pub(crate) fn param(key: &str, message: impl Into<String>) -> Error {
    Error::Param {
        key: key.to_string(),
        message: message.into(),
    }
}

/// Refuses a non-finite vector.
pub(crate) fn finite_vector(key: &str, v: DVec3) -> Result<()> {
    match v.is_finite() {
        true => Ok(()),
        false => Err(param(key, format!("must be finite, got {v:?}"))),
    }
}

/// Refuses a zero, non-finite or non-unit quaternion (`|q|` off 1 by more than 1e-6).
pub(crate) fn unit_quaternion(key: &str, q: DQuat) -> Result<()> {
    let length = q.length();
    if !length.is_finite() || (length - 1.0).abs() > 1e-6 {
        return Err(param(
            key,
            format!(
                "must be a unit quaternion [w, x, y, z], got [{}, {}, {}, {}] (length {length})",
                q.w, q.x, q.y, q.z
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyframes_interpolate_and_hold() {
        let quarter = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2);
        let motion = Motion::Keyframes(vec![
            Keyframe {
                t: 1.0,
                position: DVec3::ZERO,
                rotation: DQuat::IDENTITY,
            },
            Keyframe {
                t: 3.0,
                position: DVec3::new(2.0, 0.0, 0.0),
                rotation: quarter,
            },
        ]);
        assert_eq!(
            motion.displacement(0.0).0,
            DVec3::ZERO,
            "held before the first key"
        );
        let (p, q) = motion.displacement(2.0);
        assert!((p - DVec3::new(1.0, 0.0, 0.0)).length() < 1e-12);
        let half = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_4);
        assert!(q.angle_between(half) < 1e-9, "slerped halfway");
        assert_eq!(
            motion.displacement(10.0).0,
            DVec3::new(2.0, 0.0, 0.0),
            "held after the last key"
        );
    }

    #[test]
    fn velocity_turns_about_the_axis() {
        let motion = Motion::Velocity {
            linear: DVec3::new(0.0, -1.0, 0.0),
            angular: DVec3::new(0.0, 2.0, 0.0),
        };
        let (p, q) = motion.displacement(0.5);
        assert_eq!(p, DVec3::new(0.0, -0.5, 0.0));
        assert!((q * DVec3::X - DVec3::new(1f64.cos(), 0.0, -1f64.sin())).length() < 1e-12);
    }

    #[test]
    fn bad_motions_name_their_key() {
        let key = |m: Motion| {
            m.validate("collider[2].motion")
                .expect_err("refused")
                .to_string()
        };
        let k = |t: f64, w: f64| Keyframe {
            t,
            position: DVec3::ZERO,
            rotation: DQuat::from_xyzw(0.0, 0.0, 0.0, w),
        };
        let out_of_order = key(Motion::Keyframes(vec![k(1.0, 1.0), k(0.5, 1.0)]));
        assert!(
            out_of_order.contains("collider[2].motion.keyframes[1].t"),
            "{out_of_order}"
        );
        let zero = key(Motion::Keyframes(vec![k(0.0, 0.0)]));
        assert!(
            zero.contains("keyframes[0].rotation") && zero.contains("unit quaternion"),
            "{zero}"
        );
        assert!(key(Motion::Keyframes(vec![])).contains("at least one"));
    }
}
