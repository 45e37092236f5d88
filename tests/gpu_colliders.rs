//! Kinematic colliders on the Vulkan engine: the bundled sphere dropped onto (a) a fixed
//! ball (Jacobi: atomic sums), (b) a turning box swept by a keyframed capsule (two substeps
//! a frame; again with split contact, whose velocity solve lets each collider keep a node's
//! starting penetration), (c) a mesh collider (a torus's sampled distance) over a tilted
//! plane (no floor), every one with friction, matches `cpu-ref` per frame (volume) and at the
//! end (positions), and no node ever ends a frame more than 1 mm inside a collider. The run
//! record's contact series (each frame's pushed nodes and deepest penetration, measured on
//! the device) match `cpu-ref`'s too. Frames in flight read their own slot's poses. Without
//! the colliders' solve the sphere would fall through them (each scene checks that it
//! touched every collider), so these fail when the feature is off; without the GPU's contact
//! measures the samples have none, or no pushed nodes and no depth.
//!
//! Tolerances are those of tests/gpu_matches_cpu.rs (the GPU works in f32, the reference
//! in f64).

mod common;
mod gpu_support;

use glam::{DQuat, DVec3};
use tetrasim::backend::cpu::ReferenceBackend;
use tetrasim::collider::{Collider, DistanceGrid, Keyframe, Motion};
use tetrasim::params::{ContactMode, SimParams, Solver};
use tetrasim::{Backend, Model};

/// Largest allowed per-frame difference of the volume percentage [percentage points].
const VOLUME_POINTS: f64 = 1e-3;
/// Largest allowed final position difference, as a fraction of the bounding-box diagonal.
const POSITION_FRACTION: f64 = 1e-5;
/// How far a node may end a frame inside a collider [m].
const PENETRATION: f64 = 1e-3;
/// Largest allowed per-frame difference of the nodes a collider pushed in the frame's last
/// step: one node whose push is within f32 rounding of zero may count on one backend only
/// (none did on lavapipe).
const COUNT_SLACK: u32 = 1;

/// The bundled sphere per the `seed` placement (1 m across, its lowest node 0.1 m up).
fn sphere_with(colliders: Vec<Collider>) -> Model {
    common::seed_model(&gpu_support::bundled_sphere())
        .with_colliders(colliders)
        .unwrap()
}

/// A grid of the distance to a flat torus (major radius `r_major` about local Y, minor
/// `r_minor`) centred at `centre`.
fn torus_grid(centre: DVec3, r_major: f64, r_minor: f64) -> DistanceGrid {
    let cell = 0.02;
    let half = DVec3::new(
        r_major + r_minor + 0.1,
        r_minor + 0.1,
        r_major + r_minor + 0.1,
    );
    let origin = centre - half;
    let dims = (half * 2.0 / cell).ceil().as_uvec3() + 1;
    let mut values = Vec::new();
    for k in 0..dims.z {
        for j in 0..dims.y {
            for i in 0..dims.x {
                let p = origin + DVec3::new(i as f64, j as f64, k as f64) * cell - centre;
                let ring = DVec3::new(p.x, 0.0, p.z).length() - r_major;
                values.push((ring * ring + p.y * p.y).sqrt() - r_minor);
            }
        }
    }
    DistanceGrid {
        origin,
        cell,
        dims: dims.to_array(),
        values,
    }
}

/// The scenes: name, model, parameters, frames.
fn scenes() -> Vec<(&'static str, Model, SimParams, u32)> {
    let fixed = Collider::sphere(DVec3::new(0.2, -0.3, 0.0), 0.35).with_friction(0.5);
    let turning = Collider::cuboid(
        DVec3::new(0.0, -0.1, 0.0),
        DVec3::new(0.4, 0.12, 0.4),
        DQuat::from_rotation_y(0.3),
    )
    .moving(Motion::Velocity {
        linear: DVec3::ZERO,
        angular: DVec3::new(0.0, 3.0, 0.0),
    })
    .with_friction(0.8);
    let key = |t: f64, x: f64, turn: f64| Keyframe {
        t,
        position: DVec3::new(x, 0.0, 0.0),
        rotation: DQuat::from_rotation_x(turn),
    };
    let sweeping = Collider::capsule(
        DVec3::new(-0.8, 0.35, -0.4),
        DVec3::new(-0.8, 0.35, 0.4),
        0.1,
    )
    .moving(Motion::Keyframes(vec![
        key(0.0, 0.0, 0.0),
        key(0.1, 0.15, 0.2),
        key(0.25, 0.3, 0.0),
    ]))
    .with_friction(0.4);
    let mesh =
        Collider::mesh(torus_grid(DVec3::new(0.05, -0.05, 0.0), 0.3, 0.12)).with_friction(0.3);
    let tilted = Collider::plane(DVec3::new(0.1, 1.0, 0.0), 0.0)
        .unwrap()
        .with_friction(0.2);
    let substeps = SimParams {
        dt: 5e-4,
        substeps: 2,
        ..SimParams::default()
    };
    vec![
        (
            "fixed sphere (jacobi)",
            sphere_with(vec![fixed]),
            SimParams {
                solver: Solver::Jacobi,
                ..SimParams::default()
            },
            220,
        ),
        (
            "turning box and keyframed capsule",
            sphere_with(vec![turning.clone(), sweeping.clone()]),
            substeps.clone(),
            220,
        ),
        (
            "turning box and keyframed capsule, split contact",
            sphere_with(vec![turning, sweeping]),
            SimParams {
                contact: ContactMode::Split,
                ..substeps
            },
            220,
        ),
        (
            "mesh torus over a tilted plane (no floor)",
            sphere_with(vec![mesh, tilted]),
            SimParams {
                floor: false,
                ..SimParams::default()
            },
            220,
        ),
    ]
}

/// Each collider's least signed distance from any node of `positions` at time `t` [s],
/// with that node.
fn least_distances(model: &Model, positions: &[DVec3], t: f64) -> Vec<(f64, usize)> {
    (model.colliders.iter())
        .map(|c| {
            let pose = c.pose_at(t);
            (positions.iter().enumerate())
                .map(|(i, x)| (c.shape.distance(pose.invert(*x)).0, i))
                .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a })
        })
        .collect()
}

#[test]
fn colliders_match_the_reference_and_keep_every_node_out() {
    if !gpu_support::vulkan_available() {
        return;
    }
    // The largest deepest penetration of any scene's reference, in position tolerances.
    let mut deepest = 0.0f64;
    for (name, model, params, frames) in scenes() {
        let rest = model.total_rest_volume();
        let diag = model.bounds_diagonal();
        let frame_time = params.frame_time();

        // Vulkan: every frame's state, no node inside a collider.
        let mut gpu = gpu_support::validated(&model, &params);
        assert!(gpu.plan().has_pass("integrate") && gpu.plan().schedule.colliders > 0);
        let mut volumes = Vec::new();
        let mut contacts = Vec::new();
        let mut closest = vec![f64::INFINITY; model.colliders.len()];
        for frame in 0..frames {
            gpu.step_frame().unwrap();
            let sample = gpu.volume().unwrap();
            volumes.push(100.0 * sample.volume / rest);
            contacts.push(gpu_support::contact_of(&sample, "vulkan"));
            let state = gpu.state().unwrap();
            let t = f64::from(frame + 1) * frame_time;
            for (k, (phi, i)) in least_distances(&model, &state.positions, t)
                .into_iter()
                .enumerate()
            {
                assert!(
                    phi >= -PENETRATION,
                    "{name}: frame {frame}: node {i} is {phi} m inside collider {k}"
                );
                closest[k] = closest[k].min(phi);
            }
        }
        gpu_support::assert_no_validation_messages(&gpu);
        let gpu_state = gpu.state().unwrap();
        // Not vacuous: the sphere came down onto (or was hit by) every collider.
        for (k, phi) in closest.iter().enumerate() {
            assert!(*phi < 1e-3, "{name}: never touched collider {k} ({phi} m)");
        }

        // The reference, frame by frame.
        let mut reference = ReferenceBackend::new(&model, &params).unwrap();
        let mut worst_volume = 0.0f64;
        let mut reference_contacts = Vec::new();
        for (frame, got) in volumes.iter().enumerate() {
            reference.step_frame().unwrap();
            let sample = reference.volume().unwrap();
            reference_contacts.push(gpu_support::contact_of(&sample, "cpu-ref"));
            let want = 100.0 * sample.volume / rest;
            worst_volume = worst_volume.max((got - want).abs());
            assert!(
                (got - want).abs() <= VOLUME_POINTS,
                "{name}: frame {frame}: volume {got:.5} % vs reference {want:.5} %"
            );
        }
        let expected = reference.state().unwrap();
        let worst = common::max_distance(&gpu_state.positions, &expected.positions);
        println!(
            "{name}: worst volume difference {worst_volume:.2e} points, worst position \
             difference {:.2e} of the diagonal, closest approach per collider {closest:?} m",
            worst / diag
        );
        assert!(
            worst <= POSITION_FRACTION * diag,
            "{name}: a node is {worst} m from the reference (diagonal {diag} m)"
        );
        // The contact series: the same pushed nodes every frame (a node whose push is within
        // f32 rounding of zero may flip: COUNT_SLACK), the deepest penetration within the
        // position tolerance (a distance moves no more than the point does).
        let diff = gpu_support::contact_difference(&contacts, &reference_contacts);
        let peaks = gpu_support::contact_peaks(&reference_contacts);
        println!("{name}: contact series vulkan vs cpu-ref {diff:?}; cpu-ref's peaks {peaks:?}");
        assert!(
            diff.collider_nodes <= COUNT_SLACK && diff.body_contacts == 0,
            "{name}: pushed nodes differ by {} in a frame",
            diff.collider_nodes
        );
        assert!(
            diff.deepest_m <= POSITION_FRACTION * diag,
            "{name}: deepest penetration differs by {} m",
            diff.deepest_m
        );
        // Not vacuous: many nodes were pushed in some frame.
        assert!(
            peaks.collider_nodes >= 5,
            "{name}: at most {} nodes pushed",
            peaks.collider_nodes
        );
        deepest = deepest.max(peaks.deepest_m / (POSITION_FRACTION * diag));
    }
    // Not vacuous either: a node ended some frame inside a collider (the torus's sampled
    // distance) by more than twice the tolerance of the deepest penetration.
    assert!(
        deepest > 2.0,
        "deepest penetration {deepest} position tolerances"
    );
}

/// Largest allowed difference after one frame from the same state, as a fraction of the
/// bounding-box diagonal: f32 rounding of one frame (the states above may part more by the
/// end of a run; this check does not let differences compound).
const ONE_FRAME_FRACTION: f64 = 1e-6;

/// Every frame of every scene, stepped once on `cpu-ref` from the GPU's own state, lands
/// where the GPU's frame does. Unlike the end-of-run comparison above, a difference cannot
/// compound here: the first frame whose contact the GPU solves differently fails, naming
/// the node, where it was against each collider, and how both backends moved it.
#[test]
fn each_frame_from_the_gpu_state_matches_the_reference() {
    if !gpu_support::vulkan_available() {
        return;
    }
    for (name, model, params, frames) in scenes() {
        let diag = model.bounds_diagonal();
        let frame_time = params.frame_time();
        let mut gpu = gpu_support::validated(&model, &params);
        let mut reference = ReferenceBackend::new(&model, &params).unwrap();
        let mut worst = (0.0f64, 0u32);
        for frame in 0..frames {
            let start = gpu.state().unwrap();
            reference.set_state(&start).unwrap();
            reference.step_frame().unwrap();
            gpu.step_frame().unwrap();
            let (got, want) = (gpu.state().unwrap(), reference.state().unwrap());
            let (gap, node) = (got.positions.iter().zip(&want.positions))
                .map(|(a, b)| a.distance(*b))
                .enumerate()
                .fold(
                    (0.0f64, 0usize),
                    |a, (i, d)| if d > a.0 { (d, i) } else { a },
                );
            if gap > worst.0 {
                worst = (gap, frame);
            }
            if gap > ONE_FRAME_FRACTION * diag {
                let t0 = f64::from(frame) * frame_time;
                let t1 = t0 + frame_time;
                let against = |x: DVec3, t: f64| -> Vec<String> {
                    (model.colliders.iter())
                        .map(|c| {
                            let (phi, n) = c.shape.distance(c.pose_at(t).invert(x));
                            format!("phi {phi:.3e} (r {}) local normal {n:.3}", c.thickness)
                        })
                        .collect()
                };
                panic!(
                    "{name}: frame {frame}: one frame from the same state moves node {node} \
                     {gap:.3e} m ({:.2e} of the diagonal) from cpu-ref's\n  start x {:.7} v {:.5} \
                     against the colliders at t0 {:?}\n  vulkan x {:.7} v {:.5} at t1 {:?}\n  \
                     cpu-ref x {:.7} v {:.5} at t1 {:?}",
                    gap / diag,
                    start.positions[node],
                    start.velocities[node],
                    against(start.positions[node], t0),
                    got.positions[node],
                    got.velocities[node],
                    against(got.positions[node], t1),
                    want.positions[node],
                    want.velocities[node],
                    against(want.positions[node], t1),
                );
            }
        }
        println!(
            "{name}: largest one-frame difference {:.2e} of the diagonal (frame {})",
            worst.0 / diag,
            worst.1
        );
        gpu_support::assert_no_validation_messages(&gpu);
    }
}

/// Two frames in flight, each with its own slot's poses written before its submit, give
/// bit for bit the frames waited for one by one (the gather path has no atomics), and the
/// same contact series.
#[test]
fn frames_in_flight_read_their_own_poses() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let (name, model, params, _) = scenes().swap_remove(1);
    let frames = 220;
    let mut stepped = gpu_support::validated(&model, &params);
    let mut stepped_contacts = Vec::new();
    for _ in 0..frames {
        stepped.step_frame().unwrap();
        let sample = stepped.volume().unwrap();
        stepped_contacts.push(gpu_support::contact_of(&sample, "stepped"));
    }
    let mut pipelined = gpu_support::validated(&model, &params);
    let mut pipelined_contacts = Vec::new();
    let mut collect = |gpu: &mut tetrasim::backend::vulkan::VulkanBackend| {
        let sample = gpu.collect_frame(true).unwrap().expect("a sample");
        pipelined_contacts.push(gpu_support::contact_of(&sample, "pipelined"));
    };
    pipelined.submit_frame().unwrap();
    for _ in 1..frames {
        pipelined.submit_frame().unwrap();
        collect(&mut pipelined);
    }
    collect(&mut pipelined);
    assert_eq!(pipelined.max_frames_in_flight(), 2);
    let (a, b) = (stepped.state().unwrap(), pipelined.state().unwrap());
    assert_eq!(a, b, "{name}: same final state, bit for bit");
    // Each frame's contact measures come from its own slot's copy of the status.
    assert_eq!(
        stepped_contacts, pipelined_contacts,
        "{name}: contact series"
    );
    assert!(stepped_contacts.iter().any(|c| c.collider_nodes > 0));
    // Not vacuous: by then the capsule has hit the sphere and pushed it along +X.
    let mean_x = |p: &[DVec3]| p.iter().map(|x| x.x).sum::<f64>() / p.len() as f64;
    let pushed = mean_x(&a.positions) - mean_x(&model.positions);
    assert!(
        pushed > 0.005,
        "{name}: the sphere moved {pushed} m along X"
    );
    gpu_support::assert_no_validation_messages(&stepped);
    gpu_support::assert_no_validation_messages(&pipelined);
}
