//! The render loop: every method's `vulkan` backend on one shared context, stepped in lock
//! step; at the frames an output asks for, each method's state is drawn by one [`Renderer`]
//! straight from that backend's position buffer, and the pictures go to PNG frames, an
//! animated GIF (the methods side by side) and a contact sheet. With
//! [`RenderJob::physics`] a CPU backend steps instead, and its state is copied into the
//! `vulkan` backend's buffers at each frame drawn (for what `vulkan` does not solve).

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

use crate::runner::FrameOutput;
use tetrasim::backend::vulkan::{EngineOptions, VulkanBackend};
use tetrasim::backend::{Backend, State};
use tetrasim::error::{Error, Result};
use tetrasim::gpu::Context;
use tetrasim::model::Model;
use tetrasim::params::{Method, SimParams};
use tetrasim::render::image::{GifWriter, Image};
use tetrasim::render::renderer::Renderer;
use tetrasim::render::sheet;
use tetrasim::render::RenderOptions;
use tetrasim::sim::{create_backend, Simulation};

/// What to write.
#[derive(Debug, Clone, Default)]
pub struct Outputs {
    /// Write `DIR/METHOD_FFFFF.png` every [`Outputs::every`] frames (frame 0 included).
    pub frames_dir: Option<PathBuf>,
    /// Period of the PNG frames [frames], at least 1.
    pub every: u32,
    /// Write an animated GIF of the methods side by side here.
    pub gif: Option<PathBuf>,
    /// Period of the GIF's frames [frames]; `None`: about 60 frames over the run.
    pub gif_every: Option<u32>,
    /// Write a contact sheet (rows: methods, columns: sampled frames) here.
    pub sheet: Option<PathBuf>,
    /// Columns of the sheet: frames sampled evenly from the first to the last (at least 1).
    pub sheet_columns: u32,
    /// Also write the deformed surface or tet mesh (as `tetrasim run --out-dir`).
    pub meshes: Option<FrameOutput>,
}

impl Outputs {
    fn validate(&self) -> Result<()> {
        if self.frames_dir.is_none() && self.gif.is_none() && self.sheet.is_none() {
            return Err(Error::param(
                "render",
                "nothing to write: give --frames-dir DIR, --gif FILE or --sheet FILE.png",
            ));
        }
        if self.frames_dir.is_some() && self.every == 0 {
            return Err(Error::param("every", "must be at least 1"));
        }
        if self.gif_every == Some(0) {
            return Err(Error::param("gif-every", "must be at least 1"));
        }
        if self.sheet.is_some() && self.sheet_columns == 0 {
            return Err(Error::param("sheet-frames", "must be at least 1"));
        }
        Ok(())
    }

    /// Frames shown in the sheet's columns, for a run of `frames` frames.
    pub fn sheet_frames(&self, frames: u32) -> Vec<u32> {
        let n = self.sheet_columns.max(1);
        if n == 1 {
            return vec![frames];
        }
        (0..n)
            .map(|k| ((f64::from(k) * f64::from(frames)) / f64::from(n - 1)).round() as u32)
            .collect()
    }
}

/// One render run: the frames, methods, look and outputs.
#[derive(Debug, Clone)]
pub struct RenderJob {
    /// Frames to simulate.
    pub frames: u32,
    /// Methods, one backend and one sheet row each, in this order.
    pub methods: Vec<Method>,
    /// How to draw.
    pub render: RenderOptions,
    /// What to write.
    pub outputs: Outputs,
    /// The simulation's engine options (workgroup size, atomics; the device is the
    /// context's).
    pub engine: EngineOptions,
    /// The backend that steps (`cpu` or `cpu-ref`), its state copied into the `vulkan`
    /// backend's buffers at every frame drawn; `None`: `vulkan` steps, drawn in place.
    pub physics: Option<String>,
    /// Show a progress bar on stderr.
    pub progress: bool,
}

/// How one method's run went.
#[derive(Debug, Clone, PartialEq)]
pub struct MethodSummary {
    /// The method.
    pub method: Method,
    /// Smallest total volume over the frames [% of rest].
    pub min_volume_pct: f64,
    /// Total volume after the last frame run [% of rest].
    pub final_volume_pct: f64,
    /// Frames run before the end (or divergence).
    pub frames_run: u32,
    /// Why it stopped early, if it did.
    pub divergence: Option<String>,
}

/// What a render run did and what it cost.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderReport {
    /// Per method, in the job's order.
    pub methods: Vec<MethodSummary>,
    /// Images rendered (one method at one frame, with or without legend).
    pub images: u32,
    /// Wall time spent stepping the simulations [s] (all methods).
    pub step_s: f64,
    /// Wall time spent rendering and reading back images [s].
    pub render_s: f64,
    /// Wall time spent composing, encoding and writing files [s].
    pub write_s: f64,
    /// Samples per pixel used.
    pub samples: u32,
    /// Validation-layer messages (empty when validation is off).
    pub validation_messages: Vec<String>,
}

struct Run {
    method: Method,
    /// Holds what the renderer draws from (and steps, without `physics`).
    backend: VulkanBackend,
    /// The backend that steps, when it is not `backend`.
    physics: Option<Box<dyn Backend>>,
    sim: Simulation,
}

impl Run {
    /// Steps one frame.
    fn advance(&mut self) -> Result<()> {
        let stepper: &mut dyn Backend = match self.physics.as_mut() {
            Some(b) => b.as_mut(),
            None => &mut self.backend,
        };
        self.sim.advance(stepper, true)?;
        Ok(())
    }

    /// The state of the backend that steps.
    fn state(&mut self) -> Result<State> {
        match self.physics.as_mut() {
            Some(b) => b.state(),
            None => self.backend.state(),
        }
    }

    /// Puts the stepping backend's state into the buffers drawn from (nothing to do when
    /// `vulkan` steps).
    fn sync(&mut self) -> Result<()> {
        if let Some(b) = self.physics.as_mut() {
            let state = b.state()?;
            self.backend.set_state(&state)?;
        }
        Ok(())
    }

    /// The volume after the last frame run [% of rest] (100 before the first).
    fn volume_pct(&self) -> f64 {
        self.sim.last_volume_pct().unwrap_or(100.0)
    }

    /// What the run did, for the report.
    fn summary(&self) -> MethodSummary {
        let series = &self.sim.series.volume_pct;
        MethodSummary {
            method: self.method,
            min_volume_pct: series.iter().copied().fold(100.0, f64::min),
            final_volume_pct: self.volume_pct(),
            frames_run: series.len() as u32,
            divergence: self.sim.divergence.clone(),
        }
    }
}

/// Renders each method's images, made lazily: with and without the legend.
struct Shots {
    images: [Option<Image>; 2],
}

impl Shots {
    fn get(
        &mut self,
        renderer: &mut Renderer,
        run: &Run,
        legend: bool,
        render_s: &mut f64,
        count: &mut u32,
    ) -> Result<&Image> {
        let slot = &mut self.images[usize::from(legend)];
        if slot.is_none() {
            let t0 = Instant::now();
            *slot = Some(renderer.render(run.backend.draw_buffers(), legend, run.sim.time())?);
            *render_s += t0.elapsed().as_secs_f64();
            *count += 1;
        }
        slot.as_ref()
            .ok_or_else(|| Error::Gpu("a rendered image went missing".into()))
    }
}

/// Runs `job` for `model` with `params` (its method replaced by each of `job.methods`) on
/// `ctx`, writing the requested outputs.
pub fn render_methods(
    ctx: &Arc<Context>,
    model: &Model,
    params: &SimParams,
    job: &RenderJob,
) -> Result<RenderReport> {
    job.outputs.validate()?;
    if job.methods.is_empty() {
        return Err(Error::param("method", "no method to render"));
    }
    let mut renderer = Renderer::new(ctx, model, &job.render)?;
    let mut runs = job
        .methods
        .iter()
        .map(|&method| {
            let p = SimParams {
                method,
                ..params.clone()
            };
            Ok(Run {
                method,
                backend: VulkanBackend::with_context_and_options(
                    ctx.clone(),
                    model,
                    &p,
                    &job.engine,
                )?,
                physics: job
                    .physics
                    .as_deref()
                    .map(|name| create_backend(name, model, &p))
                    .transpose()?,
                sim: Simulation::new(model, &p),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let out = &job.outputs;
    let seconds_per_frame = params.frame_time();
    let gif_every = out.gif_every.unwrap_or((job.frames / 60).max(1));
    let sheet_frames = out.sheet_frames(job.frames);
    let mut sheet_cells: Vec<Vec<Image>> = vec![Vec::new(); runs.len()];
    let mut gif: Option<GifWriter> = None;
    let bar = progress_bar(job);
    let (mut step_s, mut render_s, mut write_s, mut images) = (0.0, 0.0, 0.0, 0u32);
    if let Some(dir) = &out.frames_dir {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }

    let mut recorders: Vec<_> = match &out.meshes {
        Some(meshes) => (runs.iter())
            .map(|run| meshes.recorder(model, run.method, params.frame_time()))
            .collect(),
        None => Vec::new(),
    };
    for frame in 0..=job.frames {
        if frame > 0 {
            let t0 = Instant::now();
            for run in runs.iter_mut() {
                run.advance()?;
            }
            step_s += t0.elapsed().as_secs_f64();
            bar.inc(1);
        }
        if let Some(meshes) = &out.meshes {
            if frame % meshes.every == 0 {
                for (run, recorder) in runs.iter_mut().zip(&mut recorders) {
                    recorder.record(frame, &run.state()?)?;
                }
            }
        }
        let want_file = out.frames_dir.is_some() && frame % out.every.max(1) == 0;
        let want_gif = out.gif.is_some() && (frame % gif_every == 0 || frame == job.frames);
        let sheet_column = out
            .sheet
            .as_ref()
            .and_then(|_| sheet_frames.iter().position(|&f| f == frame));
        if !(want_file || want_gif || sheet_column.is_some()) {
            continue;
        }
        for run in runs.iter_mut() {
            run.sync()?;
        }
        let time = format!("t = {:.3} s", f64::from(frame) * seconds_per_frame);
        let last = runs.len() - 1;
        let mut gif_cells = Vec::new();
        for (k, run) in runs.iter().enumerate() {
            let mut shots = Shots {
                images: [None, None],
            };
            let volume = format!("V {:.1} %", run.volume_pct());
            if let Some(dir) = out.frames_dir.as_ref().filter(|_| want_file) {
                let mut image = shots
                    .get(&mut renderer, run, true, &mut render_s, &mut images)?
                    .clone();
                let t0 = Instant::now();
                sheet::caption(&mut image, &[&format!("{}  {time}", run.method), &volume]);
                image.save_png(&dir.join(format!("{}_{frame:05}.png", run.method)), false)?;
                write_s += t0.elapsed().as_secs_f64();
            }
            if want_gif {
                let mut image = shots
                    .get(&mut renderer, run, k == last, &mut render_s, &mut images)?
                    .clone();
                let top = if k == 0 {
                    format!("{}  {time}", run.method)
                } else {
                    run.method.to_string()
                };
                sheet::caption(&mut image, &[&top, &volume]);
                gif_cells.push(image);
            }
            if let Some(column) = sheet_column {
                let legend = k == 0 && column + 1 == sheet_frames.len();
                let mut image = shots
                    .get(&mut renderer, run, legend, &mut render_s, &mut images)?
                    .clone();
                sheet::caption(&mut image, &[&volume]);
                sheet_cells[k].push(image);
            }
        }
        if want_gif {
            let t0 = Instant::now();
            let strip = sheet::row(&gif_cells);
            if gif.is_none() {
                let delay = (100.0 * seconds_per_frame * f64::from(gif_every))
                    .round()
                    .clamp(2.0, 500.0) as u16;
                gif = Some(GifWriter::new(strip.width, strip.height, delay)?);
            }
            if let Some(g) = gif.as_mut() {
                g.push(&strip)?;
            }
            write_s += t0.elapsed().as_secs_f64();
        }
    }
    bar.finish_and_clear();

    let t0 = Instant::now();
    for recorder in recorders {
        recorder.finish()?;
    }
    if let (Some(path), Some(g)) = (&out.gif, gif) {
        g.finish(path)?;
    }
    if let Some(path) = &out.sheet {
        let columns: Vec<String> = sheet_frames
            .iter()
            .map(|&f| format!("t = {:.2} s", f64::from(f) * seconds_per_frame))
            .collect();
        let rows: Vec<Vec<String>> = runs
            .iter()
            .map(|r| {
                vec![
                    r.method.to_string(),
                    format!("min {:.1} %", r.summary().min_volume_pct),
                ]
            })
            .collect();
        sheet::contact_sheet(&sheet_cells, &columns, &rows).save_png(path, true)?;
    }
    write_s += t0.elapsed().as_secs_f64();
    Ok(RenderReport {
        methods: runs.iter().map(Run::summary).collect(),
        images,
        step_s,
        render_s,
        write_s,
        samples: renderer.samples(),
        validation_messages: ctx.validation_messages(),
    })
}

fn progress_bar(job: &RenderJob) -> ProgressBar {
    if !job.progress {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(u64::from(job.frames));
    if let Ok(style) =
        ProgressStyle::with_template("{prefix:>9} [{bar:40}] {pos}/{len} frames ({eta})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix("render");
    bar
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sheet_frames_span_the_run_evenly() {
        let o = Outputs {
            sheet_columns: 5,
            ..Default::default()
        };
        assert_eq!(o.sheet_frames(400), vec![0, 100, 200, 300, 400]);
        let one = Outputs {
            sheet_columns: 1,
            ..Default::default()
        };
        assert_eq!(one.sheet_frames(7), vec![7]);
    }

    #[test]
    fn outputs_need_something_to_write() {
        let none = Outputs::default();
        assert!(none
            .validate()
            .unwrap_err()
            .to_string()
            .contains("nothing to write"));
        let frames = Outputs {
            frames_dir: Some("x".into()),
            every: 0,
            ..Default::default()
        };
        assert!(frames.validate().unwrap_err().to_string().contains("every"));
    }
}
