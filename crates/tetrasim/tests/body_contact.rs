//! Contact between bodies and of a body with itself (issue 24, item 3; physics.md, "Contact
//! between bodies and with itself") on the CPU backends: two spheres colliding in free space
//! keep their total momentum and end apart, and a bar folding onto itself does not pass
//! through its own surface.

use glam::DVec3;
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::backend::Backend;
use tetrasim::model::{Model, ModelBuilder};
use tetrasim::params::{Placement, SimParams};
use tetrasim::problem::Problem;
use tetrasim::sim::bundled::bundled;

/// The bundled sphere (1 m across) centred at `centre`, moving at `velocity`.
fn sphere(centre: DVec3, velocity: DVec3) -> Model {
    let mesh = bundled("meshes/sphere").expect("the bundled sphere");
    ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.0),
        })
        .offset(centre - DVec3::new(0.0, 0.5, 0.0))
        .velocity(velocity)
        .build()
        .expect("a sphere")
}

fn free_space() -> SimParams {
    SimParams {
        gravity: glam::DVec3::ZERO,
        floor: false,
        substeps: 5,
        ..SimParams::default()
    }
}

fn momentum(model: &Model, v: &[DVec3]) -> DVec3 {
    model.mass.iter().zip(v).map(|(m, v)| *v * *m).sum()
}

/// The generalised winding number of the closed surface `faces` at `p` (1 inside, 0 out).
fn winding(p: DVec3, x: &[DVec3], faces: &[[u32; 3]]) -> f64 {
    let mut total = 0.0;
    for f in faces {
        let [a, b, c] = f.map(|i| x[i as usize] - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let numerator = a.dot(b.cross(c));
        let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        total += 2.0 * numerator.atan2(denominator);
    }
    total / (4.0 * std::f64::consts::PI)
}

/// The nodes of object `a` inside object `b` at positions `x`.
fn inside(model: &Model, x: &[DVec3], a: usize, b: usize) -> usize {
    let range = |k: usize| model.objects[k]..model.objects[k + 1];
    let faces: Vec<[u32; 3]> = (model.surface.iter())
        .filter(|f| range(b).contains(&f[0]))
        .copied()
        .collect();
    range(a)
        .filter(|&i| winding(x[i as usize], x, &faces) > 0.5)
        .count()
}

#[test]
fn two_spheres_collide_keep_their_momentum_and_end_apart() {
    let model = Model::concat(&[
        sphere(DVec3::new(-0.55, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0)),
        sphere(DVec3::new(0.55, 0.1, 0.0), DVec3::new(-1.0, 0.0, 0.0)),
    ])
    .expect("two spheres");
    let problem = Problem::new(&model, &free_space()).expect("a problem");
    assert!(problem.bodies.is_some(), "two objects collide");
    let backends: Vec<Box<dyn Backend>> = vec![
        Box::new(ReferenceBackend::from_problem(&problem)),
        Box::new(ParallelBackend::from_problem(&problem)),
    ];
    let p0 = momentum(&model, &model.velocities);
    let mut finals = Vec::new();
    for mut backend in backends {
        let mut worst = 0;
        for _ in 0..60 {
            backend.step_frame().expect("a frame");
            let state = backend.state().expect("the state");
            let p = momentum(&model, &state.velocities);
            let scale = p0.length().max(1.0);
            assert!(
                (p - p0).length() < 1e-4 * scale,
                "{}: momentum {p} drifted from {p0}",
                backend.name()
            );
            worst = worst.max(
                inside(&model, &state.positions, 0, 1) + inside(&model, &state.positions, 1, 0),
            );
        }
        let state = backend.state().expect("the state");
        assert_eq!(
            worst,
            0,
            "{}: nodes went inside the other sphere",
            backend.name()
        );
        // They met and bounced: the left sphere no longer moves right as fast.
        let left = momentum(&model, &state.velocities[..model.objects[1] as usize]).x;
        let before = momentum(&model, &model.velocities[..model.objects[1] as usize]).x;
        assert!(
            left < 0.8 * before,
            "{}: no collision ({left} of {before})",
            backend.name()
        );
        finals.push(state.positions);
    }
    let d = (finals[0].iter().zip(&finals[1]))
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f64::max);
    assert!(d < 5e-3, "cpu is {d:e} m from cpu-ref");
}

/// A bar 0.1 m thick folded into a U lying on the floor: a lower arm along X from 0 to 1 m,
/// a half-turn bend of inner radius 0.05 m at x = 1, an upper arm back above it, 0.1 m
/// higher. Its rest shape is the U.
fn folded_bar(self_contact: bool) -> Model {
    let h = 0.1;
    let mut mesh = tetrasim::mesh::grid::box_tets(DVec3::ZERO, h, [23, 1, 2]);
    let bend = 0.1 * std::f64::consts::PI;
    let stretch = (2.0 + bend) / 2.3;
    let centre = DVec3::new(1.0, 0.15, 0.0);
    for p in &mut mesh.nodes {
        let s = p.x * stretch;
        let r = 0.15 - p.y;
        let (x, y) = if s <= 1.0 {
            (s, p.y)
        } else if s <= 1.0 + bend {
            let angle = (s - 1.0) / 0.1;
            (centre.x + r * angle.sin(), centre.y - r * angle.cos())
        } else {
            (1.0 - (s - 1.0 - bend), centre.y + r)
        };
        *p = DVec3::new(x, y, p.z);
    }
    ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: None,
            drop_height: None,
        })
        .self_contact(self_contact)
        .build()
        .expect("a folded bar")
}

/// The surface nodes of the bar's arms (away from the bend, whose inner crease is concave)
/// inside its own surface (winding number above 0.75; a node on a flat or convex part of the
/// surface has at most 0.5).
fn crossed(model: &Model, x: &[DVec3]) -> usize {
    let mut nodes: Vec<u32> = (model.surface.iter().flatten().copied())
        .filter(|&i| model.positions[i as usize].x < 0.9)
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
        .iter()
        .filter(|&&i| winding(x[i as usize], x, &model.surface) > 0.75)
        .count()
}

#[test]
fn a_folded_bar_lands_on_itself_with_self_contact_and_falls_through_without() {
    let params = SimParams {
        substeps: 5,
        ..SimParams::default()
    };
    let run = |model: &Model, backend: &mut dyn Backend| {
        let mut worst = 0;
        for _ in 0..60 {
            backend.step_frame().expect("a frame");
            let x = backend.state().expect("the state").positions;
            worst = worst.max(crossed(model, &x));
        }
        worst
    };
    let folded = folded_bar(true);
    let problem = Problem::new(&folded, &params).expect("a problem");
    assert!(problem.bodies.is_some(), "self-contact is on");
    assert_eq!(
        run(&folded, &mut ReferenceBackend::from_problem(&problem)),
        0,
        "cpu-ref"
    );
    assert_eq!(
        run(&folded, &mut ParallelBackend::from_problem(&problem)),
        0,
        "cpu"
    );
    // The same bar without self-contact: the upper arm sinks into the lower one.
    let ghost = folded_bar(false);
    let problem = Problem::new(&ghost, &params).expect("a problem");
    assert!(problem.bodies.is_none());
    let through = run(&ghost, &mut ReferenceBackend::from_problem(&problem));
    assert!(through > 0, "without self-contact the arms should cross");
}
