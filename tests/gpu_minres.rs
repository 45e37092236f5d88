//! MINRES after the sweeps on `vulkan` (`minres = N`; docs/GPU.md, "MINRES"): the GPU's
//! passes solve the step's constraints as one system as the CPU backends do.
//! - `vulkan` follows `cpu-ref` with it, on the floor, for every constraint method (implicit
//!   springs too), and on a tilted collider plane (a collider's held direction), with the
//!   validation layer silent. Without MINRES the same runs end far from `cpu-ref`'s with it.
//! - The bundled `distance` sphere (the `seed` preset, dropped from 0.1 m) comes to rest on
//!   `vulkan`: one sweep then 28 iterations let it rise less than 2 mm after its first contact
//!   (issue 26's bar; 1.67 mm on lavapipe, `cpu` 1.68 mm), where one sweep alone lets it rise
//!   more than 40 mm; and two runs give the same bits (no float atomics in the solve).
//! - Workgroups narrower than a subgroup (`--workgroup-size 4`) follow `cpu-ref` too: the
//!   workgroup sums' narrow path.
//! - A stiff ball dropped on the tilted plane keeps its total volume through the impact as on
//!   `cpu-ref`: the global volume constraint leaves out the nodes the plane holds
//!   (`global_volume_sum#colliders`); without that the GPU's lowest total is 0.02 points lower.

mod common;
mod gpu_support;

use common::{
    ball_mesh, max_distance, near_floor_model, over_tilted_plane, rebound, run_frames, Rebound,
};
use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::backend::vulkan::EngineOptions;
use tetrasim::params::{MassMode, Method, Placement, SpringKind};
use tetrasim::{Backend, Model, ModelBuilder, SimParams, State};

/// Frames of the comparisons with `cpu-ref`.
const FRAMES: u32 = 100;
/// Largest allowed final position difference from `cpu-ref`, as a fraction of the
/// bounding-box diagonal (the GPU solves in f32, `cpu-ref` in f64).
const POSITION_FRACTION: f64 = 1e-5;

/// `vulkan`'s distance from `cpu-ref` with MINRES after [`FRAMES`] frames of `params` on
/// `model` [diagonals], and the distance of the run without MINRES from the same
/// reference; the validation layer stays silent.
fn distance_from_reference(model: &Model, params: &SimParams) -> (f64, f64) {
    let reference = reference_state(model, params, FRAMES);
    let without = SimParams {
        minres: 0,
        ..params.clone()
    };
    let [with, without] = [params, &without]
        .map(|p| apart_from(&reference, model, p, EngineOptions::default(), FRAMES));
    (with, without)
}

/// `cpu-ref`'s state after `frames` frames of `params` on `model`.
fn reference_state(model: &Model, params: &SimParams, frames: u32) -> State {
    let mut reference = ReferenceBackend::new(model, params).unwrap();
    run_frames(&mut reference, frames);
    reference.state().unwrap()
}

/// `vulkan`'s distance from the state `reference` after `frames` frames of `params` on
/// `model` with the engine `options` [diagonals]; the validation layer stays silent.
fn apart_from(
    reference: &State,
    model: &Model,
    params: &SimParams,
    options: EngineOptions,
    frames: u32,
) -> f64 {
    let mut gpu = gpu_support::validated_with(model, params, options);
    run_frames(&mut gpu, frames);
    gpu_support::assert_no_validation_messages(&gpu);
    max_distance(&gpu.state().unwrap().positions, &reference.positions) / model.bounds_diagonal()
}

#[test]
fn vulkan_follows_cpu_ref_with_minres_on_the_floor() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = near_floor_model(&ball_mesh(3.0));
    let cases = [
        (Method::Distance, SpringKind::Explicit),
        (Method::Volume, SpringKind::Explicit),
        (Method::Volume, SpringKind::Implicit),
        (Method::Mss, SpringKind::Implicit),
    ];
    for (method, springs) in cases {
        let params = SimParams {
            method,
            springs,
            iterations: 2,
            minres: 20,
            ..SimParams::default()
        };
        let (with, without) = distance_from_reference(&model, &params);
        println!(
            "{method}, {springs} springs: vulkan within {with:.2e} diagonals of cpu-ref \
             (without MINRES {without:.2e})"
        );
        assert!(
            with < POSITION_FRACTION,
            "{method}, {springs} springs: {with:.2e} diagonals apart"
        );
        assert!(
            without > 10.0 * with.max(1e-7),
            "{method}, {springs} springs: MINRES changed nothing ({without:.2e})"
        );
    }
}

#[test]
fn vulkan_follows_cpu_ref_with_minres_on_a_tilted_collider() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // No floor: the ball falls onto a plane tilted about Z, whose push holds its nodes
    // along the plane's normal (the `colliders` variants of minres_setup and minres_forces).
    let model = over_tilted_plane(near_floor_model(&ball_mesh(3.0)));
    let params = SimParams {
        method: Method::Distance,
        floor: false,
        iterations: 2,
        minres: 20,
        ..SimParams::default()
    };
    let (with, without) = distance_from_reference(&model, &params);
    println!("tilted plane: vulkan within {with:.2e} diagonals (without MINRES {without:.2e})");
    assert!(with < POSITION_FRACTION, "{with:.2e} diagonals apart");
    assert!(without > 10.0 * with.max(1e-7), "MINRES changed nothing");
}

#[test]
fn workgroups_narrower_than_a_subgroup_follow_cpu_ref() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // Workgroups of 4 invocations, narrower than any subgroup (lavapipe's 8, NVIDIA's 32):
    // the global volume constraint's and MINRES's workgroup sums take their narrow path
    // (glsl/common/workgroup_sum.glsl). Without it a shuffle would read absent lanes; on
    // lavapipe those read 0, so there this checks the sums, on NVIDIA the path too.
    let model = near_floor_model(&ball_mesh(3.0));
    let params = SimParams {
        method: Method::Volume,
        iterations: 2,
        minres: 20,
        ..SimParams::default()
    };
    let options = EngineOptions {
        workgroup_size: Some(4),
        ..EngineOptions::default()
    };
    let reference = reference_state(&model, &params, FRAMES);
    let apart = apart_from(&reference, &model, &params, options, FRAMES);
    println!("workgroups of 4: vulkan within {apart:.2e} diagonals of cpu-ref");
    assert!(apart < POSITION_FRACTION, "{apart:.2e} diagonals apart");
}

/// The lowest total volume over `frames` frames of `backend` [% of `rest`].
fn lowest_volume(backend: &mut dyn Backend, rest: f64, frames: u32) -> f64 {
    let mut lowest = f64::INFINITY;
    for frame in 0..frames {
        backend
            .step_frame()
            .unwrap_or_else(|e| panic!("frame {frame}: {e}"));
        lowest = lowest.min(100.0 * backend.volume().unwrap().volume / rest);
    }
    lowest
}

#[test]
fn the_global_volume_counts_the_nodes_a_collider_holds_as_on_cpu_ref() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // A stiff ball (20 cm, 1000 kg/m^3, implicit springs) dropped 0.1 m onto the tilted
    // plane, one sweep, 3 MINRES iterations and MINRES's close: `global_volume_sum#colliders`
    // leaves the share of the nodes the plane holds out of the global multiplier, as cpu-ref
    // does. Measured on lavapipe: the lowest total 99.99826 % on both; without the GPU's
    // colliders' terms 99.9791 % on vulkan.
    let model = ModelBuilder::new(&ball_mesh(5.0))
        .placement(Placement {
            fit_size: Some(0.2),
            drop_height: Some(0.1),
        })
        .mass(MassMode::Density { density: 1000.0 })
        .build()
        .unwrap();
    let model = over_tilted_plane(model);
    let rest = model.total_rest_volume();
    let params = SimParams {
        method: Method::Volume,
        springs: SpringKind::Implicit,
        mass: MassMode::Density { density: 1000.0 },
        floor: false,
        iterations: 1,
        groups: 1,
        minres: 3,
        ..SimParams::default()
    };
    let frames = 250;
    let reference = lowest_volume(
        &mut ReferenceBackend::new(&model, &params).unwrap(),
        rest,
        frames,
    );
    let mut gpu = gpu_support::validated(&model, &params);
    let lowest = lowest_volume(&mut gpu, rest, frames);
    gpu_support::assert_no_validation_messages(&gpu);
    println!("lowest total volume: vulkan {lowest:.5} %, cpu-ref {reference:.5} %");
    assert!(
        (lowest - reference).abs() < 0.002,
        "lowest total volume {lowest:.5} % on vulkan, {reference:.5} % on cpu-ref"
    );
}

#[test]
fn minres_brings_the_rigid_sphere_to_rest_on_vulkan() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = common::seed_model(&gpu_support::bundled_sphere());
    let rest = model.total_rest_volume();
    let params = |minres| SimParams {
        method: Method::Distance,
        iterations: 1,
        minres,
        ..SimParams::default()
    };
    let rise = rebound(&mut gpu_support::validated(&model, &params(0)), rest, 400).rise;
    println!("1 sweep alone: rise {:.2} mm", rise * 1e3);
    assert!(rise > 0.04, "one sweep alone rose only {rise} m");
    let mut runs = Vec::new();
    for _ in 0..2 {
        let mut gpu = gpu_support::validated(&model, &params(28));
        runs.push(rebound(&mut gpu, rest, 400));
        gpu_support::assert_no_validation_messages(&gpu);
    }
    let Rebound { rise, local, .. } = runs[0];
    println!(
        "1 sweep, minres 28: rise {:.2} mm, local {local:.4} %",
        rise * 1e3
    );
    assert!(rise < 0.002, "with MINRES: rose {rise} m");
    assert!(local < 0.001, "with MINRES: local error {local} %");
    assert_eq!(runs[0].positions, runs[1].positions, "two runs differ");
}
