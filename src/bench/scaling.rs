//! `tetrasim scaling`: the same scene (a sphere of diameter 1 m meshed by the voxel mesher,
//! dropped per the preset) at several mesh sizes; cost per element-iteration against size for
//! each backend and method, as CSV, JSON and a log-log plot.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::accuracy::element_iterations_per_frame;
use super::plot::{write_png, LogChart, Series, SeriesKind, PLOT_SIZE};
use super::simulate::{simulate, Backends, SimulateOptions};
use super::stats::FrameTimes;
use super::tradeoff_files::write_csv;
use tetrasim::error::{Error, Result};
use tetrasim::mesh::{shapes, voxel, TetMesh};
use tetrasim::model::Model;
use tetrasim::params::{Method, Placement, SimParams};
use tetrasim::sim::build_model;

/// Default tet counts of the study.
pub const DEFAULT_SIZES: [usize; 5] = [1_000, 4_000, 16_000, 64_000, 256_000];

/// The scaling scene's mesh: a sphere of radius 0.5 m (icosahedron subdivided 4 times)
/// filled by the voxel mesher with about `target_tets` tets.
pub fn sphere_mesh(target_tets: usize) -> Result<TetMesh> {
    Ok(voxel::voxel_mesh(&shapes::sphere(0.5, 4), target_tets)?)
}

/// What to run at each size.
#[derive(Debug, Clone)]
pub struct ScalingOptions {
    /// Target tet counts.
    pub sizes: Vec<usize>,
    /// Methods.
    pub methods: Vec<Method>,
    /// Backend names.
    pub backends: Vec<String>,
    /// Warm-up and timed frames.
    pub frames: SimulateOptions,
}

/// One (size, method, backend) measurement; also one CSV row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScalingRecord {
    /// Requested tets.
    pub target_tets: usize,
    /// Tets of the generated mesh.
    pub tets: usize,
    /// Nodes.
    pub nodes: usize,
    /// Springs.
    pub springs: usize,
    /// Method.
    pub method: String,
    /// Backend.
    pub backend: String,
    /// Median timed frame [ms].
    pub ms_per_frame: f64,
    /// 10th percentile [ms].
    pub ms_p10: f64,
    /// 90th percentile [ms].
    pub ms_p90: f64,
    /// Element-iterations per frame.
    pub element_iterations_per_frame: f64,
    /// Median frame time per element-iteration [ns].
    pub ns_per_element_iteration: f64,
    /// Element-iterations per second at the median frame time.
    pub element_iterations_per_s: f64,
    /// Smallest volume percentage (a sanity check that the run did not blow up).
    pub min_volume_pct: f64,
    /// The run went non-finite.
    pub diverged: bool,
}

/// Runs every size x method x backend. `progress` gets each record as it finishes.
pub fn run_scaling(
    base: &SimParams,
    placement: Placement,
    options: &ScalingOptions,
    backends: &mut Backends,
    progress: &mut dyn FnMut(&ScalingRecord),
) -> Result<Vec<ScalingRecord>> {
    if options.sizes.is_empty() || options.frames.frames == 0 {
        return Err(Error::param(
            "sizes/frames",
            "need at least one size and one timed frame",
        ));
    }
    let mut records = Vec::new();
    for &target in &options.sizes {
        let mesh = sphere_mesh(target)?;
        let model: Model = build_model(&mesh, base, placement)?;
        for &method in &options.methods {
            let params = SimParams {
                method,
                ..base.clone()
            };
            for backend in &options.backends {
                let mut solver = backends.create(backend, &model, &params)?;
                let sim = simulate(solver.as_mut(), &model, &params, &options.frames)?;
                drop(solver);
                let times = FrameTimes::of(&sim.frame_ms);
                let work = element_iterations_per_frame(&model, &params);
                let r = ScalingRecord {
                    target_tets: target,
                    tets: model.tets.len(),
                    nodes: model.node_count(),
                    springs: model.springs.len(),
                    method: method.name().to_string(),
                    backend: sim.backend.clone(),
                    ms_per_frame: times.median,
                    ms_p10: times.p10,
                    ms_p90: times.p90,
                    element_iterations_per_frame: work,
                    ns_per_element_iteration: 1e6 * times.median / work.max(1.0),
                    element_iterations_per_s: work * times.fps(),
                    min_volume_pct: sim.volume_pct.iter().copied().fold(f64::INFINITY, f64::min),
                    diverged: sim.divergence.is_some(),
                };
                progress(&r);
                records.push(r);
            }
        }
    }
    Ok(records)
}

/// The plot: ns per element-iteration against tets, one line per backend and method.
pub fn chart(records: &[ScalingRecord]) -> LogChart {
    let mut keys: Vec<(String, String)> = Vec::new();
    for r in records {
        let key = (r.backend.clone(), r.method.clone());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    let series = keys
        .iter()
        .map(|(backend, method)| {
            let mut points: Vec<(f64, f64)> = records
                .iter()
                .filter(|r| &r.backend == backend && &r.method == method && !r.diverged)
                .map(|r| (r.tets as f64, r.ns_per_element_iteration))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Series {
                label: format!("{backend} {method}"),
                points,
                kind: SeriesKind::Line,
            }
        })
        .collect();
    LogChart {
        title: "cost per element-iteration vs mesh size".into(),
        x_label: "tets".into(),
        y_label: "ns per element-iteration (median frame)".into(),
        series,
    }
}

/// Files written by [`write_outputs`].
pub const OUTPUT_FILES: [&str; 3] = ["scaling.csv", "scaling.json", "scaling.png"];

/// Writes CSV, JSON and the plot into `dir` (created if missing); returns the paths.
pub fn write_outputs(dir: &Path, records: &[ScalingRecord]) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let paths: Vec<PathBuf> = OUTPUT_FILES.iter().map(|f| dir.join(f)).collect();
    write_csv(&paths[0], records)?;
    let json = serde_json::to_string_pretty(records)
        .map_err(|e| Error::param("json", format!("cannot serialise the records: {e}")))?;
    crate::runner::write_atomically(&paths[1], json.as_bytes())?;
    write_png(&paths[2], &chart(records), PLOT_SIZE)?;
    Ok(paths)
}
