//! Accuracy measures shared by `tetrasim bench` and `tetrasim tradeoff`:
//! - volume percentage (minimum and average over the frames, as in the paper) and the worst
//!   volume deviation `max |V/V0 - 1|` in percent;
//! - position error against a converged reference run of the same scene (same method, more
//!   iterations and smaller steps at the same simulated time per frame, on `cpu-ref` by
//!   default): RMS and maximum node distance over the sampled frames, relative to the
//!   bounding-box diagonal of the model's initial positions.

use serde::{Deserialize, Serialize};

use super::simulate::{simulate, Backends, Measured, Sample, SimulateOptions};
use tetrasim::error::{Error, Result};
use tetrasim::model::Model;
use tetrasim::params::{Method, SimParams};

/// Whether the method runs constraint iterations (`distance`, `volume`, `neo-hookean`).
pub fn has_iterations(method: Method) -> bool {
    matches!(
        method,
        Method::Distance | Method::Volume | Method::NeoHookean
    )
}

/// Elements one iteration of `method` visits: tets for `volume`, nodes for `neo-hookean`,
/// springs otherwise.
pub fn elements(model: &Model, method: Method) -> usize {
    match method {
        Method::Volume => model.tets.len(),
        Method::NeoHookean => model.node_count(),
        Method::Mss | Method::MssNode | Method::Distance => model.springs.len(),
    }
}

/// Element-iterations of one frame: elements x iterations (1 for spring-only methods) x
/// substeps.
pub fn element_iterations_per_frame(model: &Model, params: &SimParams) -> f64 {
    let iterations = if has_iterations(params.method) {
        params.iterations
    } else {
        1
    };
    elements(model, params.method) as f64 * f64::from(iterations) * f64::from(params.substeps)
}

/// Volume percentage summary of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct VolumeStats {
    /// Smallest volume percentage over the frames (0 when none completed).
    pub min_volume_pct: f64,
    /// Mean volume percentage over the frames (0 when none completed).
    pub avg_volume_pct: f64,
    /// Largest deviation `|V/V0 - 1|` over the frames, in percent.
    pub volume_error_pct: f64,
}

impl VolumeStats {
    /// Summarises the per-frame volume percentages (the same min and mean as
    /// [`tetrasim::metrics::RunRecord::summarise`]).
    pub fn of(volume_pct: &[f64]) -> Self {
        if volume_pct.is_empty() {
            return VolumeStats::default();
        }
        VolumeStats {
            min_volume_pct: volume_pct.iter().copied().fold(f64::INFINITY, f64::min),
            avg_volume_pct: volume_pct.iter().sum::<f64>() / volume_pct.len() as f64,
            volume_error_pct: volume_pct
                .iter()
                .map(|p| (p - 100.0).abs())
                .fold(0.0, f64::max),
        }
    }
}

/// Node distance to the reference, relative to the bounding-box diagonal.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PositionError {
    /// Root mean square over all nodes and sampled frames (dimensionless).
    pub rms_rel: f64,
    /// Largest over all nodes and sampled frames (dimensionless).
    pub max_rel: f64,
}

/// Position error of `trial` against `reference`, both sampled at the same frames, relative
/// to `diagonal` [m]. Errors when the frames or node counts differ.
pub fn position_error(
    trial: &[Sample],
    reference: &[Sample],
    diagonal: f64,
) -> Result<PositionError> {
    if trial.len() != reference.len() || trial.is_empty() {
        return Err(Error::param(
            "reference",
            format!(
                "{} trial samples against {} reference samples: both runs must sample the same frames",
                trial.len(),
                reference.len()
            ),
        ));
    }
    if !(diagonal.is_finite() && diagonal > 0.0) {
        return Err(Error::Mesh(format!(
            "bounding-box diagonal {diagonal} m: the position error needs a mesh with extent"
        )));
    }
    let mut sum_sq = 0.0;
    let mut max: f64 = 0.0;
    let mut count = 0usize;
    for (t, r) in trial.iter().zip(reference) {
        if t.frame != r.frame || t.positions.len() != r.positions.len() {
            return Err(Error::param(
                "reference",
                format!(
                    "trial sample at frame {} ({} nodes) against reference sample at frame {} ({} nodes)",
                    t.frame,
                    t.positions.len(),
                    r.frame,
                    r.positions.len()
                ),
            ));
        }
        for (a, b) in t.positions.iter().zip(&r.positions) {
            let d = a.distance(*b);
            sum_sq += d * d;
            max = max.max(d);
            count += 1;
        }
    }
    let rms = (sum_sq / count.max(1) as f64).sqrt();
    Ok(PositionError {
        rms_rel: rms / diagonal,
        max_rel: max / diagonal,
    })
}

/// How the converged reference is run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReferenceSettings {
    /// Backend (`cpu-ref`: the f64 oracle).
    pub backend: String,
    /// Constraint iterations per time step.
    pub iterations: u32,
    /// Time steps per frame; `dt` is the frame time divided by this.
    pub substeps: u32,
}

impl Default for ReferenceSettings {
    /// `cpu-ref`, 100 iterations, 8 substeps.
    fn default() -> Self {
        ReferenceSettings {
            backend: "cpu-ref".to_string(),
            iterations: 100,
            substeps: 8,
        }
    }
}

impl ReferenceSettings {
    /// The reference's parameters for a trial with `trial`'s method, physics and frame time,
    /// solved by the default solver whatever the trial's (so that every solver of one method
    /// is measured against the same converged run).
    pub fn params(&self, trial: &SimParams) -> SimParams {
        let default = SimParams::default();
        SimParams {
            dt: trial.frame_time() / f64::from(self.substeps.max(1)),
            substeps: self.substeps,
            iterations: self.iterations,
            omega: 1.0,
            solver: default.solver,
            groups: default.groups,
            global_volume: default.global_volume,
            ..trial.clone()
        }
    }
}

/// A finished reference run.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The parameters it ran with.
    pub params: SimParams,
    /// Its frames, samples and volumes.
    pub simulation: Measured,
}

impl Reference {
    /// Runs the reference of `trial` on `model` for the frames and samples of `options`
    /// (no warm-up distinction: the same frames are simulated). Errors when it diverges.
    pub fn run(
        backends: &mut Backends,
        model: &Model,
        trial: &SimParams,
        settings: &ReferenceSettings,
        options: &SimulateOptions,
    ) -> Result<Reference> {
        let params = settings.params(trial);
        params.validate()?;
        let mut solver = backends.create(&settings.backend, model, &params)?;
        let simulation = simulate(solver.as_mut(), model, &params, options)?;
        if let Some(d) = &simulation.divergence {
            return Err(Error::param(
                "reference",
                format!(
                    "the reference run ({} iterations, {} substeps on {}) diverged: {d}",
                    settings.iterations, settings.substeps, settings.backend
                ),
            ));
        }
        Ok(Reference { params, simulation })
    }

    /// Whether `trial` can be compared to this reference: same method and frame time.
    pub fn matches(&self, trial: &SimParams) -> bool {
        let (a, b) = (trial.frame_time(), self.params.frame_time());
        trial.method == self.params.method && (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
    }
}

/// Accuracy of one run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Accuracy {
    /// Volume percentage summary.
    pub volume: VolumeStats,
    /// Position error against the reference; `None` without one or when the run diverged.
    pub position: Option<PositionError>,
}

/// The accuracy of `sim` (run with `params` on `model`), against `reference` if given.
pub fn accuracy(
    sim: &Measured,
    params: &SimParams,
    model: &Model,
    reference: Option<&Reference>,
) -> Result<Accuracy> {
    let volume = VolumeStats::of(&sim.volume_pct);
    let position = match reference {
        Some(r) if sim.divergence.is_none() => {
            if !r.matches(params) {
                return Err(Error::param(
                    "reference",
                    format!(
                        "the reference ({}, frame time {} s) does not match the run ({}, frame time {} s)",
                        r.params.method,
                        r.params.frame_time(),
                        params.method,
                        params.frame_time()
                    ),
                ));
            }
            Some(position_error(
                &sim.samples,
                &r.simulation.samples,
                model.bounds_diagonal(),
            )?)
        }
        _ => None,
    };
    Ok(Accuracy { volume, position })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn sample(frame: u32, xs: &[f64]) -> Sample {
        Sample {
            frame,
            positions: xs.iter().map(|&x| DVec3::new(x, 0.0, 0.0)).collect(),
        }
    }

    #[test]
    fn position_error_is_relative_rms_and_max() {
        let r = [sample(1, &[0.0, 0.0]), sample(2, &[0.0, 0.0])];
        let t = [sample(1, &[0.0, 3.0]), sample(2, &[4.0, 0.0])];
        let e = position_error(&t, &r, 2.0).unwrap();
        // distances 0, 3, 4, 0: rms = sqrt(25 / 4) = 2.5, max = 4; over the diagonal 2.
        assert!((e.rms_rel - 1.25).abs() < 1e-12 && (e.max_rel - 2.0).abs() < 1e-12);
        assert!(position_error(&t[..1], &r, 2.0).is_err());
        assert!(position_error(&[sample(3, &[0.0, 0.0]), t[1].clone()], &r, 2.0).is_err());
    }

    #[test]
    fn volume_stats_take_the_worst_deviation_either_way() {
        let v = VolumeStats::of(&[100.0, 97.0, 101.5, 99.5]);
        assert_eq!((v.min_volume_pct, v.avg_volume_pct), (97.0, 99.5));
        assert!((v.volume_error_pct - 3.0).abs() < 1e-12);
        assert!((VolumeStats::of(&[100.0, 104.0]).volume_error_pct - 4.0).abs() < 1e-12);
    }

    #[test]
    fn reference_keeps_the_frame_time() {
        let trial = SimParams {
            dt: 5e-4,
            substeps: 2,
            iterations: 3,
            omega: 1.5,
            ..SimParams::default()
        };
        let p = ReferenceSettings::default().params(&trial);
        assert!((p.frame_time() - 1e-3).abs() < 1e-15);
        assert_eq!((p.substeps, p.iterations, p.omega), (8, 100, 1.0));
        assert_eq!(p.method, trial.method);
    }
}
