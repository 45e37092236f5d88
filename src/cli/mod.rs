//! The command line of `tetrasim`: clap structures and the glue from arguments to the library.
//! `main.rs` only parses and dispatches to [`execute`].

mod bench;
mod gpu_args;
mod info;
mod method_choice;
mod outcome;
mod output_flags;
pub mod params;
mod plan;
mod render;
mod run;
mod soak;
mod stability;
mod tradeoff;

pub use bench::BenchArgs;
pub use outcome::{BadScene, DivergedRun, InterruptedRun};
pub use render::RenderArgs;
pub use run::RunArgs;
pub use soak::SoakArgs;
pub use tradeoff::{ScalingArgs, TradeoffArgs};

/// `tetrasim`: volume-preserving mass-spring simulation of tetrahedral meshes.
#[derive(Debug, clap::Parser)]
#[command(name = "tetrasim", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands. Every subcommand takes negative numbers as values (`--gravity -9.81`).
/// Outputs are named alike everywhere: `--out-dir DIR` for a folder of files (created with
/// its parents before any work starts), `--json FILE` for machine-readable records, and a
/// flag named for its format for single files (`--gif`, `--sheet`).
#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Simulate a mesh dropped on the floor and report volume preservation (the paper's
    /// experiment with `--preset seed`).
    #[command(allow_negative_numbers = true)]
    Run(Box<RunArgs>),
    /// Print what the Vulkan engine would build for a scene (`--scene FILE`) or for run's
    /// flags: passes per time step, buffer sizes, device memory, bytes moved per frame, and
    /// each pass's and the frame's time predicted for an NVIDIA H200 (its cost model).
    #[command(allow_negative_numbers = true)]
    Plan(Box<RunArgs>),
    /// Sweep dt x ks per method and write stability heat maps (PNG) and a table.
    #[command(allow_negative_numbers = true)]
    Stability(stability::StabilityArgs),
    /// Simulate like `run` (on `--backend`; a CPU backend's state is drawn through `vulkan`'s buffers) and draw it offscreen: PNG
    /// frames, an animated GIF, a contact sheet of every method (coloured by V/V0 by default).
    #[command(allow_negative_numbers = true)]
    Render(Box<RenderArgs>),
    /// List the Vulkan devices: driver, limits, timestamps, float atomics and the atomic
    /// path and workgroup size the engine would use on each.
    Info,
    /// Print every parameter of a run with its one name as a flag, a scene key and a
    /// Python keyword, its default and meaning (Markdown; docs/reference/parameters.md).
    Params,
    /// Headless benchmark: every mesh x method x backend, frame-time percentiles, GPU pass
    /// times, throughput and volume accuracy.
    #[command(allow_negative_numbers = true)]
    Bench(Box<BenchArgs>),
    /// Speed-versus-accuracy sweep (iterations, substeps, omega, method) on one mesh: CSV,
    /// JSON, Pareto front and PNG plots.
    #[command(allow_negative_numbers = true)]
    Tradeoff(Box<TradeoffArgs>),
    /// Cost per element against mesh size (a voxel-meshed sphere at several sizes).
    #[command(allow_negative_numbers = true)]
    Scaling(Box<ScalingArgs>),
    /// A long run that watches itself (default: the bundled sphere, 100000 frames): resident
    /// and device memory, energy and volume sampled; fails when memory grows after the
    /// warm-up, the energy rises, the volume leaves its band or the run diverges.
    #[command(allow_negative_numbers = true)]
    Soak(Box<SoakArgs>),
}

impl Cli {
    /// Whether the command's settings come from flags (not from a scene file), so that its
    /// messages should name them as flags ([`in_flags`]).
    pub fn set_by_flags(&self) -> bool {
        match &self.command {
            Command::Run(args) | Command::Plan(args) => args.scene.is_none(),
            Command::Render(args) => args.run.scene.is_none(),
            Command::Soak(args) => args.run.scene.is_none(),
            _ => true,
        }
    }
}

/// The settings that messages name, as scenes and Python name them.
const SETTINGS: [&str; 7] = [
    "method",
    "springs",
    "dt",
    "substeps",
    "iterations",
    "combine",
    "omega",
];

/// `message` with the settings it names in code spans as scenes and Python name them
/// (`` `dt = 1e-4` ``, `` `springs = "implicit"` ``, `` `omega` ``) named as this command
/// line's flags (`` `--dt 1e-4` ``, `` `--springs implicit` ``, `` `--omega` ``); other text
/// unchanged.
pub fn in_flags(message: &str) -> String {
    let flag = |span: &str| -> Option<String> {
        let (name, value) = match span.split_once(" = ") {
            Some((name, value)) => (name, Some(value.trim_matches('"'))),
            None => (span, None),
        };
        SETTINGS.contains(&name).then(|| match value {
            Some(value) => format!("--{name} {value}"),
            None => format!("--{name}"),
        })
    };
    // Between backticks (odd pieces) are the code spans.
    (message.split('`').enumerate())
        .map(|(k, piece)| match k % 2 {
            1 => flag(piece).unwrap_or_else(|| piece.to_string()),
            _ => piece.to_string(),
        })
        .collect::<Vec<_>>()
        .join("`")
}

/// Runs a parsed command line.
pub fn execute(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Run(args) => run::execute(*args),
        Command::Render(args) => render::execute(*args),
        Command::Info => info::execute(),
        Command::Params => params::execute(),
        Command::Plan(args) => plan::execute(*args),
        Command::Stability(args) => stability::execute(args),
        Command::Bench(args) => bench::execute(*args),
        Command::Tradeoff(args) => tradeoff::execute_tradeoff(*args),
        Command::Scaling(args) => tradeoff::execute_scaling(*args),
        Command::Soak(args) => soak::execute(*args),
    }
}

#[cfg(test)]
mod tests {
    use super::in_flags;

    #[test]
    fn settings_are_named_as_flags() {
        let advice = "set `springs = \"implicit\"` (or `method = \"neo-hookean\"`), or \
                      `dt = 1.77e-4` or less, more `iterations`, a smaller `omega`; `ks` 5000";
        assert_eq!(
            in_flags(advice),
            "set `--springs implicit` (or `--method neo-hookean`), or `--dt 1.77e-4` or less, \
             more `--iterations`, a smaller `--omega`; `ks` 5000"
        );
    }
}
