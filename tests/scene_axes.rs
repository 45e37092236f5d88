//! An object's `rotation` and gravity as a vector: a Z-up scene. The bundled box (1 m
//! along X, 0.5 m square) is turned 90 degrees about Y so that it stands along Z, falls 5 cm
//! under `gravity = [0, 0, -9.81]` onto the plane `z = 0` (a plane collider; the floor stays
//! `y = 0` and is not in the scene) and comes to rest there, on `cpu` and on `vulkan`.
//! Without the rotation the box would lie along X; with gravity along -Y it would fall
//! past the plane's side by metres in 0.6 s.

mod gpu_support;

use std::path::Path;

use tetrasim::backend::cpu::ParallelBackend;
use tetrasim::backend::Backend;
use tetrasim::glam::{DQuat, DVec3};
use tetrasim::problem::Problem;
use tetrasim_cli::launch::{stage, Staged};
use tetrasim_cli::scene::Scene;

/// Frames of 1 ms: 0.1 s of fall, then 1.9 s to settle.
const FRAMES: u32 = 2000;

/// The last frames, over which the plane's force is averaged: the body still rocks on its
/// springs, so the plane's mean force is the weight plus the change of the body's momentum
/// over that time, divided by the time.
const AVERAGED: u32 = 1000;

fn z_up_scene() -> Scene {
    let mesh = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/box");
    let half = std::f64::consts::FRAC_1_SQRT_2;
    Scene::parse(&format!(
        "[solver]\nframes = {FRAMES}\ngravity = [0.0, 0.0, -9.81]\n\
         [[object]]\nmesh = {:?}\nrotation = [{half}, 0.0, {half}, 0.0]\n\
         offset = [0.0, 0.0, 0.55]\n\
         [[collider]]\ntype = \"plane\"\nnormal = [0.0, 0.0, 1.0]\ndistance = 0.0\n",
        mesh.display().to_string()
    ))
    .unwrap()
}

/// Each axis's extent of `points`.
fn extent(points: &[DVec3]) -> DVec3 {
    let lo = points.iter().fold(DVec3::MAX, |a, &p| a.min(p));
    let hi = points.iter().fold(DVec3::MIN, |a, &p| a.max(p));
    hi - lo
}

fn centroid(points: &[DVec3]) -> DVec3 {
    points.iter().sum::<DVec3>() / points.len() as f64
}

#[test]
fn rotation_turns_the_mesh_about_its_centre_before_the_offset() {
    let staged = stage(&z_up_scene()).unwrap();
    let mesh = tetrasim::sim::load_mesh(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/box"),
        None,
    )
    .unwrap()
    .mesh;
    // The box is centred on the origin: each node is turned there, then lifted.
    let turn = DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2);
    for (placed, &p) in staged.model.positions.iter().zip(&mesh.nodes) {
        let expected = turn * p + DVec3::new(0.0, 0.0, 0.55);
        assert!(placed.distance(expected) < 1e-6, "{placed} vs {expected}");
    }
    let size = extent(&staged.model.positions);
    assert!(
        (size.z - 1.0).abs() < 1e-6 && (size.x - 0.5).abs() < 1e-6,
        "{size}"
    );
}

/// The body's momentum [kg m/s].
fn momentum(staged: &Staged, backend: &mut dyn Backend) -> DVec3 {
    let v = backend.state().unwrap().velocities;
    v.iter().zip(&staged.model.mass).map(|(v, m)| *v * *m).sum()
}

/// What the last [`AVERAGED`] frames say of the plane: its mean force (`cpu` only) and the
/// body's change of momentum over them divided by their time.
struct Window {
    plane: Option<DVec3>,
    momentum_rate: DVec3,
}

/// The run's end state and its last frames' [`Window`] (one step per frame).
fn run(staged: &Staged, backend: &mut dyn Backend) -> (Vec<DVec3>, Window) {
    let mut sum = Some(DVec3::ZERO);
    let mut start = DVec3::ZERO;
    for frame in 0..staged.frames {
        if frame == staged.frames - AVERAGED {
            start = momentum(staged, backend);
        }
        backend.step_frame().unwrap();
        if frame >= staged.frames - AVERAGED {
            let plane = backend.reactions().unwrap().map(|r| r.colliders[0]);
            sum = sum.zip(plane).map(|(s, f)| s + f);
        }
    }
    let time = f64::from(AVERAGED) * staged.params.dt;
    let window = Window {
        plane: sum.map(|s| s / f64::from(AVERAGED)),
        momentum_rate: (momentum(staged, backend) - start) / time,
    };
    (backend.state().unwrap().positions, window)
}

/// The end state rests on the plane where it fell: its lowest node on `z = 0`, its
/// centroid not moved across (gravity has no X or Y part), still standing along Z.
fn assert_rests_on_the_plane(name: &str, start: &[DVec3], end: &[DVec3]) {
    let lowest = end.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    assert!(lowest.abs() < 0.01, "{name}: lowest node at z = {lowest}");
    let across = (centroid(end) - centroid(start)).truncate().length();
    assert!(across < 1e-3, "{name}: moved {across} m across");
    let size = extent(end);
    assert!(size.z > 0.9 && size.x < 0.6, "{name}: extent {size}");
}

#[test]
fn a_z_up_body_falls_along_z_and_rests_on_the_plane_z_0_on_cpu() {
    let staged = stage(&z_up_scene()).unwrap();
    let problem = Problem::new(&staged.model, &staged.params).unwrap();
    let mut backend = ParallelBackend::from_problem(&problem);
    let (end, window) = run(&staged, &mut backend);
    assert_rests_on_the_plane("cpu", &staged.model.positions, &end);
    // The plane carries the weight, straight up, and what the body's momentum changed:
    // F + M g = dP/dt over the window.
    let weight = DVec3::new(0.0, 0.0, staged.model.mass.iter().sum::<f64>() * 9.81);
    let plane = window.plane.expect("cpu measures the colliders' forces");
    let expected = weight + window.momentum_rate;
    assert!(
        plane.distance(expected) < 1e-4 * weight.z,
        "mean plane force {plane}, weight {weight} plus momentum rate {}",
        window.momentum_rate
    );
}

#[test]
fn a_z_up_body_falls_along_z_and_rests_on_the_plane_z_0_on_vulkan() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let staged = stage(&z_up_scene()).unwrap();
    let mut backend = gpu_support::validated(&staged.model, &staged.params);
    let (end, _) = run(&staged, &mut backend);
    assert_rests_on_the_plane("vulkan", &staged.model.positions, &end);
    gpu_support::assert_no_validation_messages(&backend);
}
