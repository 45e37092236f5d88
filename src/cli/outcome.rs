//! How a command ends, for its exit status (`src/main.rs`): a bad scene file (2), a
//! diverged run (3), a run ended by SIGINT or SIGTERM (130).

/// A scene file that cannot be read, parsed, validated or staged (a bad key, value, mesh or
/// collider surface): `tetrasim` exits with status 2, as for bad flags, having written
/// nothing.
#[derive(Debug, thiserror::Error)]
#[error(transparent)]
pub struct BadScene(pub tetrasim::Error);

/// A run that diverged: `tetrasim` exits with status 3 (after writing the metrics).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct DivergedRun(pub String);

/// A run ended by SIGINT or SIGTERM: `tetrasim` exits with status 130, its record, frames
/// and checkpoint written as far as it got.
#[derive(Debug, thiserror::Error)]
#[error(
    "interrupted: {method} ended after frame {frames} of {of}; its record, frames and \
     checkpoint are written as far as it got"
)]
pub struct InterruptedRun {
    /// The method that was running.
    pub method: String,
    /// Frames it completed.
    pub frames: u32,
    /// Frames it was to run.
    pub of: u32,
}
