//! Hands that grab on the Vulkan engine: the bundled box pinned at both ends, grabbed on
//! top in the middle, pulled up 0.2 m over 0.1 s and let go at 0.15 s
//! (crates/tetrasim/tests/colliders.rs, `a_grab_pulls_a_clamped_block_up_and_lets_go`),
//! validation layer on: the held nodes stay on their targets while held, the block rises
//! and falls back after the release, and the run matches `cpu-ref` per frame (volume) and
//! at the end (positions) within the backends' tolerances (tests/gpu_matches_cpu.rs).
//! Without the attachment in the colliders' solve the block would not rise.

mod common;
mod gpu_support;

use glam::{DQuat, DVec3};
use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::collider::{Grab, Keyframe, Motion};
use tetrasim::params::{Placement, SimParams};
use tetrasim::sim::bundled::bundled;
use tetrasim::{Backend, ModelBuilder};

const SUBSTEPS: u32 = 5;

#[test]
fn a_grab_pulls_a_pinned_block_up_on_the_gpu_and_lets_go() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let mesh = bundled("meshes/box").expect("the bundled box");
    let placement = Placement {
        fit_size: Some(1.0),
        drop_height: Some(0.0),
    };
    let free = ModelBuilder::new(&mesh)
        .placement(placement)
        .build()
        .unwrap();
    let lo = free.positions.iter().map(|p| p.x).fold(f64::MAX, f64::min);
    let hi = free.positions.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    let top = free.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
    let key = |t: f64, y: f64| Keyframe {
        t,
        position: DVec3::new(0.0, y, 0.0),
        rotation: DQuat::IDENTITY,
    };
    let grab = Grab::new(DVec3::new((lo + hi) / 2.0, top, 0.0), 0.3)
        .moving(Motion::Keyframes(vec![key(0.0, 0.0), key(0.1, 0.2)]))
        .release_at(0.15);
    let model = ModelBuilder::new(&mesh)
        .placement(placement)
        .pinned_in_box(
            DVec3::new(lo - 1.0, -1.0, -1.0),
            DVec3::new(lo + 1e-6, 2.0, 1.0),
        )
        .pinned_in_box(
            DVec3::new(hi - 1e-6, -1.0, -1.0),
            DVec3::new(hi + 1.0, 2.0, 1.0),
        )
        .build()
        .and_then(|m| m.with_grab(grab))
        .unwrap();
    let held = model.grabs[0].clone();
    let params = SimParams {
        substeps: SUBSTEPS,
        ..SimParams::default()
    };
    let rest = model.total_rest_volume();
    let mut gpu = gpu_support::validated(&model, &params);
    let mut reference = ReferenceBackend::new(&model, &params).unwrap();
    let (mut peak, mut rise, mut worst_off, mut worst_volume) = (0.0f64, 0.0, 0.0f64, 0.0f64);
    for frame in 1..=40u32 {
        gpu.step_frame().unwrap();
        reference.step_frame().unwrap();
        let got = 100.0 * gpu.volume().unwrap().volume / rest;
        let want = 100.0 * reference.volume().unwrap().volume / rest;
        worst_volume = worst_volume.max((got - want).abs());
        let x = gpu.state().unwrap().positions;
        let t = f64::from(frame * SUBSTEPS) * 1e-3;
        rise = (held.nodes.iter())
            .map(|&i| x[i as usize].y - model.positions[i as usize].y)
            .sum::<f64>()
            / held.nodes.len() as f64;
        peak = peak.max(rise);
        if held.holds(t) {
            let off = (held.nodes.iter())
                .map(|&i| x[i as usize].distance(held.target(model.positions[i as usize], t)))
                .fold(0.0, f64::max);
            worst_off = worst_off.max(off);
            assert!(off < 1e-5, "at {t} s: a held node is {off:e} m off");
        }
    }
    gpu_support::assert_no_validation_messages(&gpu);
    assert!(peak > 0.19, "pulled up only {peak} m");
    assert!(rise < 0.5 * peak, "still up {rise} m after letting go");
    let x = gpu.state().unwrap().positions;
    let want = reference.state().unwrap().positions;
    let worst = common::max_distance(&x, &want);
    let diag = model.bounds_diagonal();
    println!(
        "grab: worst held node off its target {worst_off:.2e} m, peak {peak:.3} m, volume \
         difference {worst_volume:.2e} points, final positions {:.2e} of the diagonal",
        worst / diag
    );
    assert!(worst_volume <= 1e-3, "volume off by {worst_volume} points");
    assert!(
        worst <= 1e-5 * diag,
        "a node is {worst} m off the reference"
    );
}
