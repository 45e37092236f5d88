//! tetrasim: volume-preserving mass-spring simulation of tetrahedral meshes.
//!
//! A tet mesh becomes a [`Model`] (rest lengths, rest volumes, masses, pinned nodes); a
//! [`Backend`] advances its [`State`] (node positions and velocities) frame by frame under
//! gravity, springs, implicit distance or volume constraints and a frictional floor
//! `y = 0`. Three backends implement the same trait: `cpu-ref` (f64, the reference),
//! `cpu` (f32, multi-threaded) and `vulkan` (compute shaders). Everything in SI units.
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
//! Runnable programs: `cargo run --release --example drop` (a body falls and comes to
//! rest; every frame reads the positions back) and `cargo run --release --example pull`
//! (one end of a bar pinned, the other dragged by the program through
//! [`Backend::set_state`]). Both take the backend name as their first argument.
//!
//! # One time step
//!
//! A frame is `substeps` time steps of length `dt` ([`SimParams`]); every backend runs the
//! same step (`docs/PHYSICS.md`, "One time step"; the code is `cpu::ReferenceBackend`):
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
//! The stable API, for programs that embed the engine:
//!
//! | Module | What for |
//! |---|---|
//! | [`prelude`] | `use tetrasim::prelude::*;` brings everything below that a loop needs |
//! | [`backend`] | [`Backend`] (step, read and write the state, volume), [`State`], [`VolumeSample`] |
//! | [`model`] | [`ModelBuilder`] (placement, masses, pinned nodes, initial velocity) and [`Model`] |
//! | [`params`] | [`SimParams`] and its enums: [`Method`], [`Solver`], [`MassMode`], [`Placement`] |
//! | [`mesh`] | [`TetMesh`], [`SurfaceMesh`], readers and writers (`mesh::io`), generators (`mesh::grid`) |
//! | [`runner`] | [`create_backend`] by name, [`load_mesh`] (files and the bundled meshes), the CLI's frame loop `runner::run` |
//! | [`error`] | [`Error`], [`Result`] |
//! | [`cpu`], [`engine`] | the concrete backends, for their extra methods (`engine::EngineOptions` picks the GPU) |
//! | [`metrics`] | volume percentages and the run record `runner::run` returns |
//! | [`prep`] | surface file to tet mesh (TetGen or the voxel mesher) |
//!
//! The other modules are public only for the `tetrasim` binary, the benchmarks and the
//! tests (command line, scene files, presets, rendering, stability maps, benchmark tables,
//! Vulkan plumbing, the per-constraint formulas); they are hidden from these docs and may
//! change without notice.

/// The types and functions an embedding program needs: `use tetrasim::prelude::*;`.
pub mod prelude {
    pub use crate::backend::{Backend, Divergence, State, VolumeSample};
    pub use crate::error::{Error, Result};
    pub use crate::mesh::io::read_tet_mesh;
    pub use crate::mesh::{SurfaceMesh, TetMesh};
    pub use crate::model::{Model, ModelBuilder};
    pub use crate::params::{MassMode, Method, Placement, SimParams, Solver};
    pub use crate::runner::{build_model, create_backend, load_mesh, LoadedMesh, BACKENDS};
    pub use glam::DVec3;
    pub use std::path::Path;
}

/// The vector library of positions and velocities ([`glam::DVec3`]), re-exported so that a
/// program uses the same version.
pub use glam;

pub mod backend;
#[doc(hidden)]
pub mod bench;
#[doc(hidden)]
pub mod cli;
pub mod cpu;
pub mod engine;
pub mod error;
#[doc(hidden)]
pub mod gpu;
#[doc(hidden)]
pub mod launch;
pub mod metrics;
pub mod model;
pub mod params;
#[doc(hidden)]
pub mod physics;
#[doc(hidden)]
pub mod preset;
#[doc(hidden)]
pub mod render;
pub mod runner;
#[doc(hidden)]
pub mod scene;
#[doc(hidden)]
pub mod stability;

pub use backend::{Backend, State, VolumeSample};
pub use error::{Error, Result};
pub use model::{Model, ModelBuilder};
pub use params::{MassMode, Method, Placement, SimParams, Solver};
pub use runner::{create_backend, load_mesh};
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
