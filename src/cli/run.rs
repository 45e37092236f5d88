//! `tetrasim run`: a scene file (`--scene FILE`), or the preset overridden by flags, which
//! build a one-object scene; both go through [`crate::launch::stage`].

use std::path::PathBuf;

use anyhow::Context as _;

use crate::engine::EngineOptions;
use crate::launch::stage;
use crate::metrics::{pass_table, short_run_warnings, table, write_json};
use crate::params::{
    AtomicsMode, ConstraintCombine, MassMode, Method, SimParams, Solver as SolverKind,
};
use crate::preset::{Preset, PresetName};
use crate::runner::{run_methods, OutputFormat, OutputUnits, RunOptions, DEFAULT_MESH};
use crate::scene::{Collider, Material, Object, Output, Pin, Scene, Solver};

/// `--method` values: one method or `all`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodChoice {
    /// Springs only, spring-centric.
    Mss,
    /// Springs only, node-centric.
    MssNode,
    /// Springs and distance constraints.
    Distance,
    /// Springs and volume constraints.
    Volume,
    /// mss, distance and volume (the paper's three), in that order.
    All,
}

impl MethodChoice {
    /// The methods this choice runs, in order.
    pub fn methods(self) -> Vec<Method> {
        match self {
            MethodChoice::Mss => vec![Method::Mss],
            MethodChoice::MssNode => vec![Method::MssNode],
            MethodChoice::Distance => vec![Method::Distance],
            MethodChoice::Volume => vec![Method::Volume],
            MethodChoice::All => vec![Method::Mss, Method::Distance, Method::Volume],
        }
    }
}

/// Arguments of `tetrasim run`. Every physics value defaults to the preset's.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// A scene file (TOML, see `tetrasim::scene`): objects, colliders, solver and outputs.
    /// The mesh, physics and output flags below must not be given with it.
    #[arg(long, conflicts_with_all = SCENE_CONFLICTS)]
    pub scene: Option<PathBuf>,
    /// Tet mesh (TetGen PREFIX, .vtk, .vtu, .msh, .mesh) or a surface file (.ply/.obj/.off/.stl).
    #[arg(long, default_value = DEFAULT_MESH)]
    pub mesh: PathBuf,
    /// When --mesh is a surface: tets to aim at when meshing it in-process (default 5000;
    /// refused with a tet mesh).
    #[arg(long)]
    pub target_tets: Option<usize>,
    /// Method to run.
    #[arg(long, value_enum, default_value = "all")]
    pub method: MethodChoice,
    /// Solver backend: cpu-ref (f64 reference), cpu (f32, all cores; the default) or vulkan
    /// (GPU).
    #[arg(long)]
    pub backend: Option<String>,
    /// GPU for `--backend vulkan`: an index or a name fragment from `tetrasim info`
    /// (default: discrete > integrated > virtual > CPU).
    #[arg(long)]
    pub device: Option<String>,
    /// Float atomics of the GPU scatter passes: auto, ext (atomicAdd on float) or cas.
    #[arg(long, value_enum)]
    pub atomics: Option<AtomicsMode>,
    /// GPU workgroup size (a power of two; default from the device limits, at most 1024).
    #[arg(long)]
    pub workgroup_size: Option<u32>,
    /// Turn on the Vulkan validation layer and print its messages.
    #[arg(long)]
    pub validation: bool,
    /// Parameter preset; the flags below override its values.
    #[arg(long, value_enum, default_value = "seed")]
    pub preset: PresetName,
    /// Frames to simulate.
    #[arg(long)]
    pub frames: Option<u32>,
    /// Time step [s].
    #[arg(long)]
    pub dt: Option<f64>,
    /// Time steps per frame.
    #[arg(long)]
    pub substeps: Option<u32>,
    /// Constraint iterations per time step.
    #[arg(long)]
    pub iterations: Option<u32>,
    /// Relaxation factor of the constraint forces.
    #[arg(long)]
    pub omega: Option<f64>,
    /// Spring stiffness [N/m].
    #[arg(long)]
    pub ks: Option<f64>,
    /// Spring damping [N s/m].
    #[arg(long)]
    pub kd: Option<f64>,
    /// Fraction of tangential velocity removed on floor contact, in [0, 1].
    #[arg(long)]
    pub friction: Option<f64>,
    /// Gravity along -Y [m/s^2].
    #[arg(long)]
    pub gravity: Option<f64>,
    /// How constraint forces are combined: `scaled` (momentum-conserving, default), `sum`
    /// (the paper's literal reading), `average` (first edition, drifts; for comparison).
    #[arg(long, value_enum)]
    pub combine: Option<ConstraintCombine>,
    /// How each iteration sweeps the constraints: `gauss-seidel` (colour groups, default),
    /// `jacobi` (the paper's method) or `chebyshev` (Jacobi with Chebyshev semi-iteration).
    #[arg(long, value_enum)]
    pub solver: Option<SolverKind>,
    /// Colour groups of the Gauss-Seidel solver (default 8).
    #[arg(long)]
    pub groups: Option<u32>,
    /// Spectral radius estimate of the Chebyshev solver, in (0, 1) (default 0.95).
    #[arg(long)]
    pub rho: Option<f64>,
    /// One global volume constraint per object, solved after the local constraints in every
    /// iteration: `true` (`--global-volume` alone) or `false`; default: on for
    /// `gauss-seidel`, off for `jacobi` (the paper's method) and `chebyshev`.
    #[arg(long, num_args = 0..=1, default_missing_value = "true", value_name = "BOOL")]
    pub global_volume: Option<bool>,
    /// Skip a constraint whose denominator A is at or below this.
    #[arg(long)]
    pub epsilon: Option<f64>,
    /// Mass of every node [kg] (the preset: 1).
    #[arg(long, conflicts_with = "density")]
    pub node_mass: Option<f64>,
    /// Lumped masses from this density [kg/m^3] instead of equal node masses.
    #[arg(long)]
    pub density: Option<f64>,
    /// Remove the floor (free fall).
    #[arg(long)]
    pub no_floor: bool,
    /// Scale the mesh so its bounding box's largest side is this long [m].
    #[arg(long)]
    pub fit_size: Option<f64>,
    /// Height of the lowest node above the floor at the start [m].
    #[arg(long)]
    pub drop_height: Option<f64>,
    /// Write the run records (one JSON object per method, with a time axis) to this file
    /// (its folder is created first; `--metrics` is the older name).
    #[arg(long, alias = "metrics", value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Write the deformed mesh every `--every` frames into this folder (created with its
    /// parents before the run starts).
    #[arg(long, value_name = "DIR")]
    pub out_dir: Option<PathBuf>,
    /// Frames between mesh files in --out-dir (default 10).
    #[arg(long)]
    pub every: Option<u32>,
    /// Mesh file format in --out-dir: ply (surface, per-vertex quality V/V0; default), obj
    /// (surface), vtk or vtu (tet mesh with displacement, velocity, V/V0, inverted; vtu adds
    /// METHOD.pvd, a ParaView time series with the simulated times).
    #[arg(long, value_enum)]
    pub format: Option<OutputFormat>,
    /// Units of the files in --out-dir: simulation (metres, fitted and lifted; default) or
    /// input (the mesh file's own units and position, to overlay the scan).
    #[arg(long, value_enum)]
    pub units: Option<OutputUnits>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// The flags a scene file replaces.
const SCENE_CONFLICTS: [&str; 27] = [
    "mesh",
    "method",
    "preset",
    "frames",
    "dt",
    "substeps",
    "iterations",
    "omega",
    "ks",
    "kd",
    "friction",
    "gravity",
    "combine",
    "solver",
    "groups",
    "rho",
    "global_volume",
    "epsilon",
    "node_mass",
    "density",
    "no_floor",
    "fit_size",
    "drop_height",
    "json",
    "out_dir",
    "format",
    "units",
];

impl RunArgs {
    /// The preset with every given flag applied.
    pub fn preset(&self) -> Preset {
        let mut p = Preset::named(self.preset);
        let s = &mut p.params;
        macro_rules! set {
            ($($field:ident => $target:expr),*) => { $(if let Some(v) = self.$field { $target = v; })* };
        }
        set!(frames => p.frames, dt => s.dt, substeps => s.substeps, iterations => s.iterations,
             omega => s.omega, ks => s.ks, kd => s.kd, friction => s.friction, gravity => s.gravity,
             combine => s.combine, solver => s.solver, groups => s.groups, rho => s.rho, epsilon => s.constraint_epsilon, atomics => s.atomics);
        if let Some(mass) = self.node_mass {
            s.mass = MassMode::PerNode { mass };
        }
        if let Some(density) = self.density {
            s.mass = MassMode::Density { density };
        }
        if self.no_floor {
            s.floor = false;
        }
        if self.global_volume.is_some() {
            s.global_volume = self.global_volume;
        }
        if let Some(size) = self.fit_size {
            p.placement.fit_size = Some(size);
        }
        if let Some(height) = self.drop_height {
            p.placement.drop_height = Some(height);
        }
        p
    }

    /// The one-object scene these flags stand for (method: the first of `--method`).
    pub fn scene(&self) -> Scene {
        let p = self.preset();
        let s = &p.params;
        let (node_mass, density) = match s.mass {
            MassMode::PerNode { mass } => (Some(mass), None),
            MassMode::Density { density } => (None, Some(density)),
        };
        Scene {
            solver: Solver {
                dt: s.dt,
                substeps: s.substeps,
                iterations: s.iterations,
                omega: s.omega,
                combine: s.combine,
                solver: s.solver,
                groups: self.groups,
                global_volume: s.global_volume,
                rho: self.rho,
                atomics: s.atomics,
                epsilon: s.constraint_epsilon,
                gravity: s.gravity,
                frames: p.frames,
            },
            objects: vec![Object {
                mesh: self.mesh.clone(),
                target_tets: self.target_tets,
                method: self.method.methods()[0],
                fit_size: p.placement.fit_size,
                drop_height: p.placement.drop_height,
                velocity: [0.0; 3],
                material: Material {
                    ks: s.ks,
                    kd: s.kd,
                    node_mass,
                    density,
                },
                pin: Pin::default(),
            }],
            colliders: if s.floor {
                vec![Collider::Floor {
                    friction: s.friction,
                }]
            } else {
                Vec::new()
            },
            output: Output {
                json: self.json.clone(),
                dir: self.out_dir.clone(),
                // `--every` also sets render's picture period; it belongs to the mesh
                // files only when there are some (run refuses it alone, see `execute`).
                every: self.every.filter(|_| self.out_dir.is_some()),
                format: self.format,
                units: self.units,
            },
        }
    }

    /// Refuses solver flags the chosen solver does not use (`--groups` without
    /// Gauss-Seidel, `--rho` without Chebyshev) instead of ignoring them.
    fn check_solver_flags(&self, params: &SimParams) -> crate::Result<()> {
        let refuse = |flag: &str, solver: &str| {
            Err(crate::Error::param(
                flag,
                format!(
                    "acts only with --solver {solver}; the solver is {}",
                    params.solver
                ),
            ))
        };
        if self.groups.is_some() && params.solver != SolverKind::GaussSeidel {
            return refuse("groups", "gauss-seidel");
        }
        if self.rho.is_some() && params.solver != SolverKind::Chebyshev {
            return refuse("rho", "chebyshev");
        }
        Ok(())
    }

    /// The scene to run (the file, or the flags' scene) and the methods to run it with.
    pub fn scene_and_methods(&self) -> anyhow::Result<(Scene, Vec<Method>)> {
        match &self.scene {
            Some(path) => {
                let scene = Scene::load(path)?;
                let method = scene.objects[0].method;
                Ok((scene, vec![method]))
            }
            None => {
                // Flag values are checked first so that errors name the flag (`dt`), not
                // the scene key (`solver.dt`).
                let preset = self.preset();
                preset.params.validate()?;
                self.check_solver_flags(&preset.params)?;
                if preset.frames == 0 {
                    return Err(crate::Error::param("frames", "must be at least 1").into());
                }
                let scene = self.scene();
                scene.output.check(|name| name.to_string(), "--out-dir")?;
                scene.validate()?;
                Ok((scene, self.method.methods()))
            }
        }
    }
}

/// A run that diverged: `tetrasim` exits with status 3 (after writing the metrics).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct DivergedRun(pub String);

/// `jacobi`, or `gauss-seidel (8 groups)`, with ` + global volume` when it is solved.
fn solver_label(params: &SimParams) -> String {
    let mut out = match params.solver {
        SolverKind::Jacobi => "jacobi".to_string(),
        SolverKind::GaussSeidel => format!("gauss-seidel ({} groups)", params.groups),
        SolverKind::Chebyshev => format!("chebyshev (rho {})", params.rho),
    };
    if params.global_volume_on() {
        out += " + global volume";
    }
    out
}

/// Runs `tetrasim run`.
pub fn execute(args: RunArgs) -> anyhow::Result<()> {
    let (scene, methods) = args.scene_and_methods()?;
    let backend = args.backend.as_deref().unwrap_or("cpu");
    if args.scene.is_some() && args.every.is_some() {
        return Err(crate::Error::param(
            "every",
            "with --scene the period of mesh files is the scene's `output.every`",
        )
        .into());
    }
    if backend != "vulkan" {
        let gpu_only = [
            ("device", args.device.is_some()),
            ("atomics", args.atomics.is_some()),
            ("workgroup-size", args.workgroup_size.is_some()),
            ("validation", args.validation),
        ];
        if let Some((flag, _)) = gpu_only.iter().find(|(_, given)| *given) {
            return Err(crate::Error::param(
                *flag,
                format!("acts only with --backend vulkan; the backend is {backend}"),
            )
            .into());
        }
    }
    if args.scene.is_none() && args.every.is_some() && args.out_dir.is_none() {
        return Err(
            crate::Error::param("every", "acts only with --out-dir, and none is given").into(),
        );
    }
    scene.output.prepare()?;
    let staged = stage(&scene).with_context(|| match &args.scene {
        Some(path) => format!("staging the scene {}", path.display()),
        None => format!("building the model of {}", args.mesh.display()),
    })?;
    for note in &staged.notes {
        eprintln!("{note}");
    }
    let (model, params) = (&staged.model, &staged.params);
    eprintln!(
        "{}: {} nodes ({} pinned), {} tets, {} springs; backend {}, {} frames of dt {} s x {} substeps, {} iterations, solver {}",
        staged.label,
        model.node_count(),
        model.node_count() - model.free_node_count(),
        model.tets.len(),
        model.springs.len(),
        backend,
        staged.frames,
        params.dt,
        params.substeps,
        params.iterations,
        solver_label(params)
    );
    let estimate = crate::stability::estimate(model, params);
    if estimate.exceeded_by(params.dt) {
        eprintln!(
            "warning: dt exceeds the explicit stability bound of the springs: {}; the run will \
             likely diverge (docs/STABILITY.md)",
            estimate.describe(params)
        );
    }
    let out = &scene.output;
    let output = out.frames()?;
    let options = RunOptions {
        backend: backend.to_string(),
        frames: staged.frames,
        mesh_label: staged.label.clone(),
        progress: !args.quiet,
        output,
        gpu: EngineOptions {
            device: args
                .device
                .as_deref()
                .unwrap_or("auto")
                .parse()
                .unwrap_or_default(),
            validation: args.validation,
            workgroup_size: args.workgroup_size,
            // A scene without a metrics file measures the volume only after the last frame
            // (no per-frame readback); the flags' run always prints its per-frame table.
            volume_on_demand: args.scene.is_some() && out.json.is_none(),
            untimed: false,
        },
    };
    let records = run_methods(model, params, &methods, &options)?;
    print!("{}", table(&records));
    print!("{}", pass_table(&records));
    eprint!("{}", short_run_warnings(&records));
    if let Some(path) = &out.json {
        write_json(path, &records)?;
        eprintln!("metrics written to {}", path.display());
    }
    match records.iter().find_map(|r| r.divergence.as_ref()) {
        Some(d) => Err(DivergedRun(d.clone()).into()),
        None => Ok(()),
    }
}
