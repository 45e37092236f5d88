//! Hands that grab (physics.md, "Kinematic colliders": "a grab attaches the nodes within a
//! radius of a point to a moving handle ... and releases them"). A [`Grab`] holds the nodes
//! that were within its radius of its point at rest; while it holds (until its release
//! time), each of them is attached to its target, the handle's rigid motion applied to the
//! node's rest position about the point. The attachment is solved like a collider contact,
//! with the node's other forces (the floor's and the colliders' pushes come after it):
//! hard, the force that ends the step on the target, `(target - x_e) / (dt^2 w)`, or
//! compliant with stiffness `k`, `k (target - x_e) / (1 + k dt^2 w)` (a zero-length spring
//! solved implicitly). Inverse masses never change, so releasing is only the force stopping.

use glam::DVec3;

use super::motion::param;
use super::Motion;
use crate::error::Result;

/// Nodes attached to a moving handle until a release time.
#[derive(Debug, Clone, PartialEq)]
pub struct Grab {
    /// Where the handle grabs, at rest [m] (its motion turns about this point).
    pub point: DVec3,
    /// Nodes within this distance of `point` at rest are held [m].
    pub radius: f64,
    /// How the handle moves.
    pub motion: Motion,
    /// When it lets go [s] (`None`: never).
    pub release: Option<f64>,
    /// Attachment stiffness [N/m] (`None`: hard).
    pub stiffness: Option<f64>,
    /// The nodes it holds (set when it is added to a model).
    pub nodes: Vec<u32>,
}

impl Grab {
    /// A hard grab of the nodes within `radius` of `point`, holding still, never released.
    pub fn new(point: DVec3, radius: f64) -> Self {
        Grab {
            point,
            radius,
            motion: Motion::Fixed,
            release: None,
            stiffness: None,
            nodes: Vec::new(),
        }
    }

    /// The same grab moving its handle along `motion`.
    pub fn moving(mut self, motion: Motion) -> Self {
        self.motion = motion;
        self
    }

    /// The same grab letting go at time `t` [s].
    pub fn release_at(mut self, t: f64) -> Self {
        self.release = Some(t);
        self
    }

    /// The same grab with a compliant attachment of stiffness `k` [N/m].
    pub fn compliant(mut self, k: f64) -> Self {
        self.stiffness = Some(k);
        self
    }

    /// Whether it holds its nodes at time `t` [s].
    pub fn holds(&self, t: f64) -> bool {
        self.release.map_or(true, |r| t < r)
    }

    /// Where the node at rest position `rest` is held at time `t` [s].
    pub fn target(&self, rest: DVec3, t: f64) -> DVec3 {
        let (translation, rotation) = self.motion.displacement(t);
        self.point + translation + rotation * (rest - self.point)
    }

    /// Checks its values; `key` names it in messages (e.g. `grab[0]`).
    pub fn validate(&self, key: &str) -> Result<()> {
        if !self.point.is_finite() {
            return Err(param(
                &format!("{key}.point"),
                format!("must be finite, got {}", self.point),
            ));
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(param(
                &format!("{key}.radius"),
                format!("must be positive and finite, got {}", self.radius),
            ));
        }
        if let Some(t) = self.release.filter(|t| !t.is_finite()) {
            return Err(param(
                &format!("{key}.release"),
                format!("must be finite, got {t}"),
            ));
        }
        if let Some(k) = self.stiffness.filter(|k| !(k.is_finite() && *k > 0.0)) {
            return Err(param(
                &format!("{key}.stiffness"),
                format!("must be positive and finite, got {k}"),
            ));
        }
        self.motion.validate(&format!("{key}.motion"))
    }
}

/// A node's attachment in one step: where it must end and how stiffly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Attachment {
    /// Its target at the step's end [m].
    pub target: DVec3,
    /// Stiffness [N/m] (infinite: hard).
    pub stiffness: f64,
}

impl Attachment {
    /// The force [N] on a node of inverse mass `w` [1/kg] that would end the step of `dt` [s]
    /// at `end` without it.
    pub fn force(&self, end: DVec3, w: f64, dt: f64) -> DVec3 {
        let gap = self.target - end;
        match self.stiffness.is_finite() {
            true => gap * (self.stiffness / (1.0 + self.stiffness * dt * dt * w)),
            false => gap / (dt * dt * w),
        }
    }
}

/// Per node, its attachment over the step from `t` to `t + dt` (`None` for a free node):
/// the grabs still holding at the step's end, the first holding a node winning.
pub fn attachments(grabs: &[Grab], rest: &[DVec3], t: f64, dt: f64) -> Vec<Option<Attachment>> {
    let mut out = vec![None; rest.len()];
    let end = t + dt;
    for grab in grabs.iter().filter(|g| g.holds(end)) {
        for &i in &grab.nodes {
            let slot = &mut out[i as usize];
            if slot.is_none() {
                *slot = Some(Attachment {
                    target: grab.target(rest[i as usize], end),
                    stiffness: grab.stiffness.unwrap_or(f64::INFINITY),
                });
            }
        }
    }
    out
}
