//! Meshes as the rest of the system sees them: triangle surfaces (input to the preprocessor)
//! and tetrahedral meshes (input to the simulation), plus their readers and writers.

pub mod arrays;
pub mod grid;
pub mod io;
pub mod order;
pub mod repair;
pub mod shapes;
pub mod simplify;
pub mod topology;
pub mod voxel;

use glam::DVec3;

/// What reading, repairing and meshing fail with (the crate's [`crate::Error`]).
pub use crate::error::{Error, Result};

/// A triangle surface, as read from PLY/OBJ/OFF/STL (polygons already triangulated).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Vertex positions.
    pub vertices: Vec<DVec3>,
    /// Triangles as 0-based vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

/// A tetrahedral mesh, as read from TetGen `.node/.ele/.face` files.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TetMesh {
    /// Node positions.
    pub nodes: Vec<DVec3>,
    /// Tetrahedra as 0-based node indices.
    pub tets: Vec<[u32; 4]>,
    /// Boundary triangles as 0-based node indices (may be empty; see
    /// [`topology::boundary_faces`] to derive them).
    pub faces: Vec<[u32; 3]>,
}

impl SurfaceMesh {
    /// Axis-aligned bounds `(min, max)`; `None` when there are no vertices.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        bounds_of(&self.vertices)
    }
}

impl TetMesh {
    /// Axis-aligned bounds `(min, max)`; `None` when there are no nodes.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        bounds_of(&self.nodes)
    }
}

/// Axis-aligned bounds of a point set.
pub fn bounds_of(points: &[DVec3]) -> Option<(DVec3, DVec3)> {
    let first = *points.first()?;
    Some(
        points
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
    )
}
