//! The plan's unit tests: what a scene builds, and what it leaves out.

use super::*;
use crate::params::Solver;
use crate::schedule::Domain;

pub(super) const COUNTS: PlanCounts = PlanCounts {
    nodes: 10,
    springs: 30,
    tets: 12,
    colliders: 0,
    grid_values: 0,
    clamps: 0,
    clamped: 0,
    grabbed: 0,
    compliant_tets: 12,
};

/// One volume sweep in two colour groups of 7 and 5 tets (the model's 12).
pub(super) fn volume_sweep() -> [SweepPlan; 1] {
    [SweepPlan {
        kind: ConstraintKind::Volume,
        groups: vec![7, 5],
        blocks: None,
    }]
}

/// One object's global volume constraint over 8 surface nodes and 12 faces.
pub(super) const ONE_OBJECT: GlobalCounts = GlobalCounts {
    objects: 1,
    nodes: 8,
    faces: 12,
    largest: 12,
    largest_nodes: 8,
};

pub(super) fn plan(params: &SimParams, sweeps: &[SweepPlan]) -> EnginePlan {
    EnginePlan::new(COUNTS, params, 64, false, sweeps, None)
}

#[test]
fn implicit_springs_sweep_before_the_volumes_and_share_the_gather_buffers() {
    let params = SimParams {
        springs: SpringKind::Implicit,
        global_volume: Some(false),
        ..SimParams::default()
    };
    let sweeps = [
        SweepPlan {
            kind: ConstraintKind::Spring,
            groups: vec![20, 10],
            blocks: None,
        },
        SweepPlan {
            kind: ConstraintKind::Volume,
            groups: vec![5, 4, 3],
            blocks: None,
        },
    ];
    let p = plan(&params, &sweeps);
    assert_eq!(
        p.pass_list(),
        [
            "10 x (2 groups x (spring_constraint#gather, constraint_apply#gather[floor]), \
             3 groups x (volume#gather, constraint_apply#gather[floor]))",
            "integrate[floor]",
            "check",
        ]
    );
    assert!(!p.runs(PassKind::SpringGather) && !p.runs(PassKind::SpringScatter));
    assert!(!p.has(BufferId::NodeSpringOffsets));
    let (n, s, t) = (10, 30, 12);
    for (id, bytes) in [
        (BufferId::Degrees, 4 * 5 * n),
        (BufferId::GroupMembers, 4 * (s + t)),
        (BufferId::Contributions, 16 * (2 * s + 4 * t)),
        (BufferId::NodeSlotOffsets, 4 * (5 * n + 1)),
        (BufferId::NodeSlotItems, 4 * (2 * s + 4 * t)),
        (BufferId::SpringDamping, 4 * s),
        (BufferId::VolumeCompliance, 4 * t),
        (BufferId::SpringMultipliers, 4 * s),
        (BufferId::VolumeMultipliers, 4 * t),
    ] {
        assert_eq!(p.buffer(id).map(|b| b.bytes), Some(bytes), "{id:?}");
    }
    assert_eq!(p.sweep_offsets(0), SweepOffsets::default());
    assert_eq!(
        p.sweep_offsets(1),
        SweepOffsets {
            group: 2,
            member: 30,
            slot: 60,
            block: 0
        }
    );
    // Per iteration: 2 spring groups and 3 volume groups, each with its apply.
    assert_eq!(p.dispatches_per_frame(), 10 * 2 * 5 + 2);
}

#[test]
fn implicit_springs_alone_are_a_jacobi_sweep_without_a_force_pass() {
    let params = SimParams {
        method: Method::Mss,
        springs: SpringKind::Implicit,
        solver: Solver::Jacobi,
        ..SimParams::default()
    };
    let sweeps = [SweepPlan {
        kind: ConstraintKind::Spring,
        groups: vec![30],
        blocks: None,
    }];
    let p = plan(&params, &sweeps);
    assert_eq!(
        p.pass_list(),
        [
            "10 x (spring_constraint, constraint_apply#sums[floor])",
            "integrate[floor]",
            "check"
        ]
    );
    assert_eq!(p.buffer(BufferId::Degrees).map(|b| b.bytes), Some(40));
    assert!(p.has(BufferId::ConstraintSum) && !p.has(BufferId::VolumeCompliance));
    assert_eq!(
        p.buffer(BufferId::SpringMultipliers).map(|b| b.bytes),
        Some(4 * 30)
    );
    assert!(!p.has(BufferId::VolumeMultipliers));
    assert!(p.render().starts_with("method mss with implicit springs:"));
}

#[test]
fn warm_started_implicit_springs_gather_their_stored_forces_before_the_iterations() {
    let params = SimParams {
        method: Method::Mss,
        springs: SpringKind::Implicit,
        warm_start: true,
        solver: Solver::Jacobi,
        ..SimParams::default()
    };
    let sweeps = [SweepPlan {
        kind: ConstraintKind::Spring,
        groups: vec![30],
        blocks: None,
    }];
    let p = plan(&params, &sweeps);
    assert!(p.schedule.warm_start);
    assert_eq!(
        p.pass_list(),
        [
            "spring_warm_start",
            "10 x (spring_constraint, constraint_apply#sums[floor])",
            "integrate[floor]",
            "check"
        ]
    );
    assert_eq!(
        p.buffer(BufferId::NodeSpringOffsets).map(|b| b.bytes),
        Some(4 * 11)
    );
    assert_eq!(
        p.buffer(BufferId::NodeSpringItems).map(|b| b.bytes),
        Some(4 * 60)
    );
    assert!(!p.runs(PassKind::SpringGather) && !p.runs(PassKind::SpringScatter));
    assert_eq!(p.dispatches_per_frame(), 1 + 10 * 2 + 2);
    assert!(p
        .render()
        .starts_with("method mss with warm-started implicit springs:"));
    // Warm start means nothing to explicit springs.
    let explicit = plan(
        &SimParams {
            springs: SpringKind::Explicit,
            ..params
        },
        &[],
    );
    assert!(!explicit.schedule.warm_start && !explicit.runs(PassKind::SpringWarmStart));
}

#[test]
fn colliders_add_their_buffers_variants_and_count_only_when_there_are_some() {
    let params = SimParams {
        solver: Solver::GaussSeidel,
        substeps: 4,
        ..SimParams::default()
    };
    let sweeps = volume_sweep();
    let global = ONE_OBJECT;
    let collider_buffers = [
        BufferId::ColliderContacts,
        BufferId::Colliders,
        BufferId::ColliderGrids,
        BufferId::ColliderPoses,
    ];
    let without = EnginePlan::new(COUNTS, &params, 64, false, &sweeps, Some(global));
    for id in collider_buffers {
        assert!(!without.has(id), "{id:?} without colliders");
    }
    assert_eq!(without.schedule.colliders, 0);
    assert_eq!(without.upload_bytes(), 0);
    for pass in &without.passes {
        assert!(
            !pass.stage.touches(BufferId::ColliderContacts) && !pass.label().contains("collider"),
            "{}",
            pass.label()
        );
        let floor_constants = match (pass.stage.domain, pass.stage.kind) {
            (Domain::Surface, _) => 2,
            (_, kind) if kind.has_floor_constant() => 1,
            _ => 0,
        };
        assert_eq!(pass.constants.len(), floor_constants, "{}", pass.label());
    }
    assert!(!without.render().contains("collider poses"));

    let counts = PlanCounts {
        colliders: 3,
        grid_values: 100,
        ..COUNTS
    };
    let with = EnginePlan::new(counts, &params, 64, false, &sweeps, Some(global));
    let pose_row = 64 * 3 * 4;
    for (id, bytes, upload) in [
        (BufferId::ColliderContacts, 16 * 10, 0),
        (BufferId::Colliders, 64 * 3, 0),
        (BufferId::ColliderGrids, 4 * 100, 0),
        (
            BufferId::ColliderPoses,
            pose_row * u64::from(POSE_SLOTS),
            pose_row,
        ),
    ] {
        let b = with
            .buffer(id)
            .unwrap_or_else(|| panic!("{id:?} with colliders"));
        assert_eq!((b.bytes, b.upload_bytes), (bytes, upload), "{id:?}");
    }
    assert_eq!(with.upload_bytes(), pose_row);
    assert_eq!(
        with.device_bytes() - without.device_bytes(),
        // The grab buffers are 4-byte placeholders without grabs.
        16 * 10 + 64 * 3 + 4 * 100 + pose_row * u64::from(POSE_SLOTS) + 4 + 4
    );
    assert_eq!(
        with.pass_list(),
        [
            "spring_gather",
            "global_volume_prepare",
            "10 x (2 groups x (volume#gather, constraint_apply#gather_colliders[floor]), \
             global_volume_sum#colliders, global_volume#colliders[floor])",
            "integrate#colliders[floor]",
            "check",
        ]
    );
    for pass in &with.passes {
        if pass.stage.kind.has_floor_constant() {
            // The count follows the floor (and the global passes' chunks), then the
            // grabbed nodes' (none).
            let n = pass.constants.len();
            assert_eq!(pass.constants[n - 2..], [3, 0], "{}", pass.label());
            for id in collider_buffers {
                assert!(pass.stage.touches(id), "{} binds {id:?}", pass.label());
            }
        } else {
            // global_volume_sum reads the colliders' forces (the nodes they hold), and only
            // those.
            let reads = pass.stage.kind == PassKind::GlobalVolumeSum;
            assert_eq!(
                pass.stage.touches(BufferId::ColliderContacts),
                reads,
                "{}",
                pass.label()
            );
        }
    }
    // A dispatch reads its substep's poses only; the frame writes them once.
    assert!(with.bytes_per_frame() > without.bytes_per_frame() + pose_row);
    assert!(with.render().contains("write 768 B of collider poses"));
    let jacobi = EnginePlan::new(
        counts,
        &SimParams {
            solver: Solver::Jacobi,
            ..params
        },
        64,
        false,
        &sweeps,
        None,
    );
    assert!(jacobi
        .pass_list()
        .iter()
        .any(|p| p.contains("constraint_apply#sums_colliders[floor]")));
}

#[test]
fn contact_is_measured_per_frame_only_with_metrics_and_something_to_measure() {
    let params = SimParams::default();
    let sweeps = volume_sweep();
    let body = BodyCounts {
        nodes: 8,
        triangles: 12,
        buckets: 1024,
        capacity: 1024,
        thickness: 0.01,
        margin: 0.1,
    };
    let colliders = PlanCounts {
        colliders: 2,
        ..COUNTS
    };
    let grabs = PlanCounts {
        grabbed: 3,
        ..COUNTS
    };
    let plan = |counts, metrics, body| {
        EnginePlan::with_bodies(counts, &params, 64, metrics, &sweeps, None, body)
    };
    let status = |p: &EnginePlan| {
        p.buffer(BufferId::Status)
            .map(|b| (b.bytes, b.readback_bytes))
    };
    // Nothing to measure, or no per-frame metrics: the plan of before (16-byte status, no
    // pass).
    for p in [
        plan(COUNTS, true, None),
        plan(colliders, false, None),
        plan(COUNTS, false, Some(body)),
    ] {
        assert!(!p.measures_contact() && !p.runs(PassKind::ContactMeasure));
        assert_eq!(status(&p), Some((STATUS_BYTES, STATUS_BYTES)));
    }
    let without = plan(COUNTS, true, None);
    for (p, label, bindings, constants) in [
        (
            plan(colliders, true, None),
            "contact_measure#colliders",
            6,
            vec![2],
        ),
        (
            plan(COUNTS, true, Some(body)),
            "contact_measure#bodies",
            3,
            vec![],
        ),
        (
            plan(colliders, true, Some(body)),
            "contact_measure#colliders_bodies",
            7,
            vec![2],
        ),
    ] {
        assert!(p.measures_contact());
        assert_eq!(
            status(&p),
            Some((CONTACT_STATUS_BYTES, CONTACT_STATUS_BYTES))
        );
        let measure = (p.passes.iter())
            .find(|pass| pass.stage.kind == PassKind::ContactMeasure)
            .unwrap_or_else(|| panic!("{label}"));
        assert_eq!(measure.label(), label);
        assert_eq!(measure.stage.repeat, Repeat::Frame);
        assert_eq!(measure.stage.bindings.len(), bindings, "{label}");
        assert_eq!(measure.constants, constants, "{label}");
        assert_eq!(measure.elements, COUNTS.nodes);
        // After `check`, before `volume_sum` (and `reactions`): one dispatch per frame,
        // whose bytes count.
        let frame: Vec<String> = p.pass_list().into_iter().rev().take(4).collect();
        assert_eq!(frame, ["reactions", "volume_sum", label, "check"]);
        assert_eq!(p.runs_per_frame(measure), 1);
        assert!(p.pass_bytes(measure) > 16 * u64::from(COUNTS.nodes));
        // 16 more status bytes, and a partial for each collider more.
        let colliders = u64::from(p.schedule.colliders - without.schedule.colliders);
        let groups = u64::from(COUNTS.nodes.div_ceil(64));
        assert_eq!(
            p.readback_bytes(),
            without.readback_bytes() + 16 + 16 * colliders * groups
        );
    }
    // Grabs alone push no collider node and have no body contact: the contact words stay 0
    // without a pass.
    let p = plan(grabs, true, None);
    assert!(p.measures_contact() && !p.runs(PassKind::ContactMeasure));
    assert_eq!(
        status(&p),
        Some((CONTACT_STATUS_BYTES, CONTACT_STATUS_BYTES))
    );
}

#[test]
fn a_gather_over_many_slots_per_node_gets_lanes() {
    let params = SimParams {
        global_volume: Some(false),
        ..SimParams::default()
    };
    let apply = |sweeps: &[SweepPlan]| {
        let p = plan(&params, sweeps);
        let pass = (p.passes.iter())
            .find(|p| p.stage.kind == PassKind::ConstraintApply)
            .expect("an apply pass")
            .clone();
        (pass.lanes(), pass.elements, pass.constants)
    };
    // One group of 12 tets over 10 nodes: 4.8 slots a node, two lanes of at least 2 each.
    let one = [SweepPlan {
        kind: ConstraintKind::Volume,
        groups: vec![12],
        blocks: None,
    }];
    assert_eq!(apply(&one), (2, 2 * COUNTS.nodes, vec![1, 0, 0, 2]));
    // Six groups of 2: 0.8 slots a node, one lane, no constant.
    let six = [SweepPlan {
        kind: ConstraintKind::Volume,
        groups: vec![2; 6],
        blocks: None,
    }];
    assert_eq!(apply(&six), (1, COUNTS.nodes, vec![1]));
}

#[test]
fn block_sweeps_run_one_workgroup_per_block_with_their_rows_one_after_another() {
    use crate::schedule::BlockShape;
    let params = SimParams {
        springs: SpringKind::Implicit,
        global_volume: Some(false),
        block_size: 40,
        ..SimParams::default()
    };
    let shape = |blocks, nodes, largest| BlockShape {
        blocks,
        nodes,
        largest,
        colours: 7,
    };
    let sweeps = [
        SweepPlan {
            kind: ConstraintKind::Spring,
            groups: vec![30],
            blocks: Some(shape(1, 10, 30)),
        },
        SweepPlan {
            kind: ConstraintKind::Volume,
            groups: vec![12],
            blocks: Some(shape(2, 14, 7)),
        },
    ];
    let p = plan(&params, &sweeps);
    assert_eq!(
        p.pass_list(),
        [
            "10 x (spring_constraint#block, constraint_apply#gather[floor], volume#block, constraint_apply#gather[floor])",
            "integrate[floor]",
            "check"
        ]
    );
    let volume = (p.passes.iter())
        .find(|pass| pass.stage.kind == PassKind::Volume)
        .unwrap();
    // One invocation per tet of the largest block, a multiple of 32; one workgroup a block.
    assert_eq!((volume.workgroup_size, volume.elements), (32, 64));
    assert_eq!(p.block_shape(volume).map(|b| b.blocks), Some(2));
    assert_eq!(p.elements_per_dispatch(volume), 64);
    assert_eq!(
        p.sweep_offsets(1).block,
        1,
        "the volumes' rows follow the springs'"
    );
    assert_eq!(p.buffer(BufferId::BlockRows).map(|b| b.bytes), Some(16 * 3));
    assert_eq!(
        p.buffer(BufferId::BlockNodes).map(|b| b.bytes),
        Some(4 * 24)
    );
    assert_eq!(
        p.buffer(BufferId::BlockCorners).map(|b| b.bytes),
        Some(16 * 42)
    );
    // The cost model counts a block pass by its colours; one sweep per block, constant 2.
    let h200 = gpu_profile("NVIDIA H200").unwrap();
    let colour = h200.block_colour_ns * 1e-3;
    let once = h200.dispatch_us(&p, volume);
    assert!(once >= h200.dispatch_us + 7.0 * colour);
    assert_eq!(volume.constants, vec![0, 1]);
    // Swept three times: the constant says so, and the colours count three times.
    let thrice = plan(
        &SimParams {
            block_sweeps: 3,
            ..params.clone()
        },
        &sweeps,
    );
    let constants = |p: &EnginePlan, kind| {
        (p.passes.iter())
            .find(|pass| pass.stage.kind == kind)
            .map(|pass| pass.constants.clone())
            .unwrap()
    };
    assert_eq!(constants(&thrice, PassKind::SpringConstraint), vec![0, 3]);
    // The springs' blocks swept once while the volumes' are swept three times.
    let springs_once = plan(
        &SimParams {
            block_sweeps: 3,
            spring_block_sweeps: 1,
            ..params
        },
        &sweeps,
    );
    assert_eq!(
        constants(&springs_once, PassKind::SpringConstraint),
        vec![0, 1]
    );
    assert_eq!(constants(&springs_once, PassKind::Volume), vec![0, 3]);
    let volume = (thrice.passes.iter())
        .find(|pass| pass.stage.kind == PassKind::Volume)
        .unwrap();
    assert_eq!(volume.constants, vec![0, 3]);
    let swept = h200.dispatch_us(&thrice, volume);
    assert!(
        (swept - once - 14.0 * colour).abs() < 1e-9,
        "{swept} against {once}"
    );
}

#[test]
fn minres_builds_its_rows_buffers_and_passes_after_the_iterations() {
    let sweeps = volume_sweep();
    let global = ONE_OBJECT;
    let params = |minres| SimParams {
        method: Method::Volume,
        iterations: 2,
        minres,
        ..SimParams::default()
    };
    let off = EnginePlan::new(COUNTS, &params(0), 64, false, &sweeps, Some(global));
    let on = EnginePlan::new(COUNTS, &params(4), 64, false, &sweeps, Some(global));
    assert!(off.minres_counts().is_none());
    assert!(!off.has(BufferId::MinresTranspose));
    let m = on.minres_counts().expect("minres sizes");
    // 12 tet rows in one workgroup of 64, then the object's.
    assert_eq!(
        (m.tets, m.objects, m.rows(), m.workgroups()),
        (12, 1, 13, 2)
    );
    assert_eq!(m.entries(), 4 * 12 + 8);
    let bytes = |id| on.buffer(id).map(|b| b.bytes);
    assert_eq!(
        bytes(BufferId::MinresTranspose),
        Some(4 * (11 + 3 * 56 + 2))
    );
    assert_eq!(bytes(BufferId::MinresGrads), Some(16 * 56));
    assert_eq!(bytes(BufferId::MinresVectors), Some(4 * 10 * 13));
    assert_eq!(bytes(BufferId::MinresNodeVectors), Some(32 * 10));
    assert_eq!(bytes(BufferId::MinresSums), Some(4 * 3));
    assert_eq!(bytes(BufferId::MinresState), Some(64 * 5));
    // Setup, rows, 4 x 2 iteration passes, next, finish, forces, and the global volume's
    // close.
    assert_eq!(
        on.dispatches_per_frame() - off.dispatches_per_frame(),
        2 + 4 * 2 + 3 + 2
    );
    let step = on.step_list().join(" -> ");
    assert!(
        step.contains(
            "minres_setup -> minres_rows#vg -> 4 x (minres_nodes, minres_product) -> \
             minres_next -> minres_finish#v -> minres_forces[floor] -> global_volume_sum \
             -> global_volume[floor] -> integrate"
        ),
        "{step}"
    );
    let rows = on
        .passes
        .iter()
        .find(|p| p.name() == "minres_rows")
        .unwrap();
    assert_eq!((rows.workgroup_size, rows.elements), (64, 2 * 64));
    // Floor, colliders, grabs, no lanes, then the rows' segments, iterations and chunks.
    assert_eq!(rows.constants, vec![1, 0, 0, 0, 0, 0, 12, 1, 4, 1]);
    // The node passes share a node's entries (5.6 on average) between 2 lanes; the setup
    // has one invocation per node. `minres_nodes`' workgroups are also the row
    // workgroups that end the last iteration: 2 here, where its nodes need 1.
    for name in ["minres_forces", "minres_setup"] {
        let pass = on.passes.iter().find(|p| p.name() == name).unwrap();
        let lanes = if name == "minres_setup" { 1 } else { 2 };
        assert_eq!((pass.lanes(), pass.elements), (lanes, 10 * lanes), "{name}");
    }
    let nodes = on
        .passes
        .iter()
        .find(|p| p.name() == "minres_nodes")
        .unwrap();
    assert_eq!((nodes.lanes(), nodes.elements), (2, 2 * 64));
}
