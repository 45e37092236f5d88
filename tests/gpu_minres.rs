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

mod common;
mod gpu_support;

use common::{
    ball_mesh, max_distance, near_floor_model, over_tilted_plane, rebound, run_frames, Rebound,
};
use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::backend::vulkan::EngineOptions;
use tetrasim::params::{Method, SpringKind};
use tetrasim::{Backend, Model, SimParams};

/// Frames of the comparisons with `cpu-ref`.
const FRAMES: u32 = 100;
/// Largest allowed final position difference from `cpu-ref`, as a fraction of the
/// bounding-box diagonal (the GPU solves in f32, `cpu-ref` in f64).
const POSITION_FRACTION: f64 = 1e-5;

/// `vulkan`'s distance from `cpu-ref` with MINRES after `frames` frames of `params` on
/// `model` [diagonals], and the distance of the run without MINRES from the same
/// reference; the validation layer stays silent.
fn distance_from_reference(model: &Model, params: &SimParams) -> (f64, f64) {
    let mut reference = ReferenceBackend::new(model, params).unwrap();
    run_frames(&mut reference, FRAMES);
    let want = reference.state().unwrap();
    let diag = model.bounds_diagonal();
    let without = SimParams {
        minres: 0,
        ..params.clone()
    };
    let mut out = [0.0; 2];
    for (d, p) in out.iter_mut().zip([params, &without]) {
        let mut gpu = gpu_support::validated(model, p);
        run_frames(&mut gpu, FRAMES);
        *d = max_distance(&gpu.state().unwrap().positions, &want.positions) / diag;
        gpu_support::assert_no_validation_messages(&gpu);
    }
    (out[0], out[1])
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
    let mut reference = ReferenceBackend::new(&model, &params).unwrap();
    run_frames(&mut reference, FRAMES);
    let want = reference.state().unwrap();
    let options = EngineOptions {
        workgroup_size: Some(4),
        ..EngineOptions::default()
    };
    let mut gpu = gpu_support::validated_with(&model, &params, options);
    run_frames(&mut gpu, FRAMES);
    let apart =
        max_distance(&gpu.state().unwrap().positions, &want.positions) / model.bounds_diagonal();
    println!("workgroups of 4: vulkan within {apart:.2e} diagonals of cpu-ref");
    assert!(apart < POSITION_FRACTION, "{apart:.2e} diagonals apart");
    gpu_support::assert_no_validation_messages(&gpu);
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
