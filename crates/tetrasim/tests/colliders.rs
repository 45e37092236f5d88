//! Kinematic colliders on the CPU backends (issue 24, item 1; physics.md, "Kinematic
//! colliders"): every shape keeps every node outside it while it moves, friction holds or
//! lets go on a tilted plane, and `cpu` follows `cpu-ref`.

use glam::{DQuat, DVec3};
use tetrasim::backend::Backend;
use tetrasim::collider::{self, Collider, Grab, Keyframe, Motion};
use tetrasim::model::{Model, ModelBuilder};
use tetrasim::params::{Placement, SimParams};
use tetrasim::problem::Problem;
use tetrasim::sim::bundled::bundled;

/// Steps of 1 ms per frame.
const SUBSTEPS: u32 = 5;

/// The bundled sphere (1 m across), its lowest node `height` above y = 0, moved by
/// `offset`, with `colliders`.
fn sphere(height: f64, offset: DVec3, colliders: Vec<Collider>) -> Model {
    let mesh = bundled("meshes/sphere").expect("the bundled sphere");
    ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(height),
        })
        .offset(offset)
        .build()
        .and_then(|m| m.with_colliders(colliders))
        .expect("a model")
}

fn params(floor: bool) -> SimParams {
    SimParams {
        floor,
        substeps: SUBSTEPS,
        ..SimParams::default()
    }
}

/// Backends under test: `cpu-ref` and `cpu`.
fn backends(problem: &Problem) -> Vec<Box<dyn Backend>> {
    vec![
        Box::new(tetrasim::backend::cpu::ReferenceBackend::from_problem(
            problem,
        )),
        Box::new(tetrasim::backend::cpu::ParallelBackend::from_problem(
            problem,
        )),
    ]
}

/// The deepest any node is inside any collider [m] (0 when none is), at the collider poses
/// after `frames` frames.
fn deepest(model: &Model, positions: &[DVec3], frames: u32, dt: f64) -> f64 {
    let steps = u64::from(frames * SUBSTEPS);
    // The poses at the end of the last step are the start poses of the next.
    let at = collider::at_step(&model.colliders, steps, dt);
    let mut depth: f64 = 0.0;
    for c in &at {
        for &x in positions {
            let local = c.start.invert(x);
            depth = depth.max(-c.collider.shape.distance(local).0);
        }
    }
    depth
}

/// Runs `frames` frames of every backend, checking after each that no node is more than
/// 1 mm inside a collider; returns each backend's final positions.
fn run_checked(model: &Model, params: &SimParams, frames: u32) -> Vec<Vec<DVec3>> {
    let problem = Problem::new(model, params).expect("a problem");
    backends(&problem)
        .into_iter()
        .map(|mut backend| {
            let mut worst: f64 = 0.0;
            for frame in 1..=frames {
                backend.step_frame().expect("a frame");
                let x = backend.state().expect("the state").positions;
                worst = worst.max(deepest(model, &x, frame, params.dt));
            }
            assert!(
                worst < 1e-3,
                "{}: a node went {worst:e} m inside a collider",
                backend.name()
            );
            backend.state().expect("the state").positions
        })
        .collect()
}

fn centre(positions: &[DVec3]) -> DVec3 {
    positions.iter().copied().sum::<DVec3>() / positions.len() as f64
}

#[test]
fn every_shape_holds_the_sphere_up_while_it_moves() {
    let half_turn = DQuat::from_rotation_y(std::f64::consts::PI);
    let cases = vec![
        (
            "static ball",
            Collider::sphere(DVec3::new(0.0, -0.4, 0.0), 0.5),
        ),
        (
            "turning box",
            Collider::cuboid(
                DVec3::new(0.0, -0.2, 0.0),
                DVec3::new(0.6, 0.2, 0.3),
                DQuat::IDENTITY,
            )
            .moving(Motion::Velocity {
                linear: DVec3::ZERO,
                angular: DVec3::new(0.0, 3.0, 0.0),
            }),
        ),
        (
            "rising capsule",
            Collider::capsule(DVec3::new(-0.5, -0.3, 0.0), DVec3::new(0.5, -0.3, 0.0), 0.2).moving(
                Motion::Keyframes(vec![
                    Keyframe {
                        t: 0.0,
                        position: DVec3::ZERO,
                        rotation: DQuat::IDENTITY,
                    },
                    Keyframe {
                        t: 0.1,
                        position: DVec3::new(0.0, 0.1, 0.0),
                        rotation: half_turn,
                    },
                ]),
            ),
        ),
        (
            "tilted plane",
            Collider::plane(DVec3::new(0.3, 1.0, 0.0), -0.05).expect("a plane"),
        ),
    ];
    for (name, collider) in cases {
        let model = sphere(0.05, DVec3::ZERO, vec![collider.with_friction(0.3)]);
        let finals = run_checked(&model, &params(false), 80);
        // Falling freely for 0.4 s, the centre would be at 0.55 - 0.78 = -0.23 m.
        for x in &finals {
            assert!(centre(x).y > 0.1, "{name}: not held ({})", centre(x).y);
        }
        let d = (finals[0].iter().zip(&finals[1]))
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        assert!(d < 2e-3, "{name}: cpu is {d:e} m from cpu-ref");
    }
}

#[test]
fn friction_holds_a_body_on_a_tilted_plane_and_zero_friction_lets_it_slide() {
    let slope = 25f64.to_radians();
    let normal = DVec3::new(-slope.sin(), slope.cos(), 0.0);
    let slid = |friction: f64| {
        let plane = Collider::plane(normal, 0.0)
            .expect("a plane")
            .with_friction(friction);
        // A 0.3 m cube turned flat onto the plane, 2 mm above it.
        let mesh = bundled("meshes/box").expect("the bundled box");
        let mut model = ModelBuilder::new(&mesh)
            .placement(Placement {
                fit_size: Some(0.3),
                drop_height: Some(0.0),
            })
            .build()
            .and_then(|m| m.with_colliders([plane]))
            .expect("a model");
        let turn = DQuat::from_rotation_z(slope);
        let lowest = model
            .positions
            .iter()
            .map(|p| normal.dot(turn * *p))
            .fold(f64::INFINITY, f64::min);
        for p in &mut model.positions {
            *p = turn * *p + normal * (0.002 - lowest);
        }
        let start = centre(&model.positions);
        let problem = Problem::new(&model, &params(false)).expect("a problem");
        let mut backend = tetrasim::backend::cpu::ReferenceBackend::from_problem(&problem);
        for _ in 0..60 {
            backend.step_frame().expect("a frame");
        }
        let end = centre(&backend.state().expect("state").positions);
        (end - start).dot(DVec3::new(-slope.cos(), -slope.sin(), 0.0))
    };
    // Free sliding travels g sin(slope) t^2 / 2 down the slope over t = 0.3 s (0.187 m).
    let free = 0.5 * 9.81 * slope.sin() * 0.09;
    let (ice, glue) = (slid(0.0), slid(1.0));
    assert!(ice > 0.8 * free, "frictionless: slid {ice} m of {free} m");
    // It settles onto the plane (2 mm of gap and its own squash, whose sway moves its centre
    // a few cm to and fro: friction is Coulomb's, node by node, so the bottom spreads where
    // it is pressed least) but does not slide (tan 25 degrees = 0.47 < 1).
    assert!(glue < 0.15 * free, "friction 1: slid {glue} m of {free} m");
}

/// Coulomb's law, on the floor and on a `plane` collider alike: a 0.3 m cube launched along
/// the floor at 1 m/s with friction 0.5 decelerates at `mu g` and stops after
/// `v^2 / (2 mu g)` = 0.102 m, on `cpu-ref` and `cpu` (0.1023 m measured, 0.4 % over).
/// Friction as a fraction removed per step alone, the law before 2026-11-27, stops it within
/// a few millimetres.
#[test]
fn friction_stops_a_sliding_cube_where_coulomb_says() {
    let (speed, mu, g) = (1.0, 0.5, 9.81);
    let expected = speed * speed / (2.0 * mu * g);
    let mesh = bundled("meshes/box").expect("the bundled box");
    for on_plane in [false, true] {
        let colliders = match on_plane {
            true => vec![Collider::plane(DVec3::Y, 0.0)
                .expect("a plane")
                .with_friction(mu)],
            false => vec![],
        };
        let mut model = ModelBuilder::new(&mesh)
            .placement(Placement {
                fit_size: Some(0.3),
                drop_height: Some(0.0),
            })
            .build()
            .and_then(|m| m.with_colliders(colliders))
            .expect("a model");
        model
            .velocities
            .iter_mut()
            .for_each(|v| *v = DVec3::X * speed);
        // Nearly rigid (hard distance constraints), so the body's own sway does not mix in.
        let params = SimParams {
            friction: mu,
            method: tetrasim::params::Method::Distance,
            ..params(!on_plane)
        };
        let frames = (0.4 / params.frame_time()).ceil() as u32;
        let problem = Problem::new(&model, &params).expect("a problem");
        for mut backend in backends(&problem) {
            let start = centre(&model.positions);
            for _ in 0..frames {
                backend.step_frame().expect("a frame");
            }
            let state = backend.state().expect("state");
            let travel = centre(&state.positions).x - start.x;
            let still = centre(&state.velocities).length();
            let place = if on_plane { "plane" } else { "floor" };
            assert!(
                (travel - expected).abs() < 0.05 * expected && still < 0.01,
                "{} on the {place}: slid {travel} m (Coulomb: {expected} m), moving at {still} m/s",
                backend.name()
            );
        }
    }
}

#[test]
fn chebyshev_is_refused_with_colliders() {
    let model = sphere(0.1, DVec3::ZERO, vec![Collider::sphere(DVec3::ZERO, 0.1)]);
    let params = SimParams {
        solver: tetrasim::params::Solver::Chebyshev,
        ..SimParams::default()
    };
    let err = Problem::new(&model, &params)
        .expect_err("refused")
        .to_string();
    assert!(err.contains("solver") && err.contains("collider"), "{err}");
}

#[test]
fn a_clamp_follows_its_keyframes_exactly_and_drags_the_body() {
    let mesh = bundled("meshes/box").expect("the bundled box");
    let lift = Motion::Keyframes(vec![
        Keyframe {
            t: 0.0,
            position: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
        },
        Keyframe {
            t: 0.2,
            position: DVec3::new(0.0, 0.3, 0.0),
            rotation: DQuat::from_rotation_y(0.5),
        },
    ]);
    let placement = Placement {
        fit_size: Some(0.5),
        drop_height: Some(0.0),
    };
    let free = ModelBuilder::new(&mesh)
        .placement(placement)
        .build()
        .expect("a model");
    let top = free.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
    let model = ModelBuilder::new(&mesh)
        .placement(placement)
        // The top layer of nodes.
        .pinned_in_box(
            DVec3::new(-1.0, top - 1e-6, -1.0),
            DVec3::new(1.0, 1.0, 1.0),
        )
        .pin_motion(lift.clone())
        .build()
        .expect("a model");
    let clamp = model
        .clamps
        .first()
        .expect("the pins became a clamp")
        .clone();
    assert!(!clamp.nodes.is_empty());
    let problem = Problem::new(&model, &params(true)).expect("a problem");
    for mut backend in backends(&problem) {
        let start = centre(&model.positions);
        for frame in 1..=60u32 {
            backend.step_frame().expect("a frame");
            let x = backend.state().expect("state").positions;
            let t = f64::from(frame * SUBSTEPS) * 1e-3;
            let off = (clamp.nodes.iter())
                .map(|&i| x[i as usize].distance(clamp.target(model.positions[i as usize], t)))
                .fold(0.0, f64::max);
            // cpu rounds to f32: 1e-6 of a 0.5 m body.
            assert!(
                off < 1e-6,
                "{} frame {frame}: a clamped node is {off:e} m off",
                backend.name()
            );
        }
        let lifted = centre(&backend.state().expect("state").positions).y - start.y;
        assert!(
            lifted > 0.15,
            "{}: the body rose only {lifted} m with its clamp",
            backend.name()
        );
    }
}

#[test]
fn a_grab_pulls_a_clamped_block_up_and_lets_go() {
    let mesh = bundled("meshes/box").expect("the bundled box");
    let placement = Placement {
        fit_size: Some(1.0),
        drop_height: Some(0.0),
    };
    let free = ModelBuilder::new(&mesh)
        .placement(placement)
        .build()
        .expect("a model");
    let lo = free.positions.iter().map(|p| p.x).fold(f64::MAX, f64::min);
    let hi = free.positions.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    let top = free.positions.iter().map(|p| p.y).fold(f64::MIN, f64::max);
    let mid = (lo + hi) / 2.0;
    let lift = Motion::Keyframes(vec![
        Keyframe {
            t: 0.0,
            position: DVec3::ZERO,
            rotation: DQuat::IDENTITY,
        },
        Keyframe {
            t: 0.1,
            position: DVec3::new(0.0, 0.2, 0.0),
            rotation: DQuat::IDENTITY,
        },
    ]);
    let grab = Grab::new(DVec3::new(mid, top, 0.0), 0.3)
        .moving(lift)
        .release_at(0.15);
    // Clamped at both ends (static pins), grabbed on top in the middle.
    let model = ModelBuilder::new(&mesh)
        .placement(placement)
        .pinned_in_box(
            DVec3::new(lo - 1.0, -1.0, -1.0),
            DVec3::new(lo + 1e-6, 2.0, 1.0),
        )
        .pinned_in_box(
            DVec3::new(hi - 1e-6, -1.0, -1.0),
            DVec3::new(hi + 1.0, 2.0, 1.0),
        )
        .build()
        .and_then(|m| m.with_grab(grab))
        .expect("a grabbed block");
    let held = model.grabs[0].clone();
    let problem = Problem::new(&model, &params(true)).expect("a problem");
    for mut backend in backends(&problem) {
        let mut peak: f64 = 0.0;
        for frame in 1..=40u32 {
            backend.step_frame().expect("a frame");
            let x = backend.state().expect("state").positions;
            let t = f64::from(frame * SUBSTEPS) * 1e-3;
            let rise = (held.nodes.iter())
                .map(|&i| x[i as usize].y - model.positions[i as usize].y)
                .sum::<f64>()
                / held.nodes.len() as f64;
            peak = peak.max(rise);
            if held.holds(t) {
                let off = (held.nodes.iter())
                    .map(|&i| x[i as usize].distance(held.target(model.positions[i as usize], t)))
                    .fold(0.0, f64::max);
                assert!(
                    off < 1e-5,
                    "{} at {t} s: a held node is {off:e} m off",
                    backend.name()
                );
            }
            if frame == 40 {
                assert!(peak > 0.19, "{}: pulled up only {peak} m", backend.name());
                assert!(
                    rise < 0.5 * peak,
                    "{}: still up {rise} m after letting go",
                    backend.name()
                );
            }
        }
    }
    let none = ModelBuilder::new(&mesh)
        .build()
        .and_then(|m| m.with_grab(Grab::new(DVec3::new(9.0, 9.0, 9.0), 0.1)))
        .expect_err("a grab far from the body");
    assert!(
        none.to_string().contains("grab[0]") && none.to_string().contains("no node"),
        "{none}"
    );
}

#[test]
fn records_carry_contact_counts_and_the_deepest_penetration() {
    let ball = Collider::sphere(DVec3::new(0.0, -0.4, 0.0), 0.5);
    let model = sphere(0.02, DVec3::ZERO, vec![ball]);
    let params = params(false);
    let problem = Problem::new(&model, &params).expect("a problem");
    for mut backend in backends(&problem) {
        let mut run = tetrasim::sim::Simulation::new(&model, &params);
        for _ in 0..30 {
            run.advance(backend.as_mut(), true).expect("a frame");
        }
        let mut record = tetrasim::metrics::RunRecord::new(&problem, "sphere", 30, backend.name());
        run.fill_record(&mut record);
        let name = backend.name();
        assert_eq!(
            record.collider_nodes.len(),
            30,
            "{name}: one count per frame"
        );
        assert_eq!(
            record.collider_nodes[0], 0,
            "{name}: 2 cm above the ball at first"
        );
        assert!(
            record.collider_nodes[29] > 0,
            "{name}: resting on the ball at the end"
        );
        assert!(
            record.body_contacts.iter().all(|&c| c == 0),
            "{name}: one body"
        );
        let deepest = record.deepest_m.iter().copied().fold(0.0, f64::max);
        assert!(deepest < 1e-3, "{name}: {deepest} m deep");
    }
    // Without colliders the series stay empty (and out of the JSON).
    let plain = sphere(0.02, DVec3::ZERO, vec![]);
    let problem = Problem::new(&plain, &params).expect("a problem");
    let mut backend = tetrasim::backend::cpu::ReferenceBackend::from_problem(&problem);
    let mut run = tetrasim::sim::Simulation::new(&plain, &params);
    run.advance(&mut backend, true).expect("a frame");
    let mut record = tetrasim::metrics::RunRecord::new(&problem, "sphere", 1, "cpu-ref");
    run.fill_record(&mut record);
    assert!(record.collider_nodes.is_empty() && record.deepest_m.is_empty());
}
