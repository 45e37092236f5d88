//! `tetrasim render`: `run`'s scene and physics flags, drawn from the `vulkan` backend's
//! buffers (stepped there, or on `--backend cpu|cpu-ref` and copied there at each frame
//! drawn), plus what to draw and where to write it.

use std::path::PathBuf;
use std::sync::Arc;

use super::run::RunArgs;
use crate::render_session::{render_methods, Outputs, RenderJob};
use tetrasim::gpu::{Context, ContextOptions};
use tetrasim::render::{parse_size, Camera, ColourMode, RenderOptions};

/// Arguments of `tetrasim render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The scene and physics, as for `run` (`--backend`: `vulkan` by default, which steps
    /// in the buffers the picture is drawn from; `cpu` or `cpu-ref` step on the CPU and
    /// their state is uploaded at each frame drawn; `--every` is the period of
    /// `--frames-dir` and `--out-dir`).
    #[command(flatten)]
    pub run: RunArgs,
    /// Write a PNG of each method every `--every` frames into this folder
    /// (`METHOD_FFFFF.png`).
    #[arg(long)]
    pub frames_dir: Option<PathBuf>,
    /// Write an animated GIF of the methods side by side.
    #[arg(long)]
    pub gif: Option<PathBuf>,
    /// Frames between GIF frames (default: about 60 GIF frames over the run).
    #[arg(long)]
    pub gif_every: Option<u32>,
    /// Write a contact sheet: one row per method, `--sheet-frames` frames side by side.
    #[arg(long)]
    pub sheet: Option<PathBuf>,
    /// Columns of the contact sheet (frames sampled evenly from the first to the last).
    #[arg(long, default_value_t = 5)]
    pub sheet_frames: u32,
    /// Image size WIDTHxHEIGHT in pixels (of one method's picture).
    #[arg(long, default_value = "480x360")]
    pub size: String,
    /// Camera `ex,ey,ez,tx,ty,tz` [m] (default: fitted to the object's starting bounds).
    #[arg(long, allow_hyphen_values = true)]
    pub camera: Option<String>,
    /// Surface colour: flat, volume (V/V0 per node) or strain (per node, of its springs).
    #[arg(long, value_enum, default_value = "volume")]
    pub colour: ColourMode,
    /// Half range of the colour map around neutral (default 0.5 for volume, 0.2 for strain).
    #[arg(long)]
    pub range: Option<f32>,
    /// Multisample anti-aliasing samples per pixel (4, 2 or 1).
    #[arg(long, default_value_t = 4)]
    pub samples: u32,
}

/// Runs `tetrasim render`.
pub fn execute(args: RenderArgs) -> anyhow::Result<()> {
    let run = &args.run;
    let physics = match run.backend.as_deref() {
        None | Some("vulkan") => None,
        Some(b @ ("cpu" | "cpu-ref")) => Some(b.to_string()),
        Some(other) => {
            return Err(tetrasim::Error::param(
                "backend",
                format!("`{other}`: `render` steps on vulkan (the default), cpu or cpu-ref"),
            )
            .into())
        }
    };
    if run.json.is_some() {
        anyhow::bail!("--json is not written by `render`; use `tetrasim run --json FILE`");
    }
    for (flag, given) in [
        ("checkpoint", run.checkpoint.is_some()),
        ("resume", run.resume.is_some()),
    ] {
        if given {
            let message = "`render` neither saves nor resumes runs; the flag is `tetrasim run`'s";
            return Err(tetrasim::Error::param(flag, message).into());
        }
    }
    if run.gpu.frames_in_flight.is_some() {
        return Err(tetrasim::Error::param(
            "frames-in-flight",
            "`render` draws every frame it steps from the GPU's buffers, one frame at a time; \
             the flag is `tetrasim run`'s",
        )
        .into());
    }
    if run.every.is_some() && args.frames_dir.is_none() && run.out_dir.is_none() {
        return Err(tetrasim::Error::param(
            "every",
            "acts only with --frames-dir or --out-dir, and neither is given",
        )
        .into());
    }
    let (width, height) = parse_size(&args.size)?;
    let camera = args
        .camera
        .as_deref()
        .map(str::parse::<Camera>)
        .transpose()?;
    let render = RenderOptions {
        width,
        height,
        samples: args.samples,
        colour: args.colour,
        range: args.range,
        camera,
    };
    render.validate()?;
    let (scene, methods) = run.scene_and_methods()?;
    if scene.output.json.is_some() {
        anyhow::bail!("the scene's output.json is not written by `render`; use `tetrasim run`");
    }
    let output = &scene.output;
    crate::runner::prepare_outputs(output)?;
    if let Some(dir) = &args.frames_dir {
        crate::runner::create_dir(dir)?;
    }
    for file in [&args.gif, &args.sheet].into_iter().flatten() {
        crate::runner::prepare_output_file(file)?;
    }
    let every = run
        .every
        .or(scene.output.every)
        .unwrap_or(crate::scene::DEFAULT_EVERY);
    let staged = run.stage(&scene)?;
    for note in &staged.notes {
        eprintln!("{note}");
    }
    let (model, params) = (&staged.model, &staged.params);
    let engine = run.gpu.engine_options();
    let ctx = Arc::new(Context::new(&ContextOptions {
        device: engine.device.clone(),
        validation: engine.validation,
    })?);
    let job = RenderJob {
        frames: staged.frames,
        methods,
        render,
        outputs: Outputs {
            frames_dir: args.frames_dir.clone(),
            every,
            gif: args.gif.clone(),
            gif_every: args.gif_every,
            sheet: args.sheet.clone(),
            sheet_columns: args.sheet_frames,
            meshes: crate::runner::frame_output(output)?,
        },
        engine,
        physics: physics.clone(),
        progress: !run.quiet,
    };
    eprintln!(
        "{}: {} nodes, {} tets, {} surface triangles, {} colliders; {} frames stepped on {}, drawn on `{}`, {}x{} pixels",
        staged.label,
        model.node_count(),
        model.tets.len(),
        model.surface.len(),
        model.colliders.len(),
        staged.frames,
        physics.as_deref().unwrap_or("vulkan"),
        ctx.info().name,
        width,
        height
    );
    let report = render_methods(&ctx, model, params, &job)?;
    println!("method    min vol %  final vol %  frames");
    for m in &report.methods {
        println!(
            "{:<9} {:>9.2}  {:>11.2}  {:>6}{}",
            m.method.name(),
            m.min_volume_pct,
            m.final_volume_pct,
            m.frames_run,
            m.divergence
                .as_deref()
                .map(|d| format!("  {d}"))
                .unwrap_or_default()
        );
    }
    let steps = f64::from(staged.frames) * report.methods.len() as f64;
    println!(
        "stepping {:.3} ms/frame/method; rendering {:.3} ms/image ({} images, {} samples/pixel); writing {:.3} s in all",
        1e3 * report.step_s / steps.max(1.0),
        1e3 * report.render_s / f64::from(report.images.max(1)),
        report.images,
        report.samples,
        report.write_s
    );
    for message in &report.validation_messages {
        eprintln!("validation: {message}");
    }
    for (what, path) in [
        ("frames", &args.frames_dir),
        ("gif", &args.gif),
        ("sheet", &args.sheet),
    ] {
        if let Some(p) = path {
            eprintln!("{what} written to {}", p.display());
        }
    }
    Ok(())
}
