//! `tetrasim stability`: sweeps dt x ks per method and spring kind (explicit, and implicit
//! for mss and volume) on a mesh (seed placement and physics otherwise), writes a PNG heat
//! map per map, the table as CSV and JSON, and prints it with the largest stable dt per map
//! at the paper's stiffness.

use std::path::PathBuf;

use crate::bench::stability_map::plot::heat_map;
use crate::bench::stability_map::sweep::{csv, largest_stable_dt, sweep, table, SweepConfig};
use crate::preset::Preset;
use crate::runner::write_atomically;
use tetrasim::metrics::write_json_value;
use tetrasim::params::SimParams;
use tetrasim::sim::{build_model, load_mesh};

/// The paper's stiffness [N/m].
const PAPER_KS: f64 = 5000.0;

/// Arguments of `tetrasim stability`.
#[derive(Debug, clap::Args)]
pub struct StabilityArgs {
    /// TetGen prefix (PREFIX.node + PREFIX.ele).
    #[arg(long)]
    pub mesh: PathBuf,
    /// The small grid (5 dt x 4 ks over 0.25 s) instead of the full one (7 x 6 over 0.3 s).
    #[arg(long)]
    pub quick: bool,
    /// Folder for stability_METHOD.png (METHOD-implicit for implicit springs),
    /// stability.csv and stability.json.
    #[arg(long, alias = "out", value_name = "DIR")]
    pub out_dir: PathBuf,
    /// Solver backend.
    #[arg(long, default_value = "cpu")]
    pub backend: String,
}

/// Runs `tetrasim stability`.
pub fn execute(args: StabilityArgs) -> anyhow::Result<()> {
    crate::runner::create_dir(&args.out_dir)?;
    let preset = Preset::seed();
    let loaded = load_mesh(&args.mesh, None)?;
    let model = build_model(&loaded.mesh, &preset.params, preset.placement)?;
    let config = SweepConfig::new(args.quick, &args.backend, SimParams::default());
    let maps = config.maps();
    let total = maps.len() * config.dts.len() * config.kss.len();
    eprintln!(
        "{}: {} nodes, {} tets; {total} runs of {} s each on {}",
        loaded.label,
        model.node_count(),
        model.tets.len(),
        config.duration,
        args.backend
    );
    let mut done = 0;
    let cells = sweep(&model, &config, |c| {
        done += 1;
        eprint!(
            "\r{done}/{total} {} dt {:e} ks {:e}      ",
            c.method, c.dt, c.ks
        );
    })?;
    eprintln!();
    for (.., method) in &maps {
        let path = args.out_dir.join(format!("stability_{method}.png"));
        let title = format!(
            "{method} on {} ({} tets): max |V - V0| %, X = diverged",
            loaded.mesh_name(),
            model.tets.len()
        );
        heat_map(&path, &cells, method, &config.dts, &config.kss, &title)?;
        eprintln!("wrote {}", path.display());
    }
    write_atomically(&args.out_dir.join("stability.csv"), csv(&cells).as_bytes())?;
    write_json_value(&args.out_dir.join("stability.json"), &cells)?;
    print!("{}", table(&cells, &config.dts, &config.kss));
    println!(
        "largest stable dt at ks {PAPER_KS} N/m (grid {:?} s):",
        config.dts
    );
    for (.., method) in &maps {
        let estimate = cells
            .iter()
            .find(|c| c.ks == PAPER_KS && &c.method == method)
            .map_or(f64::NAN, |c| c.dt_estimate);
        match largest_stable_dt(&cells, method, PAPER_KS) {
            Some(dt) => println!("  {method:<16} {dt:e} s (springs' estimate {estimate:.2e} s)"),
            None => println!("  {method:<16} none (springs' estimate {estimate:.2e} s)"),
        }
    }
    Ok(())
}
