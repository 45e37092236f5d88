//! The errors of reading, repairing and meshing, with enough context to say what went wrong
//! and where. `tetrasim::Error` converts from this one variant by variant, with the same
//! messages.

use std::path::PathBuf;

/// Everything mesh I/O and preprocessing can fail with. Each variant names the place (file
/// and line, element index, parameter) so that a message can be acted upon.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file could not be opened, read or written.
    /// (The cause is part of the message and deliberately not a `source()`, so that a
    /// report that prints the chain, like `{:#}`, does not say it twice.)
    #[error("{path}: {cause}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        cause: std::io::Error,
    },
    /// A file was read but its content is wrong (`line` is 1-based when known).
    #[error("{path}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The 1-based line, when known.
        line: Option<usize>,
        /// What is wrong there.
        message: String,
    },
    /// A mesh is unusable (empty, bad index, degenerate element ...).
    #[error("invalid mesh: {0}")]
    Mesh(String),
    /// A parameter value is out of range; `key` names it.
    #[error("invalid parameter `{key}`: {message}")]
    Param {
        /// The parameter's name (its flag or scene key).
        key: String,
        /// What is wrong with its value.
        message: String,
    },
    /// Meshing (TetGen or the voxel mesher) failed.
    #[error("meshing failed: {0}")]
    Meshing(String),
}

/// Result with this crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            cause: source,
        }
    }
    /// A content error in `path` at `line` (1-based), if known.
    pub fn parse(
        path: impl Into<PathBuf>,
        line: Option<usize>,
        message: impl Into<String>,
    ) -> Self {
        Error::Parse {
            path: path.into(),
            line,
            message: message.into(),
        }
    }
    /// An out-of-range parameter.
    pub fn param(key: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Param {
            key: key.into(),
            message: message.into(),
        }
    }
}
