//! Shared test fixtures: meshes made in code, models and parameter sets.
#![allow(dead_code)]

pub mod python;
pub mod skip;

use glam::DVec3;
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::backend::{Backend, State};
use tetrasim::mesh::grid::{box_tets, grid_tets};
use tetrasim::mesh::TetMesh;
use tetrasim::params::{Placement, SimParams};
use tetrasim::{Model, ModelBuilder};

/// The two CPU backends of `model` with `params`, named: `cpu-ref`, then `cpu`.
pub fn cpu_backends(model: &Model, params: &SimParams) -> [(&'static str, Box<dyn Backend>); 2] {
    [
        (
            "cpu-ref",
            Box::new(ReferenceBackend::new(model, params).unwrap()),
        ),
        (
            "cpu",
            Box::new(ParallelBackend::new(model, params).unwrap()),
        ),
    ]
}

/// A solid box of `cells` unit-ish cubes (edge 0.1 m), six tets per cube.
pub fn box_mesh(cells: [usize; 3]) -> TetMesh {
    box_tets(DVec3::ZERO, 0.1, cells)
}

/// A ball made of the grid cells whose centres lie within `radius_cells` cells of the centre.
pub fn ball_mesh(radius_cells: f64) -> TetMesh {
    let n = (2.0 * radius_cells).ceil() as usize;
    let c = n as f64 / 2.0;
    grid_tets(DVec3::ZERO, 1.0, [n, n, n], |[x, y, z]| {
        let p = DVec3::new(x as f64 + 0.5, y as f64 + 0.5, z as f64 + 0.5) - DVec3::splat(c);
        p.length() <= radius_cells
    })
}

/// One tetrahedron, not regular, positively oriented.
pub fn single_tet() -> TetMesh {
    TetMesh {
        nodes: vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.1),
            DVec3::new(0.2, 0.9, 0.0),
            DVec3::new(0.1, 0.2, 1.1),
        ],
        tets: vec![[0, 1, 2, 3]],
        faces: Vec::new(),
    }
}

/// The model of `mesh` where it is (no scaling, no moving), unit node masses.
pub fn model_in_place(mesh: &TetMesh) -> Model {
    ModelBuilder::new(mesh)
        .placement(Placement {
            fit_size: None,
            drop_height: None,
        })
        .build()
        .unwrap()
}

/// The model of `mesh` fit to 1 m and 1 cm above the floor: it lands within a few frames.
pub fn near_floor_model(mesh: &TetMesh) -> Model {
    ModelBuilder::new(mesh)
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.01),
        })
        .build()
        .unwrap()
}

/// The model of `mesh` with the `seed` placement (1 m, 0.1 m above the floor).
pub fn seed_model(mesh: &TetMesh) -> Model {
    ModelBuilder::new(mesh).build().unwrap()
}

/// Parameters without gravity, floor, springs or damping.
pub fn bare_params() -> SimParams {
    SimParams {
        gravity: glam::DVec3::ZERO,
        floor: false,
        ks: 0.0,
        kd: 0.0,
        ..SimParams::default()
    }
}

/// A deterministic pseudo-random number in [-1, 1) (splitmix64 of `i`).
pub fn noise(i: u64) -> f64 {
    let mut z = i.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// A deterministic pseudo-random vector with components in [-1, 1).
pub fn noise3(i: u64) -> DVec3 {
    DVec3::new(noise(3 * i), noise(3 * i + 1), noise(3 * i + 2))
}

/// The model's initial positions jittered by up to `amount` [m] per axis and random
/// velocities of up to `speed` [m/s] per axis.
pub fn jittered_state(model: &Model, amount: f64, speed: f64, seed: u64) -> State {
    let n = model.node_count() as u64;
    State {
        positions: model
            .positions
            .iter()
            .enumerate()
            .map(|(i, p)| *p + noise3(seed + i as u64) * amount)
            .collect(),
        velocities: (0..n).map(|i| noise3(seed + n + i) * speed).collect(),
    }
}

/// Runs `frames` frames.
pub fn run_frames(backend: &mut dyn Backend, frames: u32) {
    for _ in 0..frames {
        backend.step_frame().unwrap();
    }
}

/// Largest distance between corresponding points.
pub fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max)
}

/// Mass-weighted centre of `points`.
pub fn centre_of_mass(points: &[DVec3], mass: &[f64]) -> DVec3 {
    let total: f64 = mass.iter().sum();
    points.iter().zip(mass).map(|(p, m)| *p * *m).sum::<DVec3>() / total
}

/// How a body dropped onto the floor behaves after it first reaches it, over `frames`
/// frames: how far its lowest node rises after the first contact [m] (issue 26's rebound),
/// its average local volume error [% of the rest volume], and its last positions.
pub struct Rebound {
    /// The highest its lowest node gets after the first frame that touches the floor [m].
    pub rise: f64,
    /// The average local volume error over the frames [%].
    pub local: f64,
    /// The positions after the last frame.
    pub positions: Vec<DVec3>,
}

/// Runs `frames` frames of `backend` (a model of rest volume `rest`), asserting that the
/// body reaches the floor (its lowest node within 0.1 mm of it), and measures its
/// [`Rebound`].
pub fn rebound(backend: &mut dyn Backend, rest: f64, frames: u32) -> Rebound {
    let (mut contact, mut rise, mut local) = (false, 0.0f64, 0.0);
    for frame in 0..frames {
        backend
            .step_frame()
            .unwrap_or_else(|e| panic!("frame {frame}: {e}"));
        local += 100.0 * backend.volume().unwrap().local_error / rest / f64::from(frames);
        let lowest = (backend.state().unwrap().positions.iter())
            .map(|p| p.y)
            .fold(f64::INFINITY, f64::min);
        if contact {
            rise = rise.max(lowest);
        }
        contact |= lowest < 1e-4;
    }
    assert!(contact, "the body never reached the floor");
    Rebound {
        rise,
        local,
        positions: backend.state().unwrap().positions,
    }
}

/// `model` over a plane collider through the origin, tilted about Z (normal `(0.3, 1, 0)`):
/// run without the floor, it lands on the plane, whose push holds its nodes along the
/// normal.
pub fn over_tilted_plane(model: Model) -> Model {
    let plane = tetrasim::collider::Collider::plane(DVec3::new(0.3, 1.0, 0.0), 0.0).unwrap();
    model.with_colliders(vec![plane]).unwrap()
}

/// A material given as a user would: Young's modulus `e` [Pa], Poisson's ratio `nu`, density
/// [kg/m^3], for `method` (springs from the material are implicit; the finite elements have
/// none), without a floor.
pub fn material_params(
    method: tetrasim::params::Method,
    e: f64,
    nu: f64,
    density: f64,
) -> SimParams {
    use tetrasim::params::{MassMode, Method, SpringKind};
    SimParams {
        method,
        springs: match method {
            Method::NeoHookean => SpringKind::Explicit,
            _ => SpringKind::Implicit,
        },
        youngs_modulus: Some(e),
        poisson_ratio: Some(nu),
        mass: MassMode::Density { density },
        floor: false,
        ..SimParams::default()
    }
}

/// The placement that leaves a mesh where it is and as large as it is.
pub fn unplaced() -> Placement {
    Placement {
        fit_size: None,
        drop_height: None,
    }
}

/// The CPU backend named `name` (`cpu` or `cpu-ref`) of `model` with `params`.
pub fn cpu_backend(model: &Model, params: &SimParams, name: &str) -> Box<dyn Backend> {
    match name {
        "cpu" => Box::new(ParallelBackend::new(model, params).unwrap()),
        "cpu-ref" => Box::new(ReferenceBackend::new(model, params).unwrap()),
        _ => panic!("not a CPU backend: {name}"),
    }
}
