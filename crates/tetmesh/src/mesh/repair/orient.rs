//! Edge topology of a triangle surface: non-manifold edges, consistent orientation (breadth-
//! first over manifold edges) and outward orientation (positive enclosed volume).

use std::collections::{HashMap, VecDeque};

use glam::DVec3;

use crate::mesh::SurfaceMesh;

/// For every undirected edge `[low, high]`, the faces using it.
pub fn edge_faces(triangles: &[[u32; 3]]) -> HashMap<[u32; 2], Vec<u32>> {
    let mut map: HashMap<[u32; 2], Vec<u32>> = HashMap::with_capacity(triangles.len() * 3 / 2);
    for (f, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            map.entry([a.min(b), a.max(b)]).or_default().push(f as u32);
        }
    }
    map
}

/// Whether face `t` walks the edge from `a` to `b` (rather than `b` to `a`).
fn walks(t: [u32; 3], a: u32, b: u32) -> bool {
    (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
}

/// Edges used by more than two faces, sorted.
pub fn non_manifold_edges(edges: &HashMap<[u32; 2], Vec<u32>>) -> Vec<([u32; 2], usize)> {
    let mut list: Vec<([u32; 2], usize)> = edges
        .iter()
        .filter(|(_, f)| f.len() > 2)
        .map(|(e, f)| (*e, f.len()))
        .collect();
    list.sort_unstable();
    list
}

/// Result of [`orient_consistently`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Orientation {
    /// Faces whose winding was reversed to agree with their neighbours.
    pub flipped: usize,
    /// Connected components (over manifold edges).
    pub components: usize,
    /// Edges where two faces still disagree after the walk (non-orientable surface).
    pub conflicts: usize,
    /// Component number of each face.
    pub component_of: Vec<u32>,
}

/// Reverses faces so that every manifold edge (two faces) is walked in opposite directions
/// by its two faces. Each component keeps the winding of its first face.
pub fn orient_consistently(mesh: &mut SurfaceMesh) -> Orientation {
    let edges = edge_faces(&mesh.triangles);
    let n = mesh.triangles.len();
    let mut component_of = vec![u32::MAX; n];
    let mut result = Orientation::default();
    let mut queue = VecDeque::new();
    for seed in 0..n {
        if component_of[seed] != u32::MAX {
            continue;
        }
        let comp = result.components as u32;
        result.components += 1;
        component_of[seed] = comp;
        queue.push_back(seed);
        while let Some(f) = queue.pop_front() {
            let t = mesh.triangles[f];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let Some(faces) = edges.get(&[a.min(b), a.max(b)]) else {
                    continue;
                };
                if faces.len() != 2 {
                    continue;
                }
                let g = if faces[0] as usize == f {
                    faces[1]
                } else {
                    faces[0]
                } as usize;
                if component_of[g] != u32::MAX {
                    continue;
                }
                component_of[g] = comp;
                if walks(mesh.triangles[g], a, b) {
                    mesh.triangles[g].swap(1, 2);
                    result.flipped += 1;
                }
                queue.push_back(g);
            }
        }
    }
    result.conflicts = edges
        .iter()
        .filter(|(_, f)| f.len() == 2)
        .filter(|(e, f)| {
            walks(mesh.triangles[f[0] as usize], e[0], e[1])
                == walks(mesh.triangles[f[1] as usize], e[0], e[1])
        })
        .count();
    result.component_of = component_of;
    result
}

/// Signed volume enclosed by the triangles (divergence theorem); positive when a closed
/// surface is oriented outward. In the mesh's length unit cubed.
pub fn signed_volume(vertices: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    // Relative to the first vertex to keep the sum well conditioned far from the origin.
    let Some(&o) = vertices.first() else {
        return 0.0;
    };
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| vertices[v as usize] - o);
            a.dot(b.cross(c))
        })
        .sum::<f64>()
        / 6.0
}

/// Reverses every component whose enclosed volume is negative. Returns the number of faces
/// reversed. (A cavity inside another component is also turned outward; scans have none.)
pub fn orient_outward(mesh: &mut SurfaceMesh, component_of: &[u32], components: usize) -> usize {
    let mut volume = vec![0.0; components];
    let o = mesh.vertices.first().copied().unwrap_or(DVec3::ZERO);
    for (t, &c) in mesh.triangles.iter().zip(component_of) {
        let [a, b, d] = t.map(|v| mesh.vertices[v as usize] - o);
        volume[c as usize] += a.dot(b.cross(d));
    }
    let mut flipped = 0;
    for (t, &c) in mesh.triangles.iter_mut().zip(component_of) {
        if volume[c as usize] < 0.0 {
            t.swap(1, 2);
            flipped += 1;
        }
    }
    flipped
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> SurfaceMesh {
        SurfaceMesh {
            vertices: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            triangles: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        }
    }

    #[test]
    fn flipped_face_is_fixed_and_volume_positive() {
        let mut m = tetra();
        assert!((signed_volume(&m.vertices, &m.triangles) - 1.0 / 6.0).abs() < 1e-15);
        m.triangles[2] = [1, 3, 2];
        let o = orient_consistently(&mut m);
        assert_eq!((o.flipped, o.components, o.conflicts), (1, 1, 0));
        assert!((signed_volume(&m.vertices, &m.triangles) - 1.0 / 6.0).abs() < 1e-15);
        // Everything inside out: one component flipped back.
        for t in &mut m.triangles {
            t.swap(0, 1);
        }
        let o = orient_consistently(&mut m);
        assert_eq!(o.flipped, 0);
        assert_eq!(orient_outward(&mut m, &o.component_of, o.components), 4);
        assert!(signed_volume(&m.vertices, &m.triangles) > 0.0);
    }

    #[test]
    fn fin_is_non_manifold() {
        let mut m = tetra();
        m.vertices.push(DVec3::new(-1.0, -1.0, 0.0));
        m.triangles.push([0, 1, 4]);
        let nm = non_manifold_edges(&edge_faces(&m.triangles));
        assert_eq!(nm, vec![([0, 1], 3)]);
    }
}
