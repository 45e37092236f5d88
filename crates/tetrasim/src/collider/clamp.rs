//! Pins that move (physics.md, "Kinematic colliders": "Pins that move"): a set of pinned
//! nodes (inverse mass 0) carried rigidly by a [`Motion`] about their centroid, a clamp.
//! Each step, every backend gives a clamped node the velocity that takes it from where it is
//! to its target at the step's end; symplectic Euler with `w = 0` then lands it there, and
//! the constraints, which predict positions as `x + dt v` for a pinned node, see the move.

use glam::DVec3;

use super::Motion;

/// Pinned nodes that follow a rigid motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Clamp {
    /// The nodes it holds (all pinned).
    pub nodes: Vec<u32>,
    /// The centre the motion turns them about [m] (their centroid at rest).
    pub centre: DVec3,
    /// How it moves from the rest positions.
    pub motion: Motion,
}

impl Clamp {
    /// Where the node at rest position `rest` is at time `t` [s].
    pub fn target(&self, rest: DVec3, t: f64) -> DVec3 {
        let (translation, rotation) = self.motion.displacement(t);
        self.centre + translation + rotation * (rest - self.centre)
    }
}

/// Per node of a model with `nodes` nodes, the clamp that holds it (empty without clamps):
/// how the forces out share the pins' force among the clamps.
pub fn clamp_of_nodes(clamps: &[Clamp], nodes: usize) -> Vec<Option<u32>> {
    if clamps.is_empty() {
        return Vec::new();
    }
    let mut of = vec![None; nodes];
    for (c, clamp) in clamps.iter().enumerate() {
        for &i in &clamp.nodes {
            of[i as usize] = Some(c as u32);
        }
    }
    of
}

/// The velocity [m/s] of every clamped node for step `step` of length `dt` [s]: from its
/// position `x(i)` to its target at the step's end, `t = (step + 1) dt`, over `dt`.
/// `rest` are the model's initial positions; `set(i, v)` receives each.
pub fn drive(
    clamps: &[Clamp],
    rest: &[DVec3],
    step: u64,
    dt: f64,
    x: impl Fn(usize) -> DVec3,
    mut set: impl FnMut(usize, DVec3),
) {
    let t = (step + 1) as f64 * dt;
    for clamp in clamps {
        for &i in &clamp.nodes {
            let i = i as usize;
            set(i, (clamp.target(rest[i], t) - x(i)) / dt);
        }
    }
}
