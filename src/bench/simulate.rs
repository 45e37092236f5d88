//! The measured frame loop of the benchmarks and the trade-off study: frames advanced by the
//! one driver ([`tetrasim::sim::Simulation`]), with the volume sampled every frame, plus per-frame wall times,
//! warm-up frames whose times are dropped, GPU pass times over the timed frames only, and
//! node positions read back at chosen frames for the position error.

use glam::DVec3;

use tetrasim::backend::vulkan::EngineOptions;
use tetrasim::backend::{Backend, GpuReport};
use tetrasim::error::{Error, Result};
use tetrasim::model::Model;
use tetrasim::params::SimParams;
use tetrasim::problem::Problem;
use tetrasim::sim::{Advance, BackendFactory, Simulation};

/// The benchmarks' backends: a [`BackendFactory`] whose `vulkan` backends run without GPU
/// timestamps and measure the volume on demand, outside the timed `step_frame` (as the CPU
/// backends do); [`Backends::pass_report`] measures the pass breakdown in a separate,
/// timestamped run on the same context.
pub struct Backends {
    factory: BackendFactory,
}

/// Frames of the timestamped run that measures the pass breakdown (after 5 warm-up frames).
pub const PASS_REPORT_FRAMES: u32 = 20;

impl Backends {
    /// Backends with these GPU options (device, validation, workgroup size).
    pub fn new(gpu: EngineOptions) -> Self {
        Backends {
            factory: BackendFactory::new(EngineOptions {
                untimed: true,
                volume_on_demand: true,
                ..gpu
            }),
        }
    }

    /// The backend `name` (`vulkan`, `cpu`, `cpu-ref`) for `model` with `params`; a
    /// `vulkan` one untimed, with the volume measured on demand.
    pub fn create(
        &mut self,
        name: &str,
        model: &Model,
        params: &SimParams,
    ) -> Result<Box<dyn Backend>> {
        self.factory.create(name, &Problem::new(model, params)?)
    }

    /// Device, atomics and GPU time per pass of `model` under `params`, from a separate
    /// timestamped run of 5 warm-up and [`PASS_REPORT_FRAMES`] frames with the volume
    /// measured every frame (so `volume_sum` is in the breakdown).
    pub fn pass_report(&mut self, model: &Model, params: &SimParams) -> Result<Option<GpuReport>> {
        let options = EngineOptions {
            untimed: false,
            volume_on_demand: false,
            ..self.factory.options().clone()
        };
        let mut gpu = self
            .factory
            .vulkan(&Problem::new(model, params)?, &options)?;
        for frame in 0..5 + PASS_REPORT_FRAMES {
            if frame == 5 {
                gpu.reset_pass_times()?;
            }
            match gpu.step_frame() {
                Ok(()) => {}
                Err(Error::Diverged(_)) => break,
                Err(e) => return Err(e),
            }
        }
        gpu.gpu_report()
    }
}

/// How many frames to run and what to keep.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulateOptions {
    /// Frames simulated first whose wall times are dropped (they still advance the scene).
    pub warmup: u32,
    /// Timed frames after the warm-up.
    pub frames: u32,
    /// Read the node positions back after every this many frames (counted from the start,
    /// warm-up included) and after the last frame; `None`: never.
    pub sample_every: Option<u32>,
}

impl SimulateOptions {
    /// All frames, warm-up included.
    pub fn total_frames(&self) -> u32 {
        self.warmup + self.frames
    }

    /// The frames (1-based count of completed frames) after which positions are read back.
    pub fn sample_frames(&self) -> Vec<u32> {
        let total = self.total_frames();
        let Some(every) = self.sample_every.filter(|&e| e > 0) else {
            return Vec::new();
        };
        let mut frames: Vec<u32> = (1..=total).filter(|f| f % every == 0).collect();
        if total > 0 && frames.last() != Some(&total) {
            frames.push(total);
        }
        frames
    }
}

/// Node positions after a frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    /// Frames completed when the positions were read (1-based).
    pub frame: u32,
    /// Node positions [m].
    pub positions: Vec<DVec3>,
}

/// What one simulation measured.
#[derive(Debug, Clone)]
pub struct Measured {
    /// Backend name.
    pub backend: String,
    /// Wall time of each timed frame's `step_frame` [ms] (warm-up frames left out).
    pub frame_ms: Vec<f64>,
    /// Volume percentage after every completed frame, warm-up included.
    pub volume_pct: Vec<f64>,
    /// Inverted tets after every completed frame.
    pub inverted: Vec<u32>,
    /// Local volume error after every completed frame [%].
    pub local_error_pct: Vec<f64>,
    /// Positions at [`SimulateOptions::sample_frames`] (fewer when the run diverged).
    pub samples: Vec<Sample>,
    /// Where and why the run diverged, if it did.
    pub divergence: Option<String>,
    /// Device, atomics and GPU pass times over the timed frames (`vulkan` only).
    pub gpu: Option<GpuReport>,
}

/// Runs `options.total_frames()` frames of `solver` on `model` (see the module doc). A
/// divergence ends the run early and is recorded, not returned as an error.
pub fn simulate(
    backend: &mut dyn Backend,
    model: &Model,
    params: &SimParams,
    options: &SimulateOptions,
) -> Result<Measured> {
    let total = options.total_frames();
    if total == 0 {
        return Err(Error::param("frames", "must be at least 1"));
    }
    let sample_frames = options.sample_frames();
    // Grown as frames run: a reservation of every frame asks for all of it at once.
    let mut frame_ms = Vec::with_capacity(options.frames.min(1 << 16) as usize);
    let mut samples = Vec::with_capacity(sample_frames.len());
    let mut run = Simulation::new(model, params);
    for frame in 0..total {
        if frame == options.warmup && options.warmup > 0 {
            backend.reset_timing()?;
        }
        let Advance::Stepped(step_s) = run.advance(backend, true)? else {
            break;
        };
        if frame >= options.warmup {
            frame_ms.push(1e3 * step_s);
        }
        if sample_frames.contains(&(frame + 1)) {
            samples.push(Sample {
                frame: frame + 1,
                positions: backend.state()?.positions,
            });
        }
    }
    let series = run.series;
    let mut sim = Measured {
        backend: backend.name().to_string(),
        frame_ms,
        volume_pct: series.volume_pct,
        inverted: series.inverted,
        local_error_pct: series.local_error_pct,
        samples,
        divergence: run.divergence,
        gpu: None,
    };
    sim.gpu = backend.gpu_report()?;
    Ok(sim)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_frames_include_the_last() {
        let o = SimulateOptions {
            warmup: 2,
            frames: 9,
            sample_every: Some(5),
        };
        assert_eq!(o.sample_frames(), vec![5, 10, 11]);
        let none = SimulateOptions {
            sample_every: None,
            ..o.clone()
        };
        assert!(none.sample_frames().is_empty());
        let exact = SimulateOptions {
            warmup: 0,
            frames: 10,
            sample_every: Some(5),
        };
        assert_eq!(exact.sample_frames(), vec![5, 10]);
    }
}
