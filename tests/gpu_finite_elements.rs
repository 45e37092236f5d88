//! The Vulkan engine's finite elements (`neo-hookean`, docs/GPU.md, "Finite elements on the
//! GPU") follow `cpu-ref`'s on lavapipe with the validation layer on: the same motion
//! within the tolerance `cpu` (f32, threads) meets against it, 1 % of the motion's size
//! (the conjugate gradients carry single precision's rounding further than the sweeps; see
//! tests/finite_elements.rs, `cpu_follows_the_reference`).
//!
//! Scenes: a cantilever sagging from its pinned end (the coarse level, the Newton steps
//! relinearised as it swings), a free block dropped onto the floor (the floor's contact
//! held in the solve, the rigid-part correction on a body a contact holds), and a block
//! pressed by a sphere collider moving down onto it.

mod common;
mod gpu_support;

use common::{material_params, unplaced};
use glam::DVec3;
use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::collider::{Collider, Motion};
use tetrasim::mesh::grid::box_tets;
use tetrasim::params::Method;
use tetrasim::{Backend, Model, ModelBuilder, SimParams};

/// The largest distance between the two runs' nodes over `frames` frames against the
/// largest displacement of the reference's over the run: within 1 %. (A node a collider
/// carries on its surface is at the edge of contact every step, which f32 and f64 can
/// decide apart: the sphere's block differs by up to 3.4 % of the motion so far a few
/// frames after the press begins, 0.34 % of the run's.)
fn compare(name: &str, model: &Model, params: &SimParams, frames: u32) {
    let mut reference = ReferenceBackend::new(model, params).unwrap();
    let mut gpu = gpu_support::validated(model, params);
    let (mut worst, mut scale, mut at) = (0.0f64, 0.0f64, 0);
    for frame in 0..frames {
        reference.step_frame().unwrap();
        gpu.step_frame().unwrap();
        let (want, got) = (reference.state().unwrap(), gpu.state().unwrap());
        let moved = (want.positions.iter().zip(&model.positions))
            .map(|(x, x0)| (*x - *x0).length())
            .fold(0.0, f64::max);
        scale = scale.max(moved);
        let off = (want.positions.iter().zip(&got.positions))
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max);
        if off > worst {
            (worst, at) = (off, frame);
        }
    }
    println!(
        "{name}: {frames} frames, the nodes within {worst:.2e} m of cpu-ref's (frame {at}; \
         {:.3} % of the motion, {scale:.3e} m)",
        100.0 * worst / scale
    );
    assert!(scale > 1e-3, "{name}: nothing moved ({scale} m)");
    assert!(
        worst <= 1e-2 * scale,
        "{name}: at frame {at} a node is {worst:.3e} m from the reference's (the motion: \
         {scale:.3e} m)"
    );
    gpu_support::assert_no_validation_messages(&gpu);
}

/// A 0.6 m rubber-like beam of `cells`, `params`' material, optionally pinned at x = 0.
fn beam(cells: [usize; 3], params: &SimParams, pinned: bool) -> Model {
    let h = 0.6 / cells[0] as f64;
    let mesh = box_tets(DVec3::new(0.0, 0.01, 0.0), h, cells);
    let builder = ModelBuilder::new(&mesh)
        .placement(unplaced())
        .material(params);
    let builder = match pinned {
        true => builder.pinned_in_box(DVec3::splat(-1.0), DVec3::new(1e-9, 1.0, 1.0)),
        false => builder,
    };
    builder.build().unwrap()
}

#[test]
fn a_sagging_cantilever_follows_the_reference() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let params = material_params(Method::NeoHookean, 1e7, 0.3, 1000.0);
    compare(
        "cantilever 12x2x2",
        &beam([12, 2, 2], &params, true),
        &params,
        150,
    );
}

#[test]
fn a_finer_cantilever_follows_the_reference() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // 2304 tets: 24 aggregates in the coarse level, rebuilt every 10 steps.
    let params = material_params(Method::NeoHookean, 1e7, 0.45, 1000.0);
    compare(
        "cantilever 24x4x4",
        &beam([24, 4, 4], &params, true),
        &params,
        60,
    );
}

#[test]
fn a_block_dropped_on_the_floor_follows_the_reference() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // A soft beam 1 cm above the floor: it lands at frame 45 and bounces on it.
    let params = SimParams {
        floor: true,
        ..material_params(Method::NeoHookean, 1e5, 0.4, 1000.0)
    };
    let model = beam([6, 2, 2], &params, false);
    compare("block on the floor", &model, &params, 120);
}

#[test]
fn a_block_pressed_by_a_sphere_follows_the_reference() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // A sphere of 5 cm moving down at 0.2 m/s onto a block pinned at its bottom.
    let params = material_params(Method::NeoHookean, 1e5, 0.4, 1000.0);
    let mesh = box_tets(DVec3::new(0.0, 0.01, 0.0), 0.05, [4, 2, 4]);
    let sphere = Collider::sphere(DVec3::new(0.1, 0.163, 0.1), 0.05).moving(Motion::Velocity {
        linear: DVec3::new(0.0, -0.2, 0.0),
        angular: DVec3::ZERO,
    });
    let model = ModelBuilder::new(&mesh)
        .placement(unplaced())
        .material(&params)
        .pinned_in_box(DVec3::splat(-1.0), DVec3::new(1.0, 0.01 + 1e-9, 1.0))
        .build()
        .unwrap()
        .with_colliders(vec![sphere])
        .unwrap();
    compare("block under a sphere", &model, &params, 150);
}
