//! The inversion floor on the `cpu` team (`inversion_floor`, docs/PHYSICS.md "Inversion
//! floor"): each member takes its block of a volume group's tets, measures each where its
//! nodes end the step and writes the one-sided force that lifts a tet below the floor back
//! to it ([`inversion_floor`]) into the tet's result slots, which `constraint_apply` then
//! gathers as it gathers the volume constraints'.

use super::iterations::{Inputs, Outputs};
use super::*;
use crate::physics::{end_position, inversion_floor};

/// The inversion floor of tets `block` (positions in the sweep's `members.items`) of group
/// `g` of the volume sweep `s`, against the current forces.
///
/// # Safety
/// No other thread may touch `block` of the tets' results, or write `f`, during the call.
pub(super) unsafe fn floor(
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    s: usize,
    g: usize,
    block: std::ops::Range<usize>,
) {
    let sweep = &inputs.sweeps[s];
    let n = inputs.x.len();
    let a_scale = &sweep.a_scale[g * n..(g + 1) * n];
    let (x, v, w, k) = (inputs.x, inputs.v, inputs.inv_mass, inputs.k);
    // SAFETY: nobody writes `f` (the caller's promise).
    let f = unsafe { outputs.f.whole() };
    // SAFETY: `block` of the results is this thread's alone (the caller's promise).
    let out = unsafe { outputs.tet_out.part(block.clone()) };
    let members = &sweep.members.items[block.clone()];
    let tets = &sweep.tet_nodes[block];
    out.fill([Vec3A::ZERO; 4]);
    // A position correction: none in split contact's velocity solve.
    if k.solve == Solve::Velocity {
        return;
    }
    for ((out, &t), ids) in out.iter_mut().zip(members).zip(tets) {
        let ids = ids.map(|i| i as usize);
        let end = ids.map(|i| end_position(x[i], v[i], f[i], w[i], k.dt));
        let rest = inputs.rest_volume[t as usize];
        let Some((c, grad)) = inversion_floor(end, rest, k.inversion_floor) else {
            continue;
        };
        let mut a = 0.0;
        for (&i, g) in ids.iter().zip(&grad) {
            a += a_scale[i] * w[i] * g.dot(*g);
        }
        if let Some(lambda) = implicit_multiplier(c, a, 0.0, k.dt, k.epsilon) {
            *out = grad.map(|g| g * -lambda);
        }
    }
}

/// The inversion floor of the blocks `range` of the volume sweep `s` (block Gauss-Seidel):
/// each block's tets one after another against the block's copies of its nodes' forces,
/// which each tet's force moves as the volume sweep's do.
///
/// # Safety
/// No other thread may touch these blocks' results, or write `f`, during the call.
pub(super) unsafe fn floor_blocks(
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    s: usize,
    range: std::ops::Range<usize>,
) {
    let sweep = &inputs.sweeps[s];
    let Some(blocks) = &sweep.blocks else {
        return;
    };
    let a_scale = &sweep.a_scale[..sweep.nodes];
    let (x, v, w, k) = (inputs.x, inputs.v, inputs.inv_mass, inputs.k);
    let positions = blocks.positions(&range);
    // SAFETY: nobody writes `f`; these blocks' results are this thread's alone (the
    // caller's promise).
    let (f, out) = unsafe { (outputs.f.whole(), outputs.tet_out.part(positions.clone())) };
    out.fill([Vec3A::ZERO; 4]);
    // A position correction: none in split contact's velocity solve.
    if k.solve == Solve::Velocity {
        return;
    }
    let mut local: Vec<Vec3A> = Vec::new();
    for b in range {
        blocks.load(b, f, &mut local);
        for p in blocks.first[b] as usize..blocks.first[b + 1] as usize {
            let t = sweep.members.items[p] as usize;
            let ids = sweep.tet_nodes[p].map(|i| i as usize);
            let corners = blocks.corners[p].map(|l| l as usize);
            let end = [0, 1, 2, 3].map(|j| {
                let i = ids[j];
                end_position(x[i], v[i], local[corners[j]], w[i], k.dt)
            });
            let Some((c, grad)) = inversion_floor(end, inputs.rest_volume[t], k.inversion_floor)
            else {
                continue;
            };
            let mut a = 0.0;
            for (&i, g) in ids.iter().zip(&grad) {
                a += a_scale[i] * w[i] * g.dot(*g);
            }
            let Some(lambda) = implicit_multiplier(c, a, 0.0, k.dt, k.epsilon) else {
                continue;
            };
            let forces = grad.map(|g| g * -lambda);
            for j in 0..4 {
                local[corners[j]] += forces[j] * blocks.scale[ids[j]];
            }
            out[p - positions.start] = forces;
        }
    }
}
