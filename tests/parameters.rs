//! The parameter table (docs/reference/parameters.md) is `tetrasim params`'s output, so it
//! cannot drift from the code; every solver and material key has its row with its flag,
//! scene key and Python keyword, and the Python keywords are `SimParams`'s (what
//! `tetrasim.default_params()` lists).

use std::process::Command;

use tetrasim_cli::overrides::{MaterialOverrides, SolverOverrides};

#[test]
fn the_parameter_table_is_the_codes() {
    let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .arg("params")
        .output()
        .unwrap();
    assert!(out.status.success());
    let generated = String::from_utf8(out.stdout).unwrap();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/reference/parameters.md");
    let committed = std::fs::read_to_string(path).unwrap();
    assert!(
        generated == committed,
        "docs/reference/parameters.md differs from `tetrasim params`: regenerate it with \
         `target/release/tetrasim params > docs/reference/parameters.md`"
    );
    let params = serde_json::to_value(tetrasim::params::SimParams::default()).unwrap();
    for key in SolverOverrides::KEYS {
        let flag = key.replace('_', "-");
        let row = format!("| `--{flag}` | `solver.{key}` |");
        assert!(generated.contains(&row), "no row {row}");
        // `frames` is the run's length; `accuracy` the dial Python's `Simulation` writes
        // before the other keywords (python/tests/test_simulation.py).
        assert!(
            ["frames", "accuracy"].contains(&key) || params.get(key).is_some(),
            "{key} is not a SimParams key"
        );
    }
    for key in MaterialOverrides::KEYS {
        let flag = key.replace('_', "-");
        let row = format!("| `--{flag}` | `object[].material.{key}` | `{key}` |");
        assert!(generated.contains(&row), "no row {row}");
    }
}

#[test]
fn old_names_still_work_with_a_warning_naming_the_new_one() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("old.toml");
    let sphere = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/sphere");
    std::fs::write(
        &scene,
        format!(
            "[solver]\nframes = 2\nepsilon = 1e-20\n[[object]]\nmesh = {sphere:?}\n\
             [[collider]]\ntype = \"plane\"\nnormal = [0, 1, 0]\noffset = 0.0\n\
             motion = {{ keyframes = [{{ t = 0.0 }}, {{ t = 1.0, position = [0, 1, 0] }}] }}\n"
        ),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args([
            "run",
            "--quiet",
            "--poisson",
            "0.4",
            "--youngs",
            "1e5",
            "--density",
            "1000",
        ])
        .args(["--springs", "implicit", "--scene"])
        .arg(&scene)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    for says in [
        "--youngs is now --youngs-modulus",
        "--poisson is now --poisson-ratio",
        "`solver.epsilon` is now `solver.constraint_epsilon`",
        "`collider[0].offset` is now `collider[0].distance`",
        "`collider[0].motion.keyframes[1].position` is now",
    ] {
        assert!(stderr.contains(says), "no `{says}` in {stderr}");
    }
}
