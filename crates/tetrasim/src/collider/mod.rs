//! Kinematic colliders (physics.md, third edition, "Kinematic colliders"): shapes with a
//! signed distance (negative inside) and outward normal, each with its friction and its
//! motion. A node in contact has the one-sided constraint `phi(x) - thickness >= 0`, solved
//! like the floor's in the same iterations ([`crate::physics::contact_push`]); the collider
//! is never pushed back (infinite mass).
//!
//! The floor of `SimParams::floor` stays its own, cheaper path (the plane `y = 0`); a
//! [`Shape::Plane`] is any other half-space.

mod clamp;
mod first_contact;
mod grab;
mod grid;
mod motion;
mod surface;

use std::sync::Arc;

use glam::{DQuat, DVec3};

pub use clamp::{clamp_of_nodes, drive, Clamp};
pub use first_contact::{free_fall_contact_time, HORIZON_S};
pub use grab::{attachments, Attachment, Grab};
pub use grid::DistanceGrid;
use motion::{finite_vector, param, unit_quaternion};
pub use motion::{Keyframe, Motion, Pose};
pub use surface::{MAX_CELLS, MIN_CELLS, PAD_CELLS};

use crate::error::Result;
use crate::physics::{
    contact_push, end_position, floor_holds, held_direction, surface_friction, Real, Solve, Vector,
    HELD_GAP,
};

/// A collider's shape in its local frame (see [`Collider::pose`] for how it is placed).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// The half-space below the local plane `y = 0` (the outward normal is local +Y).
    Plane,
    /// A ball of this radius [m] about the local origin.
    Sphere {
        /// Radius [m].
        radius: f64,
    },
    /// A box `|x| <= half_extents` about the local origin.
    Cuboid {
        /// Half its size along local X, Y, Z [m].
        half_extents: DVec3,
    },
    /// The points within `radius` of the local segment from `(0, -half_length, 0)` to
    /// `(0, half_length, 0)`.
    Capsule {
        /// Half the length of its axis [m].
        half_length: f64,
        /// Radius [m].
        radius: f64,
    },
    /// A closed surface, as a sampled signed distance.
    Grid(Arc<DistanceGrid>),
}

/// The `kind` numbers of the shapes on the GPU (`SHAPE_*` in glsl/physics/contact.glsl).
impl Shape {
    /// The GPU's shape code.
    pub fn code(&self) -> u32 {
        match self {
            Shape::Plane => 0,
            Shape::Sphere { .. } => 1,
            Shape::Cuboid { .. } => 2,
            Shape::Capsule { .. } => 3,
            Shape::Grid(_) => 4,
        }
    }

    /// The shape's name in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Plane => "plane",
            Shape::Sphere { .. } => "sphere",
            Shape::Cuboid { .. } => "box",
            Shape::Capsule { .. } => "capsule",
            Shape::Grid(_) => "mesh",
        }
    }

    /// The largest distance of a point of the shape from the local origin [m] (infinite
    /// for a plane).
    pub fn bound(&self) -> f64 {
        match self {
            Shape::Plane => f64::INFINITY,
            Shape::Sphere { radius } => *radius,
            Shape::Cuboid { half_extents } => half_extents.length(),
            Shape::Capsule {
                half_length,
                radius,
            } => half_length + radius,
            // The shape lies inside the sampled box.
            Shape::Grid(grid) => grid.origin.abs().max(grid.end().abs()).length(),
        }
    }

    /// Signed distance [m] of the local point `p` and the outward unit normal there.
    pub fn distance(&self, p: DVec3) -> (f64, DVec3) {
        match self {
            Shape::Plane => (p.y, DVec3::Y),
            Shape::Sphere { radius } => ball(p, *radius),
            Shape::Cuboid { half_extents } => cuboid(p, *half_extents),
            Shape::Capsule {
                half_length,
                radius,
            } => ball(
                p - DVec3::new(0.0, p.y.clamp(-half_length, *half_length), 0.0),
                *radius,
            ),
            Shape::Grid(grid) => grid.sample(p),
        }
    }
}

/// Distance to a ball of radius `r` about the origin (a point at the centre goes up).
fn ball(p: DVec3, r: f64) -> (f64, DVec3) {
    let length = p.length();
    match length > 0.0 {
        true => (length - r, p / length),
        false => (-r, DVec3::Y),
    }
}

/// Distance to the box `|p| <= h`: outside, to its nearest point; inside, minus the depth
/// below its nearest face (whose normal is the normal).
fn cuboid(p: DVec3, h: DVec3) -> (f64, DVec3) {
    let q = p.abs() - h;
    let outside = q.max(DVec3::ZERO);
    if outside != DVec3::ZERO {
        let length = outside.length();
        return (length, p.signum() * outside / length);
    }
    let axis = if q.x >= q.y && q.x >= q.z {
        DVec3::X
    } else if q.y >= q.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    (q.max_element(), axis * p.signum())
}

/// A kinematic collider: its shape, where it is declared, how it moves and its friction.
#[derive(Debug, Clone, PartialEq)]
pub struct Collider {
    /// The shape in its local frame.
    pub shape: Shape,
    /// Its declared placement (at rest, before any motion): the local origin is its centre.
    pub pose: Pose,
    /// How it moves from the declared placement.
    pub motion: Motion,
    /// Friction, in `[0, 1]`: a contacting node's tangential velocity relative to the
    /// collider's surface loses this fraction of itself per step, but never more than this
    /// times the velocity the collider's push gave it along the normal (Coulomb's law with
    /// `mu = friction`; [`crate::physics::surface_friction`]).
    pub friction: f64,
    /// Contact thickness `r` [m]: nodes are kept at `phi >= r`.
    pub thickness: f64,
}

impl Collider {
    /// A fixed collider of `shape` at `pose`, frictionless and without thickness.
    pub fn new(shape: Shape, pose: Pose) -> Self {
        Collider {
            shape,
            pose,
            motion: Motion::Fixed,
            friction: 0.0,
            thickness: 0.0,
        }
    }

    /// The half-space `normal . x <= offset` (`normal` need not be unit). Fails on a zero
    /// or non-finite normal (named `normal`).
    pub fn plane(normal: DVec3, offset: f64) -> Result<Self> {
        let n = normal.try_normalize().ok_or_else(|| {
            param(
                "normal",
                format!("must be a non-zero, finite vector, got {normal:?}"),
            )
        })?;
        let pose = Pose {
            position: n * offset,
            rotation: DQuat::from_rotation_arc(DVec3::Y, n),
        };
        Ok(Collider::new(Shape::Plane, pose))
    }

    /// A ball.
    pub fn sphere(center: DVec3, radius: f64) -> Self {
        Collider::new(
            Shape::Sphere { radius },
            Pose {
                position: center,
                rotation: DQuat::IDENTITY,
            },
        )
    }

    /// An oriented box.
    pub fn cuboid(center: DVec3, half_extents: DVec3, rotation: DQuat) -> Self {
        Collider::new(
            Shape::Cuboid { half_extents },
            Pose {
                position: center,
                rotation,
            },
        )
    }

    /// A capsule around the segment `a`-`b` (`a == b`: a ball).
    pub fn capsule(a: DVec3, b: DVec3, radius: f64) -> Self {
        let axis = b - a;
        let rotation = match axis.try_normalize() {
            Some(d) => DQuat::from_rotation_arc(DVec3::Y, d),
            None => DQuat::IDENTITY,
        };
        let shape = Shape::Capsule {
            half_length: axis.length() / 2.0,
            radius,
        };
        Collider::new(
            shape,
            Pose {
                position: (a + b) / 2.0,
                rotation,
            },
        )
    }

    /// A closed surface's sampled distance, in its own coordinates.
    pub fn mesh(grid: DistanceGrid) -> Self {
        Collider::new(Shape::Grid(Arc::new(grid)), Pose::IDENTITY)
    }

    /// The same collider with `motion`.
    pub fn moving(mut self, motion: Motion) -> Self {
        self.motion = motion;
        self
    }

    /// The same collider with `friction`.
    pub fn with_friction(mut self, friction: f64) -> Self {
        self.friction = friction;
        self
    }

    /// Its placement at time `t` [s].
    pub fn pose_at(&self, t: f64) -> Pose {
        let (translation, rotation) = self.motion.displacement(t);
        Pose {
            position: self.pose.position + translation,
            rotation: (rotation * self.pose.rotation).normalize(),
        }
    }

    /// Checks its values; `key` names it in messages (e.g. `collider[1]`).
    pub fn validate(&self, key: &str) -> Result<()> {
        let positive = |name: &str, value: f64| match value.is_finite() && value > 0.0 {
            true => Ok(()),
            false => Err(param(
                &format!("{key}.{name}"),
                format!("must be positive and finite, got {value}"),
            )),
        };
        match &self.shape {
            Shape::Plane => {}
            Shape::Sphere { radius } => positive("radius", *radius)?,
            Shape::Cuboid { half_extents } => {
                for (axis, h) in ["x", "y", "z"].iter().zip(half_extents.to_array()) {
                    positive(&format!("half_extents.{axis}"), h)?;
                }
            }
            Shape::Capsule {
                half_length,
                radius,
            } => {
                positive("radius", *radius)?;
                if !half_length.is_finite() {
                    return Err(param(&format!("{key}.b"), "must be finite"));
                }
            }
            Shape::Grid(grid) => {
                if grid.dims.iter().any(|&d| d < 2)
                    || grid.values.len() != grid.dims.iter().map(|&d| d as usize).product::<usize>()
                    || grid.values.iter().any(|v| !v.is_finite())
                    || grid.cell.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
                {
                    return Err(param(
                        &format!("{key}.path"),
                        "the distance grid is malformed",
                    ));
                }
            }
        }
        finite_vector(&format!("{key}.center"), self.pose.position)?;
        unit_quaternion(&format!("{key}.rotation"), self.pose.rotation)?;
        if !(0.0..=1.0).contains(&self.friction) {
            return Err(param(
                &format!("{key}.friction"),
                format!("must be in [0, 1], got {}", self.friction),
            ));
        }
        if !(self.thickness.is_finite() && self.thickness >= 0.0) {
            return Err(param(
                &format!("{key}.thickness"),
                format!("must be finite and >= 0, got {}", self.thickness),
            ));
        }
        self.motion.validate(&format!("{key}.motion"))
    }
}

/// A collider during one time step: its placement at the step's start and end.
#[derive(Debug, Clone, Copy)]
pub struct ColliderAt<'a> {
    /// The collider.
    pub collider: &'a Collider,
    /// Its placement at the start of the step.
    pub start: Pose,
    /// Its placement at the end of the step (the constraint's).
    pub end: Pose,
    /// No point of the shape is farther than this from its centre [m] (infinite for a
    /// plane): a node farther than `reach` from the end pose's centre cannot touch it.
    reach: f64,
}

impl<'a> ColliderAt<'a> {
    /// `collider` over the step from `t` to `t + dt` [s].
    pub fn new(collider: &'a Collider, t: f64, dt: f64) -> Self {
        ColliderAt {
            collider,
            start: collider.pose_at(t),
            end: collider.pose_at(t + dt),
            reach: collider.shape.bound() + collider.thickness,
        }
    }

    /// [`Self::may_touch`] against the pose at the step's start.
    pub fn may_touch_at_start(&self, x: DVec3) -> bool {
        x.distance_squared(self.start.position) <= self.reach * self.reach
    }

    /// Whether the world point `x` may be within the contact thickness (a cheap test that
    /// never says no to a point that is).
    pub fn may_touch(&self, x: DVec3) -> bool {
        x.distance_squared(self.end.position) <= self.reach * self.reach
    }

    /// Signed distance [m] of the world point `x` from the collider at the step's end, and
    /// the outward unit normal there.
    pub fn distance(&self, x: DVec3) -> (f64, DVec3) {
        let (phi, normal) = self.collider.shape.distance(self.end.invert(x));
        (phi, self.end.rotation * normal)
    }

    /// Signed distance [m] of the world point `x` from the collider at the step's start.
    pub fn distance_at_start(&self, x: DVec3) -> f64 {
        self.collider.shape.distance(self.start.invert(x)).0
    }

    /// Velocity [m/s] of the collider's surface point at `x` (at the step's end) over the
    /// step: where that point was at the step's start, to `x`, over `dt`.
    pub fn surface_velocity(&self, x: DVec3, dt: f64) -> DVec3 {
        (x - self.start.apply(self.end.invert(x))) / dt
    }
}

/// The direction the contacts hold a node along in the finite elements' Newton step
/// (docs/PHYSICS.md, "Finite elements against contacts"; zero: none): the floor's `+Y`
/// where it pushes the node or the node rests on it (`floor`: whether the floor pushes,
/// `None` without a floor), else the colliders' push `pushed`, else the normal of a collider
/// the node rests on; `end` is where the node ends the step so far, `reach` one over the
/// height of its thinnest tet.
pub fn held_normal<V: Vector>(
    floor: Option<bool>,
    pushed: V,
    end: V,
    reach: V::Real,
    colliders: &[ColliderAt<'_>],
) -> V {
    let on_floor = floor.is_some_and(|pushes| floor_holds(pushes, end.y(), reach));
    let collider = match pushed != V::ZERO {
        true => pushed,
        false => resting_on(colliders, end.to_dvec3(), HELD_GAP / reach.to_f64())
            .map_or(V::ZERO, V::from_dvec3),
    };
    held_direction(on_floor, collider)
}

/// The outward normal of the first of `colliders` whose surface the world point `x` lies
/// within `gap` [m] of (its contact thickness included) at the step's end: the collider a
/// node there rests on although it does not push it yet.
fn resting_on(colliders: &[ColliderAt<'_>], x: DVec3, gap: f64) -> Option<DVec3> {
    colliders.iter().find_map(|c| {
        if !c.may_touch(x) {
            return None;
        }
        let (distance, normal) = c.distance(x);
        (distance - c.collider.thickness <= gap).then_some(normal)
    })
}

/// Whether a node the finite elements' Newton step left to itself (`free`: not pinned;
/// `held`: its contact's stiffening, zero where no contact holds it) ends at `x` inside the
/// floor (`floor`: the run has one) or within one of `colliders`' contact thickness at the
/// step's end: a contact the linearisation did not see will push it, so the conjugate
/// gradients begin a new Newton step (docs/PHYSICS.md, "Keeping the linearisation where
/// the model holds").
pub fn enters_unheld<V: Vector>(
    free: bool,
    held: V,
    floor: bool,
    colliders: &[ColliderAt<'_>],
    x: DVec3,
) -> bool {
    free && held == V::ZERO
        && ((floor && x.y < 0.0)
            || (colliders.iter()).any(|c| c.may_touch(x) && c.distance(x).0 < c.collider.thickness))
}

/// `colliders` over time step `step` (counted from 0) of length `dt` [s]: from
/// `t = step dt` to `t + dt` (the product taken in f64 on every backend).
pub fn at_step(colliders: &[Collider], step: u64, dt: f64) -> Vec<ColliderAt<'_>> {
    let t = step as f64 * dt;
    colliders
        .iter()
        .map(|c| ColliderAt::new(c, t, dt))
        .collect()
}

/// What [`solve_node`] found for one node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeContact {
    /// The colliders' total force on the node [N].
    pub force: DVec3,
    /// The last collider that pushed it (`None`: no contact).
    pub touching: Option<Touch>,
}

/// The collider that pushed a node last in a solve, as friction needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touch {
    /// Its index.
    pub collider: usize,
    /// The normal it pushed along (unit, world).
    pub normal: DVec3,
    /// The velocity its push gives the node along the normal in the step, `push w dt`
    /// [m/s]: Coulomb's bound on the friction ([`surface_friction`]).
    pub pressed: f64,
}

impl NodeContact {
    /// No contact: no force, touching nothing.
    pub const NONE: NodeContact = NodeContact {
        force: DVec3::ZERO,
        touching: None,
    };
}

/// Re-solves one node's collider contacts against its total force `f` [N], which holds the
/// colliders' force found so far, `contact`: each collider in turn pushes the node's
/// end-of-step position (given the forces so far) out to its thickness along its normal
/// ([`contact_push`]). Returns the new total force and contact. A pinned node (`w = 0`) gets
/// none. The GPU's twin is `colliders_solve` in glsl/physics/contact.glsl.
pub fn solve_node(
    colliders: &[ColliderAt<'_>],
    f: DVec3,
    contact: DVec3,
    x: DVec3,
    v: DVec3,
    w: f64,
    dt: f64,
) -> (DVec3, NodeContact) {
    solve_node_attached(colliders, None, Solve::Full, f, contact, x, v, w, dt)
}

/// [`solve_node`] for a node that may be attached to a grab's handle: the attachment's force
/// ([`Attachment::force`]) comes first, then the colliders push. Both are kept in the
/// contact's force. In split contact's velocity solve (`solve`) each collider lets the node
/// keep the penetration it starts the step with ([`Solve::slack`]); the attachment, a
/// driven tool, is solved the same in both solves.
#[allow(clippy::too_many_arguments)]
pub fn solve_node_attached(
    colliders: &[ColliderAt<'_>],
    attachment: Option<Attachment>,
    solve: Solve,
    f: DVec3,
    contact: DVec3,
    x: DVec3,
    v: DVec3,
    w: f64,
    dt: f64,
) -> (DVec3, NodeContact) {
    let other = f - contact;
    let mut out = NodeContact::NONE;
    if w <= 0.0 {
        return (other, out);
    }
    if let Some(attachment) = attachment {
        out.force = attachment.force(end_position(x, v, other, w, dt), w, dt);
    }
    for (k, c) in colliders.iter().enumerate() {
        let end = end_position(x, v, other + out.force, w, dt);
        if !c.may_touch(end) {
            continue;
        }
        let (phi, normal) = c.distance(end);
        let thickness = c.collider.thickness;
        let slack = match solve {
            Solve::Full => 0.0,
            Solve::Velocity => solve.slack(c.distance_at_start(x) - thickness),
        };
        let push = contact_push(phi + slack, thickness, w, dt);
        if push > 0.0 {
            out.force += normal * push;
            out.touching = Some(Touch {
                collider: k,
                normal,
                pressed: push * w * dt,
            });
        }
    }
    (other + out.force, out)
}

/// Half the smallest distance [m] from the point `x` to any collider's thickness shell at the
/// step's end (`phi - thickness`, or a lower bound of it for a far collider): while a node
/// starting at `x` ends the step less than this far from `x`, no collider can touch it (the
/// shapes' distances grow at most as fast as the point moves; halved for the sampled grid's
/// interpolation). Negative when it starts inside one.
pub fn clearance(colliders: &[ColliderAt<'_>], x: DVec3) -> f64 {
    let mut least = f64::INFINITY;
    for c in colliders {
        let gap = match c.may_touch(x) {
            true => c.distance(x).0 - c.collider.thickness,
            false => x.distance(c.end.position) - c.reach,
        };
        least = least.min(gap);
    }
    0.5 * least
}

/// [`solve_node_attached`] without attachment for a node with the step's [`clearance`]
/// `clear`: the same result, without evaluating any collider while the node's end position
/// (without collider forces) stays within `clear` of `x` (the velocity solve's slack is 0
/// there: the node starts outside every collider).
#[allow(clippy::too_many_arguments)]
pub fn solve_node_clear(
    colliders: &[ColliderAt<'_>],
    clear: f64,
    solve: Solve,
    f: DVec3,
    contact: DVec3,
    x: DVec3,
    v: DVec3,
    w: f64,
    dt: f64,
) -> (DVec3, NodeContact) {
    let other = f - contact;
    if end_position(x, v, other, w, dt).distance(x) < clear {
        return (other, NodeContact::NONE);
    }
    solve_node_attached(colliders, None, solve, f, contact, x, v, w, dt)
}

/// A node's velocity after the step's update `v1`, with the friction of the collider it
/// touches ([`surface_friction`] relative to the collider's surface velocity at its new
/// position `x + dt v1`).
pub fn friction_of(
    colliders: &[ColliderAt<'_>],
    contact: &NodeContact,
    x: DVec3,
    v1: DVec3,
    dt: f64,
) -> DVec3 {
    match contact.touching {
        Some(touch) => {
            let c = &colliders[touch.collider];
            let surface = c.surface_velocity(x + v1 * dt, dt);
            surface_friction(
                v1,
                surface,
                touch.normal,
                c.collider.friction,
                touch.pressed,
            )
        }
        None => v1,
    }
}

#[cfg(test)]
mod tests;
