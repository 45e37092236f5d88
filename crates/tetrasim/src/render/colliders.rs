//! The kinematic colliders ([`crate::collider`]) as lit triangles: each shape is tessellated
//! once on the host in its own local frame, uploaded once, and placed at each picture by its
//! pose at the picture's time ([`Collider::pose_at`]), one mat4 per collider in a small
//! host-visible buffer. Only the poses cross to the GPU per picture, whatever the number of
//! triangles (a `mesh` collider's isosurface has tens of thousands), and one draw covers every
//! collider (`glsl/render/collider.vert`). The 128-byte push block is full, so the poses
//! cannot go there.
//!
//! - sphere: a UV sphere; capsule: a cylinder and two hemispheres (the same surface of
//!   revolution); box: six faces;
//! - plane: a square of side [`PLANE_EXTENT`] times the floor's, centred on the point of
//!   the plane under the camera's target, clipped to above the floor `y = 0` (the part below
//!   would only show through past the floor's edge);
//! - mesh: the zero level set of its [`DistanceGrid`], by marching tetrahedra (six per
//!   cell), normals from the grid's gradient: the surface the physics sees, with no change to
//!   how a `mesh` collider is built or stored.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3};
use gpu_allocator::MemoryLocation;

use super::camera::SceneFrame;
use super::layout::binding;
use super::pipelines::Pipelines;
use crate::collider::{Collider, DistanceGrid, Pose, Shape};
use crate::error::{Error, Result};
use crate::gpu::{Buffer, Context};

/// Segments around a sphere or capsule.
pub const SLICES: u32 = 40;
/// Segments from pole to pole of a sphere (half on each hemisphere of a capsule).
pub const STACKS: u32 = 20;
/// Half side of a plane's square as a fraction of the floor's half extent (the part of the
/// floor that does not fade into the background).
pub const PLANE_EXTENT: f64 = 0.35;

/// One vertex of the collider triangles (`ColliderVertex` in glsl/render/collider.vert).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct ColliderVertex {
    /// Local position [m]; w: the collider's index.
    pub position: [f32; 4],
    /// Local unit normal (w unused).
    pub normal: [f32; 4],
}

/// A vertex in a collider's local frame: position [m] and unit outward normal. Three make
/// a triangle.
pub type Vertex = (DVec3, DVec3);

/// The triangles of `shape` in its local frame (3 vertices each); none for a plane (see
/// [`plane_patch`]).
pub fn tessellate(shape: &Shape) -> Vec<Vertex> {
    match shape {
        Shape::Plane => Vec::new(),
        Shape::Sphere { radius } => capsule(0.0, *radius),
        Shape::Capsule {
            half_length,
            radius,
        } => capsule(*half_length, *radius),
        Shape::Cuboid { half_extents } => cuboid(*half_extents),
        Shape::Grid(grid) => isosurface(grid),
    }
}

/// The capsule around the local segment `(0, -h, 0)`-`(0, h, 0)` of radius `r` (a sphere for
/// `h = 0`), as a surface of revolution about local Y: rings from the top pole to the bottom.
fn capsule(h: f64, r: f64) -> Vec<Vertex> {
    let half = STACKS / 2;
    // (ring radius, height, normal's radial and vertical parts), top pole first.
    let mut rings = Vec::new();
    for i in 0..=half {
        let a = std::f64::consts::FRAC_PI_2 * f64::from(i) / f64::from(half);
        rings.push((r * a.sin(), h + r * a.cos(), a.sin(), a.cos()));
    }
    for i in 0..=half {
        let a = std::f64::consts::FRAC_PI_2 * (1.0 + f64::from(i) / f64::from(half));
        if i == 0 && h == 0.0 {
            continue; // the equator is already there
        }
        rings.push((r * a.sin(), -h + r * a.cos(), a.sin(), a.cos()));
    }
    let at = |ring: (f64, f64, f64, f64), k: u32| {
        let phi = std::f64::consts::TAU * f64::from(k) / f64::from(SLICES);
        let (s, c) = phi.sin_cos();
        (
            DVec3::new(ring.0 * c, ring.1, ring.0 * s),
            DVec3::new(ring.2 * c, ring.3, ring.2 * s),
        )
    };
    let mut out = Vec::new();
    for pair in rings.windows(2) {
        let (upper, lower) = (pair[0], pair[1]);
        for k in 0..SLICES {
            let (a, b) = (at(upper, k), at(upper, k + 1));
            let (c, d) = (at(lower, k), at(lower, k + 1));
            if upper.0 > 0.0 {
                out.extend([a, c, b]);
            }
            if lower.0 > 0.0 {
                out.extend([b, c, d]);
            }
        }
    }
    out
}

/// The box `|p| <= h`: two triangles per face.
fn cuboid(h: DVec3) -> Vec<Vertex> {
    let mut out = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut n = DVec3::ZERO;
            n[axis] = sign;
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f64, b: f64| {
                let mut p = n * h;
                p[u] = a * h[u];
                p[v] = b * h[v];
                (p, n)
            };
            let (p00, p10, p11, p01) = (
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            );
            out.extend([p00, p10, p11, p00, p11, p01]);
        }
    }
    out
}

/// The zero level set of `grid` by marching tetrahedra: each cell split into the six tets
/// around its main diagonal (the same split in every cell, so neighbours share their
/// faces' crossings and the surface has no cracks). Normals: the grid's gradient.
fn isosurface(grid: &DistanceGrid) -> Vec<Vertex> {
    // Corner k of a cell is at offset (k & 1, k >> 1 & 1, k >> 2 & 1).
    const TETS: [[usize; 4]; 6] = [
        [0, 1, 3, 7],
        [0, 3, 2, 7],
        [0, 2, 6, 7],
        [0, 6, 4, 7],
        [0, 4, 5, 7],
        [0, 5, 1, 7],
    ];
    let [nx, ny, nz] = grid.dims;
    let mut out = Vec::new();
    let crossing = |(p, a): (DVec3, f64), (q, b): (DVec3, f64)| {
        let x = p + (q - p) * (a / (a - b));
        (x, grid.sample(x).1)
    };
    for k in 0..nz - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let corners: [(DVec3, f64); 8] = std::array::from_fn(|c| {
                    let (di, dj, dk) = (c as u32 & 1, c as u32 >> 1 & 1, c as u32 >> 2 & 1);
                    let offset =
                        DVec3::new(f64::from(i + di), f64::from(j + dj), f64::from(k + dk));
                    (
                        grid.origin + offset * grid.cell,
                        grid.at(i + di, j + dj, k + dk),
                    )
                });
                let inside = corners.iter().filter(|c| c.1 < 0.0).count();
                if inside == 0 || inside == 8 {
                    continue;
                }
                for tet in TETS {
                    let v = tet.map(|c| corners[c]);
                    let (ins, outs): (Vec<_>, Vec<_>) = v.iter().partition(|c| c.1 < 0.0);
                    match (ins.len(), outs.len()) {
                        (1, 3) => out.extend(outs.iter().map(|&&o| crossing(*ins[0], o))),
                        (3, 1) => out.extend(ins.iter().map(|&&i| crossing(i, *outs[0]))),
                        (2, 2) => {
                            let (a, b, c, d) = (*ins[0], *ins[1], *outs[0], *outs[1]);
                            let q = [
                                crossing(a, c),
                                crossing(a, d),
                                crossing(b, d),
                                crossing(b, c),
                            ];
                            out.extend([q[0], q[1], q[2], q[0], q[2], q[3]]);
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    out
}

/// A square of half side `half` [m] of the plane collider at `pose` (local `y = 0`),
/// centred on the plane's point nearest to `centre` (world), clipped to world `y >= 0`.
pub fn plane_patch(pose: &Pose, centre: DVec3, half: f64) -> Vec<Vertex> {
    let mut c = pose.invert(centre);
    c.y = 0.0;
    let square = [(-1.0, -1.0), (-1.0, 1.0), (1.0, 1.0), (1.0, -1.0)]
        .map(|(a, b)| c + DVec3::new(a * half, 0.0, b * half));
    // Sutherland-Hodgman against the one edge world y = 0.
    let height = |p: DVec3| pose.apply(p).y;
    let mut polygon = Vec::new();
    for (k, &p) in square.iter().enumerate() {
        let q = square[(k + 1) % 4];
        let (hp, hq) = (height(p), height(q));
        if hp >= 0.0 {
            polygon.push(p);
        }
        if (hp >= 0.0) != (hq >= 0.0) {
            polygon.push(p + (q - p) * (hp / (hp - hq)));
        }
    }
    let mut out = Vec::new();
    for k in 1..polygon.len().saturating_sub(1) {
        out.extend([polygon[0], polygon[k], polygon[k + 1]].map(|p| (p, DVec3::Y)));
    }
    out
}

/// The world bounds of every collider but planes (which have none) at time `t` [s]: its
/// tessellation placed by [`Collider::pose_at`]. `None` without such a collider.
pub fn bounds_at(colliders: &[Collider], t: f64) -> Option<(DVec3, DVec3)> {
    colliders
        .iter()
        .flat_map(|c| {
            let pose = c.pose_at(t);
            tessellate(&c.shape)
                .into_iter()
                .map(move |(p, _)| pose.apply(p))
        })
        .fold(None, |b, p| match b {
            None => Some((p, p)),
            Some((lo, hi)) => Some((p.min(lo), p.max(hi))),
        })
}

fn matrix(pose: &Pose) -> [[f32; 4]; 4] {
    DMat4::from_rotation_translation(pose.rotation, pose.position)
        .as_mat4()
        .to_cols_array_2d()
}

/// The colliders' GPU data: their triangles (local frames, uploaded once) and their poses
/// (rewritten for each picture). The buffers free themselves on drop.
pub struct ColliderDraw {
    colliders: Vec<Collider>,
    /// [`ColliderVertex`] per vertex, 3 per triangle.
    vertices: Buffer,
    /// Vertices to draw.
    pub vertex_count: u32,
    /// mat4 per collider (host-visible).
    poses: Buffer,
}

impl ColliderDraw {
    /// Tessellates and uploads `colliders`; planes get a patch around the `frame`'s target.
    pub fn new(ctx: &Arc<Context>, colliders: &[Collider], frame: &SceneFrame) -> Result<Self> {
        let centre = frame.camera.target.as_dvec3();
        let half = PLANE_EXTENT * f64::from(frame.floor_half_extent);
        let mut vertices = Vec::new();
        for (k, c) in colliders.iter().enumerate() {
            let triangles = match c.shape {
                Shape::Plane => plane_patch(&c.pose_at(0.0), centre, half),
                _ => tessellate(&c.shape),
            };
            vertices.extend(triangles.into_iter().map(|(p, n)| ColliderVertex {
                position: p.as_vec3().extend(k as f32).to_array(),
                normal: n.as_vec3().extend(0.0).to_array(),
            }));
        }
        let vertex_count = u32::try_from(vertices.len())
            .map_err(|_| Error::Mesh(format!("{} collider vertices exceed u32", vertices.len())))?;
        // Never empty: every binding of the set must point at a buffer.
        if vertices.is_empty() {
            vertices.push(ColliderVertex::zeroed());
        }
        let vertices =
            Buffer::with_data(ctx, "collider vertices", bytemuck::cast_slice(&vertices))?;
        let poses = Buffer::new(
            ctx,
            "collider poses",
            64 * colliders.len().max(1) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let mut draw = ColliderDraw {
            colliders: colliders.to_vec(),
            vertices,
            vertex_count,
            poses,
        };
        draw.set_time(0.0)?;
        Ok(draw)
    }

    /// Places every collider at its pose at time `t` [s]. The GPU must not be reading the
    /// poses (the renderer waits for each picture).
    pub fn set_time(&mut self, t: f64) -> Result<()> {
        let poses: Vec<[[f32; 4]; 4]> = self
            .colliders
            .iter()
            .map(|c| matrix(&c.pose_at(t)))
            .collect();
        if poses.is_empty() {
            return Ok(());
        }
        self.poses.write(bytemuck::cast_slice(&poses))
    }

    /// Points the render set's collider bindings at these buffers.
    pub fn bind(&self, pipelines: &Pipelines) {
        pipelines.bind(binding::COLLIDER_VERTICES, &self.vertices);
        pipelines.bind(binding::COLLIDER_POSES, &self.poses);
    }
}

#[cfg(test)]
mod tests {
    use glam::DQuat;

    use super::*;

    fn closed_and_on(shape: &Shape, distance_tol: f64) -> usize {
        let tris = tessellate(shape);
        assert!(!tris.is_empty() && tris.len() % 3 == 0);
        for (p, n) in &tris {
            let (phi, normal) = shape.distance(*p);
            assert!(phi.abs() <= distance_tol, "{shape:?}: {p} at {phi}");
            assert!((n.length() - 1.0).abs() < 1e-6);
            // (A box's corners have no one normal: there, the face's points outwards.)
            let agrees = match shape {
                Shape::Cuboid { .. } => n.dot(*p) > 0.0,
                _ => n.dot(normal) > 0.7,
            };
            assert!(agrees, "{shape:?}: normal {n} vs {normal} at {p}");
        }
        // The enclosed volume by the divergence theorem, with each triangle's winding made
        // to agree with its normals: positive and close to the shape's.
        let mut volume = 0.0;
        for t in tris.chunks(3) {
            let cross = (t[1].0 - t[0].0).cross(t[2].0 - t[0].0);
            let sign = if cross.dot(t[0].1 + t[1].1 + t[2].1) >= 0.0 {
                1.0
            } else {
                -1.0
            };
            volume += sign * t[0].0.dot(cross) / 6.0;
        }
        let expected = match shape {
            Shape::Sphere { radius } => 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3),
            Shape::Capsule {
                half_length,
                radius,
            } => std::f64::consts::PI * radius * radius * (2.0 * half_length + 4.0 / 3.0 * radius),
            Shape::Cuboid { half_extents } => {
                8.0 * half_extents.x * half_extents.y * half_extents.z
            }
            _ => volume,
        };
        assert!(
            (volume / expected - 1.0).abs() < 0.03,
            "{shape:?}: volume {volume} vs {expected}"
        );
        tris.len() / 3
    }

    #[test]
    fn shapes_tessellate_onto_their_surfaces_with_outward_normals() {
        closed_and_on(&Shape::Sphere { radius: 0.3 }, 1e-12);
        closed_and_on(
            &Shape::Capsule {
                half_length: 0.5,
                radius: 0.1,
            },
            1e-12,
        );
        let n = closed_and_on(
            &Shape::Cuboid {
                half_extents: DVec3::new(0.8, 0.1, 0.4),
            },
            1e-12,
        );
        assert_eq!(n, 12);
        assert!(tessellate(&Shape::Plane).is_empty());
    }

    #[test]
    fn a_grid_isosurface_lies_on_the_sampled_surface() {
        // A sphere of radius 0.5 sampled exactly on a 24-cell grid.
        let (cell, n) = (0.05, 25u32);
        let origin = DVec3::splat(-0.6);
        let mut values = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let p = origin + DVec3::new(i as f64, j as f64, k as f64) * cell;
                    values.push(p.length() - 0.5);
                }
            }
        }
        let grid = DistanceGrid {
            origin,
            cell,
            dims: [n; 3],
            values,
        };
        let shape = Shape::Grid(Arc::new(grid));
        // Linear interpolation of |p| - r cuts corners by at most cell^2 / (8 r) or so.
        let tris = closed_and_on(&shape, 0.01);
        for (p, _) in tessellate(&shape) {
            assert!((p.length() - 0.5).abs() < 0.01, "{p}");
        }
        assert!(tris > 500, "{tris}");
    }

    #[test]
    fn a_plane_patch_is_clipped_to_above_the_floor() {
        // The tilted_plane scene's ramp: rising towards -X through the origin.
        let c = Collider::plane(DVec3::new(0.342, 0.94, 0.0), 0.0).unwrap();
        let pose = c.pose_at(0.0);
        let tris = plane_patch(&pose, DVec3::new(0.0, 0.5, 0.0), 1.0);
        assert!(!tris.is_empty());
        let world: Vec<DVec3> = tris.iter().map(|(p, _)| pose.apply(*p)).collect();
        assert!(world.iter().all(|p| p.y >= -1e-9), "{world:?}");
        assert!(world.iter().any(|p| p.x < -0.5 && p.y > 0.1));
        assert!(world.iter().all(|p| p.x <= 1e-9));
        // A level plane above the floor is a whole square (two triangles).
        let level = Collider::plane(DVec3::Y, 0.2).unwrap();
        assert_eq!(plane_patch(&level.pose_at(0.0), DVec3::ZERO, 1.0).len(), 6);
        // One below the floor is nothing.
        let under = Collider::plane(DVec3::Y, -0.2).unwrap();
        assert!(plane_patch(&under.pose_at(0.0), DVec3::ZERO, 1.0).is_empty());
    }

    #[test]
    fn bounds_follow_the_pose_and_skip_planes() {
        let ball = Collider::sphere(DVec3::new(1.0, 0.5, 0.0), 0.25);
        let rod = Collider::capsule(DVec3::new(-1.0, 1.0, 0.0), DVec3::new(1.0, 1.0, 0.0), 0.1);
        let ramp = Collider::plane(DVec3::Y, 0.0).unwrap();
        let (lo, hi) = bounds_at(&[ball, rod, ramp], 0.0).unwrap();
        assert!(lo.abs_diff_eq(DVec3::new(-1.1, 0.25, -0.25), 1e-9), "{lo}");
        assert!(hi.abs_diff_eq(DVec3::new(1.25, 1.1, 0.25), 1e-9), "{hi}");
        let turned = Collider::cuboid(
            DVec3::ZERO,
            DVec3::new(1.0, 0.1, 0.1),
            DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        );
        let (lo, hi) = bounds_at(&[turned], 0.0).unwrap();
        assert!(
            (hi.y - 1.0).abs() < 1e-9 && (lo.x + 0.1).abs() < 1e-9,
            "{lo} {hi}"
        );
        assert!(bounds_at(&[], 0.0).is_none());
    }
}
