//! `tetrasim params`: every parameter of a run with its one name, as a flag, a scene key and
//! a Python keyword, its unit, default and meaning, generated from the code: `run`'s flags
//! (their clap help and defaults), the key lists of the solver and material tables
//! ([`SolverOverrides::KEYS`], [`MaterialOverrides::KEYS`]) and the defaults of
//! [`SimParams`]. docs/reference/parameters.md is its output, and `tests/parameters.rs`
//! checks that it has not drifted.

use clap::CommandFactory as _;

use super::Cli;
use crate::overrides::{MaterialOverrides, SolverOverrides};
use tetrasim::params::SimParams;

/// Where a flag that is neither a solver nor a material key lives in scenes and Python
/// (`None`: a choice of the command line only).
const PLACES: &[(&str, Option<&str>, Option<&str>)] = &[
    (
        "scene",
        None,
        Some("`Simulation.from_scene(path, **overrides)`"),
    ),
    (
        "mesh",
        Some("`object[].mesh`"),
        Some("`Simulation(mesh)`, `Scene.add_body(mesh)`"),
    ),
    (
        "target_tets",
        Some("`object[].target_tets`"),
        Some("`read_mesh(path, target_tets)`"),
    ),
    ("method", Some("`object[].method`"), Some("`method`")),
    ("backend", None, Some("`backend`")),
    ("preset", None, None),
    (
        "friction",
        Some("`collider[].friction` (the floor's)"),
        Some("`friction`"),
    ),
    (
        "no_floor",
        Some("a `[[collider]]` of type `floor`, or none"),
        Some("`floor`"),
    ),
    ("fit_size", Some("`object[].fit_size`"), Some("`fit_size`")),
    (
        "no_fit",
        Some("`fit_size` and `drop_height` left out"),
        Some("`fit_size=None, drop_height=None`"),
    ),
    (
        "drop_height",
        Some("`object[].drop_height`"),
        Some("`drop_height`"),
    ),
    ("rotation", Some("`object[].rotation`"), Some("`rotation`")),
    ("json", Some("`output.json`"), Some("`sim.record()`")),
    (
        "out_dir",
        Some("`output.out_dir`"),
        Some("`Series(sim, path)`"),
    ),
    (
        "every",
        Some("`output.every`"),
        Some("`Series.add()` when you choose"),
    ),
    (
        "format",
        Some("`output.format`"),
        Some("`Series(sim, path, format)`"),
    ),
    ("units", Some("`output.units`"), None),
    ("checkpoint", None, Some("`sim.save(path)`")),
    ("checkpoint_every", None, None),
    ("resume", None, Some("`sim.load(path)`")),
    ("device", None, Some("`device`")),
];

/// Defaults that differ between the command line, scenes and Python, said as such.
const DEFAULTS: &[(&str, &str)] = &[
    ("method", "`all` (command line), `volume` (scenes, Python); `neo-hookean` for a material given by its Young's modulus"),
    ("no_floor", "a floor (command line, Python), none (scenes)"),
    (
        "fit_size",
        "`1` (command line, Python), the mesh's size (scenes)",
    ),
    (
        "drop_height",
        "`0.1` (command line, Python), where the mesh is (scenes)",
    ),
    ("frames", "`400`"),
    ("node_mass", "`1`"),
    ("backend", "`cpu`"),
    ("preset", "`seed`"),
    ("every", "`10`"),
    ("format", "`ply`"),
    ("units", "`simulation`"),
];

/// One row of the table.
struct Row {
    flag: String,
    scene: String,
    python: String,
    default: String,
    meaning: String,
}

/// The rows: every flag of `run`, in its help's order.
fn rows() -> Vec<Row> {
    let command = Cli::command();
    let Some(run) = command.find_subcommand("run") else {
        return Vec::new();
    };
    let defaults = serde_json::to_value(SimParams::default()).unwrap_or_default();
    let code = |s: &str| format!("`{s}`");
    run.get_arguments()
        .filter(|a| a.get_long().is_some() && !a.is_hide_set())
        .map(|arg| {
            let id = arg.get_id().as_str();
            let long = arg.get_long().unwrap_or(id);
            let (scene, python) = if SolverOverrides::has(id) {
                let python = match id {
                    "frames" => "`Scene(frames=...)`, `sim.step(frames)`".to_string(),
                    _ => code(id),
                };
                (code(&format!("solver.{id}")), python)
            } else if MaterialOverrides::has(id) {
                (code(&format!("object[].material.{id}")), code(id))
            } else {
                let place = PLACES.iter().find(|(key, _, _)| *key == id);
                let scene = place.and_then(|p| p.1).unwrap_or("");
                let python = place.and_then(|p| p.2).unwrap_or("");
                (scene.to_string(), python.to_string())
            };
            let said = DEFAULTS.iter().find(|(key, _)| *key == id).map(|d| d.1);
            let default = match (said, defaults.get(id)) {
                (Some(said), _) => said.to_string(),
                (None, Some(v)) if !v.is_null() => code(&v.to_string().replace('"', "")),
                _ => String::new(),
            };
            let help = arg.get_help().map(|h| h.to_string()).unwrap_or_default();
            let meaning = help.trim_end_matches('.');
            Row {
                flag: code(&format!("--{long}")),
                scene,
                python,
                default,
                meaning: meaning.replace('|', "\\|").replace('\n', " "),
            }
        })
        .collect()
}

/// The table as Markdown, with a line on where it comes from.
pub fn markdown() -> String {
    let mut out = String::from(
        "# Parameters\n\nEvery parameter of a run with its one name as a flag (`tetrasim run`), a \
         scene key and a Python keyword (`tetrasim.Simulation`, `tetrasim.Scene`), its \
         default and its meaning with the unit in brackets. Generated by `tetrasim params` \
         from the code (`tests/parameters.rs` checks that this page has not drifted); the \
         flags' `--help` says more. A name changed on 2026-12-06 is still read, with a \
         warning naming the new one: `--epsilon`, `--youngs`, `--poisson`; scene keys \
         `solver.epsilon`, a plane's `offset` (now `distance`), a mesh collider's `path` \
         (now `mesh`), a keyframe's `position` (now `translation`), `output.dir` (now \
         `out_dir`).\n\n| flag | scene key | Python | default | meaning |\n| --- | --- | --- \
         | --- | --- |\n",
    );
    for row in rows() {
        out += &format!(
            "| {} | {} | {} | {} | {} |\n",
            row.flag, row.scene, row.python, row.default, row.meaning
        );
    }
    out
}

/// Prints the table.
pub fn execute() -> anyhow::Result<()> {
    print!("{}", markdown());
    Ok(())
}
