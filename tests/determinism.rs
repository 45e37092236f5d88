//! Bit-identical reruns: the default solver (Gauss-Seidel by colour groups, the gather path
//! without float atomics; on `vulkan` Chebyshev with the global constraint as well) on
//! `vulkan` and on `cpu` gives the same positions, velocities and
//! per-frame volumes to the last bit when a run is repeated, on the bundled sphere jittered
//! and dropped onto the floor (200 frames: fall, impact, rest).
//!
//! Not vacuous: the same comparison tells apart two runs whose starts differ by one unit in
//! the last place of one coordinate (so it would see any nondeterminism that grows as such a
//! difference does), and the run deforms. The atomic Jacobi path is run twice as well and
//! whether it repeated is printed (float atomics add in whatever order the threads arrive;
//! on lavapipe they may still repeat).

mod gpu_support;

use gpu_support::{bundled_sphere, jittered};
use tetrasim::backend::cpu::ParallelBackend;
use tetrasim::params::{Placement, SimParams, Solver};
use tetrasim::{Backend, Model, ModelBuilder};

const FRAMES: u32 = 200;

/// Everything a run produces, as bits.
#[derive(Debug, PartialEq)]
struct Trace {
    volumes: Vec<u64>,
    positions: Vec<[u64; 3]>,
    velocities: Vec<[u64; 3]>,
}

fn trace(backend: &mut dyn Backend) -> Trace {
    let mut volumes = Vec::new();
    for _ in 0..FRAMES {
        backend.step_frame().unwrap();
        volumes.push(backend.volume().unwrap().volume.to_bits());
    }
    let state = backend.state().unwrap();
    let bits = |v: &[glam::DVec3]| v.iter().map(|p| p.to_array().map(f64::to_bits)).collect();
    Trace {
        volumes,
        positions: bits(&state.positions),
        velocities: bits(&state.velocities),
    }
}

fn model() -> Model {
    let sphere = ModelBuilder::new(&bundled_sphere())
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.05),
        })
        .build()
        .unwrap();
    jittered(&sphere, 0.01, 0.3, 17)
}

/// The model with one coordinate of one node moved by one unit in the last place of f32.
fn nudged(model: &Model) -> Model {
    let mut m = model.clone();
    let x = m.positions[7].x as f32;
    m.positions[7].x = f64::from(f32::from_bits(x.to_bits() + 1));
    m
}

fn vulkan(model: &Model, params: &SimParams) -> Trace {
    let mut gpu = gpu_support::validated(model, params);
    let t = trace(&mut gpu);
    gpu_support::assert_no_validation_messages(&gpu);
    t
}

#[test]
fn the_default_solver_repeats_bit_for_bit_on_vulkan() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = model();
    let params = SimParams::default();
    assert_eq!(params.solver, Solver::GaussSeidel, "the default solver");
    let first = vulkan(&model, &params);
    let second = vulkan(&model, &params);
    assert!(
        first == second,
        "two vulkan runs of the default solver differ"
    );
    let other = vulkan(&nudged(&model), &params);
    assert!(
        other.positions != first.positions && other.volumes != first.volumes,
        "the comparison cannot see a one-ulp change of the start"
    );
    let least = first
        .volumes
        .iter()
        .map(|&v| f64::from_bits(v))
        .fold(f64::INFINITY, f64::min);
    assert!(
        least < model.total_rest_volume() * (1.0 - 1e-5),
        "no deformation"
    );

    // Chebyshev gathers per node too (no float atomics), with the global volume constraint
    // reduced over chunks of the surface: it repeats as well.
    let chebyshev = SimParams {
        solver: Solver::Chebyshev,
        rho: 0.9,
        global_volume: Some(true),
        ..params.clone()
    };
    let (a, b) = (vulkan(&model, &chebyshev), vulkan(&model, &chebyshev));
    assert!(a == b, "two vulkan runs of chebyshev+global differ");
    assert!(a != first, "chebyshev ran the default solver");

    let jacobi = SimParams {
        solver: Solver::Jacobi,
        ..params
    };
    let (a, b) = (vulkan(&model, &jacobi), vulkan(&model, &jacobi));
    println!(
        "atomic jacobi path repeated bit for bit: {} (not required)",
        a == b
    );
}

#[test]
fn the_default_solver_repeats_bit_for_bit_on_cpu() {
    let model = model();
    let params = SimParams::default();
    let run = |m: &Model| trace(&mut ParallelBackend::new(m, &params).unwrap());
    let first = run(&model);
    assert!(first == run(&model), "two cpu runs differ");
    assert!(
        run(&nudged(&model)).positions != first.positions,
        "the comparison cannot see a one-ulp change of the start"
    );
}
