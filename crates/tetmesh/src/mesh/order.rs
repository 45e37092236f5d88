//! A locality-preserving numbering of a tet mesh: nodes along a Morton (Z-order) curve, tets
//! in the Morton order of their centroids. Each constraint pass reads the positions of its
//! tets' four nodes; numbered this way, tets that follow each other in memory touch nodes
//! that sit together in memory, so caches (and a GPU's coalescing) serve most reads. TetGen
//! numbers the input surface's vertices first and appends its Steiner points, so in its
//! order consecutive tets touch nodes far apart (measured in docs/BENCHMARKS.md, "Node and
//! tet order": as slow as a random numbering on a 212k-tet bunny).

use glam::DVec3;

use super::{bounds_of, TetMesh};

/// Bits per axis of [`morton_code`] (3 x 21 = 63 bits).
const BITS: u32 = 21;

/// Spreads the low 21 bits of `x` so that bit `k` lands on bit `3 k`.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

/// The Morton (Z-order) code of `p` in the box `lo..hi`: each axis quantised to 21 bits,
/// the bits interleaved (x lowest). Points outside the box are clamped to it.
pub fn morton_code(p: DVec3, lo: DVec3, hi: DVec3) -> u64 {
    let cells = f64::from((1u32 << BITS) - 1);
    let q = |v: f64, a: f64, b: f64| -> u64 {
        let t = if b > a { (v - a) / (b - a) } else { 0.0 };
        (t.clamp(0.0, 1.0) * cells).round() as u64
    };
    spread(q(p.x, lo.x, hi.x))
        | (spread(q(p.y, lo.y, hi.y)) << 1)
        | (spread(q(p.z, lo.z, hi.z)) << 2)
}

/// `mesh` renumbered for locality (see the module doc): the same nodes, tets (each with its
/// corners in the same order, so its orientation is kept) and boundary faces, only in a
/// different order. Ties keep the input order, so the result is deterministic.
pub fn spatially_ordered(mesh: &TetMesh) -> TetMesh {
    let Some((lo, hi)) = bounds_of(&mesh.nodes) else {
        return mesh.clone();
    };
    let mut order: Vec<u32> = (0..mesh.nodes.len() as u32).collect();
    order.sort_by_key(|&i| morton_code(mesh.nodes[i as usize], lo, hi));
    let mut new_index = vec![0u32; mesh.nodes.len()];
    for (new, &old) in order.iter().enumerate() {
        new_index[old as usize] = new as u32;
    }
    let nodes: Vec<DVec3> = order.iter().map(|&i| mesh.nodes[i as usize]).collect();
    let mut tets: Vec<[u32; 4]> = mesh
        .tets
        .iter()
        .map(|t| t.map(|i| new_index[i as usize]))
        .collect();
    let centroid_code = |t: &[u32; 4]| {
        let c = t.iter().map(|&i| nodes[i as usize]).sum::<DVec3>() / 4.0;
        morton_code(c, lo, hi)
    };
    tets.sort_by_cached_key(centroid_code);
    let faces = mesh
        .faces
        .iter()
        .map(|f| f.map(|i| new_index[i as usize]))
        .collect();
    TetMesh { nodes, tets, faces }
}

/// How far apart in memory a tet's nodes are: the median over tets of the spread (largest
/// minus smallest) of their node indices, as a fraction of the node count. About 1/2 for a
/// random numbering; small for a local one (a Morton order's few tets across its octant
/// boundaries spread widely, so the median, not the mean).
pub fn median_index_spread(mesh: &TetMesh) -> f64 {
    if mesh.tets.is_empty() || mesh.nodes.is_empty() {
        return 0.0;
    }
    let mut spreads: Vec<u32> = mesh
        .tets
        .iter()
        .map(|t| {
            let (lo, hi) = t
                .iter()
                .fold((u32::MAX, 0), |(lo, hi), &i| (lo.min(i), hi.max(i)));
            hi - lo
        })
        .collect();
    let middle = spreads.len() / 2;
    let (_, median, _) = spreads.select_nth_unstable(middle);
    f64::from(*median) / mesh.nodes.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::tet_volume;
    use crate::mesh::grid::box_tets;

    #[test]
    fn morton_codes_interleave_the_axes() {
        let (lo, hi) = (DVec3::ZERO, DVec3::ONE);
        assert_eq!(morton_code(lo, lo, hi), 0);
        assert_eq!(morton_code(hi, lo, hi), (1u64 << 63) - 1);
        // The first step along x, y, z sets bit 0, 1, 2.
        let step = 1.0 / f64::from((1u32 << BITS) - 1);
        assert_eq!(morton_code(DVec3::new(step, 0.0, 0.0), lo, hi), 1);
        assert_eq!(morton_code(DVec3::new(0.0, step, 0.0), lo, hi), 2);
        assert_eq!(morton_code(DVec3::new(0.0, 0.0, step), lo, hi), 4);
        assert_eq!(morton_code(DVec3::splat(-5.0), lo, hi), 0, "clamped");
    }

    /// A box mesh with its nodes and tets shuffled (deterministically).
    fn shuffled_box() -> TetMesh {
        let mesh = box_tets(DVec3::ZERO, 0.1, [12, 9, 7]);
        let n = mesh.nodes.len();
        // A multiplicative permutation: i -> i * k mod n with k coprime to n.
        let k = (n / 2..n).find(|k| gcd(*k, n) == 1).unwrap();
        let perm: Vec<usize> = (0..n).map(|i| i * k % n).collect();
        let mut new_index = vec![0u32; n];
        for (new, &old) in perm.iter().enumerate() {
            new_index[old] = new as u32;
        }
        let mut tets: Vec<[u32; 4]> = mesh
            .tets
            .iter()
            .map(|t| t.map(|i| new_index[i as usize]))
            .collect();
        tets.reverse();
        TetMesh {
            nodes: perm.iter().map(|&i| mesh.nodes[i]).collect(),
            tets,
            faces: mesh
                .faces
                .iter()
                .map(|f| f.map(|i| new_index[i as usize]))
                .collect(),
        }
    }

    fn gcd(a: usize, b: usize) -> usize {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }

    fn sorted_volumes(m: &TetMesh) -> Vec<f64> {
        let mut v: Vec<f64> = m
            .tets
            .iter()
            .map(|t| tet_volume(t.map(|i| m.nodes[i as usize])))
            .collect();
        v.sort_by(f64::total_cmp);
        v
    }

    #[test]
    fn ordering_renumbers_without_changing_the_mesh() {
        let mesh = shuffled_box();
        let ordered = spatially_ordered(&mesh);
        assert_eq!(ordered.nodes.len(), mesh.nodes.len());
        assert_eq!(ordered.tets.len(), mesh.tets.len());
        assert_eq!(ordered.faces.len(), mesh.faces.len());
        // The same node positions, and the same tets with the same signed volumes (corner
        // order, so orientation, kept).
        let key = |p: &DVec3| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
        let mut a: Vec<_> = mesh.nodes.iter().map(key).collect();
        let mut b: Vec<_> = ordered.nodes.iter().map(key).collect();
        a.sort();
        b.sort();
        assert_eq!(a, b);
        assert_eq!(sorted_volumes(&mesh), sorted_volumes(&ordered));
        assert!(sorted_volumes(&ordered)[0] > 0.0);
        // Faces name the same triangles.
        let tri = |m: &TetMesh, f: &[u32; 3]| {
            let mut p: Vec<_> = f.iter().map(|&i| key(&m.nodes[i as usize])).collect();
            p.sort();
            p
        };
        let mut fa: Vec<_> = mesh.faces.iter().map(|f| tri(&mesh, f)).collect();
        let mut fb: Vec<_> = ordered.faces.iter().map(|f| tri(&ordered, f)).collect();
        fa.sort();
        fb.sort();
        assert_eq!(fa, fb);
        // Ordering an ordered mesh changes nothing.
        assert_eq!(spatially_ordered(&ordered), ordered);
    }

    #[test]
    fn ordering_brings_each_tets_nodes_together() {
        let mesh = shuffled_box();
        let before = median_index_spread(&mesh);
        let after = median_index_spread(&spatially_ordered(&mesh));
        assert!(before > 0.2, "the shuffled box is not scattered: {before}");
        assert!(after < 0.15 * before, "spread {before} -> {after}");
        println!("median index spread {before:.4} -> {after:.4}");
    }
}
