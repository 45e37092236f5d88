//! `cpu`'s finite elements on the team: one iteration of the Newton step's preconditioned
//! conjugate gradients per dispatch of the `elastic` pass, the same arithmetic as `cpu-ref`
//! (`backend/cpu/reference/elastic.rs`) in single precision with double-precision dot
//! products. The finite elements' one group holds every node in order, so a node's place in
//! the group is the node. Nodes are shared out in chunks of [`CHUNK`]; each dot product is
//! summed per chunk and the chunks' sums added in order by every member, so the result has
//! the same bits on a team of any size.

use super::iterations::{Inputs, Outputs};
use super::*;
use crate::backend::cpu::shared::SharedSlice;
use crate::backend::cpu::team::Member;
use crate::physics::{elastic_linearise, elastic_product, sym3_apply, ElasticLinear, Sym3};

/// Nodes per chunk of a dot product's partial sums.
const CHUNK: usize = 256;

/// The conjugate gradients' vectors, kept from step to step (empty without finite
/// elements): per node the linearisation point, the residual, the preconditioned residual,
/// the search direction, the matrix times it and the inverse diagonal block; per tet its
/// stiffness at the linearisation point and its product's corners; per chunk a partial sum.
#[derive(Debug, Clone, Default)]
pub(super) struct NewtonVectors {
    at: Vec<Vec3A>,
    r: Vec<Vec3A>,
    z: Vec<Vec3A>,
    p: Vec<Vec3A>,
    q: Vec<Vec3A>,
    inverse: Vec<Sym3<f32>>,
    linear: Vec<ElasticLinear<Vec3A>>,
    corners: Vec<[Vec3A; 4]>,
    sums: Vec<f64>,
}

impl NewtonVectors {
    /// The vectors of `nodes` nodes and `tets` tets.
    pub(super) fn new(nodes: usize, tets: usize) -> Self {
        NewtonVectors {
            at: vec![Vec3A::ZERO; nodes],
            r: vec![Vec3A::ZERO; nodes],
            z: vec![Vec3A::ZERO; nodes],
            p: vec![Vec3A::ZERO; nodes],
            q: vec![Vec3A::ZERO; nodes],
            inverse: vec![[0.0; 6]; nodes],
            linear: vec![ElasticLinear::default(); tets],
            corners: vec![[Vec3A::ZERO; 4]; tets],
            sums: vec![0.0; nodes.div_ceil(CHUNK)],
        }
    }

    /// The vectors shared with the team.
    pub(super) fn share(&mut self) -> NewtonShared<'_> {
        NewtonShared {
            at: SharedSlice::new(&mut self.at),
            r: SharedSlice::new(&mut self.r),
            z: SharedSlice::new(&mut self.z),
            p: SharedSlice::new(&mut self.p),
            q: SharedSlice::new(&mut self.q),
            inverse: SharedSlice::new(&mut self.inverse),
            linear: SharedSlice::new(&mut self.linear),
            corners: SharedSlice::new(&mut self.corners),
            sums: SharedSlice::new(&mut self.sums),
        }
    }
}

/// [`NewtonVectors`] shared by the team.
pub(super) struct NewtonShared<'a> {
    at: SharedSlice<'a, Vec3A>,
    r: SharedSlice<'a, Vec3A>,
    z: SharedSlice<'a, Vec3A>,
    p: SharedSlice<'a, Vec3A>,
    q: SharedSlice<'a, Vec3A>,
    inverse: SharedSlice<'a, Sym3<f32>>,
    linear: SharedSlice<'a, ElasticLinear<Vec3A>>,
    corners: SharedSlice<'a, [Vec3A; 4]>,
    sums: SharedSlice<'a, f64>,
}

/// What each member keeps between the iterations of a step (all members the same values).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct NewtonScalars {
    /// `r . z`.
    rz: f64,
    /// Converged, or the direction met non-positive curvature: no further increments.
    done: bool,
}

/// Iteration `iteration` of sweep `s`'s conjugate gradients as `member`: the force
/// increments `m/dt^2 alpha p` in the node results. Four phases between barriers (the
/// first iteration linearises the step in three more); the caller's wait ends the last.
///
/// # Safety
/// Every member must call it with the same arguments; nobody else may touch the forces,
/// the node results or the vectors during the call.
pub(super) unsafe fn iteration(
    member: &Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    s: usize,
    iteration: usize,
    scalars: &mut NewtonScalars,
) {
    let Family::Elastic(family) = &inputs.sweeps[s].family else {
        return;
    };
    let cg = &outputs.newton;
    let n = inputs.x.len();
    let chunks = member.block(n.div_ceil(CHUNK));
    let nodes = chunks.start * CHUNK..(chunks.end * CHUNK).min(n);
    let own_tets = member.block(inputs.tets.len());
    let (x, v, w, k, tets) = (inputs.x, inputs.v, inputs.inv_mass, inputs.k, inputs.tets);
    let dt = k.dt;
    // Each member's chunks' partial sums of `a_i . b_i`, then (after a wait) their total.
    let partial = |a: &[Vec3A], b: &[Vec3A]| {
        // SAFETY: these chunks' sums are this member's.
        let sums = unsafe { cg.sums.part(chunks.clone()) };
        for (c, sum) in chunks.clone().zip(sums) {
            let range = c * CHUNK - nodes.start..((c + 1) * CHUNK).min(n) - nodes.start;
            *sum = (a[range.clone()].iter().zip(&b[range]))
                .map(|(a, b)| f64::from(a.dot(*b)))
                .sum();
        }
    };
    // SAFETY: after a wait nobody writes the sums until the next phase.
    let total = || unsafe { cg.sums.whole() }.iter().sum::<f64>();
    if iteration == 0 {
        // SAFETY: nobody writes the forces; these nodes' vectors are this member's.
        unsafe {
            let f = outputs.f.whole();
            for (i, at) in nodes.clone().zip(cg.at.part(nodes.clone())) {
                *at = end_position(x[i], v[i], f[i], w[i], dt);
            }
        }
        member.wait();
        // SAFETY: nobody writes the forces or `at`; these tets' and nodes' vectors are this
        // member's.
        unsafe {
            let at = cg.at.whole();
            let linear = cg.linear.part(own_tets.clone());
            for (linear, t) in linear.iter_mut().zip(own_tets.clone()) {
                *linear = elastic_linearise(&family.tets[t], tets[t].map(|k| at[k as usize]));
            }
            let (f, floor, contact) = (
                outputs.f.whole(),
                outputs.floor_force.whole(),
                outputs.contact.whole(),
            );
            let at = cg.at.whole();
            let (r, z) = (cg.r.part(nodes.clone()), cg.z.part(nodes.clone()));
            let (p, inverse) = (cg.p.part(nodes.clone()), cg.inverse.part(nodes.clone()));
            for (j, i) in nodes.clone().enumerate() {
                let pushed = contact.get(i).copied().unwrap_or(Vec3A::ZERO);
                let phi = f[i] - k.gravity * family.mass[i] - Vec3A::Y * floor[i] - pushed;
                (r[j], inverse[j]) = family.newton_row(i, w[i], dt, phi, tets, |q| x[q], |q| at[q]);
                z[j] = sym3_apply(inverse[j], r[j]);
                p[j] = z[j];
            }
            partial(r, z);
        }
        member.wait();
        scalars.rz = total();
        scalars.done = !positive(scalars.rz);
        member.wait();
    }
    // SAFETY: these nodes' results are this member's.
    let out = unsafe { outputs.node_out.part(nodes.clone()) };
    if scalars.done {
        out.fill(Vec3A::ZERO);
        return;
    }
    // SAFETY: nobody writes `p` or the stiffnesses; these tets' corners are this member's.
    unsafe {
        let (p, linear) = (cg.p.whole(), cg.linear.whole());
        let corners = cg.corners.part(own_tets.clone());
        for (corners, t) in corners.iter_mut().zip(own_tets.clone()) {
            let d = tets[t].map(|k| p[k as usize]);
            *corners = elastic_product(&family.tets[t], &linear[t], d);
        }
    }
    member.wait();
    // SAFETY: nobody writes `p` or the corners; these nodes' products are this member's.
    unsafe {
        let (p, corners, q) = (cg.p.whole(), cg.corners.whole(), cg.q.part(nodes.clone()));
        for (j, i) in nodes.clone().enumerate() {
            q[j] = family.product(i, w[i], dt, p[i], |item| corners[item / 4][item % 4]);
        }
        partial(&p[nodes.clone()], q);
    }
    member.wait();
    let curvature = total();
    member.wait();
    if !positive(curvature) {
        scalars.done = true;
        out.fill(Vec3A::ZERO);
        return;
    }
    let alpha = (scalars.rz / curvature) as f32;
    // SAFETY: these nodes' vectors are this member's.
    unsafe {
        let (r, z) = (cg.r.part(nodes.clone()), cg.z.part(nodes.clone()));
        let (p, q) = (cg.p.part(nodes.clone()), cg.q.part(nodes.clone()));
        let inverse = cg.inverse.part(nodes.clone());
        for (j, i) in nodes.clone().enumerate() {
            out[j] = p[j] * (alpha * family.mass[i] / (dt * dt));
            r[j] -= q[j] * alpha;
            z[j] = sym3_apply(inverse[j], r[j]);
        }
        partial(r, z);
    }
    member.wait();
    let rz = total();
    let beta = (rz / scalars.rz) as f32;
    // SAFETY: these nodes' vectors are this member's.
    unsafe {
        let (z, p) = (cg.z.part(nodes.clone()), cg.p.part(nodes.clone()));
        for (p, z) in p.iter_mut().zip(z.iter()) {
            *p = *z + *p * beta;
        }
    }
    scalars.rz = rz;
    scalars.done = !positive(rz);
}

/// Whether `x` is a positive number (not NaN): the conjugate gradients go on only then.
fn positive(x: f64) -> bool {
    x > 0.0
}
