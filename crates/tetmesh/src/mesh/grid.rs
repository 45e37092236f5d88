//! Structured tetrahedral grids: boxes of cubes, each split into six tets along its main
//! diagonal (Kuhn/Freudenthal), which conforms across neighbouring cells. Used for generated
//! test meshes and by the voxel mesher, which keeps only the cells inside a surface.

use glam::DVec3;

use super::TetMesh;
use crate::geometry::tet_volume;

/// The six tets of a unit cube, as corner numbers `x + 2y + 4z`, each walking from corner 0
/// to corner 7 along one permutation of the axes.
const KUHN_TETS: [[usize; 4]; 6] = [
    [0, 1, 3, 7], // x, y, z
    [0, 1, 5, 7], // x, z, y
    [0, 2, 3, 7], // y, x, z
    [0, 2, 6, 7], // y, z, x
    [0, 4, 5, 7], // z, x, y
    [0, 4, 6, 7], // z, y, x
];

/// A regular grid of `cells` cubes of edge `h` starting at `origin`, keeping the cells for
/// which `keep(cell_index)` is true. Unused nodes are dropped, tets are positively oriented,
/// and boundary faces are filled in.
pub fn grid_tets(
    origin: DVec3,
    h: f64,
    cells: [usize; 3],
    mut keep: impl FnMut([usize; 3]) -> bool,
) -> TetMesh {
    let [nx, ny, nz] = cells;
    let node_id = |x: usize, y: usize, z: usize| x + (nx + 1) * (y + (ny + 1) * z);
    let mut used = vec![u32::MAX; (nx + 1) * (ny + 1) * (nz + 1)];
    let mut nodes = Vec::new();
    let mut tets = Vec::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                if !keep([x, y, z]) {
                    continue;
                }
                let corner = |c: usize| (x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
                for tet in KUHN_TETS {
                    let ids = tet.map(|c| {
                        let (cx, cy, cz) = corner(c);
                        let id = node_id(cx, cy, cz);
                        if used[id] == u32::MAX {
                            used[id] = nodes.len() as u32;
                            nodes.push(origin + DVec3::new(cx as f64, cy as f64, cz as f64) * h);
                        }
                        used[id]
                    });
                    let p = ids.map(|i| nodes[i as usize]);
                    let oriented = if tet_volume(p) < 0.0 {
                        [ids[0], ids[1], ids[3], ids[2]]
                    } else {
                        ids
                    };
                    tets.push(oriented);
                }
            }
        }
    }
    let faces = super::topology::boundary_faces(&tets);
    TetMesh { nodes, tets, faces }
}

/// A solid box of `cells` cubes of edge `h`, lowest corner at `origin`.
pub fn box_tets(origin: DVec3, h: f64, cells: [usize; 3]) -> TetMesh {
    grid_tets(origin, h, cells, |_| true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_has_expected_counts_and_volume() {
        let mesh = box_tets(DVec3::ZERO, 0.5, [2, 3, 4]);
        assert_eq!(mesh.nodes.len(), 3 * 4 * 5);
        assert_eq!(mesh.tets.len(), 6 * 24);
        let volume: f64 = mesh
            .tets
            .iter()
            .map(|t| {
                let p = t.map(|i| mesh.nodes[i as usize]);
                tet_volume(p)
            })
            .inspect(|v| assert!(*v > 0.0))
            .sum();
        assert!((volume - 1.0 * 1.5 * 2.0).abs() < 1e-12);
        // A conforming mesh of a box has 2 triangles per boundary square.
        assert_eq!(mesh.faces.len(), 2 * 2 * (2 * 3 + 3 * 4 + 2 * 4));
    }
}
