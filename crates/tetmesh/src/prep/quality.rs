//! Measures of a tet mesh: volumes and dihedral angles.

use glam::DVec3;

use crate::geometry::tet_volume;
use crate::mesh::TetMesh;

/// Volume and shape figures of a tet mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TetQuality {
    /// Sum of signed tet volumes (length unit cubed).
    pub volume: f64,
    /// Tets with signed volume <= 0.
    pub non_positive: usize,
    /// Smallest and largest dihedral angle over all tets [degrees].
    pub min_dihedral_deg: f64,
    /// Largest dihedral angle over all tets [degrees].
    pub max_dihedral_deg: f64,
}

/// The six dihedral angles of tet `p` [radians], one per edge.
pub fn dihedral_angles(p: [DVec3; 4]) -> [f64; 6] {
    // Outward unit normal of the face opposite vertex k.
    const OTHERS: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];
    let normal = |k: usize| {
        let [a, b, c] = OTHERS[k];
        let n = (p[b] - p[a]).cross(p[c] - p[a]);
        let n = if n.dot(p[k] - p[a]) > 0.0 { -n } else { n };
        n.normalize_or_zero()
    };
    let n = [normal(0), normal(1), normal(2), normal(3)];
    // Edge (i, j) lies between the faces opposite the other two vertices (k, l).
    const OPPOSITE: [(usize, usize); 6] = [(2, 3), (1, 3), (1, 2), (0, 3), (0, 2), (0, 1)];
    OPPOSITE.map(|(k, l)| (-n[k].dot(n[l])).clamp(-1.0, 1.0).acos())
}

/// Volume, inverted count and dihedral angle range of `mesh`.
pub fn tet_quality(mesh: &TetMesh) -> TetQuality {
    let mut q = TetQuality {
        volume: 0.0,
        non_positive: 0,
        min_dihedral_deg: f64::INFINITY,
        max_dihedral_deg: 0.0,
    };
    for t in &mesh.tets {
        let p = t.map(|i| mesh.nodes[i as usize]);
        let v = tet_volume(p);
        q.volume += v;
        if v <= 0.0 {
            q.non_positive += 1;
        }
        for a in dihedral_angles(p) {
            q.min_dihedral_deg = q.min_dihedral_deg.min(a.to_degrees());
            q.max_dihedral_deg = q.max_dihedral_deg.max(a.to_degrees());
        }
    }
    if mesh.tets.is_empty() {
        q.min_dihedral_deg = 0.0;
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_and_corner_tets() {
        let regular = [
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
        ];
        for a in dihedral_angles(regular) {
            assert!((a - (1.0f64 / 3.0).acos()).abs() < 1e-12);
        }
        let corner = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let a = dihedral_angles(corner).map(f64::to_degrees);
        // Edges at the origin: 90 degrees; the others: acos(1/sqrt(3)) = 54.7356 degrees.
        for (i, expect) in [90.0, 90.0, 90.0, 54.7356, 54.7356, 54.7356]
            .iter()
            .enumerate()
        {
            assert!((a[i] - expect).abs() < 1e-3, "{i}: {}", a[i]);
        }
    }
}
