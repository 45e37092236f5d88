//! Self-intersections of a triangle surface: pairs of faces that cross each other, found with
//! a sparse uniform grid over face bounding boxes and an exact-topology, floating-point
//! triangle-triangle test. Faces that merely touch (shared vertices or edges, or contact within
//! round-off) are not counted.

use std::collections::HashMap;

use glam::{DVec3, I64Vec3};
use rayon::prelude::*;

/// Pairs `(f, g)` with `f < g` of faces that cross each other, sorted.
pub fn self_intersections(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    if triangles.len() < 2 {
        return Vec::new();
    }
    let boxes: Vec<(DVec3, DVec3)> = triangles
        .iter()
        .map(|t| {
            let p = t.map(|v| vertices[v as usize]);
            (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
        })
        .collect();
    let Some((lo, hi)) = crate::mesh::bounds_of(vertices) else {
        return Vec::new();
    };
    let diag = (hi - lo).length();
    if diag.is_nan() || diag <= 0.0 {
        return Vec::new();
    }
    let mean_extent = boxes
        .iter()
        .map(|(a, b)| (*b - *a).max_element())
        .sum::<f64>()
        / boxes.len() as f64;
    let h = mean_extent.max(diag / 512.0);
    let cell = |p: DVec3| ((p - lo) / h).floor().as_i64vec3();
    let mut grid: HashMap<I64Vec3, Vec<u32>> = HashMap::new();
    for (f, (a, b)) in boxes.iter().enumerate() {
        let (ca, cb) = (cell(*a), cell(*b));
        for z in ca.z..=cb.z {
            for y in ca.y..=cb.y {
                for x in ca.x..=cb.x {
                    grid.entry(I64Vec3::new(x, y, z))
                        .or_default()
                        .push(f as u32);
                }
            }
        }
    }
    // Round-off scale for the orientation determinants (length^3).
    let eps = 1e-12 * diag * diag * diag;
    let cells: Vec<(I64Vec3, Vec<u32>)> = grid.into_iter().collect();
    let mut pairs: Vec<(u32, u32)> = cells
        .par_iter()
        .flat_map_iter(|(c, faces)| {
            let mut found = Vec::new();
            for (i, &f) in faces.iter().enumerate() {
                for &g in &faces[i + 1..] {
                    let (bf, bg) = (boxes[f as usize], boxes[g as usize]);
                    if bf.0.cmpgt(bg.1).any() || bg.0.cmpgt(bf.1).any() {
                        continue;
                    }
                    // Test each pair once: in the cell holding the low corner of the overlap.
                    if cell(bf.0.max(bg.0)) != *c {
                        continue;
                    }
                    if triangles_cross(vertices, triangles[f as usize], triangles[g as usize], eps)
                    {
                        found.push((f.min(g), f.max(g)));
                    }
                }
            }
            found
        })
        .collect();
    pairs.sort_unstable();
    pairs
}

/// `((b - a) x (c - a)) . (d - a)`: six times the signed volume of `abcd`.
fn orient(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    (b - a).cross(c - a).dot(d - a)
}

/// Whether segment `pq` passes through the interior of triangle `abc` (strictly, by more
/// than `eps`).
fn segment_crosses(p: DVec3, q: DVec3, [a, b, c]: [DVec3; 3], eps: f64) -> bool {
    let (dp, dq) = (orient(a, b, c, p), orient(a, b, c, q));
    if !((dp > eps && dq < -eps) || (dp < -eps && dq > eps)) {
        return false;
    }
    let s = [orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)];
    s.iter().all(|&x| x > eps) || s.iter().all(|&x| x < -eps)
}

/// Whether two faces cross: an edge of one passes through the other. Edges with an end at a
/// vertex of the other face are skipped (touching at a shared vertex is no crossing).
fn triangles_cross(vertices: &[DVec3], f: [u32; 3], g: [u32; 3], eps: f64) -> bool {
    let pos = |t: [u32; 3]| t.map(|v| vertices[v as usize]);
    let edge_crosses = |e: [u32; 3], other: [u32; 3]| {
        (0..3).any(|k| {
            let (u, v) = (e[k], e[(k + 1) % 3]);
            if other.contains(&u) || other.contains(&v) {
                return false;
            }
            segment_crosses(vertices[u as usize], vertices[v as usize], pos(other), eps)
        })
    };
    edge_crosses(f, g) || edge_crosses(g, f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_pair_found_touching_pair_not() {
        let vertices = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 2.0, 0.0),
            // Pierces the first triangle.
            DVec3::new(0.5, 0.5, -1.0),
            DVec3::new(0.5, 0.5, 1.0),
            DVec3::new(0.5, -1.0, 1.0),
            // Shares vertex 0 with the first triangle; crosses its plane only outside it.
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(-1.0, -1.0, -1.0),
        ];
        let triangles = vec![[0, 1, 2], [3, 4, 5], [0, 6, 7]];
        assert_eq!(self_intersections(&vertices, &triangles), vec![(0, 1)]);
    }
}
