//! `tetrasim bench`: every mesh x method x backend, warm-up then timed frames; frame-time
//! percentiles, throughput, GPU pass times and accuracy in one [`BenchRecord`] each.

use std::fmt::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::accuracy::{accuracy, element_iterations_per_frame, Reference, ReferenceSettings};
use super::simulate::{simulate, Backends, Measured, SimulateOptions};
use super::stats::FrameTimes;
use tetrasim::error::{Error, Result};
use tetrasim::gpu::PassTime;
use tetrasim::metrics::RunRecord;
use tetrasim::model::Model;
use tetrasim::params::{Method, SimParams};
use tetrasim::problem::Problem;

/// One mesh to benchmark: its label (path) and its model.
#[derive(Debug, Clone)]
pub struct BenchMesh {
    /// Label for the record (usually the path).
    pub label: String,
    /// The placed model.
    pub model: Model,
}

/// What to run.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Methods, in order.
    pub methods: Vec<Method>,
    /// Backend names, in order.
    pub backends: Vec<String>,
    /// Warm-up frames (simulated, not timed) and timed frames.
    pub frames: SimulateOptions,
    /// Also measure the position error against this reference (one reference run per mesh
    /// and method, shared by the backends).
    pub reference: Option<ReferenceSettings>,
}

/// One (mesh, method, backend) result. The fields of `tetrasim run`'s JSON come first
/// (flattened), with `ms_per_frame` the **median** timed frame; per-frame series cover all
/// frames, warm-up included.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchRecord {
    /// The run record (its `passes` is left empty: see [`BenchRecord::passes`]).
    #[serde(flatten)]
    pub run: RunRecord,
    /// Mean timed frame [ms].
    pub ms_mean: f64,
    /// 10th percentile of the timed frames [ms].
    pub ms_p10: f64,
    /// 90th percentile of the timed frames [ms].
    pub ms_p90: f64,
    /// Frames per second at the median frame time.
    pub fps: f64,
    /// Elements (springs, or tets for `volume`) x iterations x substeps per second at the
    /// median frame time.
    pub element_iterations_per_s: f64,
    /// Warm-up frames (simulated, not timed).
    pub warmup_frames: u32,
    /// Timed frames.
    pub timed_frames: u32,
    /// GPU time per frame of each pass over the timed frames [ms] (empty on CPU backends).
    pub passes: Vec<PassTime>,
    /// Largest `|V/V0 - 1|` over the frames [%].
    pub volume_error_pct: f64,
    /// RMS node distance to the reference over the bounding-box diagonal (`None` without
    /// `--accuracy` or when the run diverged).
    pub pos_rms_rel: Option<f64>,
    /// Largest node distance to the reference over the bounding-box diagonal.
    pub pos_max_rel: Option<f64>,
}

/// Builds the record of `sim`, run with `params` on `mesh`.
pub fn record(
    mesh: &BenchMesh,
    params: &SimParams,
    options: &SimulateOptions,
    sim: &Measured,
    reference: Option<&Reference>,
) -> Result<BenchRecord> {
    let model = &mesh.model;
    let acc = accuracy(sim, params, model, reference)?;
    let times = FrameTimes::of(&sim.frame_ms);
    let mut run = RunRecord {
        volume_pct: sim.volume_pct.clone(),
        inverted_tets: sim.inverted.clone(),
        local_error_pct: sim.local_error_pct.clone(),
        collider_nodes: Vec::new(),
        body_contacts: Vec::new(),
        deepest_m: Vec::new(),
        ms_per_frame: times.median,
        wall_s: 1e-3 * sim.frame_ms.iter().sum::<f64>(),
        diverged: sim.divergence.is_some(),
        divergence: sim.divergence.clone(),
        device: sim.gpu.as_ref().map(|g| g.device.clone()),
        atomics: sim.gpu.as_ref().map(|g| g.atomics.clone()),
        ..tetrasim::metrics::RunRecord::new(
            &Problem::new(model, params)?,
            &mesh.label,
            options.total_frames(),
            &sim.backend,
        )
    };
    run.summarise();
    run.ms_per_frame = times.median;
    let passes = sim
        .gpu
        .as_ref()
        .map(|g| g.passes.clone())
        .unwrap_or_default();
    Ok(BenchRecord {
        run,
        ms_mean: times.mean,
        ms_p10: times.p10,
        ms_p90: times.p90,
        fps: times.fps(),
        element_iterations_per_s: element_iterations_per_frame(model, params) * times.fps(),
        warmup_frames: options.warmup,
        timed_frames: sim.frame_ms.len() as u32,
        passes,
        volume_error_pct: acc.volume.volume_error_pct,
        pos_rms_rel: acc.position.map(|p| p.rms_rel),
        pos_max_rel: acc.position.map(|p| p.max_rel),
    })
}

/// Runs every mesh x method x backend with `params` (its method replaced). `progress` gets
/// one line per finished record.
pub fn run_suite(
    meshes: &[BenchMesh],
    params: &SimParams,
    options: &BenchOptions,
    backends: &mut Backends,
    progress: &mut dyn FnMut(&BenchRecord),
) -> Result<Vec<BenchRecord>> {
    if options.frames.frames == 0 {
        return Err(Error::param("frames", "must be at least 1 timed frame"));
    }
    let mut records = Vec::new();
    for mesh in meshes {
        for &method in &options.methods {
            let params = SimParams {
                method,
                ..params.clone()
            };
            let sim_options = SimulateOptions {
                sample_every: options.reference.as_ref().map(|_| 10),
                ..options.frames.clone()
            };
            let reference = match &options.reference {
                Some(settings) => Some(Reference::run(
                    backends,
                    &mesh.model,
                    &params,
                    settings,
                    &sim_options,
                )?),
                None => None,
            };
            for backend in &options.backends {
                let mut solver = backends.create(backend, &mesh.model, &params)?;
                let mut sim = simulate(solver.as_mut(), &mesh.model, &params, &sim_options)?;
                drop(solver);
                if backend == "vulkan" {
                    sim.gpu = backends.pass_report(&mesh.model, &params)?;
                }
                let r = record(mesh, &params, &sim_options, &sim, reference.as_ref())?;
                progress(&r);
                records.push(r);
            }
        }
    }
    Ok(records)
}

/// Mesh label without folders (`meshes/sphere` -> `sphere`).
fn short(label: &str) -> &str {
    label.rsplit(['/', '\\']).next().unwrap_or(label)
}

/// The benchmark table: one row per record.
pub fn table(records: &[BenchRecord]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<12} {:>7} {:<9} {:<8} {:>9} {:>9} {:>9} {:>8} {:>10} {:>8} {:>8} {:>9}",
        "mesh",
        "tets",
        "method",
        "backend",
        "ms median",
        "p10",
        "p90",
        "fps",
        "Melem-it/s",
        "min vol%",
        "avg vol%",
        "pos rms"
    );
    for r in records {
        let pos = r
            .pos_rms_rel
            .map_or("-".to_string(), |e| format!("{e:.2e}"));
        let note = if r.run.diverged {
            "  diverged"
        } else if r.run.ends_before_contact().is_some() {
            "  ended before the floor"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "{:<12} {:>7} {:<9} {:<8} {:>9.3} {:>9.3} {:>9.3} {:>8.1} {:>10.2} {:>8.2} {:>8.2} {:>9}{note}",
            short(&r.run.mesh),
            r.run.tets,
            r.run.method,
            r.run.backend,
            r.run.ms_per_frame,
            r.ms_p10,
            r.ms_p90,
            r.fps,
            r.element_iterations_per_s / 1e6,
            r.run.min_volume_pct,
            r.run.avg_volume_pct,
            pos
        );
    }
    out
}

/// GPU pass times of the records that have them, one line per record.
pub fn pass_lines(records: &[BenchRecord]) -> String {
    let mut out = String::new();
    for r in records.iter().filter(|r| !r.passes.is_empty()) {
        let total: f64 = r.passes.iter().map(|p| p.ms_per_frame).sum();
        let mut parts: Vec<&PassTime> = r.passes.iter().collect();
        parts.sort_by(|a, b| b.ms_per_frame.total_cmp(&a.ms_per_frame));
        let list: Vec<String> = parts
            .iter()
            .map(|p| format!("{} {:.3}", p.name, p.ms_per_frame))
            .collect();
        let _ = writeln!(
            out,
            "{} {} {}: GPU {total:.3} ms/frame = {}",
            short(&r.run.mesh),
            r.run.method,
            r.run.backend,
            list.join(" + ")
        );
    }
    out
}

/// Writes `records` as a pretty JSON array (through a temporary file and a rename).
pub fn write_json(path: &Path, records: &[BenchRecord]) -> Result<()> {
    let text = serde_json::to_string_pretty(records)
        .map_err(|e| Error::param("json", format!("cannot serialise the records: {e}")))?;
    crate::runner::write_atomically(path, text.as_bytes())
}
