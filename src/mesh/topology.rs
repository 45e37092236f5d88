//! Topology derived from tetrahedra: unique edges and boundary faces.

use std::collections::HashMap;

/// The unique edges of a set of tetrahedra, each as `[low, high]`, sorted.
pub fn unique_edges(tets: &[[u32; 4]]) -> Vec<[u32; 2]> {
    const PAIRS: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
    let mut edges: Vec<[u32; 2]> = tets
        .iter()
        .flat_map(|t| {
            PAIRS
                .iter()
                .map(move |&(a, b)| [t[a].min(t[b]), t[a].max(t[b])])
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// The faces that belong to exactly one tetrahedron, oriented outward for positively
/// oriented tetrahedra (counter-clockwise seen from outside).
pub fn boundary_faces(tets: &[[u32; 4]]) -> Vec<[u32; 3]> {
    // Faces opposite each vertex, wound so the normal points away from that vertex when the
    // tet has positive signed volume.
    const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];
    let mut count: HashMap<[u32; 3], (u32, [u32; 3])> = HashMap::new();
    for t in tets {
        for f in FACES {
            let face = [t[f[0]], t[f[1]], t[f[2]]];
            let mut key = face;
            key.sort_unstable();
            count
                .entry(key)
                .and_modify(|e| e.0 += 1)
                .or_insert((1, face));
        }
    }
    let mut faces: Vec<[u32; 3]> = count
        .into_values()
        .filter(|(n, _)| *n == 1)
        .map(|(_, f)| f)
        .collect();
    faces.sort_unstable();
    faces
}
