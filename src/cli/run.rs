//! `tetrasim run`: a scene file (`--scene FILE`), or the preset overridden by flags, which
//! build a one-object scene; both go through [`crate::launch::stage`].

use std::path::PathBuf;

use anyhow::Context as _;

use tetrasim::backend::vulkan::EngineOptions;

use super::gpu_args::GpuArgs;
pub use super::method_choice::MethodChoice;
use super::outcome::{BadScene, DivergedRun, InterruptedRun};
use crate::launch::{stage, Staged};
use crate::overrides::{MaterialOverrides, SolverOverrides};
use crate::preset::{Preset, PresetName};
use crate::runner::{run_methods, Checkpointing, OutputFormat, OutputUnits, RunOptions};
use crate::scene::{material_method, Collider, Object, Output, Pins, Scene};
use tetrasim::metrics::{pass_table, short_run_warnings, table, write_json};
use tetrasim::params::{Method, SimParams, Solver as SolverKind};
use tetrasim::sim::DEFAULT_MESH;

/// Arguments of `tetrasim run`. Every physics value defaults to the preset's.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// A scene file (TOML, every key in docs/reference/scene.md): objects, colliders, solver and outputs.
    /// Every flag below overrides its values: the solver's, the preset's, every object's
    /// material, method, placement (--fit-size, --no-fit, --drop-height, --rotation) and
    /// --target-tets, the floor and the outputs; --mesh a one-object scene's mesh.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Tet mesh (TetGen PREFIX, .vtk, .vtu, .msh, .mesh) or a surface file (.ply/.obj/.off/.stl).
    #[arg(long, value_name = "PATH")]
    pub mesh: Option<PathBuf>,
    /// When --mesh is a surface: tets to aim at when meshing it in-process (default 5000;
    /// refused with a tet mesh).
    #[arg(long)]
    pub target_tets: Option<usize>,
    /// Method to run (default `all`, the paper's three; for a material given by
    /// --youngs-modulus `neo-hookean`, or `volume` where a flag asks for springs; with
    /// --scene, one method for every object instead of the scene's).
    #[arg(long, value_enum)]
    pub method: Option<MethodChoice>,
    /// Solver backend: cpu-ref (f64 reference), cpu (f32, all cores; the default) or vulkan
    /// (GPU).
    #[arg(long)]
    pub backend: Option<String>,
    /// GPU options (`--backend vulkan` only).
    #[command(flatten)]
    pub gpu: GpuArgs,
    /// Parameter preset; the flags below override its values.
    #[arg(long, value_enum)]
    pub preset: Option<PresetName>,
    /// Time stepping and solver (a scene's `[solver]`).
    #[command(flatten)]
    pub solver: SolverOverrides,
    /// Spring constants and mass (a scene object's `material`).
    #[command(flatten)]
    pub material: MaterialOverrides,
    /// Floor friction in [0, 1]: Coulomb's mu; a node on the floor loses this fraction of its
    /// sliding per step at most (default 0).
    #[arg(long)]
    pub friction: Option<f64>,
    /// Remove the floor (free fall).
    #[arg(long)]
    pub no_floor: bool,
    /// Scale the mesh so its bounding box's largest side is this long [m].
    #[arg(long)]
    pub fit_size: Option<f64>,
    /// Keep the mesh's own size and position (real size, e.g. with --youngs-modulus and --density):
    /// no scaling, and no lift unless --drop-height is given, which then only lifts it.
    #[arg(long, conflicts_with = "fit_size")]
    pub no_fit: bool,
    /// Height of the lowest node above the floor at the start [m].
    #[arg(long)]
    pub drop_height: Option<f64>,
    /// Turn the mesh about its bounding box's centre before placing it: a unit quaternion
    /// `w,x,y,z` (`--rotation=0.7071,-0.7071,0,0` stands a Z-up part on the floor).
    #[arg(long, value_name = "W,X,Y,Z", value_parser = parse_quaternion)]
    pub rotation: Option<[f64; 4]>,
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
    /// METHOD.pvd, a ParaView time series with the simulated times), or usd (the whole run
    /// as one animated stage, METHOD.usda, written when it ends).
    #[arg(long, value_enum)]
    pub format: Option<OutputFormat>,
    /// Units of the files in --out-dir: simulation (metres, fitted and lifted; default) or
    /// input (the mesh file's own units and position, to overlay the scan).
    #[arg(long, value_enum)]
    pub units: Option<OutputUnits>,
    /// Save the run to this checkpoint file when it ends, and every --checkpoint-every
    /// frames (each replacing the last, through a temporary file): `--resume FILE` continues
    /// it bit for bit (one method; cpu-ref, cpu, and vulkan without warm-started springs).
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Frames between checkpoints (needs --checkpoint).
    #[arg(long, value_name = "N", requires = "checkpoint")]
    pub checkpoint_every: Option<u32>,
    /// Resume from a checkpoint of the same run (the same scene or flags and backend) and
    /// run on to --frames (counted from the run's start); the record holds every frame.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Four comma-separated numbers (`w,x,y,z`; brackets allowed).
fn parse_quaternion(text: &str) -> Result<[f64; 4], String> {
    let inner = text.trim().trim_start_matches('[').trim_end_matches(']');
    let numbers: Vec<f64> = inner
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected four numbers w,x,y,z, got `{text}`"))?;
    let q: [f64; 4] = numbers
        .try_into()
        .map_err(|_| format!("expected four numbers w,x,y,z, got `{text}`"))?;
    let length = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    match (length - 1.0).abs() <= crate::scene::QUATERNION_TOLERANCE {
        true => Ok(q),
        false => Err(format!("must be a unit quaternion, got length {length}")),
    }
}

impl RunArgs {
    /// The mesh of `--mesh` (the bundled sphere when not given).
    pub fn mesh(&self) -> PathBuf {
        self.mesh.clone().unwrap_or_else(|| DEFAULT_MESH.into())
    }

    /// The preset of `--preset` (`seed` when not given).
    pub fn preset(&self) -> PresetName {
        self.preset.unwrap_or(PresetName::Seed)
    }

    /// The methods `--method` names; when not given, a material given by its Young's
    /// modulus runs as a scene's object would ([`material_method`]: the finite elements, or
    /// `volume` where a flag asks for springs), anything else `all`.
    pub fn methods(&self) -> Vec<Method> {
        let params = self.params();
        match self.method {
            Some(choice) => choice.methods(),
            None if params.youngs_modulus.is_some() => vec![material_method(&params)],
            None => MethodChoice::All.methods(),
        }
    }

    /// `scene` with the given flags over its values: the solver's, every object's material
    /// and method, the floor (`--no-floor` removes it, `--friction` sets its friction) and
    /// the outputs. The flags' values are checked first, so that their errors name the
    /// flag; then the scene as it now is ([`BadScene`], naming its keys).
    pub fn override_scene(&self, scene: &mut Scene) -> anyhow::Result<()> {
        let mut flags = SimParams::default();
        self.solver.apply(&mut flags);
        flags.validate()?;
        if let Some(friction) = self.friction {
            if !(0.0..=1.0).contains(&friction) {
                let message = format!("must be in [0, 1], got {friction}");
                return Err(tetrasim::Error::param("friction", message).into());
            }
        }
        scene.solver = self.solver.over(&scene.solver);
        let method = match self.method.map(MethodChoice::methods).as_deref() {
            Some([one]) => Some(*one),
            Some(_) => {
                let message = "with --scene, name one method (every object runs it)";
                return Err(tetrasim::Error::param("method", message).into());
            }
            None => None,
        };
        if let Some(preset) = self.preset {
            scene.base = Preset::named(preset).params;
        }
        if let Some(mesh) = &self.mesh {
            if scene.objects.len() != 1 {
                let message = format!(
                    "names one body's mesh, and the scene has {} objects",
                    scene.objects.len()
                );
                return Err(tetrasim::Error::param("mesh", message).into());
            }
            scene.objects[0].mesh = mesh.clone();
        }
        for object in &mut scene.objects {
            object.material = self.material.over(&object.material);
            object.method = method.or(object.method);
            object.target_tets = self.target_tets.or(object.target_tets);
            if self.no_fit {
                (object.fit_size, object.drop_height) = (None, None);
            }
            object.fit_size = self.fit_size.or(object.fit_size);
            object.drop_height = self.drop_height.or(object.drop_height);
            object.rotation = self.rotation.or(object.rotation);
        }
        if self.no_floor {
            scene
                .colliders
                .retain(|c| !matches!(c, Collider::Floor { .. }));
        }
        if let Some(friction) = self.friction {
            let floor = scene.colliders.iter_mut().find_map(|c| match c {
                Collider::Floor { friction } => Some(friction),
                _ => None,
            });
            match floor {
                Some(f) => *f = friction,
                None => {
                    let message = "sets the floor's friction, and the scene has no floor";
                    return Err(tetrasim::Error::param("friction", message).into());
                }
            }
        }
        let output = &mut scene.output;
        output.json = self.json.clone().or(output.json.take());
        output.dir = self.out_dir.clone().or(output.dir.take());
        // `--every` is also `render`'s picture period: it sets the mesh files' only when
        // there are some (`run` refuses it alone, see `execute`).
        if output.dir.is_some() {
            output.every = self.every.or(output.every);
        }
        output.format = self.format.or(output.format);
        output.units = self.units.or(output.units);
        scene.validate().map_err(BadScene)?;
        Ok(())
    }

    /// The checkpoints these flags ask for (one method only); the checkpoint's folder is
    /// made (or refused) before the run.
    pub fn checkpointing(&self, methods: &[Method]) -> anyhow::Result<Checkpointing> {
        let flag = match (&self.checkpoint, &self.resume) {
            (Some(_), _) => "checkpoint",
            (None, Some(_)) => "resume",
            (None, None) => return Ok(Checkpointing::default()),
        };
        if methods.len() > 1 {
            let message = "saves or resumes one method's run: name it with --method";
            return Err(tetrasim::Error::param(flag, message).into());
        }
        if self.checkpoint_every == Some(0) {
            return Err(tetrasim::Error::param("checkpoint-every", "must be at least 1").into());
        }
        if let Some(path) = &self.checkpoint {
            crate::runner::prepare_output_file(path)?;
        }
        Ok(Checkpointing {
            save: self.checkpoint.clone(),
            every: self.checkpoint_every,
            resume: self.resume.clone(),
        })
    }

    /// The preset's parameters with every given flag applied.
    pub fn params(&self) -> SimParams {
        let mut params = Preset::named(self.preset()).params;
        self.solver.apply(&mut params);
        self.material.apply(&mut params);
        if let Some(friction) = self.friction {
            params.friction = friction;
        }
        if self.no_floor {
            params.floor = false;
        }
        params
    }

    /// The one-object scene these flags stand for (method: the first of `--method`).
    pub fn scene(&self) -> Scene {
        let preset = Preset::named(self.preset());
        let params = self.params();
        Scene {
            base: preset.params,
            solver: SolverOverrides {
                frames: Some(self.solver.frames.unwrap_or(preset.frames)),
                ..self.solver.clone()
            },
            objects: vec![Object {
                mesh: self.mesh(),
                target_tets: self.target_tets,
                method: Some(self.methods()[0]),
                fit_size: match self.no_fit {
                    true => None,
                    false => self.fit_size.or(preset.placement.fit_size),
                },
                drop_height: match self.no_fit {
                    true => self.drop_height,
                    false => self.drop_height.or(preset.placement.drop_height),
                },
                rotation: self.rotation,
                offset: [0.0; 3],
                velocity: [0.0; 3],
                material: self.material.clone(),
                pin: Pins::default(),
                self_contact: false,
            }],
            colliders: if params.floor {
                vec![Collider::Floor {
                    friction: params.friction,
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
            grabs: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Refuses solver flags the chosen solver does not use (`--groups` without
    /// Gauss-Seidel, `--rho` without Chebyshev) instead of ignoring them.
    fn check_solver_flags(&self, params: &SimParams) -> tetrasim::Result<()> {
        match self.solver.misplaced(params.solver) {
            Some((flag, needs)) => Err(tetrasim::Error::param(
                flag,
                format!(
                    "acts only with --solver {needs}; the solver is {}",
                    params.solver
                ),
            )),
            None => Ok(()),
        }
    }

    /// The scene to run (the file, or the flags' scene) and the methods to run it with.
    pub fn scene_and_methods(&self) -> anyhow::Result<(Scene, Vec<Method>)> {
        match &self.scene {
            Some(path) => {
                let mut scene = Scene::load(path).map_err(BadScene)?;
                for warning in &scene.warnings {
                    eprintln!("{warning} (in {})", path.display());
                }
                self.override_scene(&mut scene)?;
                let method = scene.params_for(0).method;
                Ok((scene, vec![method]))
            }
            None => {
                // Flag values are checked first so that errors name the flag (`dt`), not
                // the scene key (`solver.dt`).
                let params = self.params();
                params.validate()?;
                self.check_solver_flags(&params)?;
                let scene = self.scene();
                if scene.frames() == 0 {
                    return Err(tetrasim::Error::param("frames", "must be at least 1").into());
                }
                scene.output.check(|name| name.to_string(), "--out-dir")?;
                scene.validate()?;
                Ok((scene, self.methods()))
            }
        }
    }
}

impl RunArgs {
    /// Stages `scene` (the scene file, or the flags' scene), saying which it was; a scene
    /// file that cannot be staged is a [`BadScene`].
    pub fn stage(&self, scene: &Scene) -> anyhow::Result<Staged> {
        match &self.scene {
            Some(path) => stage(scene)
                .map_err(BadScene)
                .with_context(|| format!("staging the scene {}", path.display())),
            None => stage(scene)
                .with_context(|| format!("building the model of {}", self.mesh().display())),
        }
    }
}

/// `jacobi`, or `gauss-seidel (8 groups)`, with ` + global volume` when it is solved and
/// ` + anderson M` with Anderson acceleration, ` + minres K` with MINRES after the sweeps,
/// and the inversion sweeps when they run.
pub(super) fn solver_label(params: &SimParams) -> String {
    if !params.has_springs() {
        return format!(
            "newton (conjugate gradients, two-level preconditioned, {} per step)",
            params.iterations
        );
    }
    let mut out = match params.solver {
        SolverKind::Jacobi => "jacobi".to_string(),
        SolverKind::GaussSeidel if params.solves_in_blocks() => {
            format!("block gauss-seidel (blocks of {} tets)", params.block_size)
        }
        SolverKind::GaussSeidel => format!("gauss-seidel ({} groups)", params.groups),
        SolverKind::Chebyshev => match params.chebyshev_rho() {
            used if used < params.rho => format!(
                "chebyshev (rho {}, lowered to {used:.4} for {} iterations)",
                params.rho, params.iterations
            ),
            _ => format!("chebyshev (rho {})", params.rho),
        },
    };
    if params.solves_global_volume() {
        out += " + global volume";
    }
    if params.anderson > 0 {
        out += &format!(" + anderson {}", params.anderson);
    }
    if params.minres > 0 {
        out += &format!(" + minres {}", params.minres);
    }
    if params.inversion_sweeps > 0 {
        out += &format!(
            " + {} inversion sweeps (floor {})",
            params.inversion_sweeps, params.inversion_floor
        );
    }
    out
}

/// Runs `tetrasim run`.
pub fn execute(args: RunArgs) -> anyhow::Result<()> {
    let (scene, methods) = args.scene_and_methods()?;
    let backend = args.backend.as_deref().unwrap_or("cpu");
    if backend != "vulkan" {
        if let Some(flag) = args.gpu.first_given() {
            return Err(tetrasim::Error::param(
                flag,
                format!("acts only with --backend vulkan; the backend is {backend}"),
            )
            .into());
        }
    }
    if args.every.is_some() && scene.output.dir.is_none() {
        let message = "acts only with --out-dir (or a scene's output.dir), and none is given";
        return Err(tetrasim::Error::param("every", message).into());
    }
    // Staged (and checked against the device's memory and the disk's free space) before
    // the output folders are made, so that a bad scene or one too large writes nothing.
    let staged = args.stage(&scene)?;
    let gpu = EngineOptions {
        // A scene without a metrics file measures the volume only after the last frame
        // (no per-frame readback); the flags' run always prints its per-frame table.
        volume_on_demand: args.scene.is_some() && scene.output.json.is_none(),
        ..args.gpu.engine_options()
    };
    let (model, params) = (&staged.model, &staged.params);
    crate::runner::check_disk_space(&scene.output, model, methods.len(), staged.frames)?;
    crate::runner::preflight(backend, model, params, &methods, staged.frames, &gpu)?;
    crate::runner::prepare_outputs(&scene.output)?;
    let checkpointing = args.checkpointing(&methods)?;
    for note in &staged.notes {
        eprintln!("{note}");
    }
    // The springs are counted where a method runs them (the finite elements have none).
    let springs = match methods.iter().any(|m| m.has_springs()) {
        true => format!(", {} springs", model.springs.len()),
        false => String::new(),
    };
    eprintln!(
        "{}: {} nodes ({} pinned), {} tets{springs}; backend {}, {} frames of dt {} s x {} substeps, {} iterations, solver {}",
        staged.label,
        model.node_count(),
        model.node_count() - model.free_node_count(),
        model.tets.len(),
        backend,
        staged.frames,
        params.dt,
        params.substeps,
        params.iterations,
        solver_label(params)
    );
    if let Some(accuracy) = scene.solver.accuracy {
        eprintln!("accuracy {}", accuracy.describe(params));
    }
    if args.scene.is_none() && args.method.is_none() {
        // The one default that differs between the command line and scenes or Python.
        match params.youngs_modulus {
            Some(_) => eprintln!(
                "method {}: the default for a material given by its Young's modulus \
                 (neo-hookean unless a flag asks for springs; --method names another)",
                params.method
            ),
            None => eprintln!(
                "methods mss, distance and volume: the command line's default (--method all); \
                 scenes and Python default to volume, and a material given by its Young's \
                 modulus to neo-hookean"
            ),
        }
    }
    let estimate = tetrasim::stability::estimate(model, params);
    if estimate.exceeded_by(params.dt) {
        eprintln!(
            "warning: dt exceeds the explicit stability bound of the springs: {}; the run will \
             likely diverge (docs/STABILITY.md)",
            estimate.describe(params)
        );
    }
    let out = &scene.output;
    let output = crate::runner::frame_output(out)?;
    let options = RunOptions {
        backend: backend.to_string(),
        frames: staged.frames,
        mesh_label: staged.label.clone(),
        progress: !args.quiet,
        output,
        gpu,
        checkpoint: checkpointing,
    };
    crate::runner::listen_for_interrupts()?;
    let records = run_methods(model, params, &methods, &options)?;
    // The paper's column only for its experiment: the `seed` preset's drop from flags.
    let paper = args.scene.is_none() && args.preset() == crate::preset::PresetName::Seed;
    print!("{}", table(&records, paper));
    print!("{}", pass_table(&records));
    eprint!("{}", short_run_warnings(&records));
    if let Some(path) = &out.json {
        write_json(path, &records)?;
        eprintln!("metrics written to {}", path.display());
    }
    if let Some(r) = records.iter().find(|r| r.interrupted) {
        return Err(InterruptedRun {
            method: r.method.clone(),
            frames: r.frames_run,
            of: r.frames,
        }
        .into());
    }
    match records.iter().find_map(|r| r.divergence.as_ref()) {
        Some(d) => Err(DivergedRun(d.clone()).into()),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use clap::Parser as _;

    use crate::cli::Cli;

    fn parse(extra: &[&str]) -> Result<Cli, clap::Error> {
        let mut args = vec!["tetrasim", "run", "--scene", "s.toml"];
        args.extend(extra);
        Cli::try_parse_from(args)
    }

    #[test]
    fn a_scene_takes_every_flag() {
        assert!(parse(&[]).is_ok());
        for flag in [
            &["--atomics", "ext", "--device", "0"][..],
            &["--dt", "0.1"],
            &["--frames", "3"],
            &["--global-volume"],
            &["--constraint-epsilon", "0"],
            &["--epsilon", "0"],
            &["--youngs", "1e5"],
            &["--ks", "1"],
            &["--node-mass", "1"],
            &["--friction", "0.5"],
            &["--no-floor"],
            &[
                "--mesh",
                "m",
                "--fit-size",
                "1",
                "--rotation",
                "1,0,0,0",
                "--preset",
                "seed",
            ],
        ] {
            assert!(parse(flag).is_ok(), "{flag:?} refused");
        }
    }
}
