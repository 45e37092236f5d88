//! The finite elements' part of a plan (`neo-hookean`; docs/GPU.md, "Finite elements on the
//! GPU"): the sizes of the coarse level and of the objects, the buffers they take, and each
//! `elastic_*` pass's invocations, workgroup and specialisation constants.

use super::{device_only, BufferPlan, EnginePlan, PlanCounts, GLOBAL_WORKGROUP};
use crate::backend::vulkan::CoarseIndex;
use crate::physics::Aggregates;
use crate::schedule::{BufferId, PassKind};

/// Planes of a vec4 per node in `ElasticNodes` (`ELASTIC_PLANES`, glsl/physics/newton.glsl).
pub const ELASTIC_PLANES: u64 = 14;

/// Words of `ElasticState` before the node passes' partials (`ELASTIC_STATE_PARTIALS`).
pub const ELASTIC_STATE_WORDS: u64 = 16;

/// Steps the backtracking tries: a step and its halvings (`BACKTRACK_STEPS`).
pub const BACKTRACK_STEPS: u64 = 9;

/// Bytes of a coarse assembly item's 6 x 6 block (`COARSE_SCRATCH`).
pub const COARSE_ITEM_BYTES: u64 = 144;

/// Words per object of `ElasticObjects` (first node, end, free, held; centre, acceleration
/// and angular acceleration as vec4s).
pub const OBJECT_WORDS: u64 = 16;

/// The sizes the finite elements' buffers and passes follow.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ElasticCounts {
    /// Aggregates of the coarse level (0: block-Jacobi alone).
    pub aggregates: u32,
    /// Their nodes (every free node once).
    pub members: u32,
    /// Objects (a rigid-part correction workgroup each).
    pub objects: u32,
    /// Words of the coarse assembly's index ([`CoarseIndex::words`]).
    pub index_words: u32,
    /// Its scratch rows ([`CoarseIndex::scratch_rows`]).
    pub scratch_rows: u32,
}

impl ElasticCounts {
    /// The counts of `aggregates` and `index` on a model of `objects` objects.
    pub fn of(aggregates: &Aggregates, index: &CoarseIndex, objects: usize) -> Self {
        ElasticCounts {
            aggregates: aggregates.len() as u32,
            members: aggregates.members.iter().map(Vec::len).sum::<usize>() as u32,
            objects: objects as u32,
            index_words: index.words().len() as u32,
            scratch_rows: index.scratch_rows(aggregates) as u32,
        }
    }

    /// Unknowns of the coarse level (six per aggregate).
    pub fn unknowns(&self) -> u64 {
        6 * u64::from(self.aggregates)
    }
}

/// The workgroup of the finite elements' passes on a plan of `workgroup_size`: their node
/// passes' partials are summed per workgroup in shared memory, as the global passes' are.
pub fn elastic_workgroup(workgroup_size: u32) -> u32 {
    workgroup_size.min(GLOBAL_WORKGROUP)
}

/// The workgroup of `elastic_coarse_factor`, one workgroup whose invocations share the
/// factor's rows: the plan's finite-element workgroup, but at least 128 invocations (what
/// every Vulkan device allows), as with fewer an invocation's rows of the largest coarse
/// level (`MOST_AGGREGATES`, 384 unknowns) take near lavapipe's 65535 loop iterations, after
/// which it ends the invocation silently (glsl/common/coarse_dot.glsl).
pub fn coarse_factor_workgroup(workgroup_size: u32) -> u32 {
    elastic_workgroup(workgroup_size).max(128)
}

impl EnginePlan {
    /// The plan with the finite elements' sizes `e`: their buffers, and their passes'
    /// invocations, workgroup and constants. Nothing without the `elastic` pass.
    pub fn with_elastic(mut self, e: ElasticCounts) -> Self {
        if !self.runs(PassKind::Elastic) {
            return self;
        }
        let wg = elastic_workgroup(self.workgroup_size);
        self.elastic = Some(e);
        self.buffers.extend(elastic_buffers(self.counts, e, wg));
        let counts = self.counts;
        for pass in self.passes.iter_mut() {
            let kind = pass.stage.kind;
            if kind == PassKind::Integrate {
                // ELASTIC_WARM, constant 4: the next step starts from the elastic forces.
                pass.constants.resize(pass.constants.len().max(4), 0);
                pass.constants[3] = 1;
                continue;
            }
            if !kind.is_elastic() {
                continue;
            }
            pass.workgroup_size = match kind {
                PassKind::ElasticCoarseFactor => coarse_factor_workgroup(self.workgroup_size),
                _ => wg,
            };
            let (elements, constants) = elastic_pass(kind, counts, e, pass.workgroup_size);
            pass.elements = elements;
            if let Some(constants) = constants {
                pass.constants = constants;
            }
        }
        self
    }

    /// The finite elements' sizes, when the plan runs them.
    pub fn elastic_counts(&self) -> Option<ElasticCounts> {
        self.elastic
    }
}

/// Node passes' workgroups on `counts` (the partials `elastic_begin` and `elastic_alpha`
/// add) and the potential's (over max(nodes, tets), `elastic_backtrack`'s).
fn partials(counts: PlanCounts, wg: u32) -> (u32, u32) {
    (
        counts.nodes.div_ceil(wg),
        counts.nodes.max(counts.tets).div_ceil(wg),
    )
}

/// `kind`'s invocations and, where it has its own, its specialisation constants (the
/// others keep the schedule's: the floor and colliders of `elastic_start`, the colliders of
/// `elastic` from [`super::PassPlan::of`]).
fn elastic_pass(
    kind: PassKind,
    counts: PlanCounts,
    e: ElasticCounts,
    wg: u32,
) -> (u32, Option<Vec<u32>>) {
    use PassKind::*;
    let (n, t, a) = (counts.nodes, counts.tets, e.aggregates);
    let unknowns = (e.unknowns() as u32).max(6);
    let (node_partials, potential_partials) = partials(counts, wg);
    // AGGREGATES is constant 2 where common/coarse.glsl is included.
    let coarse = Some(vec![0, a]);
    let one = wg;
    match kind {
        ElasticContacts
        | ElasticStart
        | ElasticRows
        | ElasticDirection
        | ElasticCurvature
        | Elastic
        | ElasticCorrectionCurvature => (n, None),
        ElasticLinearise | ElasticProduct | ElasticCorrectionProduct => (t, None),
        ElasticPotential => (n.max(t), None),
        ElasticCoarseModes | ElasticRestrict => (a * wg, coarse),
        ElasticCoarseTets => (if a > 0 { t } else { 0 }, coarse),
        ElasticCoarseNodes => (e.members, coarse),
        ElasticCoarseGather => (a * a * wg, coarse),
        ElasticCoarseFactor => (if a > 0 { one } else { 0 }, Some(vec![unknowns])),
        ElasticCoarseInverse | ElasticCoarseSolve => (e.unknowns() as u32, Some(vec![unknowns])),
        ElasticProlong => (n, coarse),
        ElasticBegin | ElasticAlpha => (one, Some(vec![node_partials])),
        ElasticBacktrack => (one, Some(vec![potential_partials])),
        ElasticRigidPart | ElasticRigidApply => (e.objects * wg, Some(Vec::new())),
        _ => (0, None),
    }
}

/// The finite elements' buffers for a model of `counts` with `e`'s sizes, their passes in
/// workgroups of `wg`.
fn elastic_buffers(counts: PlanCounts, e: ElasticCounts, wg: u32) -> Vec<BufferPlan> {
    use BufferId::*;
    let (n, t) = (u64::from(counts.nodes), u64::from(counts.tets));
    let (a, u) = (u64::from(e.aggregates), e.unknowns());
    let (_, potential_partials) = partials(counts, wg);
    let state = ELASTIC_STATE_WORDS + BACKTRACK_STEPS * u64::from(potential_partials);
    [
        (ElasticTets, 64 * t),
        (NodeTetOffsets, 4 * (n + 1)),
        (NodeTetItems, 4 * 4 * t),
        (ElasticLinear, 96 * t),
        (ElasticCorners, 64 * t),
        (ElasticNodes, 16 * ELASTIC_PLANES * n),
        (ElasticState, 4 * state),
        (CoarseMatrix, 4 * (2 * u * u + u)),
        (CoarseVector, 4 * 2 * u),
        (CoarseAggregates, 4 * (a + 1 + u64::from(e.members) + n)),
        (CoarseModes, 16 * a),
        (CoarseIndex, 4 * u64::from(e.index_words)),
        (CoarseScratch, COARSE_ITEM_BYTES * u64::from(e.scratch_rows)),
        (ElasticObjects, 4 * OBJECT_WORDS * u64::from(e.objects)),
    ]
    .into_iter()
    .map(|(id, bytes)| device_only(id, bytes))
    .collect()
}
