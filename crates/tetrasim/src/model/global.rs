//! The data of the global volume constraints (physics.md, "One global volume constraint",
//! after Hong, Jung, Choi and Welch 2006): one constraint per object,
//! `C_g = sum_t V_t(x) - sum_t V0_t`, evaluated through the object's boundary faces (the sum
//! of their [`face_volume`](crate::physics::face_volume)s is the sum of its tets' signed
//! volumes), so only surface nodes carry a gradient.

use super::{Csr, Model};
use crate::mesh::topology;

/// The global volume constraints of a model: per object its surface nodes, boundary faces
/// and rest volume; all objects' lists concatenated.
#[derive(Debug, Clone, PartialEq)]
pub struct GlobalVolume {
    /// Per object.
    pub objects: Vec<GlobalObject>,
    /// Surface nodes of every object (model node indices), object after object.
    pub nodes: Vec<u32>,
    /// Outward boundary faces of every object (model node indices), object after object.
    pub faces: Vec<[u32; 3]>,
    /// Row `k` (a position in `nodes`): `3 * face + corner` for each face at that node.
    pub node_faces: Csr,
}

/// One object's share of [`GlobalVolume`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalObject {
    /// First position of its surface nodes in [`GlobalVolume::nodes`].
    pub node_first: u32,
    /// Number of its surface nodes.
    pub node_count: u32,
    /// First position of its faces in [`GlobalVolume::faces`].
    pub face_first: u32,
    /// Number of its faces.
    pub face_count: u32,
    /// Its rest volume `sum_t V0_t` [m^3].
    pub rest_volume: f64,
}

impl GlobalVolume {
    /// The constraints of `model`'s objects ([`Model::objects`]).
    pub fn new(model: &Model) -> Self {
        let mut out = GlobalVolume {
            objects: Vec::new(),
            nodes: Vec::new(),
            faces: Vec::new(),
            node_faces: Csr::default(),
        };
        for range in model.objects.windows(2) {
            let (lo, hi) = (range[0], range[1]);
            let inside = |t: &[u32; 4]| t.iter().all(|&i| (lo..hi).contains(&i));
            let tets: Vec<[u32; 4]> = model.tets.iter().copied().filter(inside).collect();
            let rest_volume = model
                .tets
                .iter()
                .zip(&model.rest_volume)
                .filter(|(t, _)| inside(t))
                .map(|(_, v)| v)
                .sum();
            let faces = topology::boundary_faces(&tets);
            let mut nodes: Vec<u32> = faces.iter().flatten().copied().collect();
            nodes.sort_unstable();
            nodes.dedup();
            out.objects.push(GlobalObject {
                node_first: out.nodes.len() as u32,
                node_count: nodes.len() as u32,
                face_first: out.faces.len() as u32,
                face_count: faces.len() as u32,
                rest_volume,
            });
            out.nodes.extend(nodes);
            out.faces.extend(faces);
        }
        out.node_faces = node_faces(&out.nodes, &out.faces, model.node_count());
        out
    }
}

/// Row `k`: the corners (`3 * face + corner`) of `faces` at node `nodes[k]`.
fn node_faces(nodes: &[u32], faces: &[[u32; 3]], node_count: usize) -> Csr {
    let mut position = vec![u32::MAX; node_count];
    for (k, &i) in nodes.iter().enumerate() {
        position[i as usize] = k as u32;
    }
    Csr::from_pairs(nodes.len(), || {
        faces.iter().enumerate().flat_map(|(f, face)| {
            let position = &position;
            face.iter()
                .enumerate()
                .map(move |(corner, &i)| (position[i as usize] as usize, (3 * f + corner) as u32))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::grid::box_tets;
    use crate::model::ModelBuilder;
    use crate::physics::face_volume;
    use glam::DVec3;

    #[test]
    fn two_boxes_are_two_closed_surfaces_with_their_volumes() {
        let a = ModelBuilder::new(&box_tets(DVec3::ZERO, 0.5, [2, 2, 2]))
            .build()
            .unwrap();
        let b = ModelBuilder::new(&box_tets(DVec3::ZERO, 0.5, [3, 1, 2]))
            .build()
            .unwrap();
        let model = Model::concat(&[a.clone(), b.clone()]).unwrap();
        let g = GlobalVolume::new(&model);
        assert_eq!(g.objects.len(), 2);
        for (o, m) in g.objects.iter().zip([&a, &b]) {
            assert!((o.rest_volume - m.total_rest_volume()).abs() < 1e-12);
            let faces = &g.faces[o.face_first as usize..(o.face_first + o.face_count) as usize];
            let o_point = model.positions[faces[0][0] as usize] + DVec3::new(0.3, 0.1, -0.2);
            let volume: f64 = faces
                .iter()
                .map(|f| face_volume(f.map(|i| model.positions[i as usize]), o_point).0)
                .sum();
            assert!((volume - m.total_rest_volume()).abs() < 1e-12, "{volume}");
        }
        for (k, &i) in g.nodes.iter().enumerate() {
            for &e in g.node_faces.row(k) {
                assert_eq!(g.faces[e as usize / 3][e as usize % 3], i);
            }
        }
        assert_eq!(g.node_faces.items.len(), 3 * g.faces.len());
    }
}
