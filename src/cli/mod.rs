//! The command line of `tetrasim`: clap structures and the glue from arguments to the library.
//! `main.rs` only parses and dispatches to [`execute`].

mod bench;
mod info;
mod run;
mod tradeoff;

pub use bench::BenchArgs;
pub use run::RunArgs;
pub use tradeoff::{ScalingArgs, TradeoffArgs};

/// `tetrasim`: volume-preserving mass-spring simulation of tetrahedral meshes.
#[derive(Debug, clap::Parser)]
#[command(name = "tetrasim", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum Command {
    /// Simulate a mesh dropped on the floor and report volume preservation (the paper's
    /// experiment with `--preset seed`).
    Run(Box<RunArgs>),
    /// List the Vulkan devices: driver, limits, timestamps, float atomics and the atomic
    /// path and workgroup size the engine would use on each.
    Info,
    /// Headless benchmark: every mesh x method x backend, frame-time percentiles, GPU pass
    /// times, throughput and volume accuracy.
    Bench(Box<BenchArgs>),
    /// Speed-versus-accuracy sweep (iterations, substeps, omega, method) on one mesh: CSV,
    /// JSON, Pareto front and PNG plots.
    Tradeoff(Box<TradeoffArgs>),
    /// Cost per element against mesh size (a voxel-meshed sphere at several sizes).
    Scaling(Box<ScalingArgs>),
}

/// Runs a parsed command line.
pub fn execute(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Run(args) => run::execute(*args),
        Command::Info => info::execute(),
        Command::Bench(args) => bench::execute(*args),
        Command::Tradeoff(args) => tradeoff::execute_tradeoff(*args),
        Command::Scaling(args) => tradeoff::execute_scaling(*args),
    }
}
