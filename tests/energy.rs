//! Energy (physics.md, second edition): a body dropped onto the floor never gains energy.
//! Kinetic + gravitational + spring energy stays below its starting value plus 1 % of the
//! drop's potential energy (`M g h`, h = 0.1 m) over 1000 frames of the seed preset on the
//! bundled sphere, for every method, on `cpu-ref` and `cpu`. The first edition's per-node
//! averaging, whose unbalanced forces push a resting body sideways, fails it (last test).

mod gpu_support;

use gpu_support::bundled_sphere;
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::backend::State;
use tetrasim::params::{Method, Placement};
use tetrasim::{Backend, Model, ModelBuilder, SimParams};

const FRAMES: u32 = 1000;
const DROP: f64 = 0.1;

/// Kinetic + gravitational (above y = 0) + spring energy [J].
fn energy(state: &State, model: &Model, params: &SimParams) -> f64 {
    let mut e = 0.0;
    for ((x, v), &m) in state
        .positions
        .iter()
        .zip(&state.velocities)
        .zip(&model.mass)
    {
        e += 0.5 * m * v.length_squared() + m * -params.gravity.dot(*x);
    }
    for (s, &[i, j]) in model.springs.iter().enumerate() {
        let l = state.positions[i as usize].distance(state.positions[j as usize]);
        e += 0.5 * params.ks * (l - model.rest_length[s]).powi(2);
    }
    e
}

/// Largest energy gain over the run [J] and the allowed gain [J].
fn gain(backend: &mut dyn Backend, model: &Model, params: &SimParams, label: &str) -> (f64, f64) {
    let e0 = energy(&backend.state().unwrap(), model, params);
    let total_mass: f64 = model.mass.iter().sum();
    let allowed = 0.01 * total_mass * params.gravity.length() * DROP;
    let mut worst = f64::NEG_INFINITY;
    let mut worst_frame = 0;
    let mut last = e0;
    for frame in 0..FRAMES {
        backend.step_frame().unwrap();
        last = energy(&backend.state().unwrap(), model, params);
        if last - e0 > worst {
            (worst, worst_frame) = (last - e0, frame);
        }
    }
    println!(
        "{label}: largest gain {:.3} % of the drop's energy (frame {worst_frame}), final {:.1} %",
        100.0 * worst / (allowed / 0.01),
        100.0 * (last - e0) / (allowed / 0.01)
    );
    (worst, allowed)
}

fn check(backend: &mut dyn Backend, model: &Model, params: &SimParams, label: &str) {
    let (worst, allowed) = gain(backend, model, params, label);
    assert!(
        worst <= allowed,
        "{label}: energy rose {worst:.4} J above the start (allowed {allowed:.4} J, 1 % of \
         the drop's potential energy)"
    );
}

fn sphere() -> Model {
    ModelBuilder::new(&bundled_sphere())
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(DROP),
        })
        .build()
        .unwrap()
}

#[test]
fn no_method_gains_energy_over_1000_frames() {
    let model = sphere();
    for method in Method::ALL {
        let params = SimParams {
            method,
            ..SimParams::default()
        };
        let mut reference = ReferenceBackend::new(&model, &params).unwrap();
        check(
            &mut reference,
            &model,
            &params,
            &format!("cpu-ref {method}"),
        );
        let mut fast = ParallelBackend::new(&model, &params).unwrap();
        check(&mut fast, &model, &params, &format!("cpu {method}"));
    }
}

#[test]
fn per_node_averaging_gains_energy() {
    let model = sphere();
    let params = SimParams {
        method: Method::Volume,
        combine: tetrasim::params::ConstraintCombine::Average,
        ..SimParams::default()
    };
    let mut fast = ParallelBackend::new(&model, &params).unwrap();
    let (worst, allowed) = gain(&mut fast, &model, &params, "cpu volume averaged");
    assert!(
        worst > allowed,
        "averaging gained only {worst} J (bound {allowed} J): the test would not catch it"
    );
}
