//! The command line's frame loop: create the backend by name, step frames through the
//! engine's driver ([`tetrasim::sim::Simulation`]), sample the volume, time the steps, show
//! progress, write surfaces on request, and return a [`RunRecord`]. `run`, `bench`, `render`
//! and the tests run experiments through here.

mod interrupt;
mod output;
mod preflight;
mod space;

pub use interrupt::{interrupt_flag, listen_for_interrupts};
pub use output::{
    create_dir, frame_output, prepare_output_file, prepare_outputs, write_atomically, FrameOutput,
    OutputFormat, OutputUnits, Recorder,
};
pub use preflight::preflight;
pub use space::check_disk_space;

use std::path::PathBuf;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

use tetrasim::backend::vulkan::EngineOptions;
use tetrasim::error::Result;
use tetrasim::metrics::RunRecord;
use tetrasim::model::Model;
use tetrasim::params::{Method, SimParams};
use tetrasim::problem::Problem;
use tetrasim::sim::{BackendFactory, Checkpoint, Simulation};

/// How to run one experiment, besides the model and the physics.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Backend name (see [`tetrasim::sim::BACKENDS`]).
    pub backend: String,
    /// Frames to simulate.
    pub frames: u32,
    /// Mesh label for the record (usually its path).
    pub mesh_label: String,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Write the deformed surface or tet mesh every few frames.
    pub output: Option<FrameOutput>,
    /// Device, validation and workgroup size of the `vulkan` backend.
    pub gpu: EngineOptions,
    /// Checkpoints to write and the one to resume from.
    pub checkpoint: Checkpointing,
}

/// A run's checkpoints ([`Checkpoint`]).
#[derive(Debug, Clone, Default)]
pub struct Checkpointing {
    /// Where to save the run's checkpoint: every `every` frames (`None`: only when the
    /// run ends), each replacing the last.
    pub save: Option<PathBuf>,
    /// Frames between checkpoints (needs `save`).
    pub every: Option<u32>,
    /// The checkpoint to resume from: the run continues from its frame to `frames`.
    pub resume: Option<PathBuf>,
}

/// Runs `params.method` on `model` for `options.frames` frames. A run that goes non-finite
/// stops and comes back with `diverged: true` (not as an error); other failures are errors.
pub fn run(model: &Model, params: &SimParams, options: &RunOptions) -> Result<RunRecord> {
    let started = Instant::now();
    let problem = Problem::new(model, params)?;
    let mut backend =
        BackendFactory::new(options.gpu.clone()).create(&options.backend, &problem)?;
    let mut record = RunRecord::new(
        &problem,
        &options.mesh_label,
        options.frames,
        backend.name(),
    );
    let bar = progress_bar(options, params.method);
    let frame_time = params.frame_time();
    let mut sim = Simulation::new(model, params);
    if let Some(flag) = interrupt_flag() {
        sim.stop_on(flag);
    }
    if let Some(path) = &options.checkpoint.resume {
        let checkpoint = Checkpoint::read(path)?;
        if checkpoint.frames() >= options.frames {
            return Err(tetrasim::Error::param(
                "resume",
                format!(
                    "{} is at frame {}: a run of {} frames has nothing left to run",
                    path.display(),
                    checkpoint.frames(),
                    options.frames
                ),
            ));
        }
        checkpoint.resume(model, params, backend.as_mut(), &mut sim)?;
    }
    let mut recorder =
        (options.output.as_ref()).map(|out| out.recorder(model, params.method, frame_time));
    if let Some(recorder) = &mut recorder {
        recorder.record(sim.frames(), &backend.state()?)?;
    }
    // With `volume_on_demand` the volume is sampled after the last frame only.
    let every_frame = !options.gpu.volume_on_demand;
    let frames = options.frames;
    let sample = |n: u32| every_frame || n == frames;
    let mut progress = |sim: &Simulation| {
        if let Some(pct) = sim.last_volume_pct() {
            bar.set_message(format!("{pct:.2} %"));
        }
        bar.inc(1);
    };
    // Frames in flight between the outputs and checkpoints, which need the state of their
    // frame.
    let next = |done: u32, every: u32| (done / every + 1) * every;
    let checkpoint_every = (options.checkpoint.save.as_ref()).and(options.checkpoint.every);
    while sim.frames() < frames && !sim.stopped() && !sim.interrupted() {
        let done = sim.frames();
        let until = [
            options.output.as_ref().map(|out| next(done, out.every)),
            checkpoint_every.map(|every| next(done, every)),
        ]
        .into_iter()
        .flatten()
        .fold(frames, u32::min);
        sim.advance_frames(
            backend.as_mut(),
            until - sim.frames(),
            &sample,
            &mut progress,
        )?;
        if let (Some(out), Some(recorder)) = (&options.output, &mut recorder) {
            let done = sim.frames();
            if !sim.stopped() && done % out.every == 0 {
                recorder.record(done, &backend.state()?)?;
            }
        }
        let (done, save) = (sim.frames(), &options.checkpoint.save);
        if let (Some(path), false) = (save, sim.stopped()) {
            let at_end = done == frames || sim.interrupted();
            if checkpoint_every.is_some_and(|every| done % every == 0) || at_end {
                Checkpoint::take(model, params, backend.as_mut(), &sim)?.write(path)?;
            }
        }
    }
    bar.finish_and_clear();
    if let Some(recorder) = recorder {
        recorder.finish()?;
    }
    sim.fill_record(&mut record);
    if !every_frame {
        record.frames_run = sim.frames();
    }
    record.ms_per_frame = if sim.frames() > 0 {
        1e3 * sim.stepping_s / f64::from(sim.frames())
    } else {
        0.0
    };
    record.wall_s = started.elapsed().as_secs_f64();
    if let Some(gpu) = backend.gpu_report()? {
        for message in &gpu.validation_messages {
            eprintln!("validation: {message}");
        }
        record.device = Some(gpu.device);
        record.atomics = Some(gpu.atomics);
        record.passes = Some(gpu.passes);
    }
    Ok(record)
}

/// Runs each of `methods` in turn (same model and parameters otherwise).
pub fn run_methods(
    model: &Model,
    params: &SimParams,
    methods: &[Method],
    options: &RunOptions,
) -> Result<Vec<RunRecord>> {
    let mut records = Vec::new();
    for &method in methods {
        let params = SimParams {
            method,
            ..params.clone()
        };
        let record = run(model, &params, options)?;
        // An interrupted run ends the methods still to run too.
        let interrupted = record.interrupted;
        records.push(record);
        if interrupted {
            break;
        }
    }
    Ok(records)
}

fn progress_bar(options: &RunOptions, method: Method) -> ProgressBar {
    if !options.progress {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(u64::from(options.frames));
    if let Ok(style) = ProgressStyle::with_template(
        "{prefix:>9} [{bar:40}] {pos}/{len} frames, volume {msg} ({eta})",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(method.name());
    bar
}
