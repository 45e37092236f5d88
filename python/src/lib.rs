//! `tetrasim._tetrasim`: the engine for Python (PyO3). Meshes and simulations with numpy
//! arrays in and out; the Python layer (`python/tetrasim/`) adds keyword parameters,
//! meshio conversion and sweeps. Every engine error becomes a Python exception with the
//! engine's message: `ValueError` for parameters and mesh content, `OSError` (or its
//! `FileNotFoundError`) for files, `DivergedError` (a `RuntimeError`) when a run diverges,
//! `RuntimeError` for the GPU and meshing.

mod arrays;
mod mesh;
mod series;
mod simulation;

use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyMemoryError, PyOSError, PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;

create_exception!(
    tetrasim,
    DivergedError,
    PyRuntimeError,
    "The simulation became non-finite or faster than its speed limit; the message says where and the likely cause."
);

/// The Python exception for an engine error.
pub(crate) fn to_py(error: tetrasim::Error) -> PyErr {
    use tetrasim::Error;
    let message = error.to_string();
    match error {
        Error::Io { cause, .. } if cause.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(message)
        }
        Error::Io { .. } => PyOSError::new_err(message),
        Error::Parse { .. } | Error::Mesh(_) | Error::Param { .. } => {
            PyValueError::new_err(message)
        }
        Error::Diverged(_) => DivergedError::new_err(message),
        Error::Memory(_) => PyMemoryError::new_err(message),
        _ => PyRuntimeError::new_err(message),
    }
}

/// The Python exception for a mesh library error.
pub(crate) fn mesh_error(error: tetmesh::Error) -> PyErr {
    to_py(tetrasim::Error::from(error))
}

/// The tables of the scene text `text` as JSON, once it is valid (a `ValueError` names
/// the key that is wrong).
#[pyfunction]
fn scene_json(text: &str) -> PyResult<String> {
    tetrascene::scene::scene_json(text).map_err(to_py)
}

/// The scene file (TOML) of the tables `json`, once they make a valid scene.
#[pyfunction]
fn scene_toml(json: &str) -> PyResult<String> {
    tetrascene::scene::scene_toml(json).map_err(to_py)
}

/// The extension module.
#[pymodule]
fn _tetrasim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<mesh::Mesh>()?;
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<series::Series>()?;
    m.add_function(wrap_pyfunction!(mesh::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::prep, m)?)?;
    m.add_function(wrap_pyfunction!(simulation::default_params, m)?)?;
    m.add_function(wrap_pyfunction!(simulation::material_method, m)?)?;
    m.add_function(wrap_pyfunction!(simulation::accuracy_params, m)?)?;
    m.add_function(wrap_pyfunction!(scene_json, m)?)?;
    m.add_function(wrap_pyfunction!(scene_toml, m)?)?;
    m.add("DivergedError", m.py().get_type::<DivergedError>())?;
    m.add("BACKENDS", tetrasim::sim::BACKENDS.to_vec())?;
    m.add("HAS_TETGEN", cfg!(feature = "tetgen"))?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
