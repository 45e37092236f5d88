//! `tetrasim tradeoff`: the speed-versus-accuracy sweep. Each point is one setting of method,
//! solver (with its colour groups and global volume constraint), iterations, substeps (with
//! `dt = frame time / substeps`, so every point simulates the same time per frame) and omega; it records the cost (median ms per frame on the chosen backend)
//! and the accuracy (volume error, position error against the method's converged reference).

use serde::{Deserialize, Serialize};

use super::accuracy::{
    accuracy, element_iterations_per_frame, has_iterations, Reference, ReferenceSettings,
};
use super::pareto::pareto_front;
use super::simulate::{simulate, Backends, SimulateOptions};
pub use super::solver_setting::SolverSetting;
use super::stats::FrameTimes;
use tetrasim::error::{Error, Result};
use tetrasim::model::Model;
use tetrasim::params::{Method, SimParams, Solver};

/// One setting of the sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SweepPoint {
    /// Method.
    pub method: Method,
    /// Solver (ignored by the springs-only methods).
    pub solver: SolverSetting,
    /// Constraint iterations per time step (1 for spring-only methods).
    pub iterations: u32,
    /// Time steps per frame.
    pub substeps: u32,
    /// Relaxation factor.
    pub omega: f64,
}

/// Which settings to sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepSpec {
    /// Methods, in order.
    pub methods: Vec<Method>,
    /// Solvers of the constraint methods, in order.
    pub solvers: Vec<SolverSetting>,
    /// Iteration counts (constraint methods), each at every substep count with omega 1.
    pub iterations: Vec<u32>,
    /// Substep counts.
    pub substeps: Vec<u32>,
    /// Extra omegas, each at `omega_iterations` iterations, the first substep count and the
    /// first solver.
    pub omegas: Vec<f64>,
    /// Iterations of the omega points.
    pub omega_iterations: u32,
}

impl Default for SweepSpec {
    /// mss, distance and volume; the four [`SolverSetting::DEFAULTS`]; iterations 1, 2, 5,
    /// 10, 20, 50; substeps 1, 2, 4; omega 0.5 and 1.5 at 10 iterations.
    fn default() -> Self {
        SweepSpec {
            methods: vec![Method::Mss, Method::Distance, Method::Volume],
            solvers: SolverSetting::DEFAULTS.to_vec(),
            iterations: vec![1, 2, 5, 10, 20, 50],
            substeps: vec![1, 2, 4],
            omegas: vec![0.5, 1.5],
            omega_iterations: 10,
        }
    }
}

impl SweepSpec {
    /// A small sweep for smoke runs: iterations 1, 5, 20; substeps 1, 2; omega 1.5.
    pub fn quick() -> Self {
        SweepSpec {
            iterations: vec![1, 5, 20],
            substeps: vec![1, 2],
            omegas: vec![1.5],
            ..SweepSpec::default()
        }
    }

    /// Checks that every list is non-empty and every value in range.
    pub fn validate(&self) -> Result<()> {
        if self.methods.is_empty() || self.substeps.is_empty() {
            return Err(Error::param(
                "methods/substeps",
                "need at least one value each",
            ));
        }
        if self.methods.iter().any(|&m| has_iterations(m))
            && (self.iterations.is_empty() || self.solvers.is_empty())
        {
            return Err(Error::param(
                "iterations/solvers",
                "need at least one value each",
            ));
        }
        if let Some(bad) = self
            .iterations
            .iter()
            .chain(&self.substeps)
            .find(|&&v| v == 0)
        {
            return Err(Error::param(
                "iterations/substeps",
                format!("{bad}: must be at least 1"),
            ));
        }
        if let Some(bad) = self.omegas.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
            return Err(Error::param(
                "omega",
                format!("{bad}: must be a finite number > 0"),
            ));
        }
        Ok(())
    }

    /// Every point, method by method.
    pub fn points(&self) -> Vec<SweepPoint> {
        let mut points = Vec::new();
        for &method in &self.methods {
            if !has_iterations(method) {
                for &substeps in &self.substeps {
                    points.push(SweepPoint {
                        method,
                        solver: SolverSetting::DEFAULTS[0],
                        iterations: 1,
                        substeps,
                        omega: 1.0,
                    });
                }
                continue;
            }
            // The inversion floor sweeps volume constraints: a setting with it is the volume
            // method's alone. The finite elements have no sweeps: one setting, the engine's
            // (their CG ignores it), and no relaxation factor.
            let finite_elements = method == Method::NeoHookean;
            let engine = [SolverSetting::new(Solver::GaussSeidel, 8, false)];
            let solvers = (self.solvers.iter()).filter(|s| {
                (s.inversion_sweeps == 0 && s.block_size == 0) || method == Method::Volume
            });
            let solvers: Vec<SolverSetting> = match finite_elements {
                true => engine.to_vec(),
                false => solvers.copied().collect(),
            };
            for solver in solvers {
                for &substeps in &self.substeps {
                    for &iterations in &self.iterations {
                        points.push(SweepPoint {
                            method,
                            solver,
                            iterations,
                            substeps,
                            omega: 1.0,
                        });
                    }
                }
            }
            for &omega in (self.omegas.iter()).filter(|&&w| w != 1.0 && !finite_elements) {
                points.push(SweepPoint {
                    method,
                    solver: self.solvers[0],
                    iterations: self.omega_iterations.max(1),
                    substeps: self.substeps[0],
                    omega,
                });
            }
        }
        points
    }
}

/// How each point is run.
#[derive(Debug, Clone)]
pub struct TradeoffOptions {
    /// Backend whose cost is measured.
    pub backend: String,
    /// Frames (warm-up frames are simulated and scored, only left out of the timing) and
    /// sampling of the positions.
    pub frames: SimulateOptions,
    /// The converged reference of each method.
    pub reference: ReferenceSettings,
}

/// One point's result; also one CSV row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TradeoffRecord {
    /// Mesh label.
    pub mesh: String,
    /// Tetrahedra.
    pub tets: usize,
    /// Springs.
    pub springs: usize,
    /// Method.
    pub method: String,
    /// Solver label ([`SolverSetting::label`]; `jacobi` in records older than the field).
    #[serde(default = "jacobi_label")]
    pub solver: String,
    /// Backend whose cost was measured.
    pub backend: String,
    /// Constraint iterations per time step.
    pub iterations: u32,
    /// Time steps per frame.
    pub substeps: u32,
    /// Time step [s].
    pub dt: f64,
    /// Relaxation factor.
    pub omega: f64,
    /// Frames simulated.
    pub frames: u32,
    /// Median wall time of a timed frame [ms].
    pub ms_per_frame: f64,
    /// 10th percentile [ms].
    pub ms_p10: f64,
    /// 90th percentile [ms].
    pub ms_p90: f64,
    /// Element-iterations per frame (the work, independent of the machine).
    pub element_iterations_per_frame: f64,
    /// Element-iterations per second at the median frame time.
    pub element_iterations_per_s: f64,
    /// Smallest volume percentage.
    pub min_volume_pct: f64,
    /// Mean volume percentage.
    pub avg_volume_pct: f64,
    /// Largest `|V/V0 - 1|` [%].
    pub volume_error_pct: f64,
    /// Mean local volume error `100 sum_t |V_t - V0_t| / sum_t V0_t` over the frames [%]
    /// (0 in records older than the field).
    #[serde(default)]
    pub avg_local_error_pct: f64,
    /// RMS node distance to the reference over the bounding-box diagonal.
    pub pos_rms_rel: Option<f64>,
    /// Largest node distance to the reference over the bounding-box diagonal.
    pub pos_max_rel: Option<f64>,
    /// The run went non-finite.
    pub diverged: bool,
    /// On the Pareto front of (ms per frame, volume error).
    pub pareto_volume: bool,
    /// On the Pareto front of (ms per frame, RMS position error).
    pub pareto_position: bool,
}

fn jacobi_label() -> String {
    "jacobi".into()
}

impl TradeoffRecord {
    /// Method and solver, e.g. `volume gauss-seidel:8+global` (`mss` alone).
    pub fn series(&self) -> String {
        match self.method.as_str() {
            "mss" | "mss-node" => self.method.clone(),
            _ => format!("{} {}", self.method, self.solver),
        }
    }
}

/// Runs every point of `spec` on `model` (physics from `base`; its `dt * substeps` is the
/// frame time every point keeps). `progress` gets each record as it finishes.
pub fn run_tradeoff(
    model: &Model,
    mesh_label: &str,
    base: &SimParams,
    spec: &SweepSpec,
    options: &TradeoffOptions,
    backends: &mut Backends,
    progress: &mut dyn FnMut(&TradeoffRecord),
) -> Result<Vec<TradeoffRecord>> {
    spec.validate()?;
    let frame_time = base.frame_time();
    let mut references: Vec<Reference> = Vec::new();
    let mut records = Vec::new();
    for point in spec.points() {
        let params = SimParams {
            method: point.method,
            iterations: point.iterations,
            substeps: point.substeps,
            dt: frame_time / f64::from(point.substeps),
            omega: point.omega,
            ..point.solver.apply(base)
        };
        params.validate()?;
        let reference = match references.iter().position(|r| r.matches(&params)) {
            Some(i) => &references[i],
            None => {
                let r = Reference::run(
                    backends,
                    model,
                    &params,
                    &options.reference,
                    &options.frames,
                )?;
                references.push(r);
                &references[references.len() - 1]
            }
        };
        let mut solver = backends.create(&options.backend, model, &params)?;
        let sim = simulate(solver.as_mut(), model, &params, &options.frames)?;
        drop(solver);
        let acc = accuracy(&sim, &params, model, Some(reference))?;
        let times = FrameTimes::of(&sim.frame_ms);
        let work = element_iterations_per_frame(model, &params);
        let record = TradeoffRecord {
            mesh: mesh_label.to_string(),
            tets: model.tets.len(),
            springs: model.springs.len(),
            method: point.method.name().to_string(),
            solver: match has_iterations(point.method) {
                true => point.solver.label(),
                false => "-".into(),
            },
            backend: sim.backend.clone(),
            iterations: point.iterations,
            substeps: point.substeps,
            dt: params.dt,
            omega: point.omega,
            frames: sim.volume_pct.len() as u32,
            ms_per_frame: times.median,
            ms_p10: times.p10,
            ms_p90: times.p90,
            element_iterations_per_frame: work,
            element_iterations_per_s: work * times.fps(),
            min_volume_pct: acc.volume.min_volume_pct,
            avg_volume_pct: acc.volume.avg_volume_pct,
            volume_error_pct: acc.volume.volume_error_pct,
            avg_local_error_pct: match sim.local_error_pct.len() {
                0 => 0.0,
                n => sim.local_error_pct.iter().sum::<f64>() / n as f64,
            },
            pos_rms_rel: acc.position.map(|p| p.rms_rel),
            pos_max_rel: acc.position.map(|p| p.max_rel),
            diverged: sim.divergence.is_some(),
            pareto_volume: false,
            pareto_position: false,
        };
        progress(&record);
        records.push(record);
    }
    mark_pareto(&mut records);
    Ok(records)
}

/// A record's (cost, volume error) point; NaN for a diverged run.
pub(super) fn volume_point(r: &TradeoffRecord) -> (f64, f64) {
    if r.diverged {
        (f64::NAN, f64::NAN)
    } else {
        (r.ms_per_frame, r.volume_error_pct)
    }
}

/// A record's (cost, position error) point; NaN without one or for a diverged run.
pub(super) fn position_point(r: &TradeoffRecord) -> (f64, f64) {
    match r.pos_rms_rel {
        Some(e) if !r.diverged => (r.ms_per_frame, e),
        _ => (f64::NAN, f64::NAN),
    }
}

/// Sets `pareto_volume` (over all settings) and `pareto_position` (within each method: the
/// position errors of different methods are measured against different references, so they
/// are not compared) on every record. Diverged runs are never on a front.
pub fn mark_pareto(records: &mut [TradeoffRecord]) {
    let vol: Vec<(f64, f64)> = records.iter().map(volume_point).collect();
    let fv = pareto_front(&vol);
    let methods: Vec<String> = records.iter().map(|r| r.method.clone()).collect();
    let pos: Vec<(f64, f64)> = records.iter().map(position_point).collect();
    for (i, r) in records.iter_mut().enumerate() {
        r.pareto_volume = fv.contains(&i);
        let masked: Vec<(f64, f64)> = pos
            .iter()
            .zip(&methods)
            .map(|(&p, m)| {
                if *m == methods[i] {
                    p
                } else {
                    (f64::NAN, f64::NAN)
                }
            })
            .collect();
        r.pareto_position = pareto_front(&masked).contains(&i);
    }
}

#[cfg(test)]
#[path = "tradeoff_tests.rs"]
mod tests;
