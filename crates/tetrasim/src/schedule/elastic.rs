//! The finite elements' stages (`neo-hookean`; docs/GPU.md, "Finite elements on the GPU"):
//! one iteration of the step's Newton solve as the GPU runs it, pass after pass, without a
//! host round trip. Each iteration's passes run in this order, after the sweep's group and
//! before `constraint_apply`, which adds the iteration's force increments:
//!
//! ```text
//! elastic_contacts                                    first iteration: the floor's and the
//!                                                     colliders' solve (cpu-ref's
//!                                                     `contact_solve`)
//! elastic_start, elastic_linearise, elastic_rows      at a linearisation (iteration 0, or
//!                                                     after a step beyond the trust): where
//!                                                     the nodes end, the stiffness, the
//!                                                     Newton rows
//! elastic_coarse_{modes,tets,nodes,gather,factor,     first iteration, every tenth step:
//! inverse}                                            the coarse level and its inverse
//! elastic_restrict, elastic_coarse_solve,             the preconditioner (at a
//! elastic_prolong, elastic_begin, elastic_direction   linearisation or while the solve goes
//!                                                     on), r . z, beta, the direction
//! elastic_product, elastic_curvature, elastic_alpha,  the conjugate-gradient step,
//! elastic_potential, elastic_backtrack, elastic       backtracked beyond the trust, and the
//!                                                     force increments (`elastic`)
//! elastic_rigid_part, elastic_correction_product,     last iteration: the rigid part of the
//! elastic_correction_curvature, elastic_rigid_apply   free objects' elastic forces removed
//! ```
//!
//! Which of them do anything in an iteration is decided on the GPU from the solve's state
//! (`ElasticState`), so the frame's commands stay the same every frame. The CPU backends
//! run the whole iteration in `elastic`'s arm; the others are no-ops there.

use super::stages::stage;
use super::{Access, BufferId, Domain, PassKind, Repeat, Stage};

/// The finite elements' stages for sweep `sweep`, in execution order.
pub(super) fn stages(sweep: usize) -> Vec<Stage> {
    use Access::{Read, ReadWrite, Write};
    use BufferId::*;
    use Domain::{Coarse, Nodes, Tets as EveryTet};
    use PassKind::*;
    use Repeat::{FirstIteration, Iteration, LastIteration};
    let state = (ElasticState, Read);
    let sums = (ElasticState, ReadWrite);
    let node_tets = [
        (ElasticTets, Read),
        (NodeTetOffsets, Read),
        (NodeTetItems, Read),
    ];
    let aggregates = [(CoarseAggregates, Read), (CoarseModes, Read)];
    let rows = [
        (Positions, Read),
        (Velocities, Read),
        (Tets, Read),
        (ElasticCorners, Read),
        (ElasticNodes, ReadWrite),
        state,
    ];
    let product = [
        (Tets, Read),
        (ElasticTets, Read),
        (ElasticNodes, Read),
        (ElasticLinear, Read),
        (ElasticCorners, Write),
        sums,
    ];
    let curvature = [
        (Positions, Read),
        (Velocities, Read),
        (ElasticCorners, Read),
        (ElasticNodes, ReadWrite),
        sums,
    ];
    let rigid = [
        (Positions, Read),
        (Velocities, Read),
        (Forces, Read),
        (ElasticNodes, ReadWrite),
        (ElasticObjects, ReadWrite),
    ];
    let list = vec![
        stage(
            ElasticContacts,
            FirstIteration,
            Nodes,
            vec![(Positions, Read), (Velocities, Read), (Forces, ReadWrite)],
        ),
        stage(
            ElasticStart,
            Iteration,
            Nodes,
            vec![
                (Positions, Read),
                (Velocities, Read),
                (Forces, Read),
                (ElasticNodes, ReadWrite),
                state,
            ],
        ),
        stage(
            ElasticLinearise,
            Iteration,
            EveryTet,
            vec![
                (Positions, Read),
                (Tets, Read),
                (ElasticTets, Read),
                (ElasticNodes, Read),
                (ElasticLinear, ReadWrite),
                (ElasticCorners, Write),
                state,
            ],
        ),
        stage(
            ElasticRows,
            Iteration,
            Nodes,
            [&rows[..], &node_tets].concat(),
        ),
        stage(
            ElasticCoarseModes,
            FirstIteration,
            Coarse,
            vec![
                (ElasticNodes, Read),
                (CoarseAggregates, Read),
                (CoarseModes, ReadWrite),
                state,
            ],
        ),
        stage(
            ElasticCoarseTets,
            FirstIteration,
            EveryTet,
            [
                &[
                    (Tets, Read),
                    (ElasticTets, Read),
                    (ElasticLinear, Read),
                    (ElasticNodes, Read),
                    (CoarseIndex, Read),
                    (CoarseScratch, Write),
                    state,
                ][..],
                &aggregates,
                &node_tets,
            ]
            .concat(),
        ),
        stage(
            ElasticCoarseNodes,
            FirstIteration,
            Coarse,
            [
                &[
                    (Velocities, Read),
                    (ElasticTets, Read),
                    (ElasticNodes, Read),
                    (CoarseIndex, Read),
                    (CoarseScratch, Write),
                    state,
                ][..],
                &aggregates,
            ]
            .concat(),
        ),
        stage(
            ElasticCoarseGather,
            FirstIteration,
            Coarse,
            vec![
                (CoarseIndex, Read),
                (CoarseScratch, Read),
                (CoarseMatrix, Write),
                state,
            ],
        ),
        stage(
            ElasticCoarseFactor,
            FirstIteration,
            Coarse,
            vec![(CoarseMatrix, ReadWrite), state],
        ),
        stage(
            ElasticCoarseInverse,
            FirstIteration,
            Coarse,
            vec![(CoarseMatrix, ReadWrite), state],
        ),
        stage(
            ElasticRestrict,
            Iteration,
            Coarse,
            [
                &[(ElasticNodes, Read), (CoarseVector, Write), state][..],
                &aggregates,
            ]
            .concat(),
        ),
        stage(
            ElasticCoarseSolve,
            Iteration,
            Coarse,
            vec![(CoarseMatrix, Read), (CoarseVector, ReadWrite), state],
        ),
        stage(
            ElasticProlong,
            Iteration,
            Nodes,
            [
                &[(ElasticNodes, ReadWrite), (CoarseVector, Read), sums][..],
                &aggregates,
            ]
            .concat(),
        ),
        stage(ElasticBegin, Iteration, Coarse, vec![sums]),
        stage(
            ElasticDirection,
            Iteration,
            Nodes,
            vec![(ElasticNodes, ReadWrite), state],
        ),
        stage(ElasticProduct, Iteration, EveryTet, product.to_vec()),
        stage(
            ElasticCurvature,
            Iteration,
            Nodes,
            [&curvature[..], &node_tets].concat(),
        ),
        stage(ElasticAlpha, Iteration, Coarse, vec![sums]),
        stage(
            ElasticPotential,
            Iteration,
            EveryTet,
            [
                &[
                    (Positions, Read),
                    (Velocities, Read),
                    (Tets, Read),
                    (ElasticNodes, Read),
                    sums,
                ][..],
                &node_tets,
            ]
            .concat(),
        ),
        stage(ElasticBacktrack, Iteration, Coarse, vec![sums]),
        stage(
            Elastic,
            Iteration,
            Nodes,
            vec![
                (Positions, Read),
                (Velocities, Read),
                (Forces, Read),
                (ElasticNodes, ReadWrite),
                sums,
                (GroupMembers, Read),
                (Contributions, Write),
            ],
        ),
        stage(ElasticRigidPart, LastIteration, Coarse, rigid.to_vec()),
        stage(
            ElasticCorrectionProduct,
            LastIteration,
            EveryTet,
            product.to_vec(),
        ),
        stage(
            ElasticCorrectionCurvature,
            LastIteration,
            Nodes,
            [&curvature[..], &node_tets].concat(),
        ),
        stage(
            ElasticRigidApply,
            LastIteration,
            Coarse,
            [&rigid[..], &[(Contributions, Write)]].concat(),
        ),
    ];
    list.into_iter()
        .map(|stage| Stage {
            sweep: Some(sweep),
            ..stage
        })
        .collect()
}
