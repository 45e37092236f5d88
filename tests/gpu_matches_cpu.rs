//! The Vulkan engine computes what the f64 reference computes: for every method and both
//! float-atomic paths, on a small ball dropped per the `seed` preset, the per-frame volume
//! percentage and the final positions match `cpu-ref`.
//!
//! Tolerances (the GPU works in f32, the reference in f64; atomics add in any order):
//! - volume: every frame within [`VOLUME_POINTS`] percentage points (observed on lavapipe:
//!   at most 1.5e-5 here, and 3.4e-5 over the whole 400-frame seed run on the bunny);
//! - positions: every node within [`POSITION_FRACTION`] of the bounding-box diagonal after
//!   the run, which includes the fall and the impact on the floor (observed: at most 1.3e-7).

mod common;
mod gpu_support;

use tetrasim::cpu::ReferenceBackend;
use tetrasim::params::{AtomicsMode, Method, SimParams};
use tetrasim::Backend;

/// Largest allowed per-frame difference of the volume percentage [percentage points].
const VOLUME_POINTS: f64 = 1e-3;
/// Largest allowed final position difference, as a fraction of the bounding-box diagonal.
const POSITION_FRACTION: f64 = 1e-5;
/// Frames of the run: the ball falls 0.1 m (about 143 frames) and then hits the floor.
const FRAMES: u32 = 200;

#[test]
fn every_method_and_atomic_path_matches_the_reference() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = common::seed_model(&common::ball_mesh(4.5));
    let rest = model.total_rest_volume();
    let diag = model.bounds_diagonal();
    for method in Method::ALL {
        let params = SimParams {
            method,
            ..SimParams::default()
        };
        let mut reference = ReferenceBackend::new(&model, &params).unwrap();
        let mut expected = Vec::new();
        for _ in 0..FRAMES {
            reference.step_frame().unwrap();
            expected.push(100.0 * reference.volume().unwrap().volume / rest);
        }
        let expected_state = reference.state().unwrap();
        let least = expected.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            least < 99.95,
            "{method}: the reference never deformed (least volume {least} %)"
        );
        for atomics in [AtomicsMode::Ext, AtomicsMode::Cas] {
            let params = SimParams {
                atomics,
                ..params.clone()
            };
            let mut gpu = gpu_support::validated(&model, &params);
            let mut worst_volume = 0.0f64;
            for (frame, want) in expected.iter().enumerate() {
                gpu.step_frame().unwrap();
                let got = 100.0 * gpu.volume().unwrap().volume / rest;
                worst_volume = worst_volume.max((got - want).abs());
                assert!(
                    (got - want).abs() <= VOLUME_POINTS,
                    "{method} {atomics:?} frame {frame}: volume {got:.4} % vs reference {want:.4} %"
                );
            }
            let state = gpu.state().unwrap();
            let (worst_node, worst_position) = state
                .positions
                .iter()
                .zip(&expected_state.positions)
                .map(|(a, b)| a.distance(*b))
                .enumerate()
                .fold(
                    (0, 0.0f64),
                    |best, (i, d)| if d > best.1 { (i, d) } else { best },
                );
            println!(
                "{method} {atomics:?}: worst volume difference {worst_volume:.2e} points, \
                 worst position difference {:.2e} of the diagonal (node {worst_node})",
                worst_position / diag
            );
            assert!(
                worst_position <= POSITION_FRACTION * diag,
                "{method} {atomics:?}: node {worst_node} is {worst_position} m from the reference (diagonal {diag} m)"
            );
            // The comparison is not vacuous: the ball fell and the impact deformed it.
            let drop = model.positions[worst_node].y - state.positions[worst_node].y;
            assert!(
                drop > 0.05,
                "{method}: node {worst_node} fell only {drop} m"
            );
            gpu_support::assert_no_validation_messages(&gpu);
        }
    }
}
