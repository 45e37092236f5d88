//! Boundary loops (holes) of a triangle surface and their filling.
//!
//! A loop follows the boundary edges in the direction their one face walks them; the filling
//! triangles walk them the other way, so the patch is oriented like its surroundings. Loops
//! of up to [`MAX_DP_LOOP`] vertices get a minimum-area triangulation (dynamic programming
//! over the loop, no new vertices); longer ones a fan around a new vertex at their centroid.

use std::collections::{HashMap, HashSet};

use glam::DVec3;

use super::orient::edge_faces;
use crate::mesh::SurfaceMesh;

/// Longest loop triangulated by minimum area (cost grows with the cube of the length).
pub const MAX_DP_LOOP: usize = 400;

/// The boundary loops of the surface, as vertex lists in the direction the adjacent faces
/// walk their edges. Loops touching at a vertex are returned separately. Boundary chains
/// that do not close (possible only next to non-manifold edges) are left out.
pub fn boundary_loops(triangles: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let edges = edge_faces(triangles);
    // Outgoing boundary half-edges per vertex.
    let mut out: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut starts = Vec::new();
    for (e, faces) in &edges {
        if faces.len() != 1 {
            continue;
        }
        let t = triangles[faces[0] as usize];
        let forward = (0..3).any(|k| t[k] == e[0] && t[(k + 1) % 3] == e[1]);
        let (a, b) = if forward { (e[0], e[1]) } else { (e[1], e[0]) };
        out.entry(a).or_default().push(b);
        starts.push(a);
    }
    starts.sort_unstable();
    starts.dedup();
    for list in out.values_mut() {
        list.sort_unstable();
    }
    let mut loops = Vec::new();
    for start in starts {
        while out.get(&start).is_some_and(|l| !l.is_empty()) {
            let mut path = vec![start];
            let mut pos: HashMap<u32, usize> = HashMap::from([(start, 0)]);
            let mut cur = start;
            // A chain that stops before closing (no outgoing edge left) is dropped.
            while let Some(next) = out.get_mut(&cur).and_then(|l| l.pop()) {
                if let Some(&j) = pos.get(&next) {
                    for v in &path[j + 1..] {
                        pos.remove(v);
                    }
                    loops.push(path.split_off(j));
                    path.push(next);
                } else {
                    pos.insert(next, path.len());
                    path.push(next);
                }
                cur = next;
                if path.len() == 1 && out.get(&cur).map_or(true, |l| l.is_empty()) {
                    break;
                }
            }
        }
    }
    loops.retain(|l| l.len() >= 3);
    loops
}

/// Fills every boundary loop. Returns `(loops filled, triangles added, vertices added)`.
pub fn fill_holes(mesh: &mut SurfaceMesh) -> (usize, usize, usize) {
    let loops = boundary_loops(&mesh.triangles);
    let (mut faces_added, mut vertices_added) = (0, 0);
    let key = |a: u32, b: u32| [a.min(b), a.max(b)];
    let mut edges: HashSet<[u32; 2]> = mesh
        .triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| key(t[k], t[(k + 1) % 3])))
        .collect();
    for lp in &loops {
        // Reverse so that the patch walks each boundary edge against its face.
        let polygon: Vec<u32> = lp.iter().rev().copied().collect();
        // A chord that is already an edge elsewhere would make it non-manifold.
        let tris = if polygon.len() <= MAX_DP_LOOP {
            min_area_triangulation(&mesh.vertices, &polygon, |a, b| edges.contains(&key(a, b)))
        } else {
            None
        };
        let tris = tris.unwrap_or_else(|| {
            let centroid = polygon
                .iter()
                .map(|&v| mesh.vertices[v as usize])
                .sum::<DVec3>()
                / polygon.len() as f64;
            let c = mesh.vertices.len() as u32;
            mesh.vertices.push(centroid);
            vertices_added += 1;
            (0..polygon.len())
                .map(|k| [polygon[k], polygon[(k + 1) % polygon.len()], c])
                .collect()
        });
        edges.extend(
            tris.iter()
                .flat_map(|t| (0..3).map(move |k| key(t[k], t[(k + 1) % 3]))),
        );
        faces_added += tris.len();
        mesh.triangles.extend(tris);
    }
    (loops.len(), faces_added, vertices_added)
}

/// Triangulates the closed polygon `poly` (vertex indices, walked in order) minimizing the
/// total area, without using a chord for which `forbidden(a, b)` holds; triangles keep the
/// polygon's orientation. `None` when every triangulation needs a forbidden chord.
pub fn min_area_triangulation(
    vertices: &[DVec3],
    poly: &[u32],
    forbidden: impl Fn(u32, u32) -> bool,
) -> Option<Vec<[u32; 3]>> {
    let n = poly.len();
    if n < 3 {
        return Some(Vec::new());
    }
    let p = |i: usize| vertices[poly[i] as usize];
    let area = |i: usize, m: usize, j: usize| 0.5 * (p(m) - p(i)).cross(p(j) - p(i)).length();
    // cost[i][j]: best triangulation of the sub-polygon i..=j (closed by the chord j -> i).
    let mut cost = vec![0.0f64; n * n];
    let mut best = vec![0usize; n * n];
    for len in 2..n {
        for i in 0..n - len {
            let j = i + len;
            if (j != n - 1 || i != 0) && forbidden(poly[i], poly[j]) {
                cost[i * n + j] = f64::INFINITY;
                continue;
            }
            let mut min = f64::INFINITY;
            let mut arg = i + 1;
            for m in i + 1..j {
                let c = cost[i * n + m] + cost[m * n + j] + area(i, m, j);
                if c < min {
                    min = c;
                    arg = m;
                }
            }
            cost[i * n + j] = min;
            best[i * n + j] = arg;
        }
    }
    if !cost[n - 1].is_finite() {
        return None;
    }
    let mut tris = Vec::with_capacity(n - 2);
    let mut stack = vec![(0, n - 1)];
    while let Some((i, j)) = stack.pop() {
        if j < i + 2 {
            continue;
        }
        let m = best[i * n + j];
        tris.push([poly[i], poly[m], poly[j]]);
        stack.push((i, m));
        stack.push((m, j));
    }
    Some(tris)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_hole_in_open_box_is_found_and_filled() {
        // A unit cube without its top (z = 1) face: one loop of 4 vertices.
        let vertices: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        let mut m = SurfaceMesh {
            vertices,
            triangles,
        };
        let loops = boundary_loops(&m.triangles);
        assert_eq!(loops.len(), 1);
        assert_eq!(loops[0].len(), 4);
        assert_eq!(fill_holes(&mut m), (1, 2, 0));
        assert!(boundary_loops(&m.triangles).is_empty());
        let v = super::super::orient::signed_volume(&m.vertices, &m.triangles);
        assert!((v - 1.0).abs() < 1e-12, "{v}");
    }

    #[test]
    fn existing_edges_are_not_used_as_chords() {
        let v = vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.5),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let t = min_area_triangulation(&v, &[0, 1, 2, 3], |a, b| (a.min(b), a.max(b)) == (1, 3))
            .unwrap();
        assert!(t.iter().all(|t| t.contains(&0) && t.contains(&2)), "{t:?}");
        assert!(min_area_triangulation(&v, &[0, 1, 2, 3], |_, _| true).is_none());
    }

    #[test]
    fn min_area_prefers_the_short_diagonal() {
        let v = vec![
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.5),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let t = min_area_triangulation(&v, &[0, 1, 2, 3], |_, _| false).unwrap();
        assert_eq!(t.len(), 2);
        // The fold along 1-3 (area 0.5 + sqrt(1.5)/2) beats 0-2 (sqrt(1.25)).
        let area: f64 = t
            .iter()
            .map(|t| {
                0.5 * (v[t[1] as usize] - v[t[0] as usize])
                    .cross(v[t[2] as usize] - v[t[0] as usize])
                    .length()
            })
            .sum();
        assert!((area - (0.5 + 1.5f64.sqrt() / 2.0)).abs() < 1e-12, "{area}");
        assert!(t.iter().all(|t| t.contains(&1) && t.contains(&3)), "{t:?}");
    }
}
