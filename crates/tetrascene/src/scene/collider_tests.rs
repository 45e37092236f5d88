//! `[[collider]]` of every type: what each becomes in the engine, and what is refused (with
//! the key's path in the scene's numbering, the floor included).

use std::path::Path;

use glam::{DQuat, DVec3};
use tetrasim::collider::{Motion, Shape};
use tetrasim::mesh::shapes::box_surface;

use super::*;

/// A one-object scene with these `[[collider]]` tables (TOML bodies).
fn scene(colliders: &[&str]) -> String {
    let mut text = "[[object]]\nmesh = \"a\"\n".to_string();
    for c in colliders {
        text += &format!("[[collider]]\n{c}\n");
    }
    text
}

/// The error of parsing these colliders.
fn refused(colliders: &[&str]) -> String {
    Scene::parse(&scene(colliders)).unwrap_err().to_string()
}

/// Writes the surface of the box `[-h, h]` (2 x 2 squares a side) to `dir/name`, less its
/// first `drop` triangles.
fn write_box(dir: &Path, name: &str, h: DVec3, drop: usize) -> std::path::PathBuf {
    let mut surface = box_surface(-h, h, 2);
    surface.triangles.drain(..drop);
    let path = dir.join(name);
    tetrasim::mesh::io::write_surface(&path, &surface).unwrap();
    path
}

#[test]
fn each_type_becomes_its_engine_collider() {
    let text = scene(&[
        "type = \"floor\"\nfriction = 0.3",
        "type = \"plane\"\nnormal = [0.0, 2.0, 0.0]\noffset = -1.0\nfriction = 0.5",
        "type = \"sphere\"\ncenter = [0.0, 1.0, 0.0]\nradius = 0.25\nthickness = 0.01",
        "type = \"box\"\ncenter = [1.0, 0.0, 0.0]\nhalf_extents = [0.5, 0.1, 0.5]\n\
         rotation = [0.7071, 0.0, 0.7071, 0.0]\nmotion = { angular_velocity = [0.0, 1.0, 0.0] }",
        "type = \"capsule\"\na = [-1.0, 0.5, 0.0]\nb = [1.0, 0.5, 0.0]\nradius = 0.1\n\
         motion = { keyframes = [{ t = 0.0 }, { t = 1.0, position = [0.0, -0.2, 0.0] }] }",
    ]);
    let scene = Scene::parse(&text).unwrap();
    let p = scene.params_for(0);
    assert!(p.floor && p.friction == 0.3, "the floor stays SimParams'");
    let colliders = scene.colliders().unwrap();
    let names: Vec<_> = colliders.iter().map(|c| c.shape.name()).collect();
    assert_eq!(
        names,
        ["plane", "sphere", "box", "capsule"],
        "scene order, no floor"
    );
    let plane = &colliders[0];
    assert_eq!(plane.friction, 0.5);
    assert!((plane.pose.position - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-12);
    assert_eq!(colliders[1].shape, Shape::Sphere { radius: 0.25 });
    assert_eq!(colliders[1].thickness, 0.01);
    let cuboid = &colliders[2];
    let quarter = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2);
    assert!(
        cuboid.pose.rotation.angle_between(quarter) < 1e-4,
        "w first, normalised"
    );
    assert!((cuboid.pose.rotation.length() - 1.0).abs() < 1e-12);
    assert_eq!(
        cuboid.motion,
        Motion::Velocity {
            linear: DVec3::ZERO,
            angular: DVec3::Y
        }
    );
    let capsule = &colliders[3];
    assert_eq!(
        capsule.shape,
        Shape::Capsule {
            half_length: 1.0,
            radius: 0.1
        }
    );
    match &capsule.motion {
        Motion::Keyframes(keys) => {
            assert_eq!(keys.len(), 2);
            assert_eq!(keys[1].position, DVec3::new(0.0, -0.2, 0.0));
            assert_eq!(
                keys[0].rotation,
                DQuat::IDENTITY,
                "rotation defaults to none"
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_mesh_collider_reads_its_surface_relative_to_the_scene() {
    let dir = tempfile::tempdir().unwrap();
    let h = DVec3::new(0.5, 0.25, 0.25);
    write_box(dir.path(), "tool.off", h, 0);
    let file = dir.path().join("scene.toml");
    std::fs::write(
        &file,
        scene(&["type = \"mesh\"\npath = \"tool.off\"\ncells = 16\nfriction = 0.2"]),
    )
    .unwrap();
    let scene = Scene::load(&file).unwrap();
    let colliders = scene.colliders().unwrap();
    let mesh = &colliders[0];
    match &mesh.shape {
        Shape::Grid(grid) => assert_eq!(grid.dims[0], 17, "cells along the longest side"),
        other => panic!("{other:?}"),
    }
    assert!(mesh.pose.position.length() < 1e-9, "centred on its bounds");
    let at = |p: DVec3| mesh.shape.distance(mesh.pose.invert(p)).0;
    let inside = DVec3::new(0.3, 0.1, 0.0);
    assert!((at(inside) + 0.15).abs() < 1e-9, "inside: {}", at(inside));
    assert!((at(DVec3::new(1.0, 0.0, 0.0)) - 0.5).abs() < 1e-9);
    // The default resolution.
    let text = scene_text_with_path(&dir.path().join("tool.off"), "");
    let colliders = Scene::parse(&text).unwrap().colliders().unwrap();
    match &colliders[0].shape {
        Shape::Grid(grid) => assert_eq!(grid.dims[0], DEFAULT_CELLS + 1),
        other => panic!("{other:?}"),
    }
}

fn scene_text_with_path(path: &Path, extra: &str) -> String {
    scene(&[&format!(
        "type = \"mesh\"\npath = {:?}\n{extra}",
        path.display().to_string()
    )])
}

#[test]
fn bad_mesh_colliders_name_their_mesh_key() {
    let dir = tempfile::tempdir().unwrap();
    let open = write_box(dir.path(), "open.off", DVec3::ONE, 1);
    let colliders = |text: String| {
        Scene::parse(&text)
            .unwrap()
            .colliders()
            .unwrap_err()
            .to_string()
    };
    let err = colliders(scene_text_with_path(&open, ""));
    assert!(
        err.contains("`collider[0].mesh`")
            && err.contains("not closed: 3 edges belong to one triangle only")
            && err.contains("open.off"),
        "{err}"
    );
    let err = colliders(scene_text_with_path(&dir.path().join("missing.off"), ""));
    assert!(
        err.contains("`collider[0].mesh`") && err.contains("missing.off"),
        "{err}"
    );
    let err = refused(&["type = \"mesh\"\npath = \"a.off\"\ncells = 2"]);
    assert!(err.contains("`collider[0].cells`"), "{err}");
}

#[test]
fn bad_colliders_name_their_key() {
    let floor = "type = \"floor\"";
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["type = \"cone\"\nradius = 1.0"],
            &["collider[0]", "unknown variant `cone`", "`floor`", "`plane`", "`sphere`", "`box`", "`capsule`", "`mesh`"],
        ),
        (&["type = \"sphere\"\ncenter = [0, 0, 0]"], &["collider[0]", "missing field `radius`"]),
        (
            &[floor, "type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0.0"],
            &["`collider[1].radius`", "positive"],
        ),
        (
            &["type = \"box\"\ncenter = [0, 0, 0]\nhalf_extents = [1, 1, 1]\nradius = 1.0"],
            &["collider[0]", "unknown field `radius`"],
        ),
        (
            &[floor, "type = \"box\"\ncenter = [0, 0, 0]\nhalf_extents = [1, 1, 1]\nrotation = [1.0, 0.0, 0.5, 0.0]"],
            &["`collider[1].rotation`", "unit quaternion [w, x, y, z]"],
        ),
        (
            &["type = \"box\"\ncenter = [0, 0, 0]\nhalf_extents = [1, 1, 1]\nrotation = [0, 0, 0, 0]"],
            &["`collider[0].rotation`", "unit quaternion"],
        ),
        (
            &[floor, "type = \"capsule\"\na = [0, 0, 0]\nb = [1, 0, 0]\nradius = 0.1\n\
              motion = { keyframes = [{ t = 0.0 }, { t = 1.0 }, { t = 0.5 }] }"],
            &["`collider[1].motion.keyframes[2].t`", "increasing time"],
        ),
        (
            &["type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1.0\n\
              motion = { keyframes = [{ t = 0.0, rotation = [2.0, 0.0, 0.0, 0.0] }] }"],
            &["`collider[0].motion.keyframes[0].rotation`"],
        ),
        (
            &["type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1.0\n\
              motion = { velocity = [1, 0, 0], keyframes = [{ t = 0.0 }] }"],
            &["`collider[0].motion`", "not both"],
        ),
        (
            &["type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1.0\nmotion = { spin = 1.0 }"],
            &["collider[0]", "unknown field `spin`"],
        ),
        (
            &[floor, floor],
            &["`collider[1]`", "second floor"],
        ),
        (
            &["type = \"plane\"\nnormal = [0, 0, 0]\noffset = 0.0"],
            &["`collider[0].normal`"],
        ),
        (
            &["type = \"sphere\"\ncenter = [0, nan, 0]\nradius = 1.0"],
            &["`collider[0].center`", "finite"],
        ),
        (
            // The key the file gives, not the field behind it (`offset` before 2026-12-06).
            &["type = \"plane\"\nnormal = [0, 1, 0]\ndistance = inf"],
            &["`collider[0].distance`", "finite"],
        ),
        (
            &["type = \"capsule\"\na = [0, 0, 0]\nb = [1, 0, 0]\nradius = 0.1\nfriction = 1.5"],
            &["`collider[0].friction`"],
        ),
        (
            &["type = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1.0\nthickness = -0.1"],
            &["`collider[0].thickness`"],
        ),
        (
            &["type = \"box\"\ncenter = [0, 0, 0]\nhalf_extents = [1, 0, 1]"],
            &["`collider[0].half_extents.y`"],
        ),
        (
            &["type = \"mesh\"\ncells = 32"],
            &["collider[0]", "missing field `mesh`"],
        ),
    ];
    for (colliders, needles) in cases {
        let err = refused(colliders);
        for needle in *needles {
            assert!(
                err.contains(needle),
                "{colliders:?}: `{needle}` missing in: {err}"
            );
        }
    }
}
