//! Block Gauss-Seidel on the `cpu` backend (docs/PHYSICS.md, "Block Gauss-Seidel"): each
//! member of the team owns whole blocks of a sweep, and solves each block's constraints one
//! after another (in colour order, as `cpu-ref` and the GPU's workgroups) against its own
//! copy of the block's nodes' forces. No fork-join per colour group: one wait per sweep.

use glam::Vec3A;

use super::iterations::{Inputs, Outputs};
use super::{
    compliant_multiplier, implicit_accumulate, ConstraintFamily, Family, NodeForces, Sweep,
};
use crate::model::{ConstraintBlocks, ConstraintKind, Csr};
use crate::SimParams;

/// A sweep's blocks in the backend's precision.
#[derive(Debug, Clone)]
pub(super) struct Blocks {
    /// Row `b`: member positions of block `b` (`blocks + 1` offsets).
    pub(super) first: Vec<u32>,
    /// Row `b`: the global indices of block `b`'s nodes.
    pub(super) nodes: Csr,
    /// Per member position: its corners' local indices in its block.
    pub(super) corners: Vec<[u32; 4]>,
    /// Per node: how far a force moves it in its block's copy, `a_scale * omega * weight`
    /// (0 for a hub, whose copies stay).
    pub(super) scale: Vec<f32>,
    /// Sweeps of each block per iteration ([`ConstraintKind::block_sweeps`]).
    pub(super) sweeps: usize,
}

impl Blocks {
    /// The blocks of `blocks`, a sweep of `kind`, with each node's `(a_scale, weight)`,
    /// under `params` (its `omega` and [`ConstraintKind::block_sweeps`] of `kind`).
    pub(super) fn new(
        blocks: ConstraintBlocks,
        kind: ConstraintKind,
        factors: &[(f64, f64)],
        params: &SimParams,
    ) -> Self {
        let scale = (0..factors.len())
            .map(|k| blocks.copy_scale(k, factors, params.omega) as f32)
            .collect();
        Blocks {
            first: blocks.first,
            nodes: blocks.nodes,
            corners: blocks.corners,
            scale,
            sweeps: kind.block_sweeps(params) as usize,
        }
    }

    /// Number of blocks.
    pub(super) fn len(&self) -> usize {
        self.first.len() - 1
    }

    /// The member positions of the blocks `range`.
    pub(super) fn positions(&self, range: &std::ops::Range<usize>) -> std::ops::Range<usize> {
        self.first[range.start] as usize..self.first[range.end] as usize
    }

    /// Block `b`'s copies of its nodes' forces `f`, into `local`.
    pub(super) fn load(&self, b: usize, f: &[Vec3A], local: &mut Vec<Vec3A>) {
        local.clear();
        local.extend(self.nodes.row(b).iter().map(|&i| f[i as usize]));
    }
}

/// Solves the blocks `range` of sweep `s` (its one group) against the forces.
///
/// # Safety
/// No other thread may touch these blocks' results and multipliers, or write `f`, during
/// the call.
pub(super) unsafe fn solve(
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    s: usize,
    range: std::ops::Range<usize>,
) {
    let sweep = &inputs.sweeps[s];
    let Some(blocks) = &sweep.blocks else {
        return;
    };
    let positions = blocks.positions(&range);
    // SAFETY: nobody writes `f`; these blocks' results and multipliers are this thread's
    // alone (the caller's promise), here and below.
    let (f, so_far) = unsafe {
        (
            outputs.f.whole(),
            outputs.multipliers[s].part(positions.clone()),
        )
    };
    let run = Run {
        inputs,
        sweep,
        blocks,
        f,
        first: positions.start,
    };
    match &sweep.family {
        Family::Springs(family) => {
            // SAFETY: as above.
            let out = unsafe { outputs.pair_out.part(positions) };
            run.blocks(range, out, so_far, &sweep.pair_nodes, family);
        }
        Family::Distances(family) => {
            // SAFETY: as above.
            let out = unsafe { outputs.pair_out.part(positions) };
            run.blocks(range, out, so_far, &sweep.pair_nodes, family);
        }
        Family::Volumes(family) => {
            // SAFETY: as above.
            let out = unsafe { outputs.tet_out.part(positions) };
            run.blocks(range, out, so_far, &sweep.tet_nodes, family);
        }
        // Validation refuses blocks for the finite elements.
        Family::Elastic(_) => {}
    }
}

/// What one thread's run of blocks reads.
struct Run<'a> {
    inputs: &'a Inputs<'a>,
    sweep: &'a Sweep,
    blocks: &'a Blocks,
    /// The iteration's forces.
    f: &'a [Vec3A],
    /// The member position of `out[0]`.
    first: usize,
}

impl Run<'_> {
    /// Blocks `range`, their results into `out` and multipliers so far in `so_far` (from
    /// position `self.first`); `nodes`: each member's nodes.
    fn blocks<const K: usize, R: NodeForces<K>, F: ConstraintFamily<f32, K>>(
        &self,
        range: std::ops::Range<usize>,
        out: &mut [R],
        so_far: &mut [f32],
        nodes: &[[u32; K]],
        family: &F,
    ) {
        let (x, v, w, k) = (
            self.inputs.x,
            self.inputs.v,
            self.inputs.inv_mass,
            self.inputs.k,
        );
        let (sweep, blocks) = (self.sweep, self.blocks);
        let a_scale = &sweep.a_scale[..sweep.nodes];
        let mut local: Vec<Vec3A> = Vec::new();
        // Per member of the block: its forces summed over the block's sweeps.
        let mut total: Vec<[Vec3A; K]> = Vec::new();
        // Per member of the block: its value, gradients, softness and damping at `x(t)`,
        // evaluated in the first sweep and kept for the others.
        let mut evaluated: Vec<(f32, [Vec3A; K], f32, f32)> = Vec::new();
        for b in range {
            blocks.load(b, self.f, &mut local);
            let span = blocks.first[b] as usize..blocks.first[b + 1] as usize;
            total.clear();
            total.resize(span.len(), [Vec3A::ZERO; K]);
            evaluated.clear();
            for (s, p) in (0..blocks.sweeps).flat_map(|s| span.clone().map(move |p| (s, p))) {
                let (element, i, q) = (&nodes[p], p - span.start, p - self.first);
                let ids = element.map(|i| i as usize);
                let corners: [usize; K] = std::array::from_fn(|j| blocks.corners[p][j] as usize);
                if s == 0 {
                    let e = sweep.members.items[p] as usize;
                    let (c, grad, softness, damping) = family.evaluate(e, ids.map(|i| x[i]));
                    let c = match softness > 0.0 {
                        true => c,
                        false => k.solve.hard(c),
                    };
                    evaluated.push((c, grad, softness, damping));
                }
                let (c, grad, softness, damping) = evaluated[i];
                let (mut a, mut bb) = (0.0, 0.0);
                for j in 0..K {
                    let i = ids[j];
                    let force = local[corners[j]];
                    implicit_accumulate(
                        &mut a, &mut bb, grad[j], w[i], a_scale[i], v[i], force, k.dt,
                    );
                }
                let bb = bb - softness * so_far[q];
                let Some(d) = compliant_multiplier(c, a, bb, k.dt, softness, damping, k.epsilon)
                else {
                    continue;
                };
                if softness > 0.0 {
                    so_far[q] += k.omega * d;
                }
                let forces = grad.map(|g| g * -d);
                for j in 0..K {
                    local[corners[j]] += forces[j] * blocks.scale[ids[j]];
                    total[i][j] += forces[j];
                }
            }
            for (p, forces) in span.zip(&total) {
                out[p - self.first] = R::from_forces(*forces);
            }
        }
    }
}
