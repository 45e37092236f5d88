//! The schedule's unit tests: the order of a step's dispatches and what each stage touches.

use super::*;
use crate::params::{ContactMode, Method, SimParams, Solver, SpringKind};
use crate::physics::Solve;

fn sweeps() -> Vec<SweepPlan> {
    vec![
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
    ]
}

fn names(schedule: &Schedule, dispatches: &[Dispatch]) -> Vec<&'static str> {
    (dispatches.iter())
        .map(|d| schedule.stages[d.stage].kind.name())
        .collect()
}

#[test]
fn a_step_unrolls_iterations_sweeps_and_groups_in_order() {
    let params = SimParams {
        springs: SpringKind::Implicit,
        iterations: 2,
        ..SimParams::default()
    };
    let schedule = Schedule::new(&params, sweeps(), true, false);
    let step = schedule.step();
    let per_iteration = [
        ["spring_constraint", "constraint_apply"].repeat(2),
        ["volume", "constraint_apply"].repeat(3),
        vec!["global_volume_sum", "global_volume"],
    ]
    .concat();
    let expected = [
        vec!["global_volume_prepare"],
        per_iteration.clone(),
        per_iteration,
        vec!["integrate"],
    ]
    .concat();
    assert_eq!(names(&schedule, &step), expected);
    // Groups are numbered over all sweeps and carry their range within their sweep.
    let groups: Vec<GroupAt> = step.iter().filter_map(|d| d.group).step_by(2).collect();
    assert_eq!(groups.len(), 2 * 5);
    assert_eq!(
        (groups[1].index, groups[1].first, groups[1].count),
        (1, 20, 10)
    );
    assert_eq!(
        (
            groups[4].sweep,
            groups[4].group,
            groups[4].index,
            groups[4].first
        ),
        (1, 2, 4, 9)
    );
    assert_eq!(step.last().and_then(|d| d.iteration), None);
    assert_eq!(step[step.len() - 2].iteration, Some(1));
    assert_eq!(
        schedule
            .frame_end()
            .map(|i| schedule.stages[i].kind)
            .collect::<Vec<_>>(),
        [PassKind::Check]
    );
}

#[test]
fn what_a_scene_does_not_use_is_not_scheduled() {
    // The paper's Jacobi with explicit springs: atomics, no gather, no global constraint.
    let params = SimParams {
        method: Method::Volume,
        solver: Solver::Jacobi,
        ..SimParams::default()
    };
    let volume = vec![SweepPlan {
        kind: ConstraintKind::Volume,
        groups: vec![12],
        blocks: None,
    }];
    let jacobi = Schedule::new(&params, volume.clone(), true, true);
    assert!(!jacobi.gather && jacobi.chebyshev.is_empty());
    assert!(jacobi.runs(PassKind::SpringScatter) && !jacobi.runs(PassKind::SpringGather));
    assert!(!jacobi.runs(PassKind::GlobalVolume), "Jacobi leaves it off");
    let solve = &jacobi.stages[1];
    assert_eq!((solve.kind, solve.domain), (PassKind::Volume, Domain::Tets));
    assert!(solve.touches(BufferId::ConstraintSum) && !solve.touches(BufferId::Contributions));
    assert!(jacobi.runs(PassKind::VolumeSum));
    // mss: no constraint stages at all; the springs gathered per node for mss-node.
    let mss = SimParams {
        method: Method::MssNode,
        ..SimParams::default()
    };
    let mss = Schedule::new(&mss, Vec::new(), false, false);
    assert_eq!(
        names(&mss, &mss.step()),
        ["spring_gather", "integrate"],
        "springs, then integration"
    );
    // Chebyshev weights one entry per iteration and its apply keeps the forces before.
    let chebyshev = SimParams {
        method: Method::Volume,
        solver: Solver::Chebyshev,
        ..SimParams::default()
    };
    let chebyshev = Schedule::new(&chebyshev, volume, false, false);
    assert_eq!(chebyshev.chebyshev.len(), chebyshev.iterations as usize);
    assert_eq!(chebyshev.chebyshev_weight(0), 1.0);
    let apply = chebyshev
        .stages
        .iter()
        .find(|s| s.kind == PassKind::ConstraintApply);
    assert!(apply.is_some_and(|s| s.writes().any(|b| b == BufferId::ChebyshevBefore)));
}

#[test]
fn split_contact_solves_twice_velocity_first() {
    let combined = SimParams {
        springs: SpringKind::Implicit,
        ..SimParams::default()
    };
    let split = SimParams {
        contact: ContactMode::Split,
        ..combined.clone()
    };
    let one = Schedule::new(&combined, sweeps(), true, false);
    let two = Schedule::new(&split, sweeps(), true, false);
    assert!(!one.runs(PassKind::SplitVelocity));
    let (once, twice) = (one.step(), two.step());
    let solve = once.len() - 1; // all but integrate
    assert_eq!(
        twice.len(),
        2 * solve + 2,
        "the solve twice, split_velocity, integrate"
    );
    let velocity = &twice[..solve + 1];
    assert!(velocity.iter().all(|d| d.solve == Solve::Velocity));
    assert!(twice[solve + 1..].iter().all(|d| d.solve == Solve::Full));
    assert_eq!(names(&two, &velocity[..solve]), names(&one, &once[..solve]));
    assert_eq!(names(&two, &velocity[solve..]), ["split_velocity"]);
    assert_eq!(names(&two, &twice[solve + 1..]), names(&one, &once));
    assert_eq!(two.solves_running(PassKind::Volume), 2);
    assert_eq!(two.solves_running(PassKind::Integrate), 1);
    assert_eq!(one.solves_running(PassKind::Volume), 1);
}

#[test]
fn anderson_ends_every_iteration_after_the_global_volume_and_body_contact() {
    let params = SimParams {
        springs: SpringKind::Implicit,
        iterations: 2,
        anderson: 5,
        ..SimParams::default()
    };
    let schedule = Schedule::new(&params, sweeps(), true, false).with_body_contact(true);
    assert_eq!(schedule.anderson, 5);
    let step = schedule.step();
    let ends: Vec<(&str, Option<u32>)> = (step.iter())
        .filter(|d| d.group.is_none() && d.iteration.is_some())
        .map(|d| (schedule.stages[d.stage].kind.name(), d.iteration))
        .collect();
    let end = |i| {
        [
            ("global_volume_sum", Some(i)),
            ("global_volume", Some(i)),
            ("contact_solve", Some(i)),
            ("contact_apply", Some(i)),
            ("anderson_sum", Some(i)),
            ("anderson_mix", Some(i)),
        ]
    };
    assert_eq!(ends, [end(0), end(1)].concat());
    let sum = schedule
        .stages
        .iter()
        .find(|s| s.kind == PassKind::AndersonSum);
    assert!(sum.is_some_and(|s| s.writes().any(|b| b == BufferId::AndersonSums)));
    // Off by default, and nothing to accelerate without constraint iterations.
    let plain = Schedule::new(&SimParams::default(), sweeps(), true, false);
    assert!(!plain.runs(PassKind::AndersonSum) && plain.anderson == 0);
    let mss = SimParams {
        method: Method::Mss,
        anderson: 5,
        ..SimParams::default()
    };
    let mss = Schedule::new(&mss, Vec::new(), false, false);
    assert!(!mss.runs(PassKind::AndersonMix) && mss.anderson == 0);
}

#[test]
fn inversion_sweeps_follow_the_iterations_group_by_group() {
    let params = SimParams {
        springs: SpringKind::Implicit,
        iterations: 2,
        anderson: 3,
        inversion_sweeps: 2,
        ..SimParams::default()
    };
    let schedule = Schedule::new(&params, sweeps(), true, false);
    let step = schedule.step();
    let names = names(&schedule, &step);
    let last_mix = names.iter().rposition(|&n| n == "anderson_mix").unwrap();
    // After the last iteration: the volume sweep's three groups, each applied, then the
    // global volume constraint, twice.
    let round = [
        ["inversion_floor", "constraint_apply"].repeat(3),
        vec!["global_volume_sum", "global_volume"],
    ]
    .concat();
    let restore = round.repeat(2);
    assert_eq!(
        names[last_mix + 1..],
        [&restore[..], &["integrate"]].concat()
    );
    let floors: Vec<&Dispatch> = (step.iter())
        .filter(|d| schedule.stages[d.stage].kind == PassKind::InversionFloor)
        .collect();
    // The volume sweep's groups (index over all sweeps: 2, 3, 4) as further iterations.
    let at: Vec<(u32, u32, Option<u32>)> = (floors.iter())
        .map(|d| (d.group.unwrap().index, d.group.unwrap().first, d.iteration))
        .collect();
    assert_eq!(
        at,
        [
            (2, 0, Some(2)),
            (3, 5, Some(2)),
            (4, 9, Some(2)),
            (2, 0, Some(3)),
            (3, 5, Some(3)),
            (4, 9, Some(3)),
        ]
    );
    assert_eq!(schedule.restore_groups(), 6);
    assert_eq!(schedule.iteration_ends(PassKind::GlobalVolume), 4);
    assert_eq!(schedule.iteration_ends(PassKind::AndersonMix), 2);
    // Off by default, and nothing to sweep without volume constraints.
    let plain = Schedule::new(&SimParams::default(), sweeps(), true, false);
    assert!(!plain.runs(PassKind::InversionFloor) && plain.restore_groups() == 0);
    let springs_only = vec![sweeps().remove(0)];
    let none = Schedule::new(&params, springs_only, false, false);
    assert!(!none.runs(PassKind::InversionFloor) && none.inversion_sweeps == 0);
}

#[test]
fn names_are_shader_stems_in_execution_order() {
    for (i, k) in PassKind::ALL.iter().enumerate() {
        assert_eq!(*k as usize, i, "ALL is in declaration order");
        assert_eq!(k.shader(), format!("passes/{}.comp", k.name()));
        assert_eq!(PassKind::from_name(k.name()), Some(*k));
    }
    assert_eq!(PassKind::from_name("nope"), None);
}

#[test]
fn minres_follows_the_iterations_before_the_inversion_sweeps() {
    let params = SimParams {
        springs: SpringKind::Implicit,
        iterations: 2,
        minres: 3,
        inversion_sweeps: 1,
        ..SimParams::default()
    };
    let schedule = Schedule::new(&params, sweeps(), true, false);
    let step = schedule.step();
    let names = names(&schedule, &step);
    let setup = names.iter().position(|&n| n == "minres_setup").unwrap();
    let iteration = ["minres_nodes", "minres_product"];
    let minres = [
        &["minres_setup", "minres_rows"][..],
        &iteration.repeat(3),
        &["minres_next", "minres_finish", "minres_forces"],
    ]
    .concat();
    assert_eq!(names[setup..setup + minres.len()], minres);
    assert_eq!(
        names[setup - 1],
        "global_volume",
        "after the last iteration"
    );
    assert_eq!(names[setup + minres.len()], "inversion_floor");
    // The passes around the iterations carry the iteration count, the iterations their own.
    let carried: Vec<Option<u32>> = step[setup..setup + minres.len()]
        .iter()
        .map(|d| d.iteration)
        .collect();
    let mut want = vec![Some(2), Some(2)];
    want.extend((0..3).flat_map(|k| [Some(k); 2]));
    want.extend([Some(2), Some(2), Some(2)]);
    assert_eq!(carried, want);
    // The rows are the springs', the tets' and the global constraints'.
    assert_eq!(MinresRowKinds::of(&schedule.sweeps, true).variant(), "svg");
    // None without constraint sweeps, or with `minres` 0.
    let off = Schedule::new(&SimParams::default(), sweeps(), true, false);
    assert!(!off.stages.iter().any(|s| s.kind.is_minres()));
    let bare = Schedule::new(&params, Vec::new(), false, false);
    assert!(!bare.stages.iter().any(|s| s.kind.is_minres()));
}

#[test]
fn minres_without_inversion_sweeps_closes_with_the_global_volume() {
    let params = SimParams {
        iterations: 2,
        minres: 3,
        ..SimParams::default()
    };
    let schedule = Schedule::new(&params, sweeps(), true, false);
    assert!(schedule.closes_minres());
    let step = schedule.step();
    let names = names(&schedule, &step);
    let forces = names.iter().position(|&n| n == "minres_forces").unwrap();
    assert_eq!(
        names[forces + 1..forces + 4],
        ["global_volume_sum", "global_volume", "integrate"]
    );
    assert!(step[forces + 1..forces + 3]
        .iter()
        .all(|d| d.iteration == Some(2)));
    let runs = |kind| names.iter().filter(|&&n| n == PassKind::name(kind)).count() as u32;
    for kind in [PassKind::GlobalVolumeSum, PassKind::GlobalVolume] {
        assert_eq!(schedule.iteration_ends(kind), 3);
        assert_eq!(runs(kind), 3);
    }
    // Inversion sweeps end with the global constraints already; without them, or without
    // MINRES, nothing closes.
    let swept = SimParams {
        inversion_sweeps: 1,
        ..params.clone()
    };
    let swept = Schedule::new(&swept, sweeps(), true, false);
    assert!(!swept.closes_minres());
    assert_eq!(swept.iteration_ends(PassKind::GlobalVolume), 3);
    let forces = (swept.step().iter())
        .position(|d| swept.stages[d.stage].kind == PassKind::MinresForces)
        .unwrap();
    assert_eq!(
        swept.stages[swept.step()[forces + 1].stage].kind,
        PassKind::InversionFloor
    );
    let local = Schedule::new(&params, sweeps(), false, false);
    assert!(!local.closes_minres() && !local.runs(PassKind::GlobalVolume));
    let plain = Schedule::new(&SimParams::default(), sweeps(), true, false);
    assert!(!plain.closes_minres());
    assert_eq!(plain.iteration_ends(PassKind::GlobalVolume), 10);
}
