//! Topology derived from tetrahedra and triangles: unique edges, boundary faces and the
//! pinched (non-manifold) vertices of a surface.

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

/// The vertices where a triangle surface is pinched: the triangles around the vertex form
/// more than one fan (umbrella), so the surface touches itself there, as two cones meeting
/// at their tips. Faces joined across an edge count as one fan, so a vertex on a
/// non-manifold edge only is not reported here (that is an edge problem). Sorted.
pub fn non_manifold_vertices(triangles: &[[u32; 3]]) -> Vec<u32> {
    // The link of each vertex: for the triangle (v, a, b), the edge a-b. The vertex is
    // manifold when its link is connected (one fan, open or closed).
    let mut links: Vec<(u32, u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1], t[2]), (t[1], t[2], t[0]), (t[2], t[0], t[1])])
        .collect();
    links.sort_unstable();
    let mut pinched = Vec::new();
    let mut nodes: Vec<u32> = Vec::new();
    let mut parent: Vec<usize> = Vec::new();
    for group in links.chunk_by(|x, y| x.0 == y.0) {
        if group.len() < 2 {
            continue;
        }
        nodes.clear();
        nodes.extend(group.iter().flat_map(|&(_, a, b)| [a, b]));
        nodes.sort_unstable();
        nodes.dedup();
        parent.clear();
        parent.extend(0..nodes.len());
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let mut fans = nodes.len();
        for &(_, a, b) in group {
            // `nodes` holds every a and b of the group, so both searches find them.
            let (Ok(ia), Ok(ib)) = (nodes.binary_search(&a), nodes.binary_search(&b)) else {
                continue;
            };
            let (ra, rb) = (root(&mut parent, ia), root(&mut parent, ib));
            if ra != rb {
                parent[ra] = rb;
                fans -= 1;
            }
        }
        if fans > 1 {
            pinched.push(group[0].0);
        }
    }
    pinched
}
