//! tetrasim: volume-preserving mass-spring simulation of tetrahedral meshes.
//!
//! A tet mesh becomes a [`Model`] (rest lengths, rest volumes, masses, pinned nodes); a
//! [`Backend`] advances its [`State`] (node positions and velocities) frame by frame under
//! gravity, springs, implicit distance or volume constraints and a frictional floor
//! `y = 0`. Three backends implement the same trait: `cpu-ref` (f64, the reference),
//! `cpu` (f32, multi-threaded) and `vulkan` (compute shaders), all under [`backend`].
//! Everything in SI units.
//!
//! This crate is the engine alone: no command line, plots or image files (the `tetrasim`
//! binary, package `tetrasim-cli`, sits on top of it), and no TetGen unless a binary turns
//! on `tetmesh/tetgen`. Features: `render` (the offscreen renderer, PNG and GIF) and `clap`
//! (`clap::ValueEnum` on the parameter enums).
//!
//! # Quick start
//!
//! Everything an embedding program needs is in the [`prelude`]. Your loop owns time: step a
//! frame, read the state back, do what you like with it.
//!
//! ```
//! use tetrasim::prelude::*;
//!
//! fn main() -> tetrasim::Result<()> {
//!     // A 0.3 m cube of 3 x 3 x 3 cells (or `load_mesh(Path::new("meshes/sphere"), None)`).
//!     let mesh = tetrasim::mesh::grid::box_tets(DVec3::ZERO, 0.1, [3, 3, 3]);
//!     // Put its lowest node 5 cm above the floor, keep its size, 1 kg per node.
//!     let model = ModelBuilder::new(&mesh)
//!         .placement(Placement { fit_size: None, drop_height: Some(0.05) })
//!         .mass(MassMode::PerNode { mass: 1.0 })
//!         .build()?;
//!     let params = SimParams::default(); // method `volume`, dt 1 ms, Gauss-Seidel
//!     let mut backend = create_backend("cpu", &model, &params)?;
//!     for _frame in 0..200 {
//!         backend.step_frame()?;
//!         let state: State = backend.state()?; // positions [m], velocities [m/s]
//!         let lowest = state.positions.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
//!         assert!(lowest > -1e-3, "the floor holds");
//!     }
//!     let volume = backend.volume()?.volume / model.total_rest_volume();
//!     assert!((volume - 1.0).abs() < 0.01, "volume ratio {volume}");
//!     Ok(())
//! }
//! ```
//!
//! Runnable programs: `cargo run --release -p tetrasim --example drop` (a body falls and comes to
//! rest; every frame reads the positions back) and `cargo run --release --example pull`
//! (one end of a bar pinned, the other dragged by the program through
//! [`Backend::set_state`]). Both take the backend name as their first argument.
//!
//! # One time step
//!
//! A frame is `substeps` time steps of length `dt` ([`SimParams`]); every backend runs the
//! same step (`docs/PHYSICS.md`, "One time step"; the code is `backend::cpu::ReferenceBackend`):
//!
//! ```text
//!  x(t), v(t)
//!    |
//!    v
//!  1. forces      F = m g + springs (ks, kd)
//!    |
//!    v
//!  2. constraints `iterations` times (methods distance, volume; none for mss, mss-node):
//!    |              for each group (Jacobi, Chebyshev: one group; Gauss-Seidel: colour groups)
//!    |                every constraint reads x, v, F -> lambda -> F += omega * sum(-lambda grad C)
//!    |                floor contact re-solved against F
//!    |              global volume constraint per object (default with Gauss-Seidel), floor
//!    v
//!  3. floor       smallest normal force n >= 0 with y(t + dt) >= 0, part of F
//!    |
//!    v
//!  4. integrate   v' = v + dt w F (contact: friction on tangential v), x' = x + dt v'
//!    |            (w = 1/m; w = 0 pins a node: it keeps its velocity, usually zero)
//!    v
//!  x(t + dt), v(t + dt)
//! ```
//!
//! # Modules
//!
//! | Module | What for |
//! |---|---|
//! | [`prelude`] | `use tetrasim::prelude::*;` brings everything below that a loop needs |
//! | [`backend`] | [`Backend`] (step, read and write the state, volume), [`State`], [`VolumeSample`]; the three backends: [`backend::cpu`] (`cpu-ref`, `cpu`) and [`backend::vulkan`] (`vulkan`, `EngineOptions` picks the GPU) |
//! | [`sim`] | [`create_backend`] by name, [`load_mesh`] (files and the bundled meshes), [`sim::build_model`], the frame driver [`sim::Simulation`] |
//! | [`model`] | [`ModelBuilder`] (placement, masses, pinned nodes, initial velocity) and [`Model`] |
//! | [`params`] | [`SimParams`] and its enums: [`Method`], [`Solver`], [`MassMode`], [`Placement`] |
//! | [`mesh`] | [`TetMesh`], [`SurfaceMesh`], readers and writers (`mesh::io`), generators (`mesh::grid`) |
//! | [`error`] | [`Error`], [`Result`] |
//! | [`metrics`] | volume percentages and the run record |
//! | [`stability`] | the stable-step estimate and the divergence speed limit |
//! | [`prep`] | surface file to tet mesh (the voxel mesher; TetGen where a binary turned it on) |
//! | `render` | the offscreen renderer (feature `render`) |
//!
//! [`gpu`] (Vulkan plumbing) and [`physics`] (the per-constraint formulas) are public for the
//! renderer, the command line and the tests; they are hidden from these docs and may change
//! without notice.

/// The types and functions an embedding program needs: `use tetrasim::prelude::*;`.
pub mod prelude {
    pub use crate::backend::{Backend, Divergence, State, VolumeSample};
    pub use crate::error::{Error, Result};
    pub use crate::mesh::io::read_tet_mesh;
    pub use crate::mesh::{SurfaceMesh, TetMesh};
    pub use crate::model::{Model, ModelBuilder};
    pub use crate::params::{MassMode, Method, Placement, SimParams, Solver};
    pub use crate::sim::{build_model, create_backend, load_mesh, LoadedMesh, BACKENDS};
    pub use glam::DVec3;
    pub use std::path::Path;
}

/// The vector library of positions and velocities ([`glam::DVec3`]), re-exported so that a
/// program uses the same version.
pub use glam;

pub mod backend;
pub mod collider;
pub mod contact;
pub mod error;
#[doc(hidden)]
pub mod gpu;
pub mod metrics;
pub mod model;
pub mod output;
pub mod params;
#[doc(hidden)]
pub mod physics;
pub mod problem;
#[cfg(feature = "render")]
pub mod render;
pub mod schedule;
pub mod sim;
pub mod stability;

pub use backend::{Backend, State, VolumeSample};
pub use error::{Error, Result};
pub use model::{Model, ModelBuilder};
pub use params::{MassMode, Method, Placement, SimParams, Solver};
pub use sim::{create_backend, load_mesh};
/// The signed tet volume and the precision traits of the physics (the `tetmesh` crate).
pub use tetmesh::geometry;
/// Mesh types, readers/writers, repair, voxel mesher, simplification (the `tetmesh` crate).
pub use tetmesh::mesh;
/// The preprocessing pipeline shared with `tetprep` (the `tetmesh` crate).
pub use tetmesh::prep;
pub use tetmesh::{SurfaceMesh, TetMesh};

/// SPIR-V of every shader under `glsl/`, compiled by `build.rs`.
#[doc(hidden)]
pub mod shaders {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}
