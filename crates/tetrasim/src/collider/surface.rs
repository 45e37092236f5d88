//! A [`DistanceGrid`] from a closed triangle surface (the `mesh` collider): the surface is
//! checked (indices in range, every edge shared by exactly two triangles, one orientation),
//! then each grid sample gets the distance to the closest point of any triangle, found through
//! a bounding volume hierarchy, and the sign of the angle-weighted pseudonormal of the closest
//! feature (face, edge or vertex; Baerentzen and Aanaes 2005), which is exact for a closed,
//! consistently oriented surface. Samples are computed in parallel (rayon).

use std::collections::HashMap;

use glam::DVec3;
use rayon::prelude::*;

use super::grid::DistanceGrid;
use super::motion::param;
use crate::error::Result;

/// Cells of padding around the surface's bounds, on each side.
pub const PAD_CELLS: u32 = 3;
/// The fewest cells along the longest side [`DistanceGrid::from_surface`] takes.
pub const MIN_CELLS: u32 = 8;
/// The most cells along the longest side [`DistanceGrid::from_surface`] takes.
pub const MAX_CELLS: u32 = 512;

impl DistanceGrid {
    /// The signed distance (negative inside) of a closed triangle surface, sampled with
    /// `cells` cells along the longest side of the surface's bounds padded by
    /// [`PAD_CELLS`] cells on every side (the other sides get as many cells as fit, centred).
    /// The surface may face in or out (its orientation is taken from its signed volume).
    ///
    /// Errors (`Error::Param`): key `path` for an empty surface, a non-finite vertex, an index
    /// out of range, a triangle repeating a vertex, an open surface (an edge not shared by
    /// exactly two triangles), inconsistent orientation or no enclosed volume; key `cells`
    /// below [`MIN_CELLS`] or above [`MAX_CELLS`].
    pub fn from_surface(
        vertices: &[DVec3],
        triangles: &[[u32; 3]],
        cells: u32,
    ) -> Result<DistanceGrid> {
        if !(MIN_CELLS..=MAX_CELLS).contains(&cells) {
            return Err(param(
                "cells",
                format!("must be {MIN_CELLS} to {MAX_CELLS}, got {cells}"),
            ));
        }
        let surface = Surface::new(vertices, triangles)?;
        let (lo, hi) = vertices
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let extent = (hi - lo).max_element();
        let cell = extent / (cells - 2 * PAD_CELLS) as f64;
        let centre = (lo + hi) / 2.0;
        let mut dims = [0u32; 3];
        let mut origin = DVec3::ZERO;
        for axis in 0..3 {
            let side = hi[axis] - lo[axis];
            let n = ((side / cell).ceil() as u32 + 2 * PAD_CELLS).clamp(2, cells);
            dims[axis] = n + 1;
            origin[axis] = centre[axis] - n as f64 * cell / 2.0;
        }
        let [nx, ny, nz] = dims.map(|d| d as usize);
        let values = (0..nx * ny * nz)
            .into_par_iter()
            .map(|index| {
                let (i, j, k) = (index % nx, (index / nx) % ny, index / (nx * ny));
                let p = origin + DVec3::new(i as f64, j as f64, k as f64) * cell;
                surface.signed_distance(p)
            })
            .collect();
        Ok(DistanceGrid {
            origin,
            cell,
            dims,
            values,
        })
    }
}

/// The closest feature of a triangle to a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Feature {
    /// Inside the face.
    Face,
    /// On edge `i`, from corner `i` to corner `i + 1` (mod 3).
    Edge(usize),
    /// At corner `i`.
    Vertex(usize),
}

/// One triangle with the pseudonormals of its features.
#[derive(Debug, Clone)]
struct Triangle {
    corners: [DVec3; 3],
    /// Outward unit normal of the face.
    face: DVec3,
    /// Pseudonormal of edge `i` (the sum of the two faces' normals).
    edges: [DVec3; 3],
    /// Vertex indices, for the vertex pseudonormals.
    ids: [u32; 3],
}

/// A node of the bounding volume hierarchy: a leaf holds `count > 0` triangles from
/// `first` in [`Surface::order`]; an inner node's children are the next node and `first`.
#[derive(Debug, Clone, Copy)]
struct Node {
    min: DVec3,
    max: DVec3,
    first: u32,
    count: u32,
}

/// A checked closed surface ready for distance queries.
struct Surface {
    triangles: Vec<Triangle>,
    /// Angle-weighted pseudonormal of each vertex.
    vertex_normals: Vec<DVec3>,
    nodes: Vec<Node>,
    /// Triangle indices, in the order of the hierarchy's leaves.
    order: Vec<u32>,
}

const LEAF_SIZE: usize = 4;

impl Surface {
    fn new(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Result<Surface> {
        if vertices.is_empty() || triangles.is_empty() {
            return Err(param(
                "path",
                format!(
                    "the surface is empty ({} vertices, {} triangles)",
                    vertices.len(),
                    triangles.len()
                ),
            ));
        }
        if let Some(i) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(param(
                "path",
                format!("vertex {i} is not finite: {}", vertices[i]),
            ));
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v as usize >= vertices.len()) {
                return Err(param(
                    "path",
                    format!(
                        "triangle {t} refers to vertex {v}, but the surface has {} vertices",
                        vertices.len()
                    ),
                ));
            }
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] {
                return Err(param(
                    "path",
                    format!("triangle {t} repeats a vertex: {tri:?}"),
                ));
            }
        }
        check_closed(triangles)?;
        // Orientation from the signed volume (divergence theorem).
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| vertices[v as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        let (lo, hi) = vertices
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let extent = (hi - lo).max_element();
        if volume.abs() <= 1e-12 * extent.powi(3) {
            return Err(param("path", "the surface encloses no volume"));
        }
        let out = volume.signum();
        let faces: Vec<DVec3> = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| vertices[v as usize]);
                ((b - a).cross(c - a) * out).normalize_or_zero()
            })
            .collect();
        let mut edge_normals: HashMap<(u32, u32), DVec3> = HashMap::new();
        let mut vertex_normals = vec![DVec3::ZERO; vertices.len()];
        for (t, tri) in triangles.iter().enumerate() {
            for i in 0..3 {
                let (a, b) = (tri[i], tri[(i + 1) % 3]);
                *edge_normals.entry((a.min(b), a.max(b))).or_default() += faces[t];
                let p = vertices[tri[i] as usize];
                let u = vertices[tri[(i + 1) % 3] as usize] - p;
                let w = vertices[tri[(i + 2) % 3] as usize] - p;
                let angle = match (u.try_normalize(), w.try_normalize()) {
                    (Some(u), Some(w)) => u.dot(w).clamp(-1.0, 1.0).acos(),
                    _ => 0.0,
                };
                vertex_normals[tri[i] as usize] += faces[t] * angle;
            }
        }
        let mut all = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            let edge = |i: usize| {
                let (a, b) = (tri[i], tri[(i + 1) % 3]);
                edge_normals[&(a.min(b), a.max(b))]
            };
            all.push(Triangle {
                corners: tri.map(|v| vertices[v as usize]),
                face: faces[t],
                edges: [edge(0), edge(1), edge(2)],
                ids: *tri,
            });
        }
        // Degenerate (zero-area) triangles lie on their neighbours' edges: no query needs them.
        let mut order: Vec<u32> = (0..all.len() as u32)
            .filter(|&t| all[t as usize].face != DVec3::ZERO)
            .collect();
        let mut nodes = Vec::with_capacity(2 * order.len() / LEAF_SIZE + 1);
        let len = order.len();
        build(&all, &mut order, 0, len, &mut nodes);
        Ok(Surface {
            triangles: all,
            vertex_normals,
            nodes,
            order,
        })
    }

    /// Signed distance of `p`: to the closest point of the surface, negative inside.
    fn signed_distance(&self, p: DVec3) -> f64 {
        let mut best = f64::INFINITY;
        let mut found = (0usize, DVec3::ZERO, Feature::Face);
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if box_distance2(&node, p) >= best {
                continue;
            }
            if node.count > 0 {
                let first = node.first as usize;
                for &t in &self.order[first..first + node.count as usize] {
                    let tri = &self.triangles[t as usize];
                    let (q, feature) = closest_on_triangle(p, tri.corners);
                    let d2 = (p - q).length_squared();
                    if d2 < best {
                        best = d2;
                        found = (t as usize, q, feature);
                    }
                }
            } else {
                let (left, right) = (stack[top] + 1, node.first);
                let dl = box_distance2(&self.nodes[left as usize], p);
                let dr = box_distance2(&self.nodes[right as usize], p);
                // Visit the nearer child first: push it last.
                let (near, far) = if dl <= dr {
                    (left, right)
                } else {
                    (right, left)
                };
                stack[top] = far;
                stack[top + 1] = near;
                top += 2;
            }
        }
        let (t, q, feature) = found;
        let tri = &self.triangles[t];
        let normal = match feature {
            Feature::Face => tri.face,
            Feature::Edge(i) => tri.edges[i],
            Feature::Vertex(i) => self.vertex_normals[tri.ids[i] as usize],
        };
        let distance = best.sqrt();
        match (p - q).dot(normal) < 0.0 {
            true => -distance,
            false => distance,
        }
    }
}

/// Refuses an open surface (an edge not shared by exactly two triangles) and one whose
/// triangles do not all face the same way (an edge used twice in the same direction).
fn check_closed(triangles: &[[u32; 3]]) -> Result<()> {
    // Per undirected edge (low, high): uses from low to high, and from high to low.
    let mut edges: HashMap<(u32, u32), (u32, u32)> = HashMap::with_capacity(triangles.len() * 3);
    for tri in triangles {
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            let uses = edges.entry((a.min(b), a.max(b))).or_default();
            match a < b {
                true => uses.0 += 1,
                false => uses.1 += 1,
            }
        }
    }
    let (mut single, mut shared, mut flipped) = (0usize, 0usize, 0usize);
    for &(forth, back) in edges.values() {
        match forth + back {
            1 => single += 1,
            2 if forth != back => flipped += 1,
            2 => {}
            _ => shared += 1,
        }
    }
    let mut problems = Vec::new();
    if single > 0 {
        problems.push(format!("{single} edges belong to one triangle only"));
    }
    if shared > 0 {
        problems.push(format!("{shared} edges belong to more than two triangles"));
    }
    if !problems.is_empty() {
        return Err(param(
            "path",
            format!(
                "the surface is not closed: {} (each edge must be shared by exactly two \
                 triangles)",
                problems.join(", ")
            ),
        ));
    }
    if flipped > 0 {
        return Err(param(
            "path",
            format!(
                "the surface is not consistently oriented: {flipped} edges are used twice in \
                 the same direction"
            ),
        ));
    }
    Ok(())
}

/// Builds the hierarchy over `order[start..end]` (median split of the centroids along the
/// longest side), appending its nodes to `nodes`; returns the root's index.
fn build(
    triangles: &[Triangle],
    order: &mut [u32],
    start: usize,
    end: usize,
    nodes: &mut Vec<Node>,
) -> u32 {
    let (mut min, mut max) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for &t in &order[start..end] {
        for c in triangles[t as usize].corners {
            min = min.min(c);
            max = max.max(c);
        }
    }
    let index = nodes.len() as u32;
    nodes.push(Node {
        min,
        max,
        first: start as u32,
        count: (end - start) as u32,
    });
    if end - start <= LEAF_SIZE {
        return index;
    }
    let centroid = |t: u32| {
        let [a, b, c] = triangles[t as usize].corners;
        (a + b + c) / 3.0
    };
    let size = max - min;
    let axis = if size.x >= size.y && size.x >= size.z {
        0
    } else if size.y >= size.z {
        1
    } else {
        2
    };
    let mid = (end - start) / 2;
    order[start..end].select_nth_unstable_by(mid, |&a, &b| {
        centroid(a)[axis].total_cmp(&centroid(b)[axis])
    });
    let left = build(triangles, order, start, start + mid, nodes);
    debug_assert_eq!(left, index + 1);
    let right = build(triangles, order, start + mid, end, nodes);
    nodes[index as usize].first = right;
    nodes[index as usize].count = 0;
    index
}

/// Squared distance from `p` to the node's box (0 inside).
fn box_distance2(node: &Node, p: DVec3) -> f64 {
    let d = (node.min - p).max(p - node.max).max(DVec3::ZERO);
    d.length_squared()
}

/// The closest point of the triangle `[a, b, c]` to `p` and the feature it lies on (Ericson,
/// Real-Time Collision Detection, 5.1.5).
fn closest_on_triangle(p: DVec3, [a, b, c]: [DVec3; 3]) -> (DVec3, Feature) {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Vertex(0));
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), Feature::Edge(0));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    (a + ab * (vb * denom) + ac * (vc * denom), Feature::Face)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes::{box_surface, sphere, torus};

    fn box_distance(p: DVec3, h: DVec3) -> f64 {
        let q = p.abs() - h;
        q.max(DVec3::ZERO).length() + q.max_element().min(0.0)
    }

    /// Points spread through the grid's box (a fixed low-discrepancy sequence).
    fn probes(grid: &DistanceGrid, n: usize) -> Vec<DVec3> {
        let size = grid.end() - grid.origin;
        (0..n)
            .map(|i| {
                let f = |a: f64| (i as f64 * a).fract();
                grid.origin + size * DVec3::new(f(0.618_034), f(0.754_878), f(0.569_840))
            })
            .collect()
    }

    #[test]
    fn a_box_surface_gives_the_boxs_distance() {
        let h = DVec3::new(0.5, 0.25, 0.25);
        let mut surface = box_surface(-h, h, 4);
        for inward in [false, true] {
            if inward {
                for t in &mut surface.triangles {
                    t.swap(1, 2);
                }
            }
            let grid = DistanceGrid::from_surface(&surface.vertices, &surface.triangles, 32)
                .expect("a closed box");
            assert_eq!(grid.dims[0], 33, "cells along the longest side");
            assert!(
                grid.origin.x < -0.5 - 2.0 * grid.cell,
                "padded: {}",
                grid.origin
            );
            // Samples are exact.
            for k in 0..grid.dims[2] {
                for j in 0..grid.dims[1] {
                    for i in 0..grid.dims[0] {
                        let p = grid.origin + DVec3::new(i as f64, j as f64, k as f64) * grid.cell;
                        let (got, want) = (grid.at(i, j, k), box_distance(p, h));
                        assert!(
                            (got - want).abs() < 1e-12,
                            "inward {inward} at {p}: {got} {want}"
                        );
                    }
                }
            }
            // Between samples, within a cell's interpolation error.
            for p in probes(&grid, 500) {
                let (got, want) = (grid.sample(p).0, box_distance(p, h));
                assert!((got - want).abs() < grid.cell, "at {p}: {got} {want}");
            }
            assert!(grid.sample(DVec3::ZERO).0 < -0.2 && grid.sample(DVec3::X).0 > 0.4);
        }
    }

    #[test]
    fn a_sphere_surface_gives_the_spheres_distance_and_sign() {
        let surface = sphere(0.5, 3);
        let grid = DistanceGrid::from_surface(&surface.vertices, &surface.triangles, 40).unwrap();
        // The faceted surface lies within 2 mm of the sphere.
        for p in probes(&grid, 2000) {
            let (got, want) = (grid.sample(p).0, p.length() - 0.5);
            assert!(
                (got - want).abs() < 0.5 * grid.cell + 2e-3,
                "at {p}: {got} {want}"
            );
            if want.abs() > grid.cell {
                assert_eq!(got < 0.0, want < 0.0, "sign at {p}");
            }
        }
        let (phi, normal) = grid.sample(DVec3::new(0.0, 0.45, 0.0));
        assert!(
            phi < 0.0 && normal.angle_between(DVec3::Y) < 0.2,
            "{phi} {normal}"
        );
    }

    #[test]
    fn a_torus_has_its_hole_outside() {
        let surface = torus(0.35, 0.15, 100, 50);
        assert_eq!(surface.triangles.len(), 10_000);
        let start = std::time::Instant::now();
        let grid = DistanceGrid::from_surface(&surface.vertices, &surface.triangles, 48).unwrap();
        eprintln!("10k triangles, 48 cells: {:?}", start.elapsed());
        let hole = grid.sample(DVec3::ZERO).0;
        assert!((hole - 0.2).abs() < 0.01, "the hole: {hole}");
        // The distance peaks at the tube's centre, where interpolation cuts the peak.
        let tube = grid.sample(DVec3::new(0.35, 0.0, 0.0)).0;
        assert!((tube + 0.15).abs() < grid.cell, "the tube's centre: {tube}");
    }

    #[test]
    fn bad_surfaces_are_refused_with_the_reason() {
        let message = |v: &[DVec3], t: &[[u32; 3]], cells: u32| {
            DistanceGrid::from_surface(v, t, cells)
                .unwrap_err()
                .to_string()
        };
        let cube = box_surface(DVec3::ZERO, DVec3::ONE, 2);
        let open = message(&cube.vertices, &cube.triangles[1..], 32);
        assert!(
            open.contains("`path`")
                && open.contains("not closed: 3 edges belong to one triangle only"),
            "{open}"
        );
        let empty = message(&[], &[], 32);
        assert!(empty.contains("empty"), "{empty}");
        let mut far = cube.triangles.clone();
        far[0][2] = 999;
        let range = message(&cube.vertices, &far, 32);
        assert!(range.contains("triangle 0 refers to vertex 999"), "{range}");
        let mut twisted = cube.triangles.clone();
        twisted[0].swap(0, 1);
        let flipped = message(&cube.vertices, &twisted, 32);
        assert!(flipped.contains("not consistently oriented"), "{flipped}");
        let coarse = message(&cube.vertices, &cube.triangles, 2);
        assert!(coarse.contains("`cells`"), "{coarse}");
    }
}
