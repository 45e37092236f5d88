//! Free fall on the GPU matches the closed form of symplectic Euler. Every case starts
//! deformed (jittered by 5 mm, so springs and constraints act) and moving sideways; internal
//! forces sum to zero (momentum-conserving scaling), so the centre of mass follows
//! `v = v0 - g k dt`, `y = y0 + k dt v0 - g dt^2 k (k + 1) / 2` after k steps, for every method
//! and both float-atomic paths. The first edition's averaging fails it (last test).

mod gpu_support;

use glam::DVec3;
use tetrasim::backend::vulkan::{AtomicsMode, EngineOptions};
use tetrasim::params::{ConstraintCombine, Method, SimParams};
use tetrasim::{Backend, Model};

const FRAMES: u32 = 5;
const SUBSTEPS: u32 = 4;

fn deformed_model() -> Model {
    let mut model = gpu_support::jittered(&gpu_support::box_model([3, 2, 2], 0.1), 0.005, 0.0, 5);
    model
        .velocities
        .iter_mut()
        .for_each(|v| *v += DVec3::new(0.3, 0.5, -0.2));
    model
}

/// Distance [m] of the GPU's centre of mass from the closed form after the run.
fn com_error(model: &Model, params: &SimParams, atomics: AtomicsMode) -> f64 {
    let options = EngineOptions {
        atomics,
        ..EngineOptions::default()
    };
    let mut gpu = gpu_support::validated_with(model, params, options);
    for _ in 0..FRAMES {
        gpu.step_frame().unwrap();
    }
    let state = gpu.state().unwrap();
    assert_eq!(gpu.frames(), FRAMES);
    gpu_support::assert_no_validation_messages(&gpu);
    let (com0, _, _) = gpu_support::momenta(
        &tetrasim::State {
            positions: model.positions.clone(),
            velocities: model.velocities.clone(),
        },
        &model.mass,
    );
    let (com, _, _) = gpu_support::momenta(&state, &model.mass);
    let k = f64::from(FRAMES * SUBSTEPS);
    let (g, dt) = (params.gravity, params.dt);
    let v0 = DVec3::new(0.3, 0.5, -0.2);
    let expected = com0 + v0 * (k * dt) + g * (dt * dt * k * (k + 1.0) / 2.0);
    com.distance(expected)
}

#[test]
fn free_fall_moves_the_centre_of_mass_by_the_closed_form_amount() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = deformed_model();
    for method in Method::ALL {
        for atomics in [AtomicsMode::Ext, AtomicsMode::Cas] {
            let params = SimParams {
                method,
                floor: false,
                substeps: SUBSTEPS,
                ..SimParams::default()
            };
            let error = com_error(&model, &params, atomics);
            println!("{method} {atomics:?}: centre of mass off the closed form by {error:.2e} m");
            // f32 positions near 1 m: a few ulps of 1.2e-7 m per step, averaged over nodes.
            assert!(
                error < 2e-6,
                "{method} {atomics:?}: centre of mass {error} m off the closed form"
            );
        }
    }
}

#[test]
fn averaged_constraints_leave_the_closed_form() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let model = deformed_model();
    for method in [Method::Distance, Method::Volume] {
        let params = SimParams {
            method,
            combine: ConstraintCombine::Average,
            floor: false,
            substeps: SUBSTEPS,
            ..SimParams::default()
        };
        let error = com_error(&model, &params, AtomicsMode::Auto);
        println!("{method} averaged: centre of mass off by {error:.2e} m");
        assert!(
            error > 1e-5,
            "{method}: averaging stayed on the closed form"
        );
    }
}
