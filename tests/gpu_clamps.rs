//! Pins that move (clamps) on the Vulkan engine: the bundled box's top layer keyframed up
//! 0.3 m and turned 0.5 rad about Y over 0.2 s (crates/tetrasim/tests/colliders.rs,
//! `a_clamp_follows_its_keyframes_exactly_and_drags_the_body`), validation layer on: every
//! clamped node ends every frame on its target, the body is dragged up, and the run matches
//! `cpu-ref` per frame (volume) and at the end (positions) within the backends' tolerances
//! (tests/gpu_matches_cpu.rs), and so does the force the clamp exerts (forces out, the
//! `reactions` pass: within 1e-3 of its largest). Without `clamp_drive` the clamped nodes
//! would not move.

mod common;
mod gpu_support;

use glam::{DQuat, DVec3};
use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::collider::{Keyframe, Motion};
use tetrasim::params::{Placement, SimParams};
use tetrasim::sim::bundled::bundled;
use tetrasim::{Backend, ModelBuilder};

const SUBSTEPS: u32 = 5;

#[test]
fn a_clamp_follows_its_keyframes_exactly_on_the_gpu_and_drags_the_body() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let mesh = bundled("meshes/box").expect("the bundled box");
    let lift = Motion::Keyframes(vec![
        Keyframe {
            t: 0.0,
            position: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
        },
        Keyframe {
            t: 0.2,
            position: DVec3::new(0.0, 0.3, 0.0),
            rotation: DQuat::from_rotation_y(0.5),
        },
    ]);
    let placement = Placement {
        fit_size: Some(0.5),
        drop_height: Some(0.0),
    };
    let free = ModelBuilder::new(&mesh)
        .placement(placement)
        .build()
        .unwrap();
    let top = free.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
    let model = ModelBuilder::new(&mesh)
        .placement(placement)
        .pinned_in_box(
            DVec3::new(-1.0, top - 1e-6, -1.0),
            DVec3::new(1.0, 1.0, 1.0),
        )
        .pin_motion(lift)
        .build()
        .unwrap();
    let clamp = model.clamps.first().expect("a clamp").clone();
    let params = SimParams {
        substeps: SUBSTEPS,
        ..SimParams::default()
    };
    let rest = model.total_rest_volume();
    let mut gpu = gpu_support::validated(&model, &params);
    assert!(gpu.plan().has_pass("clamp_drive"));
    let mut reference = ReferenceBackend::new(&model, &params).unwrap();
    let mut worst_off: f64 = 0.0;
    let mut worst_volume: f64 = 0.0;
    let (mut worst_force, mut largest_force) = (0.0f64, 0.0f64);
    for frame in 1..=60u32 {
        gpu.step_frame().unwrap();
        reference.step_frame().unwrap();
        let force = |r: Option<tetrasim::backend::Reactions>| r.expect("measured").clamps[0];
        let want = force(reference.reactions().unwrap());
        worst_force = worst_force.max((force(gpu.reactions().unwrap()) - want).length());
        largest_force = largest_force.max(want.length());
        let got = 100.0 * gpu.volume().unwrap().volume / rest;
        let want = 100.0 * reference.volume().unwrap().volume / rest;
        worst_volume = worst_volume.max((got - want).abs());
        let x = gpu.state().unwrap().positions;
        let t = f64::from(frame * SUBSTEPS) * 1e-3;
        let off = (clamp.nodes.iter())
            .map(|&i| x[i as usize].distance(clamp.target(model.positions[i as usize], t)))
            .fold(0.0, f64::max);
        worst_off = worst_off.max(off);
        // f32 like `cpu`: 1e-6 of a 0.5 m body.
        assert!(off < 1e-6, "frame {frame}: a clamped node is {off:e} m off");
    }
    gpu_support::assert_no_validation_messages(&gpu);
    let x = gpu.state().unwrap().positions;
    let want = reference.state().unwrap().positions;
    let worst = common::max_distance(&x, &want);
    let diag = model.bounds_diagonal();
    println!(
        "clamp: worst clamped node off its target {worst_off:.2e} m, volume difference \
         {worst_volume:.2e} points, final positions {:.2e} of the diagonal, its force within \
         {:.2e} of its largest ({largest_force:.3} N)",
        worst / diag,
        worst_force / largest_force
    );
    assert!(
        worst_force <= 1e-3 * largest_force && largest_force > 0.0,
        "the clamp's force is {worst_force} N off the reference's (largest {largest_force} N)"
    );
    assert!(worst_volume <= 1e-3, "volume off by {worst_volume} points");
    assert!(
        worst <= 1e-5 * diag,
        "a node is {worst} m off the reference"
    );
    let lift = |p: &[DVec3]| p.iter().map(|p| p.y).sum::<f64>() / p.len() as f64;
    let lifted = lift(&x) - lift(&model.positions);
    assert!(
        lifted > 0.15,
        "the body rose only {lifted} m with its clamp"
    );
}
