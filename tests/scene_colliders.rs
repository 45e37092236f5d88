//! Colliders in scene files from the command line: every example scene parses and stages
//! with its colliders, clamps and self-contact, and a bad `[[collider]]` makes `tetrasim run --scene` exit with 2,
//! naming the key's path, before it writes anything.

use std::path::Path;
use std::process::Command;

use tetrasim::glam::DVec3;
use tetrasim::mesh::io::write_surface;
use tetrasim::mesh::shapes::box_surface;
use tetrasim_cli::launch::stage;
use tetrasim_cli::scene::Scene;

#[test]
fn every_example_scene_parses_and_stages() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    let mut seen = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let staged = stage(&scene).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let declared = scene
            .colliders
            .iter()
            .filter(|c| c.name() != "floor")
            .count();
        assert_eq!(
            staged.model.colliders.len(),
            declared,
            "{}: every collider but the floor is on the model",
            path.display()
        );
        let moving = scene
            .objects
            .iter()
            .flat_map(|o| &o.pin.pins)
            .filter(|p| p.motion.is_some())
            .count();
        assert_eq!(
            staged.model.clamps.len(),
            moving,
            "{}: a clamp per moving pin",
            path.display()
        );
        let self_contact: Vec<bool> = scene.objects.iter().map(|o| o.self_contact).collect();
        assert_eq!(
            staged.model.self_contact,
            self_contact,
            "{}",
            path.display()
        );
        seen.push(path.file_name().unwrap().to_string_lossy().into_owned());
    }
    for name in [
        "capsule_press.toml",
        "tilted_plane.toml",
        "torus_on_rotating_box.toml",
        "clamped_block.toml",
        "two_bunnies.toml",
        "folding_bar.toml",
    ] {
        assert!(seen.iter().any(|s| s == name), "{name} missing: {seen:?}");
    }
}

/// A scene of the bundled sphere on the floor with `collider` as `[[collider]]` number 1, and
/// outputs that must not appear.
fn bad_scene(collider: &str) -> String {
    let sphere = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    format!(
        "[solver]\nframes = 5\n[[object]]\nmesh = {:?}\ndrop_height = 0.0\n\
         [[collider]]\ntype = \"floor\"\n[[collider]]\n{collider}\n\
         [output]\njson = \"out/m.json\"\ndir = \"frames\"\n",
        sphere.display().to_string()
    )
}

#[test]
fn a_bad_collider_exits_with_2_naming_its_key_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut open = box_surface(-DVec3::ONE, DVec3::ONE, 2);
    open.triangles.pop();
    write_surface(dir.path().join("open.off"), &open).unwrap();
    for (collider, needles) in [
        (
            "type = \"cone\"\nradius = 1.0",
            &["collider[1]", "unknown variant `cone`", "`capsule`"][..],
        ),
        (
            "type = \"mesh\"\npath = \"open.off\"",
            &["`collider[1].mesh`", "not closed", "one triangle only"][..],
        ),
        (
            "type = \"mesh\"\npath = \"absent.off\"",
            &["`collider[1].mesh`", "absent.off"][..],
        ),
        (
            "type = \"capsule\"\na = [0, 1.2, 0]\nb = [1, 1.2, 0]\nradius = 0.1\n\
             motion = { keyframes = [{ t = 0.5 }, { t = 0.2 }] }",
            &["`collider[1].motion.keyframes[1].t`", "increasing time"][..],
        ),
        (
            "type = \"sphere\"\ncenter = [0, 2, 0]\nradius = 0.0",
            &["`collider[1].radius`"][..],
        ),
        (
            "type = \"box\"\ncenter = [0, 2, 0]\nhalf_extents = [1, 1, 1]\n\
             rotation = [0.5, 0.5, 0.0, 0.0]",
            &["`collider[1].rotation`", "unit quaternion"][..],
        ),
    ] {
        let scene = dir.path().join("bad.toml");
        std::fs::write(&scene, bad_scene(collider)).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
            .args(["run", "--quiet", "--scene"])
            .arg(&scene)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{collider}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        for needle in needles {
            assert!(
                stderr.contains(needle),
                "{collider}: `{needle}` missing: {stderr}"
            );
        }
        let mut left: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(
            left,
            ["bad.toml", "open.off"],
            "{collider}: wrote something"
        );
    }
}
