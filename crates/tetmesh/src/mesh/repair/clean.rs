//! Cleaning steps: weld duplicate vertices, drop degenerate and duplicate faces, drop
//! unreferenced vertices.

use std::collections::HashMap;

use glam::DVec3;

use crate::mesh::SurfaceMesh;

/// Merges vertices closer than `tolerance` (absolute length) into the first one seen and
/// rewrites the triangles. Returns how many vertices were merged away. Unreferenced vertices
/// stay (see [`drop_unreferenced`]).
pub fn weld(mesh: &mut SurfaceMesh, tolerance: f64) -> usize {
    let n = mesh.vertices.len();
    let mut remap: Vec<u32> = (0..n as u32).collect();
    let mut merged = 0;
    if tolerance > 0.0 {
        let cell = |p: DVec3| (p / tolerance).floor().as_i64vec3();
        let mut grid: HashMap<glam::I64Vec3, Vec<u32>> = HashMap::new();
        for (i, &p) in mesh.vertices.iter().enumerate() {
            let c = cell(p);
            let mut found = None;
            'search: for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        if let Some(list) = grid.get(&(c + glam::I64Vec3::new(dx, dy, dz))) {
                            if let Some(&j) = list
                                .iter()
                                .find(|&&j| mesh.vertices[j as usize].distance(p) <= tolerance)
                            {
                                found = Some(j);
                                break 'search;
                            }
                        }
                    }
                }
            }
            match found {
                Some(j) => {
                    remap[i] = j;
                    merged += 1;
                }
                None => grid.entry(c).or_default().push(i as u32),
            }
        }
    } else {
        let mut seen: HashMap<[u64; 3], u32> = HashMap::new();
        for (i, p) in mesh.vertices.iter().enumerate() {
            // +0.0 and -0.0 are the same point.
            let key = [p.x + 0.0, p.y + 0.0, p.z + 0.0].map(f64::to_bits);
            let j = *seen.entry(key).or_insert(i as u32);
            if j != i as u32 {
                remap[i] = j;
                merged += 1;
            }
        }
    }
    for t in &mut mesh.triangles {
        *t = t.map(|v| remap[v as usize]);
    }
    merged
}

/// Twice the area of a triangle.
fn double_area(mesh: &SurfaceMesh, t: [u32; 3]) -> f64 {
    let [a, b, c] = t.map(|v| mesh.vertices[v as usize]);
    (b - a).cross(c - a).length()
}

/// Drops triangles with a repeated vertex or an area at most `min_area`. Returns the count.
pub fn drop_degenerate(mesh: &mut SurfaceMesh, min_area: f64) -> usize {
    let before = mesh.triangles.len();
    let keep: Vec<bool> = mesh
        .triangles
        .iter()
        .map(|&t| {
            t[0] != t[1] && t[1] != t[2] && t[0] != t[2] && 0.5 * double_area(mesh, t) > min_area
        })
        .collect();
    let mut k = keep.iter();
    mesh.triangles.retain(|_| *k.next().unwrap_or(&false));
    before - mesh.triangles.len()
}

/// Resolves faces that use the same three vertices. Copies with opposite windings cancel in
/// pairs (an opposite pair is a zero-volume double wall, as decimation leaves in scans); of
/// what is left, one copy with the prevailing winding is kept. Returns the number of faces
/// removed.
pub fn drop_duplicates(mesh: &mut SurfaceMesh) -> usize {
    let before = mesh.triangles.len();
    // Net winding per vertex set: +1 for a winding that is an even permutation of the
    // sorted vertices, -1 otherwise; and the first face seen.
    let mut net: HashMap<[u32; 3], (i32, usize)> = HashMap::with_capacity(before);
    for (f, t) in mesh.triangles.iter().enumerate() {
        let mut key = *t;
        key.sort_unstable();
        let even = [key, [key[1], key[2], key[0]], [key[2], key[0], key[1]]].contains(t);
        let entry = net.entry(key).or_insert((0, f));
        entry.0 += if even { 1 } else { -1 };
    }
    let mut kept = Vec::with_capacity(before);
    for (f, t) in mesh.triangles.iter().enumerate() {
        let mut key = *t;
        key.sort_unstable();
        let Some(&(n, first)) = net.get(&key) else {
            continue;
        };
        if n == 0 {
            continue;
        }
        if first == f {
            let even = [key, [key[1], key[2], key[0]], [key[2], key[0], key[1]]].contains(t);
            kept.push(if even == (n > 0) {
                *t
            } else {
                [t[0], t[2], t[1]]
            });
        }
    }
    mesh.triangles = kept;
    before - mesh.triangles.len()
}

/// Removes vertices no triangle uses and renumbers the rest (order kept). Returns the count.
pub fn drop_unreferenced(mesh: &mut SurfaceMesh) -> usize {
    let mut new_index = vec![u32::MAX; mesh.vertices.len()];
    for t in &mesh.triangles {
        for &v in t {
            new_index[v as usize] = 0;
        }
    }
    let mut vertices = Vec::with_capacity(mesh.vertices.len());
    for (i, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = vertices.len() as u32;
            vertices.push(mesh.vertices[i]);
        }
    }
    let dropped = mesh.vertices.len() - vertices.len();
    mesh.vertices = vertices;
    for t in &mut mesh.triangles {
        *t = t.map(|v| new_index[v as usize]);
    }
    dropped
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weld_merges_close_points_only() {
        let mut m = SurfaceMesh {
            vertices: vec![
                DVec3::ZERO,
                DVec3::X,
                DVec3::Y,
                DVec3::new(1e-9, 0.0, 0.0),
                DVec3::new(0.01, 0.0, 0.0),
            ],
            triangles: vec![[0, 1, 2], [3, 1, 4]],
        };
        assert_eq!(weld(&mut m, 1e-6), 1);
        assert_eq!(m.triangles[1], [0, 1, 4]);
        assert_eq!(drop_unreferenced(&mut m), 1);
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.triangles[1], [0, 1, 3]);
    }

    #[test]
    fn degenerate_and_duplicates() {
        let mut m = SurfaceMesh {
            vertices: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(2.0, 0.0, 0.0)],
            triangles: vec![
                [0, 1, 2],
                [0, 0, 1],
                [0, 1, 3],
                [1, 2, 0],
                [0, 2, 3],
                [3, 2, 0],
                [2, 0, 1],
            ],
        };
        assert_eq!(drop_degenerate(&mut m, 0.0), 2); // repeated index, collinear
                                                     // [0,1,2] three times the same way: one kept; [0,2,3] and [3,2,0] cancel.
        assert_eq!(drop_duplicates(&mut m), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
        // Two one way, one the other: one copy of the prevailing winding stays.
        m.triangles = vec![[0, 2, 1], [0, 1, 2], [1, 2, 0]];
        assert_eq!(drop_duplicates(&mut m), 2);
        assert_eq!(m.triangles, vec![[0, 1, 2]]);
    }
}
