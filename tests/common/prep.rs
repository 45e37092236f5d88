//! Fixtures for the repair and meshing tests (`repair.rs`, `meshing.rs`,
//! `bad_input_meshing.rs`). Included with `#[path = "common/prep.rs"] mod prep_fixtures;`.
#![allow(dead_code)]

#[path = "skip.rs"]
mod skip;
use glam::DVec3;
use std::path::PathBuf;
use tetrasim::geometry::tet_volume;
use tetrasim::mesh::{shapes, SurfaceMesh, TetMesh};

/// The unit cube `[0, 1]^3` as 8 vertices and 12 outward triangles.
pub fn cube() -> SurfaceMesh {
    shapes::box_surface(DVec3::ZERO, DVec3::ONE, 1)
}

/// Two unit spheres (320 faces each) overlapping by a third of their diameter: one surface
/// that crosses itself along a whole ring.
pub fn overlapping_spheres() -> SurfaceMesh {
    let mut m = shapes::sphere(1.0, 2);
    let other = shapes::sphere(1.0, 2);
    let base = m.vertices.len() as u32;
    m.vertices.extend(
        other
            .vertices
            .iter()
            .map(|p| *p + DVec3::new(1.3, 0.1, 0.05)),
    );
    m.triangles
        .extend(other.triangles.iter().map(|t| t.map(|v| v + base)));
    m
}

/// Signed volumes of all tets.
pub fn tet_volumes(mesh: &TetMesh) -> Vec<f64> {
    mesh.tets
        .iter()
        .map(|t| {
            let p = t.map(|i| mesh.nodes[i as usize]);
            tet_volume(p)
        })
        .collect()
}

/// `../shared/meshes/NAME` relative to the workspace root, or `None` (with a message saying
/// so) when it is absent.
pub fn scan(name: &str) -> Option<PathBuf> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/meshes")
        .join(name);
    if path.is_file() {
        Some(path)
    } else {
        skip::skipped(&format!(
            "{} is missing (the scans live in ../shared/meshes/)",
            path.display()
        ));
        None
    }
}
