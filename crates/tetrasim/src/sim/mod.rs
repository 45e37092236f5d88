//! Running a simulation from a program: a mesh from a file or the bundled set
//! ([`load_mesh`]), its model under the parameters ([`build_model`]), a backend by name
//! ([`create_backend`]), and the one frame driver every caller steps through
//! ([`Simulation::advance`], [`Simulation::advance_frames`]).

pub mod bundled;
mod driver;
mod factory;
mod load;

pub use driver::{Advance, Progress, Series, Simulation};
mod checkpoint;
pub use checkpoint::{Checkpoint, CHECKPOINT_VERSION};
pub use factory::{create_backend, create_backend_with, BackendFactory, BACKENDS};
pub use load::{load_mesh, LoadedMesh, DEFAULT_MESH, DEFAULT_TARGET_TETS};

use crate::error::Result;
use crate::mesh::TetMesh;
use crate::model::{Model, ModelBuilder};
use crate::params::{Placement, SimParams};

/// Builds the model of `mesh` with the placement and the mass mode of `params`.
pub fn build_model(mesh: &TetMesh, params: &SimParams, placement: Placement) -> Result<Model> {
    ModelBuilder::new(mesh)
        .placement(placement)
        .mass(params.mass)
        .build()
}
