//! Files written during a run: the deformed surface (PLY) or the whole tet mesh (legacy VTK,
//! with each tet's volume ratio `V / V0` as a cell field) every few frames, for ParaView or
//! MeshLab. Writing goes through the mesh writers of [`crate::mesh::io`].

use std::path::{Path, PathBuf};

use glam::DVec3;

use crate::error::{Error, Result};
use crate::mesh::{io, tet_signed_volume, SurfaceMesh, TetMesh};
use crate::model::Model;
use crate::params::Method;

/// What to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OutputFormat {
    /// The boundary surface as binary PLY: `DIR/METHOD_FRAME.ply`.
    #[default]
    Ply,
    /// The tet mesh as legacy VTK with the cell field `volume_ratio`: `DIR/METHOD_FRAME.vtk`.
    Vtk,
}

/// Periodic output of the deformed mesh.
#[derive(Debug, Clone)]
pub struct SurfaceOutput {
    /// Folder to write into (created if missing).
    pub dir: PathBuf,
    /// Write every this many frames (and the initial state, as frame 0); at least 1.
    pub every: u32,
    /// File format.
    pub format: OutputFormat,
}

impl SurfaceOutput {
    /// Checks `every` and creates the folder.
    pub fn new(dir: impl Into<PathBuf>, every: u32, format: OutputFormat) -> Result<Self> {
        if every == 0 {
            return Err(Error::param("every", "must be at least 1"));
        }
        let dir = dir.into();
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
        Ok(SurfaceOutput { dir, every, format })
    }

    /// The file of `method` at `frame`.
    pub fn path(&self, method: Method, frame: u32) -> PathBuf {
        let ext = match self.format {
            OutputFormat::Ply => "ply",
            OutputFormat::Vtk => "vtk",
        };
        self.dir.join(format!("{}_{frame:05}.{ext}", method.name()))
    }

    /// Writes the mesh of `model` at `positions` for `method` at `frame`.
    pub fn write(
        &self,
        model: &Model,
        method: Method,
        frame: u32,
        positions: &[DVec3],
    ) -> Result<()> {
        let path = self.path(method, frame);
        match self.format {
            OutputFormat::Ply => io::write_surface(&path, &deformed_surface(model, positions)),
            OutputFormat::Vtk => {
                let ratio: Vec<f64> = model
                    .tets
                    .iter()
                    .zip(&model.rest_volume)
                    .map(|(t, v0)| {
                        let p = t.map(|i| positions[i as usize]);
                        tet_signed_volume(p[0], p[1], p[2], p[3]) / v0
                    })
                    .collect();
                let mesh = TetMesh {
                    nodes: positions.to_vec(),
                    tets: model.tets.clone(),
                    faces: Vec::new(),
                };
                io::write_vtk(&path, &mesh, Some(("volume_ratio", &ratio)))
            }
        }
    }
}

/// The model's boundary surface at `positions`, with only the nodes it uses.
pub fn deformed_surface(model: &Model, positions: &[DVec3]) -> SurfaceMesh {
    let mut index = vec![u32::MAX; positions.len()];
    let mut vertices = Vec::new();
    let triangles = model
        .surface
        .iter()
        .map(|f| {
            f.map(|i| {
                let slot = &mut index[i as usize];
                if *slot == u32::MAX {
                    *slot = vertices.len() as u32;
                    vertices.push(positions[i as usize]);
                }
                *slot
            })
        })
        .collect();
    SurfaceMesh {
        vertices,
        triangles,
    }
}

/// Writes `bytes` to `path` through a temporary file and a rename.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    io::write_atomic(path, |w| w.write_all(bytes))
}
