//! physics.md, "Implicit constraint enforcement": with the force `-lambda grad C`, a single
//! isolated constraint satisfies `C + dt sum_k grad_k C . v_k(t+dt) = 0` exactly. Checked on
//! the pure functions for both constraint kinds, and end to end through both CPU backends for a
//! single tetrahedron (whose volume constraint is the only constraint there is).

mod common;

use common::{bare_params, model_in_place, noise, noise3, single_tet};
use glam::DVec3;
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::backend::{Backend, State};
use tetrasim::params::Method;
use tetrasim::physics::{distance_constraint, implicit_lambda, volume_constraint};

const DT: f64 = 1e-3;

/// `C + dt sum_k grad_k . v_k(t+dt)` after applying the constraint force.
fn residual<const K: usize>(
    c: f64,
    grad: [DVec3; K],
    w: [f64; K],
    v: [DVec3; K],
    f: [DVec3; K],
) -> f64 {
    let lambda =
        implicit_lambda(c, &grad, &w, &[1.0; K], &v, &f, DT, 1e-20).expect("not degenerate");
    (0..K).fold(c, |acc, k| {
        let v_next = v[k] + (f[k] - grad[k] * lambda) * (w[k] * DT);
        acc + DT * grad[k].dot(v_next)
    })
}

#[test]
fn distance_constraint_satisfies_the_implicit_identity() {
    for case in 0..50u64 {
        let x = [noise3(10 * case), noise3(10 * case + 1) + DVec3::X];
        let rest = 0.5 + 0.5 * noise(10 * case + 2).abs();
        let (c, grad) = distance_constraint(x[0], x[1], rest);
        let w = [
            0.5 + noise(10 * case + 3).abs(),
            0.5 + noise(10 * case + 4).abs(),
        ];
        let v = [noise3(10 * case + 5), noise3(10 * case + 6)];
        let f = [noise3(10 * case + 7) * 20.0, noise3(10 * case + 8) * 20.0];
        assert!(
            c.abs() > 1e-3,
            "case {case}: the constraint should be violated, C = {c}"
        );
        let r = residual(c, grad, w, v, f);
        assert!(r.abs() < 1e-12, "case {case}: residual {r:e} (C = {c})");
    }
}

#[test]
fn volume_constraint_satisfies_the_implicit_identity() {
    for case in 0..50u64 {
        let base = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let p = std::array::from_fn(|k| base[k] + noise3(20 * case + k as u64) * 0.2);
        let (c, grad) = volume_constraint(p, 1.0 / 6.0);
        let w = std::array::from_fn(|k| 0.5 + noise(20 * case + 4 + k as u64).abs());
        let v = std::array::from_fn(|k| noise3(20 * case + 8 + k as u64));
        let f = std::array::from_fn(|k| noise3(20 * case + 12 + k as u64) * 20.0);
        assert!(
            c.abs() > 1e-4,
            "case {case}: the constraint should be violated, C = {c}"
        );
        let r = residual(c, grad, w, v, f);
        assert!(r.abs() < 1e-12, "case {case}: residual {r:e} (C = {c})");
    }
}

/// A squashed, moving single tet under gravity: one time step of `volume` through a backend.
fn backend_residual(backend: &mut dyn Backend, start: &State, rest_volume: f64) -> f64 {
    backend.step_frame().unwrap();
    let after = backend.state().unwrap();
    let p: [DVec3; 4] = std::array::from_fn(|k| start.positions[k]);
    let (c, grad) = volume_constraint(p, rest_volume);
    (0..4).fold(c, |acc, k| acc + DT * grad[k].dot(after.velocities[k]))
}

fn squashed_moving_start(model: &tetrasim::Model) -> State {
    State {
        positions: model
            .positions
            .iter()
            .map(|p| DVec3::new(p.x, 0.6 * p.y, p.z))
            .collect(),
        velocities: (0..4).map(|k| noise3(100 + k)).collect(),
    }
}

#[test]
fn reference_backend_satisfies_the_identity_for_one_tet() {
    let model = model_in_place(&single_tet());
    let v0 = model.rest_volume[0];
    for iterations in [1, 10] {
        let params = tetrasim::SimParams {
            method: Method::Volume,
            gravity: glam::DVec3::new(0.0, -9.81, 0.0),
            iterations,
            ..bare_params()
        };
        let mut backend = ReferenceBackend::new(&model, &params).unwrap();
        let start = squashed_moving_start(&model);
        backend.set_state(&start).unwrap();
        let r = backend_residual(&mut backend, &start, v0);
        // C itself is -0.4 V0 here; the identity holds to rounding.
        assert!(
            r.abs() < 1e-9 * v0,
            "{iterations} iterations: residual {r:e}, V0 {v0}"
        );
    }
}

#[test]
fn parallel_backend_satisfies_the_identity_for_one_tet_to_f32_rounding() {
    let model = model_in_place(&single_tet());
    let v0 = model.rest_volume[0];
    let params = tetrasim::SimParams {
        method: Method::Volume,
        gravity: glam::DVec3::new(0.0, -9.81, 0.0),
        ..bare_params()
    };
    let mut backend = ParallelBackend::new(&model, &params).unwrap();
    let start = squashed_moving_start(&model);
    backend.set_state(&start).unwrap();
    let r = backend_residual(&mut backend, &start, v0);
    // Without the constraint force the residual would be about C = -0.4 V0.
    assert!(r.abs() < 1e-3 * v0, "residual {r:e}, V0 {v0}");
}
