//! The `tetrasim` command line on top of the engine library ([`tetrasim`]): the subcommands
//! ([`cli`]), the frame loop with progress and mesh files ([`runner`]), scene files
//! ([`scene`], staged into models by [`launch`]), the flags and scene keys that override
//! parameters ([`overrides`]), presets ([`preset`]), benchmarks, trade-off, scaling and
//! stability studies with their tables and plots ([`bench`]), and the render command's
//! frame loop ([`render_session`]).
//!
//! A library so that the test suite (`tests/`) can reach the same code the binary runs; it
//! is not an API for embedding. Programs that embed the engine depend on `tetrasim` alone.

pub mod bench;
pub mod cli;
pub mod preset;
pub mod render_session;
pub mod runner;

/// Scene files, their staging and the parameter overrides: the `tetrascene` crate (shared
/// with the Python package), under the names the command line has always used.
pub use tetrascene::{launch, overrides, renamed, scene};
