//! The preprocessing pipeline shared by `tetprep` and `tetrasim run --mesh surface.ply`:
//! read -> scale -> repair -> (simplify) -> mesh (TetGen or voxel) -> order -> stats.
//!
//! ```no_run
//! use tetmesh::prep::{prep_file, PrepOptions};
//! let options = PrepOptions { target_tets: Some(20_000), ..Default::default() };
//! let out = prep_file("bunny.ply".as_ref(), &options, &mut |stage| eprintln!("{stage}"))?;
//! println!("{} tets, {:.2} % of the enclosed volume", out.mesh.tets.len(), out.stats.volume_percent);
//! # Ok::<(), tetmesh::Error>(())
//! ```

pub mod options;
pub mod quality;
pub mod stats;
#[cfg(feature = "tetgen")]
pub mod tetgen;

use std::path::Path;
use std::time::Instant;

pub use options::{Mesher, PrepOptions, DEFAULT_VOXEL_TETS};
pub use stats::{PrepStats, StageTime};

/// What the pipeline fails with (the crate's [`crate::Error`]).
pub use crate::error::{Error, Result};
use crate::mesh::repair::{self, RepairReport};
use crate::mesh::{io, order, voxel, SurfaceMesh, TetMesh};

/// The tet mesh and what was measured on the way.
#[derive(Debug, Clone)]
pub struct PrepOutput {
    /// Tets positively oriented, boundary faces outward.
    pub mesh: TetMesh,
    /// The surface handed to the mesher: scaled, repaired and, when the target needed it,
    /// simplified (what `tetprep --save-surface` writes). With TetGen under `-Y` (always with
    /// a target) it is also the boundary of `mesh`; without `-Y` TetGen may add points on it.
    pub surface: SurfaceMesh,
    /// Counts, quality, volumes, times, repair report, warnings.
    pub stats: PrepStats,
}

/// Records stage times.
struct Clock(Vec<StageTime>, Instant);

impl Clock {
    fn lap(&mut self, stage: &str) {
        let now = Instant::now();
        self.0.push(StageTime {
            stage: stage.to_string(),
            seconds: (now - self.1).as_secs_f64(),
        });
        self.1 = now;
    }
}

/// Reads the surface at `path` and runs [`prep_surface`] on it. `progress` receives one line
/// per stage.
pub fn prep_file(
    path: &Path,
    options: &PrepOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<PrepOutput> {
    options.validate()?;
    let start = Instant::now();
    progress(&format!("reading {}", path.display()));
    let surface = io::read_surface(path)?;
    let read_time = start.elapsed().as_secs_f64();
    let mut out = prep_surface(&surface, options, progress).map_err(|e| match e {
        Error::Mesh(m) => Error::Mesh(format!("{}: {m}", path.display())),
        Error::Meshing(m) => Error::Meshing(format!("{}: {m}", path.display())),
        other => other,
    })?;
    out.stats.input = Some(path.display().to_string());
    out.stats.times.insert(
        0,
        StageTime {
            stage: "read".into(),
            seconds: read_time,
        },
    );
    out.stats.total_seconds += read_time;
    Ok(out)
}

/// Repairs and meshes a surface (see the module doc).
pub fn prep_surface(
    surface: &SurfaceMesh,
    options: &PrepOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<PrepOutput> {
    options.validate()?;
    let mut clock = Clock(Vec::new(), Instant::now());
    let started = clock.1;
    let mut scaled = surface.clone();
    if options.scale != 1.0 {
        for p in &mut scaled.vertices {
            *p *= options.scale;
        }
    }
    progress(&format!(
        "repairing {} vertices, {} faces",
        scaled.vertices.len(),
        scaled.triangles.len()
    ));
    let (repaired, report) = repair::repair(&scaled, &options.repair)?;
    clock.lap("repair");
    let mut warnings = report.warnings.clone();
    if report.enclosed_volume <= 0.0 {
        return Err(Error::Mesh(format!(
            "the repaired surface encloses no volume ({:e}); is it a closed shell?",
            report.enclosed_volume
        )));
    }

    let mut run = MeshRun {
        mesher: options.mesher,
        fell_back: false,
        switches: None,
        runs: 0,
        surface: None,
    };
    let mesh = match options.mesher {
        Mesher::Voxel => mesh_voxel(&repaired, options, &mut run, progress)?,
        Mesher::Tetgen => match mesh_tetgen(&repaired, &report, options, &mut run, progress) {
            Ok(mesh) => mesh,
            Err(e) if options.fallback => {
                let warning =
                    format!("TetGen failed ({e}); using the voxel mesher instead (--fallback)");
                progress(&format!("warning: {warning}"));
                warnings.push(warning);
                run.fell_back = true;
                run.mesher = Mesher::Voxel;
                run.surface = None;
                mesh_voxel(&repaired, options, &mut run, progress)?
            }
            Err(e) => return Err(e),
        },
    };
    clock.lap("mesh");
    let mesh = match options.keep_order {
        true => mesh,
        false => {
            progress("ordering nodes and tets along a Morton curve");
            let mut ordered = order::spatially_ordered(&mesh);
            // The meshers' faces are the tets' boundary in its derived order; keep it so.
            ordered.faces = crate::mesh::topology::boundary_faces(&ordered.tets);
            clock.lap("order");
            ordered
        }
    };
    progress("measuring");
    let mut stats = PrepStats::measure(&mesh, &report, options.target_tets);
    clock.lap("stats");
    stats.mesher = run.mesher.name().to_string();
    stats.fell_back = run.fell_back;
    stats.tetgen_switches = run.switches;
    stats.tetgen_runs = run.runs;
    let surface = run.surface.unwrap_or(repaired);
    stats.faces_meshed = surface.triangles.len();
    stats.meshed_non_manifold_vertices =
        crate::mesh::topology::non_manifold_vertices(&surface.triangles).len();
    stats.warnings = warnings;
    stats.total_seconds = started.elapsed().as_secs_f64();
    stats.times = clock.0;
    Ok(PrepOutput {
        mesh,
        surface,
        stats,
    })
}

/// What the meshing stage did.
struct MeshRun {
    mesher: Mesher,
    fell_back: bool,
    switches: Option<String>,
    runs: usize,
    /// The surface TetGen meshed, when it differs from the repaired one (simplified).
    surface: Option<SurfaceMesh>,
}

fn mesh_voxel(
    surface: &SurfaceMesh,
    options: &PrepOptions,
    run: &mut MeshRun,
    progress: &mut dyn FnMut(&str),
) -> Result<TetMesh> {
    let target = match (options.target_tets, options.max_volume) {
        (Some(n), _) => n,
        // Six tets of volume h^3 / 6 per cell: a cell of volume 6 * max_volume.
        (None, Some(a)) => {
            let volume = repair::orient::signed_volume(&surface.vertices, &surface.triangles);
            ((volume / a).ceil() as usize).max(6)
        }
        (None, None) => DEFAULT_VOXEL_TETS,
    };
    progress(&format!("voxel mesher: about {target} tets"));
    run.runs = 1;
    voxel::voxel_mesh(surface, target)
}

#[cfg(feature = "tetgen")]
fn mesh_tetgen(
    surface: &SurfaceMesh,
    report: &RepairReport,
    options: &PrepOptions,
    run: &mut MeshRun,
    progress: &mut dyn FnMut(&str),
) -> Result<TetMesh> {
    if let Some(n) = report.self_intersections.filter(|&n| n > 0) {
        let detail = report
            .warnings
            .iter()
            .find(|w| w.contains("self-intersections"))
            .cloned()
            .unwrap_or_default();
        return Err(Error::Meshing(format!(
            "the surface intersects itself ({n} crossing face pairs; {detail}); TetGen needs faces that do not cross. \
             Use --fallback or --mesher voxel"
        )));
    }
    let result = match options.target_tets {
        Some(n) => tetgen::mesh_for_target(surface, report.enclosed_volume, n, options, progress),
        None => {
            progress(&format!("TetGen on {} faces", surface.triangles.len()));
            tetgen::mesh_plain(surface, options)
        }
    }
    .map_err(|e| match e {
        Error::Meshing(m) => Error::Meshing(format!(
            "{m}. Use --fallback to use the voxel mesher instead"
        )),
        other => other,
    })?;
    run.switches = Some(result.switches);
    run.runs = result.runs;
    run.surface = Some(result.surface);
    Ok(result.mesh)
}

#[cfg(not(feature = "tetgen"))]
fn mesh_tetgen(
    _: &SurfaceMesh,
    _: &RepairReport,
    _: &PrepOptions,
    _: &mut MeshRun,
    _: &mut dyn FnMut(&str),
) -> Result<TetMesh> {
    Err(Error::Meshing("this build has no TetGen (built without the `tetgen` feature); use --mesher voxel or rebuild with --features tetgen".into()))
}
