//! The Vulkan engine computes what the f64 reference computes: for every method with the
//! Jacobi solver on both float-atomic paths and with the Gauss-Seidel solver (the gather
//! path, no atomics), on a small ball dropped per the `seed` preset, the per-frame volume
//! percentage and the final positions match `cpu-ref`.
//!
//! Tolerances (the GPU works in f32, the reference in f64; atomics add in any order):
//! - volume: every frame within [`VOLUME_POINTS`] percentage points (observed on lavapipe:
//!   at most 1.5e-5 here, and 3.4e-5 over the whole 400-frame seed run on the bunny);
//! - positions: every node within [`POSITION_FRACTION`] of the bounding-box diagonal after
//!   the run, which includes the fall and the impact on the floor (observed: at most 1.3e-7).

mod common;
mod gpu_support;

use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::backend::vulkan::{AtomicsMode, EngineOptions};
use tetrasim::params::{Method, SimParams, Solver};
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
    let paths = [
        (Solver::Jacobi, AtomicsMode::Ext, false),
        (Solver::Jacobi, AtomicsMode::Cas, false),
        (Solver::GaussSeidel, AtomicsMode::Auto, false),
        (Solver::GaussSeidel, AtomicsMode::Auto, true),
    ];
    for (method, (solver, atomics, global)) in Method::ALL
        .into_iter()
        .flat_map(|m| paths.into_iter().map(move |p| (m, p)))
    {
        let params = SimParams {
            method,
            solver,
            global_volume: Some(global),
            ..SimParams::default()
        };
        let mut reference = ReferenceBackend::new(&model, &params).unwrap();
        let mut expected = Vec::new();
        let mut deformed = 0.0f64;
        for _ in 0..FRAMES {
            reference.step_frame().unwrap();
            let sample = reference.volume().unwrap();
            expected.push(100.0 * sample.volume / rest);
            deformed = deformed.max(100.0 * sample.local_error / rest);
        }
        let expected_state = reference.state().unwrap();
        // Not vacuous: the impact deformed the tets (local volume error, which the global
        // volume constraint cannot hide).
        assert!(
            deformed > 0.01,
            "{method}: the reference never deformed (largest local error {deformed} %)"
        );
        {
            let options = EngineOptions {
                atomics,
                ..EngineOptions::default()
            };
            let mut gpu = gpu_support::validated_with(&model, &params, options);
            let mut worst_volume = 0.0f64;
            for (frame, want) in expected.iter().enumerate() {
                gpu.step_frame().unwrap();
                let got = 100.0 * gpu.volume().unwrap().volume / rest;
                worst_volume = worst_volume.max((got - want).abs());
                assert!(
                    (got - want).abs() <= VOLUME_POINTS,
                    "{method} {solver} global {global} {atomics:?} frame {frame}: volume {got:.4} % vs reference {want:.4} %"
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
                "{method} {solver} global {global} {atomics:?}: worst volume difference {worst_volume:.2e} points, \
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
