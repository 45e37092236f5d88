//! Headless benchmarks and the measured speed-versus-accuracy trade (issue 5).
//!
//! - [`simulate`]: the measured frame loop (warm-up, per-frame wall times, GPU pass times,
//!   position samples) and [`Backends`], which shares one Vulkan context between backends;
//! - [`accuracy`]: volume % and position error against a converged reference run;
//! - [`suite`]: `tetrasim bench` (mesh x method x backend);
//! - [`tradeoff`], [`report`] and [`tradeoff_files`]: `tetrasim tradeoff` (sweep, Pareto
//!   front, answers, files);
//! - [`cantilever`]: the trade on physics, a cantilever's field against scikit-fem's;
//! - [`scaling`]: `tetrasim scaling` (cost per element against mesh size);
//! - [`plot`]: log-log PNG charts; [`pareto`], [`stats`]: small helpers.
//!
//! Timings are wall-clock times of `step_frame` (submit and wait on the GPU); on lavapipe
//! they are CPU timings of the Vulkan path.

pub mod accuracy;
pub mod cantilever;
pub mod pareto;
pub mod plot;
pub mod report;
pub mod scaling;
pub mod simulate;
pub mod solver_setting;
pub mod stability_map;
pub mod stats;
pub mod suite;
pub mod tradeoff;
pub mod tradeoff_files;

pub use accuracy::{Accuracy, PositionError, Reference, ReferenceSettings, VolumeStats};
pub use simulate::{simulate, Backends, Measured, Sample, SimulateOptions};
pub use suite::{run_suite, BenchMesh, BenchOptions, BenchRecord};
pub use tradeoff::{run_tradeoff, SweepSpec, TradeoffOptions, TradeoffRecord};

/// The bundled meshes `tetrasim bench` runs by default (TetGen prefixes under the
/// repository's `meshes/`).
pub const BUNDLED_MESHES: [&str; 3] = ["meshes/sphere", "meshes/box", "meshes/torus"];
