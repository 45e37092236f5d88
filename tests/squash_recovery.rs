//! A finite-element body squashed flat recovers its shape (issue 51, "a body squashed flat
//! recovering its shape"; physics.md, fourth edition): a free 0.2 m cube of a rubber-like
//! material (E 1 MPa, nu 0.45, 1000 kg/m^3, no gravity, no floor) is flattened to 2 % of its
//! height, every tet nearly flat, and let go moving (0.5 m/s and 3 rad/s). After 1 s (1000
//! frames) no tet is inverted, the volume is within 1 % of the rest volume, every edge is
//! within 1 % of its rest length (the shape, whatever rotation the body ended in: a body with
//! no angular momentum still turns while it deforms), and the momentum and angular momentum
//! are those it started with: the elastic forces are internal, so an unconverged step's
//! residual must not push or turn the body (`physics::RigidPart`). On `cpu-ref`, `cpu` and
//! `vulkan` (lavapipe, the validation layer on).

mod gpu_support;

use glam::DVec3;
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::mesh::grid::box_tets;
use tetrasim::mesh::io::read_tet_mesh;
use tetrasim::params::{MassMode, Method, Placement, SpringKind};
use tetrasim::{Backend, Model, ModelBuilder, SimParams, State};

fn params() -> SimParams {
    SimParams {
        method: Method::NeoHookean,
        springs: SpringKind::Explicit,
        youngs_modulus: Some(1e6),
        poisson_ratio: Some(0.45),
        mass: MassMode::Density { density: 1000.0 },
        floor: false,
        gravity: glam::DVec3::ZERO,
        ..SimParams::default()
    }
}

/// The backend named `backend` of `model` (`vulkan` with the validation layer on).
fn backend_of(backend: &str, model: &Model, params: &SimParams) -> Box<dyn Backend> {
    match backend {
        "cpu" => Box::new(ParallelBackend::new(model, params).unwrap()),
        "vulkan" => Box::new(gpu_support::validated(model, params)),
        _ => Box::new(ReferenceBackend::new(model, params).unwrap()),
    }
}

/// Momentum and angular momentum about the origin.
fn momenta(model: &Model, state: &State) -> (DVec3, DVec3) {
    let each = (state.positions.iter().zip(&state.velocities)).zip(&model.mass);
    each.fold((DVec3::ZERO, DVec3::ZERO), |(p, l), ((x, v), m)| {
        (p + *v * *m, l + x.cross(*v * *m))
    })
}

/// Every edge of the tets, once.
fn edges(model: &Model) -> Vec<[usize; 2]> {
    let mut edges: Vec<[usize; 2]> = (model.tets.iter())
        .flat_map(|t| {
            [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)].map(|(a, b)| {
                let (i, j) = (t[a] as usize, t[b] as usize);
                [i.min(j), i.max(j)]
            })
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// Squashes the cube on `backend`, runs 1000 frames; returns the largest edge strain, the
/// volume ratio, the inverted tets and the momentum and angular momentum drifts relative
/// to `M v` and `M v L` of the start.
fn squash(backend: &str) -> (f64, f64, u32, f64, f64) {
    let params = params();
    let mesh = box_tets(DVec3::ZERO, 0.05, [4, 4, 4]);
    let placement = Placement {
        fit_size: None,
        drop_height: None,
    };
    let model = (ModelBuilder::new(&mesh).placement(placement))
        .material(&params)
        .build()
        .unwrap();
    let mut solver = backend_of(backend, &model, &params);
    let centre = DVec3::splat(0.1);
    let spin = DVec3::new(0.0, 3.0, 0.0);
    let positions: Vec<DVec3> = (model.positions.iter())
        .map(|p| DVec3::new(p.x, p.y * 0.02, p.z))
        .collect();
    let velocities = (positions.iter())
        .map(|p| DVec3::new(0.5, 0.0, 0.0) + spin.cross(*p - centre))
        .collect();
    let start = State {
        positions,
        velocities,
    };
    solver.set_state(&start).unwrap();
    let (p0, l0) = momenta(&model, &start);
    for _ in 0..1000 {
        solver.step_frame().unwrap();
    }
    let end = solver.state().unwrap();
    let strain = (edges(&model).iter())
        .map(|&[i, j]| {
            let now = (end.positions[i] - end.positions[j]).length();
            let rest = (model.positions[i] - model.positions[j]).length();
            (now / rest - 1.0).abs()
        })
        .fold(0.0, f64::max);
    let sample = solver.volume().unwrap();
    let rest: f64 = model.rest_volume.iter().sum();
    let (p, l) = momenta(&model, &end);
    let mass: f64 = model.mass.iter().sum();
    let speed = 0.5 + 3.0 * 0.2;
    let momentum = (p - p0).length() / (mass * speed);
    let angular = (l - l0).length() / (mass * speed * 0.2);
    println!(
        "{backend}: largest edge strain {strain:.2e}, volume {:.4} %, {} inverted, momentum \
         drift {momentum:.1e}, angular {angular:.1e}",
        100.0 * sample.volume / rest,
        sample.inverted
    );
    (
        strain,
        sample.volume / rest,
        sample.inverted,
        momentum,
        angular,
    )
}

fn check(backend: &str, momentum_bar: f64) {
    let (strain, volume, inverted, momentum, angular) = squash(backend);
    assert_eq!(inverted, 0, "{backend}: inverted tets after recovery");
    assert!((volume - 1.0).abs() < 0.01, "{backend}: volume {volume}");
    assert!(
        strain < 0.01,
        "{backend}: an edge is {strain} off its rest length"
    );
    assert!(
        momentum < momentum_bar,
        "{backend}: momentum drifted {momentum}"
    );
    assert!(
        angular < momentum_bar,
        "{backend}: angular momentum drifted {angular}"
    );
}

#[test]
fn a_squashed_cube_recovers_on_the_reference() {
    check("cpu-ref", 1e-9);
}

/// Single precision: the drifts are rounding (measured 1e-7), the bar 1e-5.
#[test]
fn a_squashed_cube_recovers_on_cpu() {
    check("cpu", 1e-5);
}

/// The GPU's solve, in single precision as `cpu`'s.
#[test]
fn a_squashed_cube_recovers_on_vulkan() {
    if !gpu_support::vulkan_available() {
        return;
    }
    check("vulkan", 1e-5);
}

/// A small soft body hitting the floor: the bundled sphere fitted to 5 cm (E 0.1 MPa, nu
/// 0.45, 1050 kg/m^3) dropped 0.1 m. The elastic waves cross it in 5 steps, so at the
/// impact a step's strain changes by per cents and one Newton step per time step does not
/// hold it: it flattened to 3.9 % of its volume and diverged at frame 357 (`cpu`) and 213
/// (`cpu-ref`). An untrusted CG step is now followed by a new Newton step, which took it to
/// 78 % of its volume at the worst frame with 5 tets inverted; holding the nodes the floor
/// holds inside the Newton step (docs/PHYSICS.md, "Finite elements against contacts") lands
/// it with more than 99.8 % and none inverted (measured on the three backends).
#[test]
fn a_small_soft_sphere_survives_its_impact_on_the_floor() {
    let params = SimParams {
        floor: true,
        gravity: glam::DVec3::new(0.0, -9.81, 0.0),
        youngs_modulus: Some(1e5),
        mass: MassMode::Density { density: 1050.0 },
        ..self::params()
    };
    let sphere = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    let mesh = read_tet_mesh(&sphere).unwrap();
    let placement = Placement {
        fit_size: Some(0.05),
        drop_height: Some(0.1),
    };
    let model = (ModelBuilder::new(&mesh).placement(placement))
        .material(&params)
        .build()
        .unwrap();
    let rest: f64 = model.rest_volume.iter().sum();
    for backend in ["cpu", "cpu-ref", "vulkan"] {
        if backend == "vulkan" && !gpu_support::vulkan_available() {
            continue;
        }
        let mut solver = backend_of(backend, &model, &params);
        let (mut least, mut inverted) = (f64::INFINITY, 0);
        for frame in 0..400 {
            solver
                .step_frame()
                .unwrap_or_else(|e| panic!("{backend}: frame {frame}: {e}"));
            let sample = solver.volume().unwrap();
            least = least.min(sample.volume / rest);
            inverted = inverted.max(sample.inverted);
        }
        println!(
            "{backend}: least volume {:.2} %, {inverted} inverted",
            100.0 * least
        );
        assert!(least > 0.99, "{backend}: volume fell to {least}");
        assert_eq!(inverted, 0, "{backend}: tets inverted");
    }
}
