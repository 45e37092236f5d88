//! `tetrasim.Mesh`: a tetrahedral mesh (nodes and tets as numpy arrays), read from any tet
//! format the engine reads, meshed from a surface (`prep`), or made from arrays.

use std::path::{Path, PathBuf};

use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;
use tetrasim::mesh::{io, topology, TetMesh};

use crate::arrays::{indices_from_numpy, indices_to_numpy, points_from_numpy, points_to_numpy};
use crate::{mesh_error, to_py};

/// A tetrahedral mesh: `nodes` (n, 3) float64 [the file's units, metres in the
/// simulation], `tets` (t, 4) int64 node indices, `faces` (f, 3) its boundary triangles.
#[pyclass(module = "tetrasim", name = "Mesh", frozen)]
pub struct Mesh {
    pub(crate) inner: TetMesh,
    pub(crate) label: String,
}

#[pymethods]
impl Mesh {
    /// A mesh from arrays: `nodes` (n, 3) float, `tets` (t, 4) integer node indices.
    /// Raises `ValueError` on a wrong shape, an index out of range or an empty mesh.
    #[new]
    #[pyo3(signature = (nodes, tets, label = None))]
    fn new(
        nodes: PyReadonlyArray2<'_, f64>,
        tets: PyReadonlyArray2<'_, i64>,
        label: Option<String>,
    ) -> PyResult<Self> {
        let nodes = points_from_numpy(&nodes, "nodes", None)?;
        let tets = indices_from_numpy::<4>(&tets, "tets", nodes.len())?;
        let inner = TetMesh {
            nodes,
            tets,
            faces: Vec::new(),
        };
        io::check_tet_mesh(&inner).map_err(mesh_error)?;
        Ok(Mesh {
            inner,
            label: label.unwrap_or_else(|| "arrays".to_string()),
        })
    }

    /// Node positions, (n, 3) float64 (a copy).
    #[getter]
    fn nodes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        points_to_numpy(py, &self.inner.nodes)
    }

    /// Tetrahedra, (t, 4) int64 node indices (a copy).
    #[getter]
    fn tets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        indices_to_numpy(py, &self.inner.tets)
    }

    /// Boundary triangles, (f, 3) int64 node indices, outward (the file's, or derived).
    #[getter]
    fn faces<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<i64>> {
        indices_to_numpy(py, &self.boundary())
    }

    /// Where the mesh came from (a path, a bundled name, or `arrays`).
    #[getter]
    fn label(&self) -> &str {
        &self.label
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh('{}', {} nodes, {} tets)",
            self.label,
            self.inner.nodes.len(),
            self.inner.tets.len()
        )
    }

    /// Writes the mesh to `path`, the format from its extension: a tet mesh as `.vtk`,
    /// `.vtu` or TetGen `.node` (+ `.ele`, `.face`), or its boundary surface as `.ply`,
    /// `.obj`, `.off` or `.stl`. Raises `ValueError` for another extension, `OSError` when
    /// the file cannot be written (nothing half-written is left).
    fn write(&self, path: PathBuf) -> PyResult<()> {
        write_mesh(&path, &self.inner, &self.boundary())
    }
}

impl Mesh {
    fn boundary(&self) -> Vec<[u32; 3]> {
        match self.inner.faces.is_empty() {
            true => topology::boundary_faces(&self.inner.tets),
            false => self.inner.faces.clone(),
        }
    }
}

/// Writes `mesh` (its boundary `faces`) to `path` by extension (see [`Mesh::write`]).
pub fn write_mesh(path: &Path, mesh: &TetMesh, faces: &[[u32; 3]]) -> PyResult<()> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let result = match extension.as_deref() {
        Some("vtk") => io::write_vtk_fields(path, mesh, &io::Fields::default()),
        Some("vtu") => io::write_vtu(path, mesh, &io::Fields::default()),
        Some("node") => io::tetgen::write_tetgen(path.with_extension(""), mesh),
        Some("ply" | "obj" | "off" | "stl") => {
            io::write_surface(path, &tetrasim::output::surface_of(&mesh.nodes, faces).0)
        }
        _ => {
            return Err(PyValueError::new_err(format!(
                "{}: unknown mesh format; give .vtk, .vtu, .node (tet mesh) or .ply, .obj, .off, .stl (surface)",
                path.display()
            )))
        }
    };
    result.map_err(mesh_error)
}

/// Reads a tet mesh: TetGen (`prefix` or `prefix.node`), `.vtk`, `.vtu`, `.msh`, `.mesh`,
/// one of the bundled meshes (`meshes/sphere`, `meshes/box`, `meshes/torus`) from any
/// folder, or a surface (`.ply`, `.obj`, `.off`, `.stl`) meshed in-process aiming at
/// `target_tets` tets. Raises `FileNotFoundError`, `OSError` or `ValueError` (bad content).
#[pyfunction]
#[pyo3(signature = (path, target_tets = None))]
pub fn read_mesh(py: Python<'_>, path: PathBuf, target_tets: Option<usize>) -> PyResult<Mesh> {
    let loaded = py.allow_threads(|| tetrasim::sim::load_mesh(&path, target_tets));
    match loaded {
        Ok(loaded) => Ok(Mesh {
            label: loaded.label,
            inner: loaded.mesh,
        }),
        Err(e) if !path.exists() && !path.with_extension("node").exists() => {
            Err(PyFileNotFoundError::new_err(e.to_string()))
        }
        Err(e) => Err(to_py(e)),
    }
}

/// Meshes a closed surface file (`.ply`, `.obj`, `.off`, `.stl`) into tets as `tetprep`
/// does: repair, then TetGen aiming at `target_tets` tets (default: TetGen's quality bound
/// alone), or the voxel mesher with `mesher="voxel"`. Raises `FileNotFoundError`,
/// `ValueError` (bad surface or options) or `RuntimeError` (the mesher failed).
#[pyfunction]
#[pyo3(signature = (surface, target_tets = None, mesher = "tetgen", quality = Some(2.0)))]
pub fn prep(
    py: Python<'_>,
    surface: PathBuf,
    target_tets: Option<usize>,
    mesher: &str,
    quality: Option<f64>,
) -> PyResult<Mesh> {
    use tetrasim::prep::{prep_file, Mesher, PrepOptions};
    let mesher = match mesher {
        "tetgen" => Mesher::Tetgen,
        "voxel" => Mesher::Voxel,
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown mesher `{other}`; give \"tetgen\" or \"voxel\""
            )))
        }
    };
    if !surface.exists() {
        return Err(PyFileNotFoundError::new_err(format!(
            "{}: the file does not exist",
            surface.display()
        )));
    }
    let options = PrepOptions {
        target_tets,
        quality,
        mesher,
        ..PrepOptions::default()
    };
    let out = py
        .allow_threads(|| prep_file(&surface, &options, &mut |_| {}))
        .map_err(mesh_error)?;
    Ok(Mesh {
        inner: out.mesh,
        label: surface.display().to_string(),
    })
}
