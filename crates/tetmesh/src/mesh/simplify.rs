//! Surface simplification with meshoptimizer's edge-collapse simplifier (`meshopt` crate).
//!
//! TetGen keeps every input facet, so a scan with more faces than the tet budget allows is
//! simplified first. The simplifier only picks among the existing vertices (positions stay
//! exact in `f64`; it sees them as `f32`), and unused vertices are dropped afterwards.

use meshopt::SimplifyOptions;

use super::repair::clean;
use super::SurfaceMesh;

/// Simplifies `mesh` towards `target_faces` triangles (never more than it has). The result
/// may keep more faces than asked when fewer would change the shape too much (the error bound
/// is 5 % of the mesh extent). Degenerate and duplicate faces the collapses leave are dropped.
pub fn simplify(mesh: &SurfaceMesh, target_faces: usize) -> SurfaceMesh {
    if target_faces >= mesh.triangles.len() {
        return mesh.clone();
    }
    let positions: Vec<[f32; 3]> = mesh
        .vertices
        .iter()
        .map(|p| p.as_vec3().to_array())
        .collect();
    let indices: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let kept = meshopt::simplify_decoder(
        &indices,
        &positions,
        target_faces * 3,
        0.05,
        SimplifyOptions::None,
        None,
    );
    let mut out = SurfaceMesh {
        vertices: mesh.vertices.clone(),
        triangles: kept.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    };
    clean::drop_degenerate(&mut out, 0.0);
    clean::drop_duplicates(&mut out);
    clean::drop_unreferenced(&mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::repair::orient::{edge_faces, signed_volume};
    use crate::mesh::shapes::sphere;

    #[test]
    fn sphere_keeps_closed_and_volume() {
        let s = sphere(1.0, 4); // 5120 faces
        let v0 = signed_volume(&s.vertices, &s.triangles);
        let t = simplify(&s, 1000);
        assert!(
            t.triangles.len() <= 1000 && t.triangles.len() > 800,
            "{}",
            t.triangles.len()
        );
        assert!(edge_faces(&t.triangles).values().all(|f| f.len() == 2));
        let v1 = signed_volume(&t.vertices, &t.triangles);
        assert!((v1 / v0 - 1.0).abs() < 0.03, "{v1} vs {v0}");
        assert_eq!(t.vertices.len(), t.triangles.len() / 2 + 2); // closed genus 0: V = F/2 + 2
    }
}
