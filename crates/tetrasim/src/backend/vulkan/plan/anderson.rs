//! The sizes of Anderson acceleration's passes and buffers (`anderson > 0`): its chunks of
//! nodes (one workgroup each, as the global passes) and the multipliers it mixes.

use super::{PlanCounts, GLOBAL_WORKGROUP};
use crate::model::ConstraintKind;
use crate::schedule::Schedule;

/// The Gram terms each Anderson chunk keeps room for (those of the largest memory).
pub(super) const ANDERSON_TERMS: u64 =
    crate::physics::gram_terms(crate::physics::ANDERSON_MAX_MEMORY as usize) as u64;

/// The chunks (workgroups) of Anderson's passes over `nodes` nodes for passes of
/// `workgroup_size` invocations.
pub fn anderson_chunks(nodes: u32, workgroup_size: u32) -> u32 {
    nodes.div_ceil(workgroup_size.min(GLOBAL_WORKGROUP)).max(1)
}

/// The multipliers Anderson mixes: every spring's when a sweep solves springs (implicit
/// springs are compliant), every tet's when one solves volumes and some are compliant (a
/// hard constraint never reads its multiplier).
pub(super) fn mixed_multipliers(schedule: &Schedule, counts: PlanCounts) -> (u32, u32) {
    let has = |kind| schedule.sweeps.iter().any(|w| w.kind == kind);
    let springs = has(ConstraintKind::Spring);
    let tets = has(ConstraintKind::Volume) && schedule.anderson_volumes;
    (
        if springs { counts.springs } else { 0 },
        if tets { counts.tets } else { 0 },
    )
}
