//! Block Gauss-Seidel (`block_size`, docs/PHYSICS.md "Block Gauss-Seidel"): the volume
//! constraints swept in blocks, colour by colour within each block, Jacobi between blocks.
//!
//! - It converges like the colour groups it replaces and far better than the same sweep
//!   without blocks (one group, every tet against the iteration's forces), on a dropped box.
//! - Hubs (nodes with more than `HUB_DEGREE` tets) keep their forces within a block; a
//!   spinning top whose axis nodes carry 96 and 192 tets runs the same on every backend.
//!
//! - Thread blocks (larger than a workgroup, `cpu` backends only) have no node limit and no
//!   hubs, and converge further per sweep than workgroup blocks: on the same box, one
//!   thread block (Gauss-Seidel in one order) 0.0074 % against 0.0119 % for blocks of 1024
//!   (measured on `cpu`); `cpu` follows `cpu-ref` in two thread blocks, and `vulkan`
//!   refuses them with a message naming `block_size`.
//!
//! - A second sweep of each block per iteration (`block_sweeps`) converges further: on the
//!   same box, blocks of 256 swept twice leave less local error than swept once, and
//!   `cpu` and `vulkan` follow `cpu-ref` in them.
//!
//! The `cpu` backend's blocks run on its thread team with the same bits for any team size
//! (`backend/cpu/parallel/tests.rs`); the other backends follow `cpu-ref` with blocks in
//! `tests/backends_match_reference_settings.rs` too.

mod gpu_support;

use glam::DVec3;
use tetrasim::backend::cpu::{ParallelBackend, ReferenceBackend};
use tetrasim::mesh::grid::box_tets;
use tetrasim::mesh::order::spatially_ordered;
use tetrasim::model::HUB_DEGREE;
use tetrasim::params::Placement;
use tetrasim::problem::Problem;
use tetrasim::{Backend, Model, ModelBuilder, SimParams, TetMesh};

/// A box of 12 x 4 x 12 cells (6 tets each) in Morton order (as `tetprep` writes meshes:
/// the blocks are compact), dropped 5 cm onto the floor.
fn dropped_box() -> Model {
    let mesh = spatially_ordered(&box_tets(DVec3::ZERO, 0.1, [12, 4, 12]));
    ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.05),
        })
        .build()
        .unwrap()
}

/// Average over `frames` frames on `cpu` of the local volume error, in % of the rest volume.
fn local_error(model: &Model, params: &SimParams, frames: u32) -> f64 {
    let rest = model.total_rest_volume();
    let mut backend = ParallelBackend::new(model, params).unwrap();
    let mut sum = 0.0;
    for _ in 0..frames {
        backend.step_frame().unwrap();
        sum += backend.volume().unwrap().local_error / rest;
    }
    100.0 * sum / f64::from(frames)
}

#[test]
fn blocks_converge_like_colour_groups_and_better_than_one_group() {
    let model = dropped_box();
    let blocks = SimParams {
        block_size: 256,
        ..SimParams::default()
    };
    let one_group = SimParams {
        groups: 1,
        ..SimParams::default()
    };
    let frames = 200;
    let (b, g8, g1) = (
        local_error(&model, &blocks, frames),
        local_error(&model, &SimParams::default(), frames),
        local_error(&model, &one_group, frames),
    );
    println!("local error: blocks of 256 {b:.4} %, 8 colour groups {g8:.4} %, one group {g1:.4} %");
    assert!(b < 0.5 * g1, "blocks {b} % against one group {g1} %");
    assert!(b < 1.1 * g8, "blocks {b} % against 8 colour groups {g8} %");
}

/// A spinning top: a ring of 96 nodes around an axis of three nodes (top, centre, bottom),
/// 192 tets, each of the upper and lower cones a fan around the centre.
fn spinning_top() -> TetMesh {
    let ring = 96usize;
    let mut nodes = vec![
        DVec3::new(0.0, 0.6, 0.0),
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(0.0, -0.6, 0.0),
    ];
    for i in 0..ring {
        let a = std::f64::consts::TAU * i as f64 / ring as f64;
        nodes.push(DVec3::new(a.cos(), 0.0, a.sin()));
    }
    let volume = |t: &[u32; 4]| {
        let p = t.map(|k| nodes[k as usize]);
        (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]))
    };
    let mut tets = Vec::new();
    for i in 0..ring {
        let (a, b) = (3 + i as u32, 3 + ((i + 1) % ring) as u32);
        for apex in [0, 2] {
            let mut t = [apex, 1, a, b];
            if volume(&t) < 0.0 {
                t.swap(2, 3);
            }
            tets.push(t);
        }
    }
    TetMesh {
        nodes,
        tets,
        faces: Vec::new(),
    }
}

#[test]
fn hubs_run_the_same_on_every_backend() {
    let mesh = spinning_top();
    let model = ModelBuilder::new(&mesh)
        .placement(Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.02),
        })
        .build()
        .unwrap();
    let params = SimParams {
        block_size: 32,
        ..SimParams::default()
    };
    // Not vacuous: the axis nodes are hubs, in blocks of several colours.
    let problem = Problem::new(&model, &params).unwrap();
    let blocks = problem.sweeps[0].blocks.as_ref().expect("blocks");
    let hubs = blocks.hub.iter().filter(|&&h| h).count();
    assert_eq!(
        hubs, 3,
        "top, centre and bottom have more than {HUB_DEGREE} tets"
    );
    assert!(blocks.len() >= 6, "{} blocks", blocks.len());
    assert!(blocks.most_colours() >= 2);
    let want = every_backend_follows_the_reference(&model, &params, 60, "spinning top");
    let moved = (want.positions.iter().zip(&model.positions))
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f64::max);
    assert!(moved > 0.01, "it fell: {moved} m");
}

/// Runs `frames` frames on `cpu-ref`, then on `cpu` and `vulkan` (`for_each_backend`), each
/// within 1e-5 of the diagonal of `cpu-ref`'s positions; `cpu-ref`'s last state.
fn every_backend_follows_the_reference(
    model: &Model,
    params: &SimParams,
    frames: u32,
    what: &str,
) -> tetrasim::State {
    let mut reference = ReferenceBackend::new(model, params).unwrap();
    for _ in 0..frames {
        reference.step_frame().unwrap();
    }
    let want = reference.state().unwrap();
    let diag = model.bounds_diagonal();
    gpu_support::for_each_backend(model, params, |name, backend| {
        if name == "cpu-ref" {
            return;
        }
        for _ in 0..frames {
            backend.step_frame().unwrap();
        }
        let got = backend.state().unwrap();
        let worst = (got.positions.iter().zip(&want.positions))
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max);
        println!("{what}, {name}: {:.1e} diagonals", worst / diag);
        assert!(
            worst < 1e-5 * diag,
            "{what}, {name}: a node is {worst} m off"
        );
    });
    want
}

#[test]
fn thread_blocks_converge_further_on_the_cpu_backends_and_vulkan_refuses_them() {
    let model = dropped_box();
    let blocks = |block_size| SimParams {
        block_size,
        ..SimParams::default()
    };
    // One thread block is Gauss-Seidel in one order; two run on the `cpu` team at once.
    let (workgroup, whole, halves) = (blocks(1024), blocks(4096), blocks(2048));
    for (params, count) in [(&whole, 1), (&halves, 2)] {
        let problem = Problem::new(&model, params).unwrap();
        let cut = problem.sweeps[0].blocks.as_ref().expect("blocks");
        assert_eq!(cut.len(), count, "{} tets", model.tets.len());
    }
    let frames = 200;
    let (w, t) = (
        local_error(&model, &workgroup, frames),
        local_error(&model, &whole, frames),
    );
    println!("local error: blocks of 1024 {w:.4} %, one thread block {t:.4} %");
    assert!(
        t < 0.75 * w,
        "a thread block {t} % against workgroup blocks {w} %"
    );

    let mut reference = ReferenceBackend::new(&model, &halves).unwrap();
    let mut cpu = ParallelBackend::new(&model, &halves).unwrap();
    for _ in 0..60 {
        reference.step_frame().unwrap();
        cpu.step_frame().unwrap();
    }
    let (want, got) = (reference.state().unwrap(), cpu.state().unwrap());
    let worst = (got.positions.iter().zip(&want.positions))
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f64::max);
    let diag = model.bounds_diagonal();
    println!(
        "two thread blocks, cpu against cpu-ref: {:.1e} diagonals",
        worst / diag
    );
    assert!(worst < 1e-5 * diag, "cpu: a node is {worst} m off");

    if gpu_support::vulkan_available() {
        let options = tetrasim::backend::vulkan::EngineOptions::default();
        let refused = tetrasim::backend::vulkan::VulkanBackend::new(&model, &halves, &options);
        let message = refused
            .err()
            .expect("vulkan refuses thread blocks")
            .to_string();
        assert!(
            message.contains("block_size") && message.contains("thread blocks"),
            "{message}"
        );
    }
}

#[test]
fn a_second_sweep_per_block_converges_further_on_every_backend() {
    let model = dropped_box();
    let blocks = |block_sweeps| SimParams {
        block_size: 256,
        block_sweeps,
        ..SimParams::default()
    };
    let frames = 200;
    let (once, twice) = (
        local_error(&model, &blocks(1), frames),
        local_error(&model, &blocks(2), frames),
    );
    println!("local error, blocks of 256: swept once {once:.4} %, twice {twice:.4} %");
    assert!(twice < 0.8 * once, "twice {twice} % against once {once} %");

    every_backend_follows_the_reference(&model, &blocks(2), 60, "blocks swept twice");
}
