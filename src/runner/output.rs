//! Files written during a run: the deformed mesh every few frames, for ParaView, MeshLab or
//! any viewer that reads a mesh sequence. Writing goes through the mesh writers of
//! [`tetrasim::mesh::io`].
//!
//! | `--format` | files | content |
//! | --- | --- | --- |
//! | `ply` | `METHOD_FFFFF.ply` | boundary surface, per-vertex `quality` = V/V0 of the node |
//! | `obj` | `METHOD_FFFFF.obj` | boundary surface |
//! | `vtk` | `METHOD_FFFFF.vtk` | tet mesh with the fields below (legacy ASCII VTK) |
//! | `vtu` | `METHOD_FFFFF.vtu` + `METHOD.pvd` | tet mesh with the fields below; the `.pvd` gives each file its simulated time |
//!
//! Fields of the tet formats: point data `displacement` (from the start), `velocity`,
//! `volume_ratio` (the node's incident tets: sum of V over sum of V0) and `pinned` (1 for a
//! pinned node); cell data `volume_ratio` (V/V0 of the tet) and `inverted` (1 when V <= 0).
//!
//! [`OutputUnits::Input`] writes positions, displacements and velocities in the mesh file's
//! units and frame (undoing `fit_size` and `drop_height`), so frames overlay the scan.

use std::path::{Path, PathBuf};

use glam::DVec3;

use tetrasim::backend::State;
use tetrasim::error::{Error, Result};
use tetrasim::mesh::io::{self, Field, FieldValues, Fields};
use tetrasim::mesh::{SurfaceMesh, TetMesh};
use tetrasim::model::{Model, Similarity};
use tetrasim::params::Method;
use tetrasim::physics::tet_volume;

/// What to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OutputFormat {
    /// The boundary surface as binary PLY with a per-vertex quality (V/V0):
    /// `DIR/METHOD_FFFFF.ply`.
    #[default]
    Ply,
    /// The boundary surface as Wavefront OBJ: `DIR/METHOD_FFFFF.obj`.
    Obj,
    /// The tet mesh with point and cell fields as legacy VTK: `DIR/METHOD_FFFFF.vtk`.
    Vtk,
    /// The tet mesh with point and cell fields as VTK XML, plus a ParaView time series
    /// `DIR/METHOD.pvd`: `DIR/METHOD_FFFFF.vtu`.
    Vtu,
}

impl OutputFormat {
    /// The file extension.
    pub fn extension(self) -> &'static str {
        match self {
            OutputFormat::Ply => "ply",
            OutputFormat::Obj => "obj",
            OutputFormat::Vtk => "vtk",
            OutputFormat::Vtu => "vtu",
        }
    }
}

/// The units and frame of written positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OutputUnits {
    /// Simulation units: metres, after `fit_size` and `drop_height` (the floor is y = 0).
    #[default]
    Simulation,
    /// The mesh file's own units and position (the placement undone per object).
    Input,
}

/// Periodic output of the deformed mesh.
#[derive(Debug, Clone)]
pub struct FrameOutput {
    /// Folder to write into (created if missing).
    pub dir: PathBuf,
    /// Write every this many frames (and the initial state, as frame 0); at least 1.
    pub every: u32,
    /// File format.
    pub format: OutputFormat,
    /// Units and frame of the positions.
    pub units: OutputUnits,
}

impl FrameOutput {
    /// Checks `every` and creates the folder (with its parents).
    pub fn new(
        dir: impl Into<PathBuf>,
        every: u32,
        format: OutputFormat,
        units: OutputUnits,
    ) -> Result<Self> {
        if every == 0 {
            return Err(Error::param("every", "must be at least 1"));
        }
        let dir = dir.into();
        create_dir(&dir)?;
        Ok(FrameOutput {
            dir,
            every,
            format,
            units,
        })
    }

    /// The file name of `method` at `frame`.
    pub fn file_name(&self, method: Method, frame: u32) -> String {
        format!("{}_{frame:05}.{}", method.name(), self.format.extension())
    }

    /// The file of `method` at `frame`.
    pub fn path(&self, method: Method, frame: u32) -> PathBuf {
        self.dir.join(self.file_name(method, frame))
    }

    /// The ParaView collection of `method` (written with [`OutputFormat::Vtu`]).
    pub fn pvd_path(&self, method: Method) -> PathBuf {
        self.dir.join(format!("{}.pvd", method.name()))
    }

    /// Writes the mesh of `model` in `state` for `method` at `frame`; `frame_time` is the
    /// simulated time of one frame [s] (for the `.pvd`). With [`OutputFormat::Vtu`] the
    /// method's `.pvd` is rewritten to list every frame written so far.
    pub fn write(
        &self,
        model: &Model,
        method: Method,
        frame: u32,
        frame_time: f64,
        state: &State,
    ) -> Result<()> {
        let path = self.path(method, frame);
        let data = FrameData::new(model, state, self.units);
        match self.format {
            OutputFormat::Ply => {
                let (surface, nodes) = deformed_surface_nodes(model, &data.positions);
                let quality: Vec<f64> = nodes.iter().map(|&i| data.node_ratio[i]).collect();
                Ok(io::ply::write_with_quality(
                    &path,
                    &surface,
                    io::ply::PlyEncoding::BinaryLittleEndian,
                    &quality,
                )?)
            }
            OutputFormat::Obj => Ok(io::write_surface(
                &path,
                &deformed_surface(model, &data.positions),
            )?),
            OutputFormat::Vtk => Ok(io::write_vtk_fields(
                &path,
                &data.mesh(model),
                &data.fields(),
            )?),
            OutputFormat::Vtu => {
                io::write_vtu(&path, &data.mesh(model), &data.fields())?;
                let entries: Vec<(f64, String)> = (0..=frame)
                    .step_by(self.every as usize)
                    .map(|f| (f64::from(f) * frame_time, self.file_name(method, f)))
                    .collect();
                Ok(io::write_pvd(self.pvd_path(method), &entries)?)
            }
        }
    }
}

/// Creates `dir` and its parents, or says why it cannot (e.g. a file is in the way).
pub fn create_dir(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        return Err(Error::io(
            dir,
            std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                "exists and is not a folder",
            ),
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))
}

/// Prepares to write the file `path` later: creates its folder (with parents), or says why
/// it cannot; refuses a `path` that is a folder. Run before any work starts, so a long run
/// does not fail at its end.
pub fn prepare_output_file(path: &Path) -> Result<()> {
    if path.is_dir() {
        return Err(Error::io(
            path,
            std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                "is a folder; give a file name",
            ),
        ));
    }
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => create_dir(dir),
        _ => Ok(()),
    }
}

/// One frame's positions and derived fields, in the chosen units.
struct FrameData {
    positions: Vec<DVec3>,
    displacement: Vec<DVec3>,
    velocity: Vec<DVec3>,
    node_ratio: Vec<f64>,
    pinned: Vec<u8>,
    tet_ratio: Vec<f64>,
    inverted: Vec<u8>,
}

impl FrameData {
    fn new(model: &Model, state: &State, units: OutputUnits) -> Self {
        let tet_volume: Vec<f64> = model
            .tets
            .iter()
            .map(|t| {
                let p = t.map(|i| state.positions[i as usize]);
                tet_volume(p)
            })
            .collect();
        let n = model.node_count();
        let (mut volume, mut rest) = (vec![0.0; n], vec![0.0; n]);
        for ((t, v), v0) in model.tets.iter().zip(&tet_volume).zip(&model.rest_volume) {
            for &i in t {
                volume[i as usize] += v;
                rest[i as usize] += v0;
            }
        }
        // Nodes in no tet keep the neutral ratio 1.
        let node_ratio = volume
            .iter()
            .zip(&rest)
            .map(|(v, r)| if *r > 0.0 { v / r } else { 1.0 })
            .collect();
        let transform = node_transforms(model, units);
        let positions = (0..n)
            .map(|i| transform[i].invert_point(state.positions[i]))
            .collect();
        let displacement = (0..n)
            .map(|i| transform[i].invert_vector(state.positions[i] - model.positions[i]))
            .collect();
        let velocity = (0..n)
            .map(|i| transform[i].invert_vector(state.velocities[i]))
            .collect();
        FrameData {
            positions,
            displacement,
            velocity,
            node_ratio,
            pinned: model.inv_mass.iter().map(|&w| u8::from(w == 0.0)).collect(),
            tet_ratio: tet_volume
                .iter()
                .zip(&model.rest_volume)
                .map(|(v, v0)| v / v0)
                .collect(),
            inverted: tet_volume.iter().map(|&v| u8::from(v <= 0.0)).collect(),
        }
    }

    fn mesh(&self, model: &Model) -> TetMesh {
        TetMesh {
            nodes: self.positions.clone(),
            tets: model.tets.clone(),
            faces: Vec::new(),
        }
    }

    fn fields(&self) -> Fields<'_> {
        let field = |name, values| Field { name, values };
        Fields {
            point: vec![
                field("displacement", FieldValues::Vector(&self.displacement)),
                field("velocity", FieldValues::Vector(&self.velocity)),
                field("volume_ratio", FieldValues::Scalar(&self.node_ratio)),
                field("pinned", FieldValues::Flag(&self.pinned)),
            ],
            cell: vec![
                field("volume_ratio", FieldValues::Scalar(&self.tet_ratio)),
                field("inverted", FieldValues::Flag(&self.inverted)),
            ],
        }
    }
}

/// The map from each node's written frame to the simulation: the identity in simulation
/// units, the object's placement in the input's.
fn node_transforms(model: &Model, units: OutputUnits) -> Vec<Similarity> {
    let mut out = vec![Similarity::IDENTITY; model.node_count()];
    if units == OutputUnits::Input {
        for (k, placement) in model.placements.iter().enumerate() {
            let (lo, hi) = (model.objects[k] as usize, model.objects[k + 1] as usize);
            out[lo..hi].fill(*placement);
        }
    }
    out
}

/// The model's boundary surface at `positions`, with only the nodes it uses.
pub fn deformed_surface(model: &Model, positions: &[DVec3]) -> SurfaceMesh {
    deformed_surface_nodes(model, positions).0
}

/// [`deformed_surface`] and, for each of its vertices, the model node it is.
fn deformed_surface_nodes(model: &Model, positions: &[DVec3]) -> (SurfaceMesh, Vec<usize>) {
    let mut index = vec![u32::MAX; positions.len()];
    let mut nodes = Vec::new();
    let triangles = model
        .surface
        .iter()
        .map(|f| {
            f.map(|i| {
                let slot = &mut index[i as usize];
                if *slot == u32::MAX {
                    *slot = nodes.len() as u32;
                    nodes.push(i as usize);
                }
                *slot
            })
        })
        .collect();
    let surface = SurfaceMesh {
        vertices: nodes.iter().map(|&i| positions[i]).collect(),
        triangles,
    };
    (surface, nodes)
}

/// Writes `bytes` to `path` through a temporary file and a rename.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    Ok(io::write_atomic(path, |w| w.write_all(bytes))?)
}
