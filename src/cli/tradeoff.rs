//! `tetrasim tradeoff` and `tetrasim scaling`: the speed/accuracy sweep and the size study.

use std::path::PathBuf;

use anyhow::Context as _;

use super::bench::choose_backends;
use super::gpu_args::GpuArgs;
use crate::bench::report::{equal_cost_pairs, equal_work_pairs, front_table, verdict};
use crate::bench::scaling::{self, ScalingOptions, DEFAULT_SIZES};
use crate::bench::tradeoff_files::write_outputs;
use crate::bench::{
    run_tradeoff, Backends, ReferenceSettings, SimulateOptions, SweepSpec, TradeoffOptions,
};
use crate::preset::Preset;
use tetrasim::params::Method;
use tetrasim::sim::{build_model, load_mesh};

/// Arguments of `tetrasim tradeoff`.
#[derive(Debug, clap::Args)]
pub struct TradeoffArgs {
    /// Mesh (TetGen prefix).
    #[arg(long, required_unless_present_any = ["from_json", "scene", "cantilever"])]
    pub mesh: Option<PathBuf>,
    /// Measure against physics instead of a converged run: a cantilever of 288 tets
    /// (E 10 MPa, nu 0.3 and 0.45) at rest under its weight, each method at each of
    /// --iterations (default volume and neo-hookean at 2,5,10,20,40), its displacement field
    /// against scikit-fem's P1 solution; writes cantilever.md, .csv and .json.
    #[arg(long, conflicts_with_all = ["mesh", "scene", "from_json"])]
    pub cantilever: bool,
    /// Sweep this scene (TOML, as `run --scene`: its objects, materials, pins, colliders and
    /// solver) instead of a mesh; the methods are the scene's unless --methods names others.
    #[arg(long, conflicts_with_all = ["mesh", "from_json"])]
    pub scene: Option<PathBuf>,
    /// Do not run: read the records of an earlier run (its tradeoff.json) and write the
    /// report, CSV and plots again into --out-dir.
    #[arg(long, conflicts_with = "mesh")]
    pub from_json: Option<PathBuf>,
    /// Folder for tradeoff.csv, tradeoff.json, report.md and the PNG plots.
    #[arg(long, alias = "out", value_name = "DIR")]
    pub out_dir: PathBuf,
    /// Backend whose cost is measured (vulkan, cpu, cpu-ref).
    #[arg(long, default_value = "vulkan")]
    pub backend: String,
    /// Methods (default: mss, distance, volume).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub methods: Vec<Method>,
    /// Iteration counts (default: 1,2,5,10,20,50).
    #[arg(long, value_delimiter = ',')]
    pub iterations: Vec<u32>,
    /// Solvers of the constraint methods, comma-separated, each `jacobi`, `chebyshev` or
    /// `gauss-seidel[:GROUPS|:blockB[xS]]` (blocks of B tets swept S times: block Gauss-Seidel), optionally
    /// with `+global`, `+andersonM` (Anderson
    /// acceleration of memory M) and `+inversionN` (N inversion sweeps; the volume method's
    /// points only); default: jacobi, jacobi+global, gauss-seidel:8, gauss-seidel:8+global,
    /// gauss-seidel:8+global+anderson5.
    #[arg(long, value_delimiter = ',')]
    pub solvers: Vec<crate::bench::tradeoff::SolverSetting>,
    /// Substep counts, at equal simulated time per frame (default: 1,2,4).
    #[arg(long, value_delimiter = ',')]
    pub substeps: Vec<u32>,
    /// Extra relaxation factors, at 10 iterations and the first substep count
    /// (default: 0.5,1.5).
    #[arg(long, value_delimiter = ',')]
    pub omegas: Vec<f64>,
    /// Frames per setting (default 300, --quick 200: the 0.1 m drop lasts 143 frames, then
    /// the impact and the rebound).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Of those, the first frames left out of the timing.
    #[arg(long, default_value_t = 10)]
    pub warmup: u32,
    /// Compare positions with the reference every this many frames.
    #[arg(long, default_value_t = 10)]
    pub sample_every: u32,
    /// Reference: iterations per step.
    #[arg(long, default_value_t = 100)]
    pub ref_iterations: u32,
    /// Reference: substeps per frame.
    #[arg(long, default_value_t = 8)]
    pub ref_substeps: u32,
    /// Reference: backend.
    #[arg(long, default_value = "cpu-ref")]
    pub ref_backend: String,
    /// A small sweep (iterations 1,5,20; substeps 1,2; omega 1.5) over 200 frames.
    #[arg(long)]
    pub quick: bool,
    /// GPU options of the `vulkan` rows.
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// Runs `tetrasim tradeoff`.
pub fn execute_tradeoff(args: TradeoffArgs) -> anyhow::Result<()> {
    crate::runner::create_dir(&args.out_dir)?;
    if let Some(path) = &args.from_json {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        let mut records: Vec<crate::bench::TradeoffRecord> = serde_json::from_str(&text)
            .with_context(|| format!("{}: not a tradeoff.json", path.display()))?;
        crate::bench::tradeoff::mark_pareto(&mut records);
        return finish(&args, &records);
    }
    if args.cantilever {
        return cantilever(&args);
    }
    let (model, label, params) = match (&args.scene, &args.mesh) {
        (Some(path), _) => {
            let scene = crate::scene::Scene::load(path).map_err(super::BadScene)?;
            let staged = crate::launch::stage(&scene)?;
            (staged.model, staged.label, staged.params)
        }
        (None, Some(mesh)) => {
            let preset = Preset::seed();
            let loaded = load_mesh(mesh, None)?;
            let model = build_model(&loaded.mesh, &preset.params, preset.placement)
                .with_context(|| format!("building the model of {}", loaded.label))?;
            (model, loaded.label, preset.params)
        }
        (None, None) => anyhow::bail!("give --mesh PREFIX or --scene FILE (or --from-json FILE)"),
    };
    let mut spec = if args.quick {
        SweepSpec::quick()
    } else {
        SweepSpec::default()
    };
    if !args.methods.is_empty() {
        spec.methods = args.methods.clone();
    } else if args.scene.is_some() {
        spec.methods = vec![params.method];
    }
    if !args.iterations.is_empty() {
        spec.iterations = args.iterations.clone();
    }
    if !args.solvers.is_empty() {
        spec.solvers = args.solvers.clone();
    }
    if !args.substeps.is_empty() {
        spec.substeps = args.substeps.clone();
    }
    if !args.omegas.is_empty() {
        spec.omegas = args.omegas.clone();
    }
    spec.validate()?;
    let backend = choose_backends(std::slice::from_ref(&args.backend), &[])?.remove(0);
    let total = args.frames.unwrap_or(if args.quick { 200 } else { 300 });
    if total <= args.warmup {
        anyhow::bail!("--frames {total} must exceed --warmup {}", args.warmup);
    }
    if let Some(t) = model.contact_time(params.gravity, params.floor) {
        let end = f64::from(total) * params.frame_time();
        if end < t {
            eprintln!(
                "warning: {total} frames ({end:.3} s) end before the body first reaches the floor \
                 or a collider (at {t:.3} s): the volume figures will be those of a free fall, not \
                 of the drop"
            );
        }
    }
    let options = TradeoffOptions {
        backend,
        frames: SimulateOptions {
            warmup: args.warmup,
            frames: total - args.warmup,
            sample_every: Some(args.sample_every.max(1)),
        },
        reference: ReferenceSettings {
            backend: args.ref_backend.clone(),
            iterations: args.ref_iterations,
            substeps: args.ref_substeps,
        },
    };
    let points = spec.points().len();
    eprintln!(
        "tradeoff: {} ({} tets, {} springs), {points} settings on {}, {total} frames each; references: {} iterations x {} substeps on {}",
        label,
        model.tets.len(),
        model.springs.len(),
        options.backend,
        args.ref_iterations,
        args.ref_substeps,
        args.ref_backend
    );
    let mut backends = Backends::new(args.gpu.engine_options());
    let mut done = 0;
    let records = run_tradeoff(
        &model,
        &label,
        &params,
        &spec,
        &options,
        &mut backends,
        &mut |r| {
            done += 1;
            eprintln!(
                "  [{done}/{points}] {} it {} ss {} omega {}: {:.3} ms/frame, volume error {:.3} %, local {:.3} %, pos rms {}",
                r.series(),
                r.iterations,
                r.substeps,
                r.omega,
                r.ms_per_frame,
                r.volume_error_pct,
                r.avg_local_error_pct,
                r.pos_rms_rel.map_or("-".into(), |e| format!("{e:.2e}"))
            )
        },
    )?;
    finish(&args, &records)
}

/// `tradeoff --cantilever`: springs and finite elements against scikit-fem's cantilever.
fn cantilever(args: &TradeoffArgs) -> anyhow::Result<()> {
    use crate::bench::cantilever::{run_cantilever, table};
    let methods = match args.methods.is_empty() {
        true => vec![Method::Volume, Method::NeoHookean],
        false => args.methods.clone(),
    };
    let iterations = match args.iterations.is_empty() {
        true => vec![2, 5, 10, 20, 40],
        false => args.iterations.clone(),
    };
    let most = args.frames.unwrap_or(6000);
    let backend = choose_backends(std::slice::from_ref(&args.backend), &[])?.remove(0);
    eprintln!(
        "tradeoff --cantilever: {} x iterations {iterations:?} x nu 0.3, 0.45 on {backend}, \
         each until at rest (at most {most} frames)",
        methods
            .iter()
            .map(|m| m.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let mut backends = Backends::new(args.gpu.engine_options());
    let points = run_cantilever(
        &methods,
        &iterations,
        &[0.3, 0.45],
        &backend,
        most,
        &mut backends,
        &mut |p| {
            eprintln!(
                "  nu {} {} it {}: field error {:.2} %, {} frames{}, {:.3} ms/frame",
                p.poisson_ratio,
                p.method,
                p.iterations,
                p.field_error_pct,
                p.frames,
                if p.at_rest { "" } else { " (not at rest)" },
                p.ms_per_frame
            )
        },
    )?;
    let report = table(&points);
    print!("{report}");
    let json = serde_json::to_string_pretty(&points)?;
    for (name, text) in [("cantilever.md", report), ("cantilever.json", json)] {
        let path = args.out_dir.join(name);
        crate::runner::write_atomically(&path, text.as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    let csv = args.out_dir.join("cantilever.csv");
    crate::bench::tradeoff_files::write_csv(&csv, &points)?;
    eprintln!("wrote {}", csv.display());
    Ok(())
}

/// Prints the Pareto front and the verdicts, and writes the files.
fn finish(args: &TradeoffArgs, records: &[crate::bench::TradeoffRecord]) -> anyhow::Result<()> {
    let backend = records.first().map_or("?", |r| r.backend.as_str());
    println!("Pareto front (ms per frame on {backend}, volume error):");
    print!("{}", front_table(records));
    println!("Cheapest setting per local volume error budget:");
    print!("{}", crate::bench::report::local_budget_table(records));
    println!("Substeps or iterations at equal measured cost:");
    print!("{}", verdict(&equal_cost_pairs(records)));
    println!("At equal iterations per frame (iterations x substeps):");
    print!("{}", verdict(&equal_work_pairs(records)));
    for path in write_outputs(&args.out_dir, records)? {
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

/// Arguments of `tetrasim scaling`.
#[derive(Debug, clap::Args)]
pub struct ScalingArgs {
    /// Target tet counts of the voxel-meshed sphere (default 1000,4000,16000,64000,256000).
    #[arg(long, value_delimiter = ',')]
    pub sizes: Vec<usize>,
    /// Methods (default: volume and mss).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub methods: Vec<Method>,
    /// Backends (default: vulkan and cpu).
    #[arg(long, value_delimiter = ',')]
    pub backend: Vec<String>,
    /// Warm-up frames.
    #[arg(long, default_value_t = 3)]
    pub warmup: u32,
    /// Timed frames per size.
    #[arg(long, default_value_t = 20)]
    pub frames: u32,
    /// Folder for scaling.csv, scaling.json and scaling.png.
    #[arg(long, alias = "out", value_name = "DIR")]
    pub out_dir: PathBuf,
    /// Sizes 1000 and 4000, 5 timed frames.
    #[arg(long)]
    pub quick: bool,
    /// Do not run: read an earlier scaling.json and write the CSV and plot again into --out-dir.
    #[arg(long)]
    pub from_json: Option<PathBuf>,
    /// GPU options of the `vulkan` rows.
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// Runs `tetrasim scaling`.
pub fn execute_scaling(args: ScalingArgs) -> anyhow::Result<()> {
    crate::runner::create_dir(&args.out_dir)?;
    if let Some(path) = &args.from_json {
        let text =
            std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        let records: Vec<scaling::ScalingRecord> = serde_json::from_str(&text)
            .with_context(|| format!("{}: not a scaling.json", path.display()))?;
        for path in scaling::write_outputs(&args.out_dir, &records)? {
            eprintln!("wrote {}", path.display());
        }
        return Ok(());
    }
    let preset = Preset::seed();
    let sizes = match (args.sizes.is_empty(), args.quick) {
        (false, _) => args.sizes.clone(),
        (true, true) => vec![1_000, 4_000],
        (true, false) => DEFAULT_SIZES.to_vec(),
    };
    let options = ScalingOptions {
        sizes,
        methods: if args.methods.is_empty() {
            vec![Method::Volume, Method::Mss]
        } else {
            args.methods.clone()
        },
        backends: choose_backends(&args.backend, &["vulkan", "cpu"])?,
        frames: SimulateOptions {
            warmup: args.warmup,
            frames: if args.quick { 5 } else { args.frames },
            sample_every: None,
        },
    };
    let mut backends = Backends::new(args.gpu.engine_options());
    let records = scaling::run_scaling(
        &preset.params,
        preset.placement,
        &options,
        &mut backends,
        &mut |r| {
            eprintln!(
                "  {:>8} tets {:<9} {:<8} {:>10.3} ms/frame {:>8.2} ns/element-iteration",
                r.tets, r.method, r.backend, r.ms_per_frame, r.ns_per_element_iteration
            )
        },
    )?;
    for path in scaling::write_outputs(&args.out_dir, &records)? {
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}
