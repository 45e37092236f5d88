//! Moving pins and self-contact in scene files: the example scenes' pins become the clamps
//! they declare, a bad pin motion makes `tetrasim run --scene` exit with 2 naming its key and
//! writing nothing, and the example scenes with contact between bodies, self-contact and
//! moving pins run a few frames on the `cpu` backend from the command line.

use std::path::{Path, PathBuf};
use std::process::Command;

use tetrasim_cli::launch::stage;
use tetrasim_cli::scene::Scene;

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes")
}

#[test]
fn clamped_block_holds_one_end_and_pulls_the_other() {
    let scene = Scene::load(&examples().join("clamped_block.toml")).unwrap();
    let staged = stage(&scene).unwrap();
    let model = &staged.model;
    let pinned: Vec<usize> = (0..model.node_count())
        .filter(|&i| model.inv_mass[i] == 0.0)
        .collect();
    assert_eq!(staged.model.clamps.len(), 1, "one moving pin");
    let clamp = &model.clamps[0];
    assert!(!clamp.nodes.is_empty());
    assert!(
        clamp
            .nodes
            .iter()
            .all(|&i| (model.positions[i as usize].x - 0.5).abs() < 1e-9),
        "the clamp holds the right end's face"
    );
    let left = pinned
        .iter()
        .filter(|&&i| (model.positions[i].x + 0.5).abs() < 1e-9)
        .count();
    assert_eq!(left, clamp.nodes.len(), "the left face is pinned as well");
    assert_eq!(pinned.len(), 2 * left, "only the two end faces are pinned");
    // After the keyframes the right face is 0.3 m further out and held there.
    let end = clamp.target(model.positions[clamp.nodes[0] as usize], 10.0);
    assert!((end.x - 0.8).abs() < 1e-9, "{end}");
}

/// A scene of the bundled box with this `pin`, and outputs that must not appear.
fn pin_scene(pin: &str) -> String {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/box");
    format!(
        "[solver]\nframes = 5\n[[object]]\nmesh = {:?}\ndrop_height = 0.0\n{pin}\n\
         [output]\njson = \"out/m.json\"\ndir = \"frames\"\n",
        mesh.display().to_string()
    )
}

#[test]
fn a_bad_pin_motion_exits_with_2_naming_its_key_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for (pin, needles) in [
        (
            "pin = { nodes = [0], motion = { keyframes = [{ t = 0.5 }, { t = 0.2 }] } }",
            &["`object[0].pin.motion.keyframes[1].t`", "increasing time"][..],
        ),
        (
            "pin = { motion = { velocity = [0, 1, 0] } }",
            &["`object[0].pin.motion`", "moves no node"][..],
        ),
        (
            // A box beside the mesh: valid, but it holds no node once placed.
            "pin = [{ nodes = [0] }, { box = { min = [5, 5, 5], max = [6, 6, 6] }, \
             motion = { velocity = [0, 1, 0] } }]",
            &["`object[0].pin[1].motion`", "moves no node"][..],
        ),
        (
            "pin = [{ nodes = [0] }, { nodes = [0, 1], motion = { velocity = [0, 1, 0] } }]",
            &["`object[0].pin[1].motion`", "object[0].pin[0] holds too"][..],
        ),
    ] {
        let scene = dir.path().join("bad.toml");
        std::fs::write(&scene, pin_scene(pin)).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
            .args(["run", "--quiet", "--backend", "cpu", "--scene"])
            .arg(&scene)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{pin}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        for needle in needles {
            assert!(
                stderr.contains(needle),
                "{pin}: `{needle}` missing: {stderr}"
            );
        }
        let left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(left, ["bad.toml"], "{pin}: wrote something");
    }
}

/// The example scene `name` cut to `frames` frames, its meshes named by absolute paths, in
/// `dir`.
fn shortened(name: &str, frames: u32, dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(examples().join(name)).unwrap();
    let base = examples().display().to_string();
    let text: String = text
        .lines()
        .map(|line| {
            if line.starts_with("frames = ") {
                format!("frames = {frames}\n")
            } else if let Some(rest) = line.strip_prefix("mesh = \"") {
                format!("mesh = \"{base}/{rest}\n")
            } else {
                format!("{line}\n")
            }
        })
        .collect();
    assert!(text.contains(&format!("frames = {frames}\n")), "{name}");
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn the_contact_examples_run_on_cpu_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["folding_bar.toml", "two_bunnies.toml", "clamped_block.toml"] {
        let scene = shortened(name, 5, dir.path());
        let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
            .args(["run", "--quiet", "--backend", "cpu", "--scene"])
            .arg(&scene)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{name}: {stderr}");
    }
}

/// The lowest height [m] of the nodes of the folding bar's right half (the arm the clamp
/// lays over) that end above its left half (x < -0.3), after the fold (1.6 s), on `cpu`.
fn folded_arm_lowest(self_contact: bool) -> f64 {
    use tetrasim::backend::cpu::ParallelBackend;
    use tetrasim::backend::Backend;
    use tetrasim::problem::Problem;
    let mut scene = Scene::load(&examples().join("folding_bar.toml")).unwrap();
    scene.objects[0].self_contact = self_contact;
    let staged = stage(&scene).unwrap();
    let problem = Problem::new(&staged.model, &staged.params).unwrap();
    let mut backend = ParallelBackend::from_problem(&problem);
    for _ in 0..staged.frames {
        backend.step_frame().unwrap();
    }
    let x = backend.state().unwrap().positions;
    let rest = &staged.model.positions;
    (0..x.len())
        .filter(|&i| rest[i].x > 0.05 && x[i].x < -0.3)
        .map(|i| x[i].y)
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn the_folding_bar_comes_to_rest_on_itself() {
    // The arms are 0.1 m thick: the upper one's lower face rests on the lower one's upper
    // face (y = 0.1; measured 0.098 on cpu), held by self-contact, ...
    let with = folded_arm_lowest(true);
    assert!(with > 0.08 && with < 0.12, "with self-contact: {with}");
    // ... and without self-contact it falls through the lower arm to the floor.
    let without = folded_arm_lowest(false);
    assert!(without < 0.02, "without self-contact: {without}");
}
