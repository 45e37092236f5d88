//! `cpu`'s coarse level of the finite elements' preconditioner on the team (`cpu-ref`'s in
//! `backend/cpu/reference/elastic.rs`; [`crate::physics::CoarseSpace`]): its assembly once
//! per step and its correction in every iteration, the same bits on a team of any size.

use std::ops::Range;

use super::iterations::Inputs;
use super::newton::NewtonShared;
use crate::backend::cpu::team::Member;
use crate::physics::{sym3_apply, NO_AGGREGATE};
use crate::schedule::family::ElasticNodes;

/// The coarse level of the step's first linearisation (`cpu-ref`'s): the leader sets out
/// its modes, each member fills the six columns of its block of aggregates (the same sums
/// in the same order on a team of any size), and the leader assembles and factors the
/// matrix. Three phases; the last ends with a wait.
///
/// # Safety
/// As [`super::elastic::iteration`], after a wait that ended the writes of `at`, the
/// stiffnesses and `held`.
pub(super) unsafe fn coarse_level(
    member: &Member<'_>,
    inputs: &Inputs<'_>,
    cg: &NewtonShared<'_>,
    family: &ElasticNodes<f32>,
) {
    if member.leads() {
        // SAFETY: nobody else touches the coarse level; nobody writes `at`.
        unsafe { cg.coarse.part(0..1)[0] = family.coarse_space(cg.at.whole()) };
    }
    member.wait();
    let own = member.block(family.aggregates.len());
    // SAFETY: nobody writes the coarse level, `at`, the stiffnesses or `held`; these
    // aggregates' columns are this member's.
    unsafe {
        let coarse = &cg.coarse.whole()[0];
        let n = coarse.unknowns();
        let (at, linear, held) = (cg.at.whole(), cg.linear.whole(), cg.held.whole());
        let columns = cg.columns.part(6 * n * own.start..6 * n * own.end);
        for (a, columns) in own.zip(columns.chunks_mut(6 * n)) {
            let (tets, dt) = (inputs.tets, inputs.k.dt);
            family.coarse_columns(coarse, a, tets, at, linear, held, dt, columns);
        }
    }
    member.wait();
    if member.leads() {
        // SAFETY: nobody else touches the coarse level or writes the columns.
        unsafe { cg.coarse.part(0..1)[0].assemble(cg.columns.whole()) };
    }
    member.wait();
}

/// The two-level preconditioner (`cpu-ref`'s `precondition`): `z = D^-1 r + P A_c^-1 P^T r`
/// at this member's `nodes`. Each member restricts `r` to its block of aggregates (their
/// nodes in order), then, after a wait, solves the coarse system itself (the same bits on
/// every member) and writes its nodes' `z`. One phase and the start of the next.
///
/// # Safety
/// As [`super::elastic::iteration`], after a wait that ended the writes of `r`; `nodes`
/// this member's.
pub(super) unsafe fn precondition(
    member: &Member<'_>,
    cg: &NewtonShared<'_>,
    family: &ElasticNodes<f32>,
    nodes: Range<usize>,
) {
    let aggregates = &family.aggregates;
    let own = member.block(aggregates.len());
    // SAFETY: nobody writes `r`, `at` or the coarse level; these aggregates' sums are this
    // member's.
    unsafe {
        let (r, at, coarse) = (cg.r.whole(), cg.at.whole(), &cg.coarse.whole()[0]);
        let touches = cg.touching.whole();
        let sums = cg.restricted.part(6 * own.start..6 * own.end);
        for (a, sum) in own.clone().zip(sums.chunks_mut(6)) {
            sum.fill(0.0);
            for &i in aggregates.members[a]
                .iter()
                .filter(|&&i| !touches[i as usize])
            {
                let (x, residual) = (at[i as usize].as_dvec3(), r[i as usize].as_dvec3());
                let share = coarse.restrict(a, x, residual);
                sum.iter_mut().zip(share).for_each(|(s, x)| *s += x);
            }
        }
    }
    member.wait();
    // SAFETY: nobody writes the sums, `r`, `at` or the inverse blocks until the next wait;
    // these nodes' `z` are this member's.
    unsafe {
        let coarse = &cg.coarse.whole()[0];
        let mut u = cg.restricted.whole().to_vec();
        coarse.solve(&mut u);
        let (r, at, inverse) = (cg.r.whole(), cg.at.whole(), cg.inverse.whole());
        let touches = cg.touching.whole();
        let z = cg.z.part(nodes.clone());
        for (j, i) in nodes.enumerate() {
            z[j] = sym3_apply(inverse[i], r[i]);
            if let Some(a) = Some(aggregates.of[i]).filter(|&a| a != NO_AGGREGATE && !touches[i]) {
                z[j] += coarse.prolong(a as usize, at[i].as_dvec3(), &u).as_vec3a();
            }
        }
    }
}
