//! Free fall without a floor: internal forces cancel, so the centre of mass follows the closed
//! form of symplectic Euler under gravity, `v_n = v_0 - n dt g`,
//! `x_n = x_0 + n dt v_0 - dt^2 g n (n + 1) / 2` (along -Y), for every method whose internal
//! forces sum to zero: springs, and constraints with the default momentum-conserving scaling
//! or `--combine sum`. Every case starts deformed (jittered), so the constraints act; the
//! first edition's per-node averaging fails the same check.

mod common;

use common::{box_mesh, centre_of_mass, jittered_state, run_frames};
use glam::DVec3;
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::backend::{Backend, State};
use tetrasim::params::{ConstraintCombine, MassMode, Method, Placement};
use tetrasim::{ModelBuilder, SimParams};

const FRAMES: u32 = 50;
const SUBSTEPS: u32 = 2;

fn closed_form(x0: DVec3, v0: DVec3, params: &SimParams) -> DVec3 {
    let n = f64::from(FRAMES * SUBSTEPS);
    let dt = params.dt;
    x0 + v0 * (n * dt) + params.gravity * (dt * dt * n * (n + 1.0) / 2.0)
}

fn check(
    method: Method,
    combine: ConstraintCombine,
    omega: f64,
    mass: MassMode,
    jitter: f64,
) -> f64 {
    let error = com_error(method, combine, omega, mass, jitter);
    // The body fell about 0.5 * 9.81 * 0.1^2 = 0.05 m and moved 0.1 m sideways.
    assert!(
        error < 1e-9,
        "{method} ({combine:?}, {mass:?}): centre of mass off the closed form by {error:e} m"
    );
    error
}

/// Distance [m] of the centre of mass from the closed form after the run.
fn com_error(
    method: Method,
    combine: ConstraintCombine,
    omega: f64,
    mass: MassMode,
    jitter: f64,
) -> f64 {
    let mesh = box_mesh([3, 2, 3]);
    let model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: None,
            drop_height: None,
        })
        .mass(mass)
        .build()
        .unwrap();
    let params = SimParams {
        method,
        combine,
        omega,
        mass,
        floor: false,
        substeps: SUBSTEPS,
        ..SimParams::default()
    };
    let mut start = jittered_state(&model, jitter, 0.0, 7);
    let drift = DVec3::new(0.3, 1.0, -0.2);
    start.velocities.iter_mut().for_each(|v| *v += drift);
    let mut backend = ReferenceBackend::new(&model, &params).unwrap();
    backend.set_state(&start).unwrap();
    run_frames(&mut backend, FRAMES);
    let State { positions, .. } = backend.state().unwrap();
    let com = centre_of_mass(&positions, &model.mass);
    let expected = closed_form(
        centre_of_mass(&start.positions, &model.mass),
        drift,
        &params,
    );
    com.distance(expected)
}

#[test]
fn springs_keep_the_centre_of_mass_on_the_closed_form() {
    for method in [Method::Mss, Method::MssNode] {
        check(
            method,
            ConstraintCombine::Scaled,
            1.0,
            MassMode::PerNode { mass: 1.0 },
            0.005,
        );
        check(
            method,
            ConstraintCombine::Scaled,
            1.0,
            MassMode::Density { density: 1000.0 },
            0.005,
        );
    }
}

#[test]
fn summed_constraints_keep_the_centre_of_mass_on_the_closed_form() {
    for method in [Method::Distance, Method::Volume] {
        // Plain summation overshoots by about the node degree: at omega = 1 it diverges within
        // ten frames even here (physics.md), so it is under-relaxed.
        check(
            method,
            ConstraintCombine::Sum,
            0.1,
            MassMode::PerNode { mass: 1.0 },
            0.002,
        );
    }
}

#[test]
fn scaled_constraints_on_a_deformed_body_fall_on_the_closed_form() {
    let settings = [
        (1.0, MassMode::PerNode { mass: 1.0 }),
        (1.5, MassMode::PerNode { mass: 1.0 }),
        (1.0, MassMode::Density { density: 1000.0 }),
    ];
    for method in [Method::Distance, Method::Volume] {
        for (omega, mass) in settings {
            check(method, ConstraintCombine::Scaled, omega, mass, 0.005);
        }
    }
}

#[test]
fn averaged_constraints_on_a_deformed_body_leave_the_closed_form() {
    // Not vacuous: the same deformed start with the first edition's averaging drifts.
    for method in [Method::Distance, Method::Volume] {
        let error = com_error(
            method,
            ConstraintCombine::Average,
            1.0,
            MassMode::PerNode { mass: 1.0 },
            0.005,
        );
        println!("{method} averaged: centre of mass off by {error:e} m");
        assert!(
            error > 1e-6,
            "{method}: averaging stayed on the closed form"
        );
    }
}

#[test]
fn parallel_backend_falls_on_the_closed_form_to_f32_rounding() {
    let mesh = box_mesh([3, 2, 3]);
    let model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: None,
            drop_height: None,
        })
        .build()
        .unwrap();
    for method in tetrasim::params::Method::ALL {
        let params = SimParams {
            method,
            floor: false,
            substeps: SUBSTEPS,
            ..SimParams::default()
        };
        let start = jittered_state(&model, 0.005, 0.0, 11);
        let mut backend = ParallelBackend::new(&model, &params).unwrap();
        backend.set_state(&start).unwrap();
        run_frames(&mut backend, FRAMES);
        let positions = backend.state().unwrap().positions;
        let com = centre_of_mass(&positions, &model.mass);
        let expected = closed_form(
            centre_of_mass(&start.positions, &model.mass),
            DVec3::ZERO,
            &params,
        );
        let error = com.distance(expected);
        assert!(
            error < 1e-5,
            "{method}: centre of mass {com} vs {expected}, error {error:e}"
        );
    }
}
