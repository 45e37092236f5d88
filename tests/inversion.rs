//! The inversion floor (`inversion_sweeps`, issue "Converged where it matters", item 2):
//! tets that a step would leave inside out are pushed back within that step.
//!
//! A box of 384 tets (4 x 4 x 4 cells of 0.1 m, unit node masses, no gravity, floor or
//! springs) starts tangled: every node jittered by up to 6 cm, which turns 41 to 54 tets
//! inside out (three seeds). One step of the volume method at 10 iterations leaves 2, 4 and 5
//! of them inverted without the inversion sweeps (cpu-ref, measured) and none with 4 sweeps,
//! on `cpu-ref`, `cpu` and `vulkan` (validation on, silent) when a Vulkan device exists. The
//! comparison is with the same step without the sweeps, so the test fails with them off.
//! The real-size horse's figures are `tests/real_scale.rs`'s.

mod common;
mod gpu_support;

use common::{bare_params, box_mesh, jittered_state, model_in_place};
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::params::Method;
use tetrasim::{Backend, Model, SimParams, State};

/// The tets `backend` leaves inverted after one step from `state` (at least 40 start so).
fn one_step(backend: &mut dyn Backend, state: &State) -> u32 {
    backend.set_state(state).unwrap();
    let before = backend.volume().unwrap().inverted;
    assert!(before >= 40, "only {before} tets start inverted");
    backend.step_frame().unwrap();
    backend.volume().unwrap().inverted
}

/// Each backend's inverted tets after one step from the box jittered with `seed`, `cpu-ref`
/// first.
fn inverted_after_one_step(model: &Model, params: &SimParams, seed: u64) -> Vec<u32> {
    let state = jittered_state(model, 0.06, 0.0, seed);
    let mut counts = vec![
        one_step(&mut ReferenceBackend::new(model, params).unwrap(), &state),
        one_step(&mut ParallelBackend::new(model, params).unwrap(), &state),
    ];
    if gpu_support::vulkan_available() {
        let mut gpu = gpu_support::validated(model, params);
        counts.push(one_step(&mut gpu, &state));
        gpu_support::assert_no_validation_messages(&gpu);
    }
    counts
}

#[test]
fn a_tangled_box_is_untangled_within_one_step() {
    untangles(0, 4);
}

/// The same in block Gauss-Seidel's blocks of 64 tets (6 blocks): the floor's sweeps run
/// in the blocks, colour by colour, and need 6 (with 4, one tet of seed 3000 stays
/// inverted on every backend: between blocks the floor is Jacobi).
#[test]
fn a_tangled_box_is_untangled_within_one_step_in_blocks() {
    untangles(64, 6);
}

/// One step of the tangled box leaves tets inverted without the sweeps and none with
/// `sweeps` of them, the volume sweep in blocks of `block_size` (0: colour groups).
fn untangles(block_size: u32, sweeps: u32) {
    let model = model_in_place(&box_mesh([4, 4, 4]));
    let params = |sweeps| SimParams {
        method: Method::Volume,
        inversion_sweeps: sweeps,
        block_size,
        ..bare_params()
    };
    for seed in [1000, 2000, 3000] {
        let without = inverted_after_one_step(&model, &params(0), seed);
        let with = inverted_after_one_step(&model, &params(sweeps), seed);
        println!(
            "blocks of {block_size}, seed {seed}: inverted after the step {without:?} without, \
             {with:?} with"
        );
        for (backend, (&off, &on)) in without.iter().zip(&with).enumerate() {
            assert!(
                off >= 1,
                "backend {backend}, seed {seed}: the step alone untangles the box"
            );
            assert_eq!(
                on, 0,
                "backend {backend}, seed {seed}: {on} tets stay inverted with the sweeps"
            );
        }
    }
}
