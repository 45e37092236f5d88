//! A finite-element body on a frictionless floor gains no energy (issue 51; docs/PHYSICS.md,
//! "The correction's length"): the bundled box fitted to 0.1 m, stiff (E 1 MPa, nu 0.3,
//! 1000 kg/m^3), placed at rest on the floor or dropped 1 cm onto it. Its elastic energy
//! is never negative and nothing but gravity does work on it (the floor does none, damping
//! takes energy away), so its kinetic energy plus its height's potential energy never
//! exceeds what it started with. Before the rigid-part correction on a body a contact holds
//! was sized by the step's quadratic model, the box hopped: 101 mm from rest, 73 mm after
//! the 1 cm drop. On `cpu-ref` and `cpu`.

mod common;

use common::{cpu_backend, material_params};
use glam::DVec3;
use tetrasim::mesh::io::read_tet_mesh;
use tetrasim::params::{Method, Placement};
use tetrasim::{Backend, Model, ModelBuilder};

const G: f64 = 9.81;

/// Kinetic energy plus gravity's potential energy above the floor [J].
fn mechanical_energy(model: &Model, backend: &mut dyn Backend) -> f64 {
    let state = backend.state().unwrap();
    let each = (state.positions.iter().zip(&state.velocities)).zip(&model.mass);
    each.map(|((x, v), m)| m * (0.5 * v.length_squared() + G * x.y))
        .sum()
}

/// Runs 300 frames of the box dropped from `drop` [m] on `backend`: the most its energy
/// rose above the start's [J], the highest its lowest node got after touching the floor
/// [m], the floor's force over the weight at the end, and the weight [N].
fn drop_box(drop: f64, backend: &str) -> (f64, f64, f64, f64) {
    let params = tetrasim::SimParams {
        floor: true,
        gravity: DVec3::new(0.0, -G, 0.0),
        ..material_params(Method::NeoHookean, 1e6, 0.3, 1000.0)
    };
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/box");
    let placement = Placement {
        fit_size: Some(0.1),
        drop_height: Some(drop),
    };
    let model = (ModelBuilder::new(&read_tet_mesh(&path).unwrap()).placement(placement))
        .material(&params)
        .build()
        .unwrap();
    let weight = model.mass.iter().sum::<f64>() * G;
    let mut solver = cpu_backend(&model, &params, backend);
    let start = mechanical_energy(&model, solver.as_mut());
    let (mut gain, mut rise, mut landed) = (f64::NEG_INFINITY, 0.0f64, false);
    for frame in 0..300 {
        solver
            .step_frame()
            .unwrap_or_else(|e| panic!("{backend}: frame {frame}: {e}"));
        gain = gain.max(mechanical_energy(&model, solver.as_mut()) - start);
        let positions = solver.state().unwrap().positions;
        let lowest = positions.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        if landed {
            rise = rise.max(lowest);
        }
        landed |= lowest < 1e-4;
    }
    let floor = solver.reactions().unwrap().unwrap().floor.y / weight;
    (gain, rise, floor, weight)
}

#[test]
fn a_stiff_body_on_the_floor_gains_no_energy() {
    for backend in ["cpu-ref", "cpu"] {
        for drop in [0.0, 0.01] {
            let (gain, rise, floor, weight) = drop_box(drop, backend);
            println!(
                "{backend}, dropped {drop} m: energy gain {gain:.3e} J (weight x 1 mm: {:.3e}), \
                 highest after landing {:.3} mm, floor / weight {floor:.5}",
                weight * 1e-3,
                rise * 1e3
            );
            // 1 % of the energy of lifting the box 1 mm: float rounding, not a hop.
            assert!(
                gain < 1e-5 * weight,
                "{backend}, dropped {drop} m: gained {gain} J"
            );
            assert!(rise < 1e-4, "{backend}, dropped {drop} m: rose {rise} m");
            assert!(
                (floor - 1.0).abs() < 0.01,
                "{backend}, dropped {drop} m: the floor holds {floor} of the weight"
            );
        }
    }
}
