//! The kinematic colliders on the GPU, host side: their static data and distance grids
//! (uploaded once) and their poses over each step of a frame, computed here in f64 from the
//! one motion every backend uses ([`Collider::pose_at`]) and written into the frame slot's
//! rows of the host-visible poses buffer just before the frame is submitted.

use glam::{DQuat, DVec3};

use crate::collider::{attachments, Clamp, Grab};
use crate::collider::{Collider, ColliderAt, Shape};
use crate::gpu::layout::{vec4, GpuClampNode, GpuClampPose, GpuCollider, GpuColliderPose};

/// Each collider's [`GpuCollider`] and every mesh collider's grid samples, one grid after
/// another (each collider's `grid_dims.w` its first sample).
pub fn static_data(colliders: &[Collider]) -> (Vec<GpuCollider>, Vec<f32>) {
    let mut values: Vec<f32> = Vec::new();
    let data = colliders
        .iter()
        .map(|c| {
            let mut gpu = GpuCollider {
                shape: c.shape.code(),
                reach: (c.shape.bound() + c.thickness) as f32,
                friction: c.friction as f32,
                thickness: c.thickness as f32,
                size: [0.0; 4],
                grid_origin: [0.0; 4],
                grid_dims: [0; 4],
            };
            match &c.shape {
                Shape::Plane => {}
                Shape::Sphere { radius } => gpu.size[0] = *radius as f32,
                Shape::Cuboid { half_extents } => {
                    gpu.size = crate::gpu::layout::vec4(*half_extents, 0.0)
                }
                Shape::Capsule {
                    half_length,
                    radius,
                } => gpu.size = [*half_length as f32, *radius as f32, 0.0, 0.0],
                Shape::Grid(grid) => {
                    gpu.grid_origin = crate::gpu::layout::vec4(grid.origin, grid.cell);
                    let [x, y, z] = grid.dims;
                    gpu.grid_dims = [x, y, z, values.len() as u32];
                    values.extend(grid.values.iter().map(|&v| v as f32));
                }
            }
            gpu
        })
        .collect();
    (data, values)
}

/// A quaternion as (x, y, z, w) in f32.
fn quat(q: DQuat) -> [f32; 4] {
    [q.x as f32, q.y as f32, q.z as f32, q.w as f32]
}

/// The poses of every collider over the `substeps` steps from step `first` (step `s` runs
/// from `s dt` to `(s + 1) dt`), substep after substep.
pub fn poses(colliders: &[Collider], first: u64, substeps: u32, dt: f64) -> Vec<GpuColliderPose> {
    (0..u64::from(substeps))
        .flat_map(|j| {
            let t = (first + j) as f64 * dt;
            colliders.iter().map(move |c| {
                let at = ColliderAt::new(c, t, dt);
                let moved: DVec3 = at.end.position - at.start.position;
                GpuColliderPose {
                    end_position: crate::gpu::layout::vec4(at.end.position, 0.0),
                    end_rotation: quat(at.end.rotation),
                    moved: crate::gpu::layout::vec4(moved, 0.0),
                    turned: quat(at.start.rotation * at.end.rotation.inverse()),
                }
            })
        })
        .collect()
}

/// Every clamped node, clamp after clamp, with its clamp and its rest position (`rest`,
/// the model's initial positions) relative to the clamp's centre.
pub(crate) fn clamp_nodes(clamps: &[Clamp], rest: &[DVec3]) -> Vec<GpuClampNode> {
    (clamps.iter().enumerate())
        .flat_map(|(k, c)| {
            c.nodes.iter().map(move |&i| GpuClampNode {
                node: i,
                clamp: k as u32,
                pad: [0; 2],
                offset: vec4(rest[i as usize] - c.centre, 0.0),
            })
        })
        .collect()
}

/// Every clamp's pose at the end of each of the `substeps` steps from step `first`
/// (`collider::drive`: step `s` ends at `(s + 1) dt`), substep after substep.
pub(crate) fn clamp_poses(
    clamps: &[Clamp],
    first: u64,
    substeps: u32,
    dt: f64,
) -> Vec<GpuClampPose> {
    (0..u64::from(substeps))
        .flat_map(|j| {
            let t = (first + j + 1) as f64 * dt;
            clamps.iter().map(move |c| {
                let (translation, rotation) = c.motion.displacement(t);
                GpuClampPose {
                    position: vec4(c.centre + translation, 0.0),
                    rotation: quat(rotation),
                }
            })
        })
        .collect()
}

/// The grabbed nodes' attachments over each of the `substeps` steps from step `first`
/// ([`attachments`]: the grabs holding at the step's end, the first one winning), substep
/// after substep, `grabbed` node after node: the target and the stiffness in w (infinite:
/// hard; 0: not held in that step). `rest` are the model's initial positions.
pub(crate) fn grab_targets(
    grabs: &[Grab],
    grabbed: &[u32],
    rest: &[DVec3],
    first: u64,
    substeps: u32,
    dt: f64,
) -> Vec<[f32; 4]> {
    (0..u64::from(substeps))
        .flat_map(|j| {
            let held = attachments(grabs, rest, (first + j) as f64 * dt, dt);
            (grabbed.iter())
                .map(|&i| match held[i as usize] {
                    Some(a) => vec4(a.target, a.stiffness),
                    None => [0.0; 4],
                })
                .collect::<Vec<_>>()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collider::Motion;

    /// The shader's surface velocity, `(moved - (R_turned r - r)) / dt` with `r = x - end
    /// position`, is `ColliderAt::surface_velocity`.
    #[test]
    fn relative_start_pose_gives_the_surface_velocity() {
        let c = Collider::cuboid(
            DVec3::new(0.3, 0.1, 0.0),
            DVec3::splat(0.2),
            DQuat::IDENTITY,
        )
        .moving(Motion::Velocity {
            linear: DVec3::new(0.5, 0.0, -0.2),
            angular: DVec3::new(0.0, 3.0, 1.0),
        });
        let (dt, step) = (1e-3, 17);
        let pose = poses(std::slice::from_ref(&c), step, 1, dt)[0];
        let at = ColliderAt::new(&c, step as f64 * dt, dt);
        let x = DVec3::new(0.5, 0.2, 0.1);
        let f = |v: [f32; 4]| DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
        let q = DQuat::from_xyzw(
            f64::from(pose.turned[0]),
            f64::from(pose.turned[1]),
            f64::from(pose.turned[2]),
            f64::from(pose.turned[3]),
        );
        let r = x - f(pose.end_position);
        let u = (f(pose.moved) - (q * r - r)) / dt;
        let want = at.surface_velocity(x, dt);
        assert!((u - want).length() < 1e-3, "{u} vs {want}");
    }
}
