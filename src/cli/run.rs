//! `tetrasim run`: the preset, overridden by flags, on one mesh for one or all methods.

use std::path::PathBuf;

use anyhow::Context as _;

use crate::engine::EngineOptions;
use crate::metrics::{pass_table, table, write_json};
use crate::params::{AtomicsMode, ConstraintCombine, MassMode, Method};
use crate::preset::{Preset, PresetName};
use crate::runner::{
    build_model, load_mesh, run_methods, OutputFormat, RunOptions, SurfaceOutput, DEFAULT_MESH,
};

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
    /// TetGen prefix (PREFIX.node + PREFIX.ele) or a surface file (.ply/.obj/.off/.stl).
    #[arg(long, default_value = DEFAULT_MESH)]
    pub mesh: PathBuf,
    /// Method to run.
    #[arg(long, value_enum, default_value = "all")]
    pub method: MethodChoice,
    /// Solver backend: cpu-ref (f64 reference), cpu (f32, all cores) or vulkan (GPU).
    #[arg(long, default_value = "cpu")]
    pub backend: String,
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
    /// Per-node combination of constraint forces.
    #[arg(long, value_enum)]
    pub combine: Option<ConstraintCombine>,
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
    /// Write the run records (one JSON object per method) to this file.
    #[arg(long)]
    pub metrics: Option<PathBuf>,
    /// Write the deformed mesh every `--every` frames into this folder.
    #[arg(long)]
    pub out_dir: Option<PathBuf>,
    /// Output period in frames.
    #[arg(long, default_value_t = 10)]
    pub every: u32,
    /// Output format: ply (surface) or vtk (tet mesh with volume ratios).
    #[arg(long, value_enum, default_value = "ply")]
    pub format: OutputFormat,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

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
             combine => s.combine, epsilon => s.constraint_epsilon, atomics => s.atomics);
        if let Some(mass) = self.node_mass {
            s.mass = MassMode::PerNode { mass };
        }
        if let Some(density) = self.density {
            s.mass = MassMode::Density { density };
        }
        if self.no_floor {
            s.floor = false;
        }
        if let Some(size) = self.fit_size {
            p.placement.fit_size = Some(size);
        }
        if let Some(height) = self.drop_height {
            p.placement.drop_height = Some(height);
        }
        p
    }
}

/// Runs `tetrasim run`.
pub fn execute(args: RunArgs) -> anyhow::Result<()> {
    let preset = args.preset();
    preset.params.validate()?;
    if preset.frames == 0 {
        return Err(crate::Error::param("frames", "must be at least 1").into());
    }
    let loaded = load_mesh(&args.mesh)?;
    if let Some(note) = &loaded.note {
        eprintln!("{note}");
    }
    let model = build_model(&loaded.mesh, &preset.params, preset.placement)
        .with_context(|| format!("building the model of {}", loaded.label))?;
    eprintln!(
        "{}: {} nodes, {} tets, {} springs; backend {}, {} frames of dt {} s x {} substeps, {} iterations",
        loaded.label,
        model.node_count(),
        model.tets.len(),
        model.springs.len(),
        args.backend,
        preset.frames,
        preset.params.dt,
        preset.params.substeps,
        preset.params.iterations
    );
    let output = match &args.out_dir {
        Some(dir) => Some(SurfaceOutput::new(dir, args.every, args.format)?),
        None => None,
    };
    let options = RunOptions {
        backend: args.backend.clone(),
        frames: preset.frames,
        mesh_label: loaded.label.clone(),
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
        },
    };
    let records = run_methods(&model, &preset.params, &args.method.methods(), &options)?;
    print!("{}", table(&records));
    print!("{}", pass_table(&records));
    if let Some(path) = &args.metrics {
        write_json(path, &records)?;
        eprintln!("metrics written to {}", path.display());
    }
    Ok(())
}
