//! Warm start of implicit springs on the `vulkan` backend (`warm_start`): each time step
//! starts with every spring's stored multiplier (the last step's final value, 0 initially)
//! applied as a force at x(t) (`spring_warm_start`) and as the multiplier so far in
//! iteration 0 (`spring_constraint`), and `set_state` forgets the stored multipliers.
//!
//! - That `vulkan` (and `cpu`) follow `cpu-ref` with warm start is checked with the other
//!   settings in `tests/backends_match_reference_settings.rs` (two warm-started cases).
//! - The others need no reference: warm start changes the run (but not its first step, whose
//!   stored multipliers are 0); on a beam hanging from one pinned end, at rest, the sag at 10
//!   and at 40 iterations agrees far better with warm start than without (the multipliers
//!   keep converging over the steps); `set_state` restarts from 0 multipliers.

mod gpu_support;

use glam::DVec3;
use tetrasim::mesh::grid::{box_tets, grid_tets};
use tetrasim::params::{MassMode, Method, Placement, Solver, SpringKind};
use tetrasim::{Backend, Model, ModelBuilder, SimParams, State};

const FRAMES: u32 = 60;

/// The small ball of `tests/backends_match_reference_settings.rs`, 1000 kg/m^3, dropped from
/// 1 cm and deformed, of the material of `params`.
fn ball(seed: u64, params: &SimParams) -> Model {
    let mesh = grid_tets(DVec3::ZERO, 1.0, [6, 6, 6], |[x, y, z]| {
        let p = DVec3::new(x as f64 + 0.5, y as f64 + 0.5, z as f64 + 0.5) - DVec3::splat(3.0);
        p.length() <= 3.0
    });
    let model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.01),
        })
        .mass(MassMode::Density { density: 1000.0 })
        .material(params)
        .build()
        .unwrap();
    gpu_support::jittered(&model, 0.01, 0.3, seed)
}

fn warm(method: Method, solver: Solver) -> SimParams {
    SimParams {
        method,
        solver,
        springs: SpringKind::Implicit,
        warm_start: true,
        mass: MassMode::Density { density: 1000.0 },
        youngs_modulus: Some(1e7),
        damping: Some(1e-3),
        ..SimParams::default()
    }
}

fn run(backend: &mut dyn Backend, frames: u32) -> State {
    for _ in 0..frames {
        backend.step_frame().unwrap();
    }
    backend.state().unwrap()
}

fn max_distance(a: &State, b: &State) -> f64 {
    a.positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max)
}

/// Stiff springs (E 10 MPa), which 10 iterations do not converge, so that warm start
/// matters.
fn cases() -> Vec<(&'static str, Model, SimParams)> {
    [
        ("mss, jacobi", 29, warm(Method::Mss, Solver::Jacobi)),
        (
            "volume, gauss-seidel",
            31,
            warm(Method::Volume, Solver::GaussSeidel),
        ),
    ]
    .into_iter()
    .map(|(name, seed, params)| (name, ball(seed, &params), params))
    .collect()
}

#[test]
fn warm_start_changes_the_run_but_not_its_first_step() {
    if !gpu_support::vulkan_available() {
        return;
    }
    for (name, model, params) in cases() {
        let diag = model.bounds_diagonal();
        let cold = SimParams {
            warm_start: false,
            ..params.clone()
        };
        let mut warm = gpu_support::validated(&model, &params);
        let mut cold = gpu_support::validated(&model, &cold);
        let first = max_distance(&run(&mut warm, 1), &run(&mut cold, 1)) / diag;
        let later = max_distance(&run(&mut warm, FRAMES), &run(&mut cold, FRAMES)) / diag;
        println!("{name}: warm vs cold after 1 frame {first:.2e}, after {FRAMES} more {later:.2e} diagonals");
        // The first step starts from 0 multipliers either way (f32 atomics may add in
        // another order on the Jacobi path).
        assert!(
            first <= 1e-7,
            "{name}: the first step differs ({first} diagonals)"
        );
        assert!(
            later > 1e-5,
            "{name}: warm start changed nothing ({later} diagonals)"
        );
        gpu_support::assert_no_validation_messages(&warm);
    }
}

#[test]
fn set_state_forgets_the_stored_multipliers() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // Gauss-Seidel: no float atomics, whose order could differ between the runs.
    let params = warm(Method::Mss, Solver::GaussSeidel);
    let model = ball(31, &params);
    let diag = model.bounds_diagonal();
    let mut fresh = gpu_support::validated(&model, &params);
    let start = fresh.state().unwrap();
    let want = run(&mut fresh, FRAMES);
    let mut reused = gpu_support::validated(&model, &params);
    run(&mut reused, 30);
    reused.set_state(&start).unwrap();
    let again = max_distance(&run(&mut reused, FRAMES), &want) / diag;
    let cold = SimParams {
        warm_start: false,
        ..params.clone()
    };
    let warm_effect = max_distance(
        &run(&mut gpu_support::validated(&model, &cold), FRAMES),
        &want,
    ) / diag;
    println!(
        "after set_state {again:.2e} diagonals from a fresh run; warm vs cold {warm_effect:.2e}"
    );
    // Not bit for bit: a fresh backend's first F = m g is rounded on the host, a later one
    // in `integrate` (measured 1.6e-7 m either way).
    assert!(
        again < 0.01 * warm_effect,
        "set_state kept the multipliers: {again} diagonals from a fresh run"
    );
}

/// Mean tip sag [m] of a 1 m beam (8 x 2 x 2 cubes, E 10 MPa, 1000 kg/m^3) hanging from its
/// pinned end, after `frames` frames of 1 ms, with `iterations` iterations.
fn tip_sag(warm_start: bool, iterations: u32, frames: u32) -> f64 {
    let mesh = box_tets(DVec3::ZERO, 0.125, [8, 2, 2]);
    let params = SimParams {
        method: Method::Mss,
        springs: SpringKind::Implicit,
        warm_start,
        youngs_modulus: Some(1e7),
        damping: Some(0.01),
        mass: MassMode::Density { density: 1000.0 },
        floor: false,
        iterations,
        ..SimParams::default()
    };
    let model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: None,
            drop_height: None,
        })
        .material(&params)
        .pinned_in_box(DVec3::splat(-1.0), DVec3::new(1e-9, 1.0, 1.0))
        .build()
        .unwrap();
    let tip: Vec<usize> = (0..model.node_count())
        .filter(|&i| (model.positions[i].x - 1.0).abs() < 1e-9)
        .collect();
    let mut gpu = gpu_support::validated(&model, &params);
    let x = run(&mut gpu, frames).positions;
    gpu_support::assert_no_validation_messages(&gpu);
    tip.iter()
        .map(|&i| model.positions[i].y - x[i].y)
        .sum::<f64>()
        / tip.len() as f64
}

#[test]
fn warm_start_makes_the_hanging_beam_independent_of_the_iteration_count() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let frames = 1500;
    let change = |warm_start| {
        let (ten, forty) = (
            tip_sag(warm_start, 10, frames),
            tip_sag(warm_start, 40, frames),
        );
        let change = (ten / forty - 1.0).abs();
        println!(
            "warm start {warm_start}: sag {ten:.5} m at 10 iterations, {forty:.5} m at 40 \
             ({:.2} %)",
            100.0 * change
        );
        change
    };
    let (cold, warm) = (change(false), change(true));
    assert!(
        warm < 0.25 * cold,
        "warm start: 10 and 40 iterations differ by {warm}, without by {cold}"
    );
}
