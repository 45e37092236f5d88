//! The dt x ks sweep behind `tetrasim stability`: every (method, dt, ks) cell runs the
//! model for the same simulated time (a drop onto the floor and the impact) and is
//! classified as diverged, or stable with its worst volume error.

use std::fmt::Write as _;

use serde::Serialize;

use crate::runner::{run, RunOptions};
use tetrasim::error::Result;
use tetrasim::model::Model;
use tetrasim::params::{Method, SimParams, SpringKind};

/// What to sweep.
#[derive(Debug, Clone)]
pub struct SweepConfig {
    /// Methods, one map each per spring kind.
    pub methods: Vec<Method>,
    /// Spring kinds (explicit, the paper's; implicit, with `mss` and `volume` only).
    pub springs: Vec<SpringKind>,
    /// Time steps [s], ascending.
    pub dts: Vec<f64>,
    /// Spring stiffnesses [N/m], ascending.
    pub kss: Vec<f64>,
    /// Simulated time of every cell [s] (frames of one step each).
    pub duration: f64,
    /// Backend name.
    pub backend: String,
    /// Everything else (damping, iterations, floor, masses ...).
    pub base: SimParams,
}

impl SweepConfig {
    /// The default grids: `quick` is 5 dt x 4 ks over 0.25 s, the full one 7 dt x 6 ks
    /// over 0.3 s; both contain the paper's dt 1e-3 s and ks 5000 N/m.
    pub fn new(quick: bool, backend: &str, base: SimParams) -> Self {
        let (dts, kss, duration) = if quick {
            (
                vec![1e-4, 3e-4, 1e-3, 3e-3, 1e-2],
                vec![500.0, 5e3, 5e4, 5e5],
                0.25,
            )
        } else {
            (
                vec![3e-5, 1e-4, 3e-4, 1e-3, 2e-3, 4e-3, 1e-2],
                vec![50.0, 500.0, 5e3, 2e4, 5e4, 5e5],
                0.3,
            )
        };
        SweepConfig {
            methods: vec![Method::Mss, Method::Distance, Method::Volume],
            springs: vec![SpringKind::Explicit, SpringKind::Implicit],
            dts,
            kss,
            duration,
            backend: backend.to_string(),
            base,
        }
    }
}

impl SweepConfig {
    /// The maps: every method with every spring kind it takes, named `METHOD` (explicit
    /// springs) or `METHOD-implicit`.
    pub fn maps(&self) -> Vec<(Method, SpringKind, String)> {
        let mut maps = Vec::new();
        for &springs in &self.springs {
            for &method in &self.methods {
                let takes = springs == SpringKind::Explicit
                    || matches!(method, Method::Mss | Method::Volume);
                if takes {
                    let name = match springs {
                        SpringKind::Explicit => method.name().to_string(),
                        SpringKind::Implicit => format!("{method}-implicit"),
                    };
                    maps.push((method, springs, name));
                }
            }
        }
        maps
    }
}

/// One cell's result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cell {
    /// Map name: the method, `-implicit` with implicit springs.
    pub method: String,
    /// Time step [s].
    pub dt: f64,
    /// Stiffness [N/m].
    pub ks: f64,
    /// Steps simulated (fewer than planned when it diverged).
    pub steps: u32,
    /// Whether it diverged.
    pub diverged: bool,
    /// Largest `|volume % - 100|` over the frames before the end or the divergence.
    pub max_volume_error_pct: f64,
    /// Volume % after the last completed step (0 when none completed).
    pub final_volume_pct: f64,
    /// Stable-step estimate of the springs for this ks [s].
    pub dt_estimate: f64,
}

/// Runs every cell of `config` on `model`; `progress` is told each finished cell.
pub fn sweep(
    model: &Model,
    config: &SweepConfig,
    mut progress: impl FnMut(&Cell),
) -> Result<Vec<Cell>> {
    let mut cells = Vec::new();
    for (method, springs, name) in config.maps() {
        for &ks in &config.kss {
            for &dt in &config.dts {
                let params = SimParams {
                    method,
                    springs,
                    ks,
                    dt,
                    substeps: 1,
                    ..config.base.clone()
                };
                let frames = (config.duration / dt).ceil().max(1.0) as u32;
                let options = RunOptions {
                    backend: config.backend.clone(),
                    frames,
                    mesh_label: String::new(),
                    progress: false,
                    output: None,
                    gpu: Default::default(),
                    checkpoint: Default::default(),
                };
                let r = run(model, &params, &options)?;
                let error = r
                    .volume_pct
                    .iter()
                    .map(|v| (v - 100.0).abs())
                    .fold(0.0, f64::max);
                let cell = Cell {
                    method: name.clone(),
                    dt,
                    ks,
                    steps: r.frames_run,
                    diverged: r.diverged,
                    max_volume_error_pct: error,
                    final_volume_pct: r.volume_pct.last().copied().unwrap_or(0.0),
                    dt_estimate: tetrasim::stability::estimate(model, &params).dt_max,
                };
                progress(&cell);
                cells.push(cell);
            }
        }
    }
    Ok(cells)
}

/// The largest dt of `cells` for `method` at stiffness `ks` that did not diverge, provided
/// every smaller dt did not either (`None` when the smallest already diverged).
pub fn largest_stable_dt(cells: &[Cell], method: &str, ks: f64) -> Option<f64> {
    let mut row: Vec<&Cell> = cells
        .iter()
        .filter(|c| c.method == method && c.ks == ks)
        .collect();
    row.sort_by(|a, b| a.dt.total_cmp(&b.dt));
    row.iter().take_while(|c| !c.diverged).last().map(|c| c.dt)
}

/// The cells as CSV (header line first).
pub fn csv(cells: &[Cell]) -> String {
    let mut out = String::from(
        "method,dt,ks,steps,diverged,max_volume_error_pct,final_volume_pct,dt_estimate\n",
    );
    for c in cells {
        let _ = writeln!(
            out,
            "{},{:e},{},{},{},{:.4},{:.4},{:e}",
            c.method,
            c.dt,
            c.ks,
            c.steps,
            c.diverged,
            c.max_volume_error_pct,
            c.final_volume_pct,
            c.dt_estimate
        );
    }
    out
}

/// One table per method for the terminal: rows ks, columns dt; a cell is `X` (diverged) or
/// the largest volume error in percent; `*` marks dt above the springs' estimate.
pub fn table(cells: &[Cell], dts: &[f64], kss: &[f64]) -> String {
    let mut out = String::new();
    let mut methods: Vec<&str> = Vec::new();
    for c in cells {
        if !methods.contains(&c.method.as_str()) {
            methods.push(&c.method);
        }
    }
    for method in methods {
        let _ = writeln!(
            out,
            "{method}: max |volume - 100| % per (ks, dt); X = diverged, * = dt above the estimate"
        );
        let _ = write!(out, "{:>10}", "ks \\ dt");
        for dt in dts {
            let _ = write!(out, " {dt:>9.0e}");
        }
        let _ = writeln!(out);
        for &ks in kss {
            let _ = write!(out, "{ks:>10.0e}");
            for &dt in dts {
                let cell = cells
                    .iter()
                    .find(|c| c.method == method && c.ks == ks && c.dt == dt);
                let text = match cell {
                    None => "-".to_string(),
                    Some(c) => {
                        let mark = if c.dt > c.dt_estimate { "*" } else { "" };
                        if c.diverged {
                            format!("X{mark}")
                        } else {
                            format!("{:.2}{mark}", c.max_volume_error_pct)
                        }
                    }
                };
                let _ = write!(out, " {text:>9}");
            }
            let _ = writeln!(out);
        }
        let _ = writeln!(out);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(dt: f64, diverged: bool) -> Cell {
        Cell {
            method: "mss".into(),
            dt,
            ks: 5000.0,
            steps: 10,
            diverged,
            max_volume_error_pct: 1.0,
            final_volume_pct: 99.0,
            dt_estimate: 2e-3,
        }
    }

    #[test]
    fn largest_stable_dt_stops_at_the_first_divergence() {
        let cells = [
            cell(1e-3, false),
            cell(1e-4, false),
            cell(3e-3, true),
            cell(1e-2, false),
        ];
        assert_eq!(largest_stable_dt(&cells, "mss", 5000.0), Some(1e-3));
        assert_eq!(largest_stable_dt(&cells, "mss", 1.0), None);
        assert_eq!(largest_stable_dt(&[cell(1e-4, true)], "mss", 5000.0), None);
        let t = table(&cells, &[1e-4, 1e-3, 3e-3, 1e-2], &[5000.0]);
        assert!(t.contains("X*") && t.contains("1.00"), "{t}");
        assert_eq!(csv(&cells).lines().count(), 5);
    }
}
