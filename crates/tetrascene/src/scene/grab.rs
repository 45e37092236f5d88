//! `[[grab]]`: a handle that holds the free nodes within its radius of a point (at the
//! start) and moves them with its motion, hard or through a spring, until it lets go
//! ([`tetrasim::collider::Grab`]): a surgeon's forceps, a robot's gripper.

use super::*;
use tetrasim::collider::Grab;

/// `[[grab]]`: where it grabs, how far it reaches, how it moves, when it lets go.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrabSpec {
    /// Where the handle grabs, at the start [m] (its motion turns about this point).
    pub point: [f64; 3],
    /// The free nodes within this distance of `point` at the start are held [m].
    pub radius: f64,
    /// How the handle moves (absent: it holds still), as a collider's motion.
    #[serde(default)]
    pub motion: Option<MotionSpec>,
    /// When it lets go [s] (absent: never).
    #[serde(default)]
    pub release: Option<f64>,
    /// Attachment stiffness [N/m] (absent: hard).
    #[serde(default)]
    pub stiffness: Option<f64>,
}

impl GrabSpec {
    /// The engine's grab (its nodes found when it is added to a model); errors name `key`'s
    /// motion.
    pub fn grab(&self, key: &str) -> Result<Grab> {
        let motion = match &self.motion {
            Some(spec) => spec.motion(&format!("{key}.motion"))?,
            None => Motion::Fixed,
        };
        Ok(Grab {
            motion,
            release: self.release,
            stiffness: self.stiffness,
            ..Grab::new(DVec3::from(self.point), self.radius)
        })
    }
}
