//! Block Gauss-Seidel on the `cpu` backend (docs/PHYSICS.md, "Block Gauss-Seidel"): each
//! member of the team owns whole blocks of the volume sweep, and solves each block's tets
//! one after another (in colour order, as `cpu-ref` and the GPU's workgroups) against its
//! own copy of the block's nodes' forces. No fork-join per colour group: one wait per sweep.

use glam::Vec3A;

use super::iterations::{Inputs, Outputs};
use super::{compliant_multiplier, implicit_accumulate, ConstraintFamily, Family};
use crate::model::{ConstraintBlocks, Csr};

/// A volume sweep's blocks in the backend's precision.
#[derive(Debug, Clone)]
pub(super) struct Blocks {
    /// Row `b`: member positions of block `b` (`blocks + 1` offsets).
    first: Vec<u32>,
    /// Row `b`: the global indices of block `b`'s nodes.
    nodes: Csr,
    /// Per member position: its corners' local indices in its block.
    corners: Vec<[u32; 4]>,
    /// Per node: how far a force moves it in its block's copy, `a_scale * omega * weight`
    /// (0 for a hub, whose copies stay).
    scale: Vec<f32>,
}

impl Blocks {
    /// The blocks of `blocks` with each node's `(a_scale, weight)` and `omega`.
    pub(super) fn new(blocks: ConstraintBlocks, factors: &[(f64, f64)], omega: f64) -> Self {
        Blocks {
            first: blocks.first,
            nodes: blocks.nodes,
            corners: blocks.corners,
            scale: (factors.iter().zip(&blocks.hub))
                .map(|(&(a, w), &hub)| if hub { 0.0 } else { (a * w * omega) as f32 })
                .collect(),
        }
    }

    /// Number of blocks.
    pub(super) fn len(&self) -> usize {
        self.first.len() - 1
    }
}

/// Solves the blocks `range` of the volume sweep `s` (its one group) against the forces.
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
    let (Some(blocks), Family::Volumes(family)) = (&sweep.blocks, &sweep.family) else {
        return;
    };
    let positions = blocks.first[range.start] as usize..blocks.first[range.end] as usize;
    // SAFETY: nobody writes `f`; these blocks' results and multipliers are this thread's
    // alone (the caller's promise).
    let (f, out, so_far) = unsafe {
        (
            outputs.f.whole(),
            outputs.tet_out.part(positions.clone()),
            outputs.multipliers[s].part(positions.clone()),
        )
    };
    let (x, v, w, k) = (inputs.x, inputs.v, inputs.inv_mass, inputs.k);
    let a_scale = &sweep.a_scale[..sweep.nodes];
    let mut local: Vec<Vec3A> = Vec::new();
    for b in range {
        local.clear();
        local.extend(blocks.nodes.row(b).iter().map(|&i| f[i as usize]));
        for p in blocks.first[b] as usize..blocks.first[b + 1] as usize {
            let q = p - positions.start;
            let e = sweep.members.items[p] as usize;
            let ids = sweep.tet_nodes[p].map(|i| i as usize);
            let corners = blocks.corners[p].map(|l| l as usize);
            let (c, grad, softness, damping) = family.evaluate(e, ids.map(|i| x[i]));
            let c = match softness > 0.0 {
                true => c,
                false => k.solve.hard(c),
            };
            let (mut a, mut bb) = (0.0, 0.0);
            for j in 0..4 {
                let i = ids[j];
                let force = local[corners[j]];
                implicit_accumulate(
                    &mut a, &mut bb, grad[j], w[i], a_scale[i], v[i], force, k.dt,
                );
            }
            let bb = bb - softness * so_far[q];
            let delta = compliant_multiplier(c, a, bb, k.dt, softness, damping, k.epsilon);
            let Some(d) = delta else {
                out[q] = [Vec3A::ZERO; 4];
                continue;
            };
            if softness > 0.0 {
                so_far[q] += k.omega * d;
            }
            let forces = grad.map(|g| g * -d);
            for j in 0..4 {
                local[corners[j]] += forces[j] * blocks.scale[ids[j]];
            }
            out[q] = forces;
        }
    }
}
