//! One error type for the library, with enough context to say what went wrong and where.

use std::path::PathBuf;

/// Everything the library can fail with. Each variant names the place (file and line,
/// element index, Vulkan call) so that a message can be acted upon.
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
    /// A parameter or scene value is out of range; `key` names it.
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
    /// A Vulkan call failed.
    #[error("Vulkan: {call} failed: {result}")]
    Vulkan {
        /// The Vulkan function.
        call: &'static str,
        /// The code it returned.
        result: ash::vk::Result,
    },
    /// The GPU setup is unusable (no device, missing feature, loader not found ...).
    #[error("GPU: {0}")]
    Gpu(String),
    /// A problem needs more memory than the device (or the machine) offers: said before
    /// anything is allocated, with both sizes.
    #[error("not enough memory: {0}")]
    Memory(String),
    /// The simulation became non-finite or unbounded.
    #[error("{0}")]
    Diverged(Box<Divergence>),
}

/// Result with the library's [`Error`].
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

/// Mesh and preprocessing errors (the `tetmesh` crate) become the variant of the same name,
/// with the same message.
impl From<tetmesh::Error> for Error {
    fn from(e: tetmesh::Error) -> Self {
        match e {
            tetmesh::Error::Io { path, cause } => Error::Io { path, cause },
            tetmesh::Error::Parse {
                path,
                line,
                message,
            } => Error::Parse {
                path,
                line,
                message,
            },
            tetmesh::Error::Mesh(m) => Error::Mesh(m),
            tetmesh::Error::Param { key, message } => Error::Param { key, message },
            tetmesh::Error::Meshing(m) => Error::Meshing(m),
        }
    }
}

/// Turns an `ash` result into ours, naming the call.
pub trait VkContext<T> {
    /// The value, or [`Error::Vulkan`] naming `call`.
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, ash::vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}

/// Where and why a run diverged.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Divergence {
    /// Frame (0-based) in which it was detected.
    pub frame: u32,
    /// Substep within that frame, when known.
    pub substep: Option<u32>,
    /// Method that was running.
    pub method: String,
    /// First node with a non-finite or out-of-bound value.
    pub node: Option<u32>,
    /// Human-readable cause and advice.
    pub cause: String,
}

impl std::fmt::Display for Divergence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "diverged at frame {}", self.frame)?;
        if let Some(s) = self.substep {
            write!(f, ", substep {s}")?;
        }
        write!(f, " (method {})", self.method)?;
        if let Some(n) = self.node {
            write!(f, ", first bad node {n}")?;
        }
        write!(f, ": {}", self.cause)
    }
}
