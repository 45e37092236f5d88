//! An undamped two-node spring integrated with symplectic Euler keeps its energy bounded (no
//! drift over many periods); damping makes the energy decay at the analytic rate. The same
//! holds for a whole tetrahedron of springs through the reference backend.

mod common;

use common::{bare_params, model_in_place, single_tet};
use glam::DVec3;
use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::backend::{Backend, State};
use tetrasim::params::Method;
use tetrasim::physics::{spring_force, symplectic_euler};

const KS: f64 = 100.0;
const REST: f64 = 1.0;
const MASS: f64 = 1.0;
const DT: f64 = 1e-3;

fn energy(x: [DVec3; 2], v: [DVec3; 2]) -> f64 {
    let stretch = x[0].distance(x[1]) - REST;
    0.5 * MASS * (v[0].length_squared() + v[1].length_squared()) + 0.5 * KS * stretch * stretch
}

/// Energies after every step of a two-node spring started 0.2 m stretched, at rest.
fn two_node_energies(kd: f64, steps: usize) -> Vec<f64> {
    let mut x = [DVec3::ZERO, DVec3::X * (REST + 0.2)];
    let mut v = [DVec3::ZERO; 2];
    let mut energies = vec![energy(x, v)];
    for _ in 0..steps {
        let f = spring_force(x[0], x[1], v[0], v[1], REST, KS, kd);
        let forces = [f, -f];
        for k in 0..2 {
            (x[k], v[k]) = symplectic_euler(x[k], v[k], forces[k], 1.0 / MASS, DT);
        }
        energies.push(energy(x, v));
    }
    energies
}

#[test]
fn undamped_spring_energy_stays_bounded() {
    // omega = sqrt(2 ks / m) = 14.1 rad/s: 10 s are 22 periods.
    let e = two_node_energies(0.0, 10_000);
    let e0 = e[0];
    let worst = e.iter().map(|x| (x / e0 - 1.0).abs()).fold(0.0, f64::max);
    // Symplectic Euler's energy error oscillates with relative amplitude about omega dt / 2.
    assert!(
        worst < 0.02,
        "energy deviates by {:.3} % at worst",
        100.0 * worst
    );
    let last_period_mean = e[e.len() - 445..].iter().sum::<f64>() / 445.0;
    let first_period_mean = e[..445].iter().sum::<f64>() / 445.0;
    let drift = (last_period_mean / first_period_mean - 1.0).abs();
    assert!(
        drift < 1e-3,
        "mean energy drifted by {:.4} % over 22 periods",
        100.0 * drift
    );
}

#[test]
fn damped_spring_energy_decays_at_the_analytic_rate() {
    let kd = 0.5;
    let e = two_node_energies(kd, 3_500);
    assert!(
        e.windows(2).all(|w| w[1] <= w[0] * (1.0 + 1e-3)),
        "energy should not grow"
    );
    // Relative motion has reduced mass m / 2 and damping kd: the amplitude decays as
    // exp(-kd t / m), the energy (averaged over a period) as exp(-2 kd t / m).
    for t in [1.0, 2.0, 3.0] {
        let i = (t / DT) as usize;
        let mean = e[i - 222..i + 222].iter().sum::<f64>() / 444.0;
        let expected = e[0] * (-2.0 * kd * t / MASS).exp();
        let ratio = mean / expected;
        assert!(
            (0.85..1.15).contains(&ratio),
            "t = {t} s: energy {mean} vs analytic {expected}"
        );
    }
}

fn tet_energy(model: &tetrasim::Model, s: &State, ks: f64) -> f64 {
    let kinetic: f64 = s
        .velocities
        .iter()
        .zip(&model.mass)
        .map(|(v, m)| 0.5 * m * v.length_squared())
        .sum();
    let elastic: f64 = model
        .springs
        .iter()
        .zip(&model.rest_length)
        .map(|(&[i, j], l0)| {
            let stretch = s.positions[i as usize].distance(s.positions[j as usize]) - l0;
            0.5 * ks * stretch * stretch
        })
        .sum();
    kinetic + elastic
}

#[test]
fn tetrahedron_of_springs_keeps_then_loses_its_energy() {
    let model = model_in_place(&single_tet());
    let start = State {
        positions: model
            .positions
            .iter()
            .map(|p| DVec3::new(1.2 * p.x, p.y, 0.9 * p.z))
            .collect(),
        velocities: vec![DVec3::ZERO; 4],
    };
    for (kd, low, high) in [(0.0, 0.97, 1.03), (1.0, 0.0, 0.05)] {
        let params = tetrasim::SimParams {
            method: Method::Mss,
            ks: KS,
            kd,
            ..bare_params()
        };
        let mut backend = ReferenceBackend::new(&model, &params).unwrap();
        backend.set_state(&start).unwrap();
        let e0 = tet_energy(&model, &start, KS);
        let mut worst: f64 = 1.0;
        let mut ratio = 1.0;
        for _ in 0..3000 {
            backend.step_frame().unwrap();
            ratio = tet_energy(&model, &backend.state().unwrap(), KS) / e0;
            worst = if kd == 0.0 {
                worst.max((ratio - 1.0).abs() + 1.0)
            } else {
                worst.max(ratio)
            };
        }
        assert!(
            (low..high).contains(&ratio),
            "kd {kd}: energy ratio {ratio} after 3 s"
        );
        assert!(worst < 1.03, "kd {kd}: energy ratio reached {worst}");
    }
}
