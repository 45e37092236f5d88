//! Run metrics (physics.md, "Metrics"): volume percentage and inverted tets per frame, their
//! minimum and average over a run, timings, and the JSON record and table of a run.

use std::fmt::Write as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::backend::VolumeSample;
use crate::error::{Error, Result};
use crate::gpu::PassTime;
use crate::params::{SimParams, Solver};
use crate::problem::Problem;

/// The paper's average volume percentages over all its models, for comparison:
/// `(method, percent)`.
pub const PAPER_AVG_VOLUME_PCT: [(&str, f64); 3] =
    [("mss", 68.21), ("distance", 89.64), ("volume", 98.70)];

/// The paper's average volume percentage for `method` (`mss-node` shares `mss`'s).
pub fn paper_avg_volume_pct(method: &str) -> Option<f64> {
    let key = if method == "mss-node" { "mss" } else { method };
    PAPER_AVG_VOLUME_PCT
        .iter()
        .find(|(m, _)| *m == key)
        .map(|(_, v)| *v)
}

/// `100 * V / V0` for a sample against the total rest volume `rest` [m^3].
pub fn volume_pct(sample: VolumeSample, rest: f64) -> f64 {
    100.0 * sample.volume / rest
}

/// The local volume error of a sample in percent of the rest volume `rest` [m^3]:
/// `100 sum_t |V_t - V0_t| / sum_t V0_t` (physics.md, "Local volume error").
pub fn local_error_pct(sample: VolumeSample, rest: f64) -> f64 {
    100.0 * sample.local_error / rest
}

/// What a run's engine derived from its parameters and model, recorded beside them (a
/// reader could not work them out from the parameters alone); built by [`RecordFacts::of`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordFacts {
    /// Colour groups solved in sequence per iteration in the largest sweep (1 for `jacobi`
    /// and `chebyshev`).
    pub groups: u32,
    /// Whether a global volume constraint per object was solved.
    pub global_volume: bool,
    /// The material's damping time [s] as it acted, when the springs come from a material
    /// (the parameters' `damping`, or its default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// The spectral radius estimate the Chebyshev weights used, when it is lower than the
    /// parameters' `rho`: too few iterations for that `rho`
    /// ([`crate::params::chebyshev_rho_limit`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chebyshev_rho: Option<f64>,
    /// The springs' stiffness as it acted [N/m], least, mean and largest, when a Young's
    /// modulus gave it (each spring its own: physics.md, "Material in physical units").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring_stiffness: Option<[f64; 3]>,
    /// The bodies' mass [kg] as it acted: 1 kg per node, or the density times the volume.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<f64>,
}

impl RecordFacts {
    /// The facts of a prepared problem.
    pub fn of(problem: &Problem) -> Self {
        let params = &problem.params;
        RecordFacts {
            groups: problem.groups(),
            global_volume: params.solves_global_volume(),
            damping: params.youngs_modulus.map(|_| {
                params
                    .damping
                    .unwrap_or(crate::params::DEFAULT_DAMPING_TIME)
            }),
            chebyshev_rho: Some(params.chebyshev_rho()).filter(|&used| {
                params.solver == Solver::Chebyshev && params.has_constraints() && used != params.rho
            }),
            spring_stiffness: params.youngs_modulus.and_then(|_| {
                let k = &problem.material.spring_stiffness;
                let least = k.iter().copied().reduce(f64::min)?;
                let most = k.iter().copied().reduce(f64::max)?;
                let mean = k.iter().sum::<f64>() / k.len() as f64;
                params.has_springs().then_some([least, mean, most])
            }),
            mass_kg: Some(problem.model.mass.iter().sum()),
        }
    }
}

/// `params` as a run record holds them: without `ks` and `kd` where a Young's modulus gave
/// the springs (they did not act; reading the record back gives them their defaults).
fn params_as_acted<S: serde::Serializer>(params: &SimParams, to: S) -> Result<S::Ok, S::Error> {
    use serde::ser::Error;
    use serde::Serialize;
    let mut value = serde_json::to_value(params).map_err(S::Error::custom)?;
    if let (Some(_), Some(object)) = (params.youngs_modulus, value.as_object_mut()) {
        object.remove("ks");
        object.remove("kd");
    }
    value.serialize(to)
}

/// Everything recorded about one method's run; serialised as one JSON object. Never holds a
/// NaN: a run that goes non-finite stops, keeps the frames before, and sets `diverged`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Method name (`mss`, `mss-node`, `distance`, `volume`, `neo-hookean`).
    pub method: String,
    /// Backend name (`cpu-ref`, `cpu`, `vulkan`).
    pub backend: String,
    /// Mesh path or label.
    pub mesh: String,
    /// Node count.
    pub nodes: usize,
    /// Tetrahedron count.
    pub tets: usize,
    /// Spring count.
    pub springs: usize,
    /// Frames requested.
    pub frames: u32,
    /// Frames completed (less than `frames` when the run diverged).
    pub frames_run: u32,
    /// The parameters of the run, validated, as a nested object (the keys and units of
    /// [`SimParams`]; without `ks` and `kd` where a Young's modulus gave the springs: the
    /// stiffness as it acted is `spring_stiffness`).
    #[serde(serialize_with = "params_as_acted")]
    pub params: SimParams,
    /// What the engine derived from them (their keys sit at the top level of the JSON
    /// object).
    #[serde(flatten)]
    pub derived: RecordFacts,
    /// Simulated time at the end of each completed frame [s] (the time axis of the
    /// per-frame series; empty in records older than the field).
    #[serde(default)]
    pub time_s: Vec<f64>,
    /// When the body first reaches the floor or a fixed collider falling from its start [s]
    /// ([`crate::model::Model::contact_time`]); `None` when it never does (nothing to land
    /// on, or only moving colliders).
    #[serde(default)]
    pub contact_time_s: Option<f64>,
    /// Volume percentage after each completed frame.
    pub volume_pct: Vec<f64>,
    /// Inverted tets after each completed frame.
    pub inverted_tets: Vec<u32>,
    /// Local volume error after each completed frame [%] (`100 sum_t |V_t - V0_t| /
    /// sum_t V0_t`; empty in records older than the field).
    #[serde(default)]
    pub local_error_pct: Vec<f64>,
    /// Per completed frame, the nodes a kinematic collider pushed in its last step (runs
    /// with colliders, grabs or body contact on every backend; empty otherwise).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub collider_nodes: Vec<u32>,
    /// Per completed frame, the contacts between bodies pushing in its last step (as
    /// `collider_nodes`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub body_contacts: Vec<u32>,
    /// Per completed frame, the deepest any node is inside a collider or behind its body
    /// contact's triangle [m] (as `collider_nodes`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub deepest_m: Vec<f64>,
    /// Per sampled frame, the force the pinned nodes exerted on the bodies in its last step
    /// [N, x y z] (`cpu-ref` and `cpu`; empty on `vulkan` for now;
    /// [`crate::backend::Reactions`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pin_force: Vec<[f64; 3]>,
    /// Per sampled frame, the floor's force on the bodies [N] (runs with a floor, as
    /// `pin_force`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub floor_force: Vec<[f64; 3]>,
    /// Per sampled frame, each kinematic collider's force on the bodies [N], in the scene's
    /// order without the floor (runs with colliders, as `pin_force`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub collider_force: Vec<Vec<[f64; 3]>>,
    /// Per sampled frame, each clamp's force on the bodies [N], in the scene's order (runs
    /// with clamps, as `pin_force`, of which it is a share).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub clamp_force: Vec<Vec<[f64; 3]>>,
    /// Minimum of `volume_pct` (0 when no frame completed).
    pub min_volume_pct: f64,
    /// Average of `volume_pct` (0 when no frame completed).
    pub avg_volume_pct: f64,
    /// Inverted tets at the worst frame (the one with the most).
    pub max_inverted_tets: u32,
    /// Average of `local_error_pct` (0 when no frame completed).
    #[serde(default)]
    pub avg_local_error_pct: f64,
    /// Maximum of `local_error_pct` (0 when no frame completed).
    #[serde(default)]
    pub max_local_error_pct: f64,
    /// Mean wall time of one frame's simulation (`step_frame`, no volume sampling) [ms].
    pub ms_per_frame: f64,
    /// Wall time of the whole run, sampling and output included [s].
    pub wall_s: f64,
    /// The run diverged and stopped: a position or velocity non-finite or past the speed
    /// limit, or a sampled frame's volumes inside out or blown up (docs/STABILITY.md).
    pub diverged: bool,
    /// Where and why it diverged.
    pub divergence: Option<String>,
    /// The run was asked to end (SIGINT or SIGTERM) before its last frame; the series hold
    /// the frames it completed.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub interrupted: bool,
    /// GPU device name (`vulkan` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub device: Option<String>,
    /// Float-atomic path, `ext` or `cas` (`vulkan` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atomics: Option<String>,
    /// GPU time per frame of each pass, in execution order (`vulkan` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub passes: Option<Vec<PassTime>>,
}

/// Frames whose series a new record reserves at most: a longer run grows them as it goes
/// (a reservation for `--frames 4000000000` would ask for 32 GB at once).
const RESERVED_FRAMES: u32 = 1 << 16;

impl RunRecord {
    /// The memory a record of `frames` frames of `model` may take at most [bytes]: each
    /// frame's entry in every per-frame series (time, volume, inverted tets, local error;
    /// contact counts and depth; pin, floor, collider and clamp forces, the last two a
    /// vector each with its header and allocation), twice over for a vector's growth by
    /// doubling.
    pub fn memory_needs(model: &crate::model::Model, frames: u32) -> u64 {
        let series = 8 + 8 + 4 + 8;
        let contact = 4 + 4 + 8;
        let forces = 2 * 24 + 2 * (24 + 16) + 24 * (model.colliders.len() + model.clamps.len());
        2 * (series + contact + forces) as u64 * u64::from(frames)
    }

    /// A record of `frames` frames of a prepared problem on `backend`, before any frame ran
    /// (also what `bench` fills in).
    pub fn new(problem: &Problem, mesh_label: &str, frames: u32, backend: &str) -> Self {
        let (model, params) = (&problem.model, &problem.params);
        let reserve = frames.min(RESERVED_FRAMES) as usize;
        RunRecord {
            method: params.method.name().to_string(),
            backend: backend.to_string(),
            mesh: mesh_label.to_string(),
            nodes: model.node_count(),
            tets: model.tets.len(),
            springs: model.springs.len(),
            frames,
            frames_run: 0,
            params: params.clone(),
            derived: RecordFacts::of(problem),
            time_s: Vec::with_capacity(reserve),
            // A held body does not fall freely: no free fall's contact time for it.
            contact_time_s: (model.free_node_count() == model.node_count())
                .then(|| model.contact_time(params.gravity, params.floor))
                .flatten(),
            volume_pct: Vec::with_capacity(reserve),
            inverted_tets: Vec::with_capacity(reserve),
            local_error_pct: Vec::with_capacity(reserve),
            collider_nodes: Vec::new(),
            body_contacts: Vec::new(),
            deepest_m: Vec::new(),
            pin_force: Vec::new(),
            floor_force: Vec::new(),
            collider_force: Vec::new(),
            clamp_force: Vec::new(),
            min_volume_pct: 0.0,
            avg_volume_pct: 0.0,
            max_inverted_tets: 0,
            avg_local_error_pct: 0.0,
            max_local_error_pct: 0.0,
            ms_per_frame: 0.0,
            wall_s: 0.0,
            diverged: false,
            divergence: None,
            interrupted: false,
            device: None,
            atomics: None,
            passes: None,
        }
    }

    /// The contact time, when the run ended before it: its volume figures then measure a
    /// free fall, not the drop the paper's column is about.
    pub fn ends_before_contact(&self) -> Option<f64> {
        let end = f64::from(self.frames_run) * self.params.frame_time();
        self.contact_time_s.filter(|&t| end < t)
    }

    /// Whether the volume was measured after the last frame only (a scene run without a
    /// metrics file: no per-frame readback), so that its minimum and averages are that
    /// frame's.
    pub fn measured_last_frame_only(&self) -> bool {
        !self.volume_pct.is_empty() && self.volume_pct.len() < self.frames_run as usize
    }

    /// Recomputes `min_volume_pct`, `avg_volume_pct`, `max_inverted_tets` and `frames_run`
    /// from the per-frame series.
    pub fn summarise(&mut self) {
        let n = self.volume_pct.len();
        self.frames_run = n as u32;
        if n == 0 {
            self.min_volume_pct = 0.0;
            self.avg_volume_pct = 0.0;
        } else {
            self.min_volume_pct = self
                .volume_pct
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            self.avg_volume_pct = self.volume_pct.iter().sum::<f64>() / n as f64;
        }
        self.max_inverted_tets = self.inverted_tets.iter().copied().max().unwrap_or(0);
        let local = &self.local_error_pct;
        self.avg_local_error_pct = match local.len() {
            0 => 0.0,
            n => local.iter().sum::<f64>() / n as f64,
        };
        self.max_local_error_pct = local.iter().copied().fold(0.0, f64::max);
    }
}

/// The run table: per run, min and average volume %, the local volume error's average and
/// maximum, inverted tets at the worst frame, ms per frame, and, for the paper's experiment
/// (`paper`: the `seed` preset's drop), the paper's average for the method.
pub fn table(records: &[RunRecord], paper: bool) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<9} {:<8} {:>10} {:>10} {:>11} {:>11} {:>9} {:>9} {:>10}  note",
        "method",
        "backend",
        "min vol %",
        "avg vol %",
        "avg local %",
        "max local %",
        "inverted",
        "ms/frame",
        if paper { "paper avg" } else { "" }
    );
    for r in records {
        let paper_avg =
            paper_avg_volume_pct(&r.method).map_or("-".to_string(), |p| format!("{p:.2}"));
        let note = if r.diverged {
            format!("diverged after {} frames", r.frames_run)
        } else if let Some(t) = r.ends_before_contact() {
            let why = if paper {
                ": not the paper's experiment"
            } else {
                ""
            };
            format!("ended before its first contact (at {t:.3} s){why}")
        } else if r.measured_last_frame_only() {
            "the last frame's volume only (a scene's output.json measures every frame)".into()
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "{:<9} {:<8} {:>10.2} {:>10.2} {:>11.3} {:>11.3} {:>9} {:>9.3} {:>10}  {note}",
            r.method,
            r.backend,
            r.min_volume_pct,
            r.avg_volume_pct,
            r.avg_local_error_pct,
            r.max_local_error_pct,
            r.max_inverted_tets,
            r.ms_per_frame,
            if paper { paper_avg } else { String::new() }
        );
    }
    out
}

/// A warning for each record whose run ended before the body reached the floor or a fixed
/// collider, saying how many frames the drop needs; empty when every run reached it.
pub fn short_run_warnings(records: &[RunRecord]) -> String {
    let mut out = String::new();
    for r in records {
        if let Some(t) = r.ends_before_contact() {
            let frame_time = r.params.frame_time();
            let _ = writeln!(
                out,
                "warning: {} on {} ({}) ran {} frames ({:.3} s) and ended before the body first \
                 reached the floor or a collider (at {t:.3} s, frame {}): its volume figures are \
                 those of a free fall, not of a drop",
                r.method,
                r.backend,
                r.mesh,
                r.frames_run,
                f64::from(r.frames_run) * frame_time,
                (t / frame_time).ceil()
            );
        }
    }
    out
}

/// Per-pass GPU time of every run that has it: ms per frame and share of the frame's GPU
/// time; empty when no run does.
pub fn pass_table(records: &[RunRecord]) -> String {
    let mut out = String::new();
    for r in records {
        let Some(passes) = &r.passes else { continue };
        let total: f64 = passes.iter().map(|p| p.ms_per_frame).sum();
        let _ = writeln!(
            out,
            "{} on {} (atomics {}): GPU {total:.3} ms/frame",
            r.method,
            r.device.as_deref().unwrap_or("?"),
            r.atomics.as_deref().unwrap_or("-")
        );
        let width = passes
            .iter()
            .map(|p| p.name.len())
            .max()
            .unwrap_or(0)
            .max(17);
        for PassTime {
            name,
            ms_per_frame: ms,
        } in passes
        {
            let share = if total > 0.0 { 100.0 * ms / total } else { 0.0 };
            let _ = writeln!(out, "  {name:<width$} {ms:>9.3} ms {share:>6.1} %");
        }
    }
    out
}

/// Writes `records` as a pretty JSON array to `path` (through a temporary file and a rename,
/// so a failed write leaves no half-written file).
pub fn write_json(path: &Path, records: &[RunRecord]) -> Result<()> {
    let text = serde_json::to_string_pretty(records)
        .map_err(|e| Error::param("metrics", format!("cannot serialise the run records: {e}")))?;
    Ok(crate::mesh::io::write_atomic(path, |w| {
        w.write_all(text.as_bytes())
    })?)
}

/// Writes any serialisable value as pretty JSON to `path` (temporary file, then rename).
pub fn write_json_value<T: Serialize + ?Sized>(path: &Path, value: &T) -> Result<()> {
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| Error::param("json", format!("cannot serialise {}: {e}", path.display())))?;
    Ok(crate::mesh::io::write_atomic(path, |w| {
        w.write_all(text.as_bytes())
    })?)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(pct: Vec<f64>, inverted: Vec<u32>) -> RunRecord {
        let mut r = RunRecord {
            method: "volume".into(),
            backend: "cpu-ref".into(),
            mesh: "box".into(),
            nodes: 8,
            tets: 6,
            springs: 19,
            frames: 4,
            frames_run: 0,
            params: SimParams {
                method: crate::params::Method::Volume,
                ..SimParams::default()
            },
            derived: RecordFacts {
                groups: 8,
                global_volume: false,
                damping: None,
                chebyshev_rho: None,
                spring_stiffness: None,
                mass_kg: None,
            },
            local_error_pct: pct.iter().map(|p| (100.0 - p) / 2.0).collect(),
            collider_nodes: Vec::new(),
            body_contacts: Vec::new(),
            deepest_m: Vec::new(),
            pin_force: Vec::new(),
            floor_force: Vec::new(),
            collider_force: Vec::new(),
            clamp_force: Vec::new(),
            time_s: (1..=pct.len()).map(|f| 1e-3 * f as f64).collect(),
            contact_time_s: None,
            volume_pct: pct,
            inverted_tets: inverted,
            min_volume_pct: f64::NAN,
            avg_volume_pct: f64::NAN,
            max_inverted_tets: 0,
            avg_local_error_pct: f64::NAN,
            max_local_error_pct: f64::NAN,
            ms_per_frame: 0.5,
            wall_s: 0.01,
            diverged: false,
            divergence: None,
            interrupted: false,
            device: None,
            atomics: None,
            passes: None,
        };
        r.summarise();
        r
    }

    #[test]
    fn summary_takes_min_mean_and_worst_frame() {
        let r = record(vec![100.0, 96.0, 98.0, 94.0], vec![0, 3, 1, 2]);
        assert_eq!(
            (
                r.min_volume_pct,
                r.avg_volume_pct,
                r.max_inverted_tets,
                r.frames_run
            ),
            (94.0, 97.0, 3, 4)
        );
        assert_eq!((r.avg_local_error_pct, r.max_local_error_pct), (1.5, 3.0));
        assert!(
            !table(&[r.clone()], false).contains("98.70"),
            "the paper's column"
        );
        let text = table(&[r], true);
        assert!(
            text.contains("94.00") && text.contains("97.00") && text.contains("98.70"),
            "{text}"
        );
        assert!(text.contains("1.500") && text.contains("3.000"), "{text}");
    }

    #[test]
    fn a_run_measured_after_its_last_frame_only_says_so() {
        let every = record(vec![100.0, 96.0], vec![0, 0]);
        assert!(!every.measured_last_frame_only());
        assert!(!table(&[every], true).contains("last frame"));
        let mut last = record(vec![96.0], vec![0]);
        last.frames_run = 230;
        assert!(last.measured_last_frame_only());
        let text = table(&[last], true);
        assert!(text.contains("the last frame's volume only"), "{text}");
    }

    #[test]
    fn empty_run_has_no_nan_in_json() {
        let r = record(vec![], vec![]);
        let json = serde_json::to_string(&r).unwrap();
        assert!(
            json.contains("\"min_volume_pct\":0.0") && json.contains("\"avg_volume_pct\":0.0"),
            "{json}"
        );
        assert_eq!((r.min_volume_pct, r.avg_volume_pct), (0.0, 0.0));
        assert_eq!((r.avg_local_error_pct, r.max_local_error_pct), (0.0, 0.0));
    }
}
