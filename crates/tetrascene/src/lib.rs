//! Scene files for tetrasim: a TOML file with objects (meshes, placement, materials, pins,
//! velocities), colliders, solver settings and outputs ([`scene::Scene`]), staged into one
//! [`tetrasim::model::Model`] and its [`tetrasim::params::SimParams`]
//! ([`launch::stage`]). The `tetrasim` command line (`run --scene`, `render --scene`) and the
//! Python package (`Simulation.from_scene`) read scenes through here, so a scene means the
//! same everywhere. [`overrides`] holds the parameters a scene (or a command line's flags)
//! sets on top of a base.

pub mod fuzzing;
pub mod launch;
pub mod overrides;
pub mod renamed;
pub mod scene;
