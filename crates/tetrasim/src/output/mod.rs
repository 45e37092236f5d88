//! The deformed mesh as files, for ParaView, MeshLab or any viewer that reads a mesh: what
//! `tetrasim run --format` writes every few frames and what a program writes with
//! [`write_state`]. Writing goes through the mesh writers of [`crate::mesh::io`].
//!
//! | format | content |
//! | --- | --- |
//! | `ply` | boundary surface, per-vertex `quality` = V/V0 of the node |
//! | `obj` | boundary surface |
//! | `vtk` | tet mesh with the fields below (legacy ASCII VTK) |
//! | `vtu` | tet mesh with the fields below (VTK XML) |
//! | `usd` | the run as one animated USD stage: each body's surface, its points and `volume_ratio` time-sampled ([`UsdSeries`]) |
//!
//! Fields of the tet formats: point data `displacement` (from the start), `velocity`,
//! `volume_ratio` (the node's incident tets: sum of V over sum of V0) and `pinned` (1 for a
//! pinned node); cell data `volume_ratio` (V/V0 of the tet) and `inverted` (1 when V <= 0).
//!
//! [`OutputUnits::Input`] writes positions, displacements and velocities in the mesh file's
//! units and frame (undoing `fit_size` and `drop_height`), so frames overlay the scan.

use std::path::Path;

use glam::DVec3;

use crate::backend::State;
use crate::error::{Error, Result};
use crate::mesh::io::{self, Field, FieldValues, Fields};
use crate::mesh::{SurfaceMesh, TetMesh};
use crate::model::{Model, Similarity};
use crate::physics::tet_volume;

mod usd;
pub use usd::UsdSeries;

/// What to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
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
    /// The whole run as one animated USD stage (text): each body's boundary surface with
    /// time-sampled points and volume ratio, `DIR/METHOD.usda`, written when the run ends.
    Usd,
}

impl OutputFormat {
    /// The file extension.
    pub fn extension(self) -> &'static str {
        match self {
            OutputFormat::Ply => "ply",
            OutputFormat::Obj => "obj",
            OutputFormat::Vtk => "vtk",
            OutputFormat::Vtu => "vtu",
            OutputFormat::Usd => "usda",
        }
    }
}

/// The units and frame of written positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum OutputUnits {
    /// Simulation units: metres, after `fit_size` and `drop_height` (the floor is y = 0).
    #[default]
    Simulation,
    /// The mesh file's own units and position (the placement undone per object).
    Input,
}

impl OutputFormat {
    /// The format of `path`'s extension (`ply`, `obj`, `vtk`, `vtu`, `usda`), if it is one.
    pub fn from_path(path: &Path) -> Option<Self> {
        let extension = path.extension()?.to_string_lossy().to_ascii_lowercase();
        [
            OutputFormat::Ply,
            OutputFormat::Obj,
            OutputFormat::Vtk,
            OutputFormat::Vtu,
            OutputFormat::Usd,
        ]
        .into_iter()
        .find(|f| f.extension() == extension)
    }
}

/// Writes `model` in `state` to `path` as `format`, positions in `units`.
pub fn write_frame(
    path: &Path,
    format: OutputFormat,
    units: OutputUnits,
    model: &Model,
    state: &State,
) -> Result<()> {
    let data = FrameData::new(model, state, units);
    match format {
        OutputFormat::Ply => {
            let (surface, nodes) = surface_of(&data.positions, &model.surface);
            let quality: Vec<f64> = nodes.iter().map(|&i| data.node_ratio[i]).collect();
            Ok(io::ply::write_with_quality(
                path,
                &surface,
                io::ply::PlyEncoding::BinaryLittleEndian,
                &quality,
            )?)
        }
        OutputFormat::Obj => Ok(io::write_surface(
            path,
            &deformed_surface(model, &data.positions),
        )?),
        OutputFormat::Vtk => Ok(io::write_vtk_fields(
            path,
            &data.mesh(model),
            &data.fields(),
        )?),
        OutputFormat::Vtu => Ok(io::write_vtu(path, &data.mesh(model), &data.fields())?),
        OutputFormat::Usd => {
            // One frame: a stage of one time sample (at time code 0).
            let mut stage = UsdSeries::new(model, 1.0, "tetrasim: one state");
            stage.add(0, model, state);
            stage.write(path)
        }
    }
}

/// Writes `model` in `state` to `path` in simulation units, the format from the extension
/// (`.ply`, `.obj`, `.vtk`, `.vtu`; another is an error that lists them).
pub fn write_state(path: &Path, model: &Model, state: &State) -> Result<()> {
    let format = OutputFormat::from_path(path).ok_or_else(|| {
        Error::param(
            "path",
            format!(
                "{}: unknown output format; give .ply, .obj, .vtk, .vtu or .usda",
                path.display()
            ),
        )
    })?;
    write_frame(path, format, OutputUnits::Simulation, model, state)
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
    surface_of(positions, &model.surface).0
}

/// The surface of the triangles `faces` (node indices) at `positions`, with only the nodes
/// it uses, and for each of its vertices the node it is.
pub fn surface_of(positions: &[DVec3], faces: &[[u32; 3]]) -> (SurfaceMesh, Vec<usize>) {
    let mut index = vec![u32::MAX; positions.len()];
    let mut nodes = Vec::new();
    let triangles = faces
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
