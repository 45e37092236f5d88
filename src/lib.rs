//! tetrasim: volume-preserving mass-spring simulation of tetrahedral meshes.
//!
//! ```text
//! surface file --tetprep--> TetMesh (.node/.ele/.face)
//!   --ModelBuilder--> Model (rest data) + State (x, v) + SimParams
//!   --Backend::step_frame--> State' --> metrics / renders / files
//! ```

pub mod backend;
pub mod bench;
pub mod cli;
pub mod cpu;
pub mod engine;
pub mod error;
pub mod gpu;
pub mod launch;
pub mod metrics;
pub mod model;
pub mod params;
pub mod physics;
pub mod preset;
pub mod render;
pub mod runner;
pub mod scene;
pub mod stability;

pub use backend::{Backend, State, VolumeSample};
pub use error::{Error, Result};
pub use model::{Model, ModelBuilder};
pub use params::{Method, SimParams};
/// Mesh types, readers/writers, repair, voxel mesher, simplification (the `tetmesh` crate).
pub use tetmesh::mesh;
/// The preprocessing pipeline shared with `tetprep` (the `tetmesh` crate).
pub use tetmesh::prep;
pub use tetmesh::{SurfaceMesh, TetMesh};

/// SPIR-V of every shader under `glsl/`, compiled by `build.rs`.
pub mod shaders {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}
