//! `tetrasim bench`: headless benchmark of mesh x method x backend (see [`crate::bench`]).

use std::path::PathBuf;

use anyhow::Context as _;

use super::gpu_args::GpuArgs;
use crate::bench::suite::{pass_lines, table, write_json};
use crate::bench::{
    run_suite, Backends, BenchMesh, BenchOptions, ReferenceSettings, SimulateOptions,
    BUNDLED_MESHES,
};
use crate::preset::Preset;
use tetrasim::params::Method;
use tetrasim::sim::{build_model, load_mesh, BACKENDS};

/// Whether a Vulkan device exists.
pub fn vulkan_available() -> bool {
    matches!(tetrasim::gpu::list_devices(), Ok(d) if !d.is_empty())
}

/// The backends to use: `given`, or `defaults` minus `vulkan` when no device exists (with a
/// note). Unknown names are errors.
pub fn choose_backends(given: &[String], defaults: &[&str]) -> anyhow::Result<Vec<String>> {
    for b in given {
        if !BACKENDS.contains(&b.as_str()) {
            anyhow::bail!(
                "unknown backend `{b}`; known backends: {}",
                BACKENDS.join(", ")
            );
        }
    }
    if !given.is_empty() {
        return Ok(given.to_vec());
    }
    let vulkan = vulkan_available();
    if !vulkan {
        eprintln!("note: no Vulkan device, so no `vulkan` rows (install mesa-vulkan-drivers)");
    }
    Ok(defaults
        .iter()
        .filter(|&&b| b != "vulkan" || vulkan)
        .map(|b| b.to_string())
        .collect())
}

/// A bundled mesh's name as a path: `load_mesh` reads it from the working directory when it
/// is there, else from the copy compiled into the binary (`tetrasim::sim::bundled`).
pub fn bundled_path(prefix: &str) -> PathBuf {
    PathBuf::from(prefix)
}

/// Arguments of `tetrasim bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Benchmark this scene (TOML, as `run --scene`: its objects, materials, pins,
    /// colliders and solver) instead of the bundled meshes; the methods are the scene's
    /// unless --method names others, and --iterations, --solver and --substeps override its
    /// solver.
    #[arg(long, conflicts_with_all = ["mesh", "no_bundled"])]
    pub scene: Option<PathBuf>,
    /// Also benchmark this mesh (TetGen prefix); repeatable.
    #[arg(long)]
    pub mesh: Vec<PathBuf>,
    /// Leave out the bundled meshes (meshes/sphere, box, torus).
    #[arg(long)]
    pub no_bundled: bool,
    /// Methods (default: all four); repeatable or comma-separated.
    #[arg(long, value_enum, value_delimiter = ',')]
    pub method: Vec<Method>,
    /// Backends: vulkan, cpu, cpu-ref (default: vulkan and cpu); repeatable or
    /// comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub backend: Vec<String>,
    /// Warm-up frames, simulated but not timed (default 20; --quick 5). The 0.1 m drop
    /// lasts 143 frames: runs shorter than that never reach the floor.
    #[arg(long)]
    pub warmup: Option<u32>,
    /// Timed frames (default 280; --quick 60).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Few frames: a smoke run that finishes in well under two minutes.
    #[arg(long)]
    pub quick: bool,
    /// Constraint iterations per time step (default: the seed preset's 10).
    #[arg(long)]
    pub iterations: Option<u32>,
    /// Time steps per frame (default 1); dt is scaled to keep 1 ms of simulated time per frame.
    #[arg(long)]
    pub substeps: Option<u32>,
    /// Solver of the constraint methods, `jacobi`, `chebyshev` or
    /// `gauss-seidel[:GROUPS|:blockB[xS]]` (blocks of B tets, each swept S times), optionally with `+global`, `+andersonM` and `+inversionN` (default: the engine's,
    /// gauss-seidel:8+global).
    #[arg(long)]
    pub solver: Option<crate::bench::tradeoff::SolverSetting>,
    /// Also measure the position error against a converged cpu-ref run (slow).
    #[arg(long)]
    pub accuracy: bool,
    /// Iterations of the reference run.
    #[arg(long, default_value_t = 100)]
    pub ref_iterations: u32,
    /// Substeps of the reference run.
    #[arg(long, default_value_t = 8)]
    pub ref_substeps: u32,
    /// Write one JSON record per (mesh, method, backend) to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// GPU options of the `vulkan` rows.
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// Runs `tetrasim bench`.
pub fn execute(args: BenchArgs) -> anyhow::Result<()> {
    let preset = Preset::seed();
    let staged = match &args.scene {
        Some(path) => {
            let scene = crate::scene::Scene::load(path).map_err(super::BadScene)?;
            Some(crate::launch::stage(&scene)?)
        }
        None => None,
    };
    let mut params = match &staged {
        Some(staged) => staged.params.clone(),
        None => preset.params.clone(),
    };
    if let Some(it) = args.iterations {
        params.iterations = it;
    }
    if let Some(solver) = args.solver {
        params = solver.apply(&params);
    }
    if let Some(ss) = args.substeps {
        params.dt = params.frame_time() / f64::from(ss.max(1));
        params.substeps = ss;
    }
    params.validate()?;
    if let Some(path) = &args.json {
        crate::runner::prepare_output_file(path)?;
    }
    let mut paths: Vec<PathBuf> = Vec::new();
    let scene_method = staged.as_ref().map(|s| s.params.method);
    let mut meshes = Vec::new();
    if let Some(staged) = staged {
        meshes.push(BenchMesh {
            label: staged.label,
            model: staged.model,
        });
    } else if !args.no_bundled {
        paths.extend(BUNDLED_MESHES.iter().map(|p| bundled_path(p)));
    }
    paths.extend(args.mesh.iter().cloned());
    if paths.is_empty() && meshes.is_empty() {
        anyhow::bail!("no meshes: give --mesh or --scene, or leave out --no-bundled");
    }
    for path in &paths {
        let loaded = load_mesh(path, None)?;
        let model = build_model(&loaded.mesh, &params, preset.placement)
            .with_context(|| format!("building the model of {}", loaded.label))?;
        meshes.push(BenchMesh {
            label: loaded.label,
            model,
        });
    }
    let (warmup, frames) = if args.quick { (5, 60) } else { (20, 280) };
    let options = BenchOptions {
        methods: match (args.method.is_empty(), scene_method) {
            (false, _) => args.method.clone(),
            (true, Some(method)) => vec![method],
            (true, None) => Method::ALL.to_vec(),
        },
        backends: choose_backends(&args.backend, &["vulkan", "cpu"])?,
        frames: SimulateOptions {
            warmup: args.warmup.unwrap_or(warmup),
            frames: args.frames.unwrap_or(frames),
            sample_every: None,
        },
        reference: args.accuracy.then(|| ReferenceSettings {
            backend: "cpu-ref".into(),
            iterations: args.ref_iterations,
            substeps: args.ref_substeps,
        }),
    };
    // Each method's solve, as `run`'s header names it (the finite elements' is a Newton
    // step, not the sweeps').
    let mut solvers: Vec<String> = (options.methods.iter())
        .map(|&method| {
            super::run::solver_label(&tetrasim::params::SimParams {
                method,
                ..params.clone()
            })
        })
        .collect();
    solvers.dedup();
    let solvers = solvers.join(" / ");
    eprintln!(
        "bench: {} meshes x {} methods x backends {}; {} warm-up + {} timed frames; dt {} s x {} substeps, {} iterations, solver {}",
        meshes.len(),
        options.methods.len(),
        options.backends.join(", "),
        options.frames.warmup,
        options.frames.frames,
        params.dt,
        params.substeps,
        params.iterations,
        solvers,
    );
    let mut backends = Backends::new(args.gpu.engine_options());
    let records = run_suite(&meshes, &params, &options, &mut backends, &mut |r| {
        eprintln!(
            "  {} {} {}: {:.3} ms/frame",
            r.run.mesh, r.run.method, r.run.backend, r.run.ms_per_frame
        )
    })?;
    print!("{}", table(&records));
    let runs: Vec<_> = records.iter().map(|r| r.run.clone()).collect();
    eprint!("{}", tetrasim::metrics::short_run_warnings(&runs));
    print!("{}", pass_lines(&records));
    if let Some(path) = &args.json {
        write_json(path, &records)?;
        eprintln!("records written to {}", path.display());
    }
    Ok(())
}
