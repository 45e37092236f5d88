//! `cpu`'s finite elements on the team: one iteration of the Newton step's preconditioned
//! conjugate gradients per dispatch of the `elastic` pass, the same arithmetic as `cpu-ref`
//! (`backend/cpu/reference/elastic.rs`) in single precision with double-precision dot
//! products. The finite elements' one group holds every node in order, so a node's place in
//! the group is the node. Nodes are shared out in chunks of [`CHUNK`]; each dot product is
//! summed per chunk and the chunks' sums added in order by every member, so the result has
//! the same bits on a team of any size.

use super::coarse::{coarse_level, precondition};
use super::correction::remove_rigid_parts;
use super::iterations::{Inputs, Outputs};
use super::newton::CHUNK;
use super::*;
use crate::backend::cpu::team::Member;
use crate::collider;
use crate::physics::{
    elastic_energy, elastic_linearise, elastic_product_strain, elastic_relinearise, held_increment,
    rebuilds, touching, ElasticTet,
};
use crate::schedule::family::{backtrack, ElasticNodes};

/// What each member keeps between the iterations of a step (all members the same values).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct NewtonScalars {
    /// `r . z`.
    rz: f64,
    /// Converged, or the direction met non-positive curvature: no further increments.
    done: bool,
    /// The step's incremental potential at `at + dx`, once a step has needed it.
    potential: Option<f64>,
    /// The last step went beyond the linearisation's trust: the next iteration begins a
    /// new Newton step (as `cpu-ref`).
    relinearise: bool,
}

impl NewtonScalars {
    /// Whether iteration `iteration` begins with a linearisation (the first of a step, or
    /// after an untrusted one), before which the contacts are solved (`cpu-ref`'s order).
    pub(super) fn linearises(&self, iteration: usize) -> bool {
        iteration == 0 || self.relinearise
    }
}

/// Iteration `iteration` of sweep `s`'s conjugate gradients as `member`: the force
/// increments `m/dt^2 alpha p` in the node results. Six phases between barriers (an
/// iteration that linearises the step adds five, the step's first three more for the
/// preconditioner's coarse level); the caller's wait ends the last.
/// The last iteration of the step also removes the rigid part of each free object's
/// elastic forces, as `cpu-ref` does (three more phases, more where a contact holds one;
/// [`remove_rigid_parts`]).
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
    // SAFETY: the caller's promise.
    unsafe { increments(member, inputs, outputs, s, iteration, scalars) };
    let Family::Elastic(family) = &inputs.sweeps[s].family else {
        return;
    };
    if iteration + 1 != inputs.k.iterations as usize || family.free_objects.is_empty() {
        return;
    }
    member.wait();
    // SAFETY: the caller's promise; the wait ended the writes of the results and `r`.
    unsafe { remove_rigid_parts(member, inputs, outputs, family) };
}

/// The conjugate gradients' force increments of one iteration (see [`iteration`]).
///
/// # Safety
/// As [`iteration`].
unsafe fn increments(
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
    if scalars.linearises(iteration) {
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
            let rates = cg.corners.part(own_tets.clone());
            for ((linear, rate), t) in linear.iter_mut().zip(rates).zip(own_tets.clone()) {
                // The step's first linearisation takes every tet's stiffness; a later one
                // keeps those of the tets that barely moved since (`cpu-ref`'s rule).
                let p = tets[t].map(|k| at[k as usize]);
                *linear = match iteration {
                    0 => elastic_linearise(&family.tets[t], p),
                    _ => elastic_relinearise(&family.tets[t], p, linear),
                };
                let (start, end) = (|k| x[k], |k| at[k]);
                *rate = family.rate_corners(t, tets[t], linear, dt, start, end);
            }
        }
        member.wait();
        // SAFETY: nobody writes the forces, `at` or the corners; these nodes' vectors are
        // this member's.
        unsafe {
            let (f, floor, contact) = (
                outputs.f.whole(),
                outputs.floor_force.whole(),
                outputs.contact.whole(),
            );
            let at = cg.at.whole();
            let (r, inverse) = (cg.r.part(nodes.clone()), cg.inverse.part(nodes.clone()));
            let (y, dx) = (cg.y.part(nodes.clone()), cg.dx.part(nodes.clone()));
            let held = cg.held.part(nodes.clone());
            let touches = cg.touching.part(nodes.clone());
            let colliders = inputs.colliders.as_ref().map_or(&[][..], |c| c.at);
            let rates = cg.corners.whole();
            for (j, i) in nodes.clone().enumerate() {
                let pushed = contact.get(i).copied().unwrap_or(Vec3A::ZERO);
                let phi = f[i] - k.gravity * family.mass[i] - Vec3A::Y * floor[i] - pushed;
                (y[j], dx[j]) = (at[i] - phi * (w[i] * dt * dt), Vec3A::ZERO);
                let on_floor = inputs.floor.then_some(floor[i] > 0.0);
                let normal =
                    collider::held_normal(on_floor, pushed, at[i], family.reach[i], colliders);
                let end = |q| at[q];
                let rate = |item: usize| rates[item / 4][item % 4];
                (r[j], inverse[j], held[j]) =
                    family.newton_row(i, w[i], dt, phi, normal, tets, end, rate);
                touches[j] = touching(on_floor, pushed, held[j]);
            }
        }
        member.wait();
        // SAFETY: nobody writes the coarse level until `coarse_level` (after this read).
        let built = unsafe { cg.coarse.whole()[0].is_built() };
        if iteration == 0 && rebuilds(inputs.step, built) {
            // SAFETY: the caller's promise.
            unsafe { coarse_level(member, inputs, cg, family) };
        }
        // SAFETY: the caller's promise.
        unsafe { precondition(member, cg, family, nodes.clone()) };
        // SAFETY: these nodes' vectors are this member's.
        unsafe {
            let (r, z, p) = (
                cg.r.part(nodes.clone()),
                cg.z.part(nodes.clone()),
                cg.p.part(nodes.clone()),
            );
            p.copy_from_slice(z);
            partial(r, z);
        }
        member.wait();
        scalars.rz = total();
        scalars.done = !positive(scalars.rz);
        scalars.potential = None;
        scalars.relinearise = false;
        member.wait();
    }
    // SAFETY: these nodes' results are this member's.
    let out = unsafe { outputs.node_out.part(nodes.clone()) };
    if scalars.done {
        out.fill(Vec3A::ZERO);
        return;
    }
    // The product's corners and, per chunk of tets, the largest strain change per unit
    // step (the step's trust measure, of the same `dF`).
    let tet_chunks = member.block(tets.len().div_ceil(CHUNK));
    let chunk_tets = tet_chunks.start * CHUNK..(tet_chunks.end * CHUNK).min(tets.len());
    // SAFETY: nobody writes `p` or the stiffnesses; these tets' corners and chunks' sums
    // are this member's.
    unsafe {
        let (p, linear) = (cg.p.whole(), cg.linear.whole());
        let corners = cg.corners.part(chunk_tets.clone());
        let sums = cg.tet_sums.part(tet_chunks.clone());
        for (c, sum) in tet_chunks.zip(sums) {
            let mut most = 0.0f32;
            for t in c * CHUNK..((c + 1) * CHUNK).min(tets.len()) {
                let d = tets[t].map(|k| p[k as usize]);
                let (product, strain) = elastic_product_strain(&family.tets[t], &linear[t], d);
                corners[t - chunk_tets.start] = product;
                most = most.max(strain);
            }
            *sum = f64::from(most);
        }
    }
    member.wait();
    // SAFETY: nobody writes `p` or the corners; these nodes' products are this member's.
    unsafe {
        let (p, corners, q) = (cg.p.whole(), cg.corners.whole(), cg.q.part(nodes.clone()));
        let held = cg.held.whole();
        for (j, i) in nodes.clone().enumerate() {
            let corner = |item: usize| corners[item / 4][item % 4];
            q[j] = family.product(i, w[i], dt, p[i], held[i], corner);
        }
        partial(&p[nodes.clone()], q);
    }
    member.wait();
    let curvature = total();
    // SAFETY: after a wait nobody writes the tets' sums until the next phase.
    let strain = unsafe { cg.tet_sums.whole() }
        .iter()
        .copied()
        .fold(0.0, f64::max);
    member.wait();
    if !positive(curvature) {
        scalars.done = true;
        out.fill(Vec3A::ZERO);
        return;
    }
    // Backtracking as `cpu-ref`'s: an untrusted step that raises the potential is halved.
    let stepped = backtrack(
        scalars.rz / curvature,
        strain,
        curvature,
        scalars.potential,
        |a| {
            // SAFETY: the caller's promise (every member evaluates the same steps).
            unsafe { potential(member, inputs, outputs, family, a as f32) }
        },
    );
    (scalars.potential, scalars.relinearise) = (stepped.potential, stepped.relinearise);
    let Some(alpha) = stepped.alpha else {
        scalars.done = true;
        out.fill(Vec3A::ZERO);
        return;
    };
    let alpha = alpha as f32;
    // A checked step the model predicted keeps the linearisation unless a node the
    // contacts left free ends inside one (`cpu-ref`'s check): each chunk's flag in the sums.
    let check_contacts = stepped.checked && !scalars.relinearise;
    // SAFETY: these nodes' vectors and chunks' sums are this member's; nobody writes the
    // contacts' forces or `at`.
    unsafe {
        let r = cg.r.part(nodes.clone());
        let (p, q) = (cg.p.part(nodes.clone()), cg.q.part(nodes.clone()));
        let dx = cg.dx.part(nodes.clone());
        let held = cg.held.part(nodes.clone());
        let (floor, contact) = (outputs.floor_force.whole(), outputs.contact.whole());
        for (j, i) in nodes.clone().enumerate() {
            let (h, d) = (held[j], p[j] * alpha);
            let pushed = Vec3A::Y * floor[i] + contact.get(i).copied().unwrap_or(Vec3A::ZERO);
            out[j] = held_increment(family.increment(i, dt, h, p[j], alpha), h, d, pushed);
            dx[j] += p[j] * alpha;
            r[j] -= q[j] * alpha;
        }
        if check_contacts {
            let (at, sums) = (cg.at.whole(), cg.sums.part(chunks.clone()));
            let colliders = inputs.colliders.as_ref().map_or(&[][..], |c| c.at);
            for (c, sum) in chunks.clone().zip(sums) {
                let inside = (c * CHUNK..((c + 1) * CHUNK).min(n)).any(|i| {
                    let (j, end) = (i - nodes.start, (at[i] + dx[i - nodes.start]).as_dvec3());
                    collider::enters_unheld(w[i] > 0.0, held[j], inputs.floor, colliders, end)
                });
                *sum = if inside { 1.0 } else { 0.0 };
            }
        }
    }
    member.wait();
    if check_contacts {
        // Read before `precondition`'s wait, after which the sums are written again.
        scalars.relinearise = total() > 0.0;
    }
    // SAFETY: the caller's promise.
    unsafe { precondition(member, cg, family, nodes.clone()) };
    // SAFETY: these nodes' vectors are this member's.
    unsafe { partial(cg.r.part(nodes.clone()), cg.z.part(nodes.clone())) };
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

/// The step's incremental potential with the nodes at `at + dx + alpha p` (`cpu-ref`'s
/// `potential`): the free nodes' inertia `m / (2 dt^2) |x - y|^2` and contacts'
/// stiffening `(h . d)^2 / 2` (`d`: the node's move in the step) plus the tets' energy,
/// summed in double precision per chunk and the chunks in order. Three phases.
///
/// # Safety
/// As [`iteration`].
unsafe fn potential(
    member: &Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    family: &ElasticNodes<f32>,
    alpha: f32,
) -> f64 {
    let cg = &outputs.newton;
    let (n, tets, w) = (inputs.x.len(), inputs.tets, inputs.inv_mass);
    let chunks = member.block(n.div_ceil(CHUNK));
    let scale = 1.0 / (2.0 * f64::from(inputs.k.dt).powi(2));
    // SAFETY: nobody writes `at`, `dx`, `p` or `y`; these chunks' trial positions and sums
    // are this member's.
    unsafe {
        let (at, dx, p, y) = (cg.at.whole(), cg.dx.whole(), cg.p.whole(), cg.y.whole());
        let held = cg.held.whole();
        let nodes = chunks.start * CHUNK..(chunks.end * CHUNK).min(n);
        let trial = cg.trial.part(nodes.clone());
        let sums = cg.sums.part(chunks.clone());
        for (c, sum) in chunks.clone().zip(sums) {
            *sum = 0.0;
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                let d = dx[i] + p[i] * alpha;
                let x = at[i] + d;
                trial[i - nodes.start] = x;
                if w[i] > 0.0 {
                    let m = f64::from(family.mass[i]);
                    *sum += m * scale * (x.as_dvec3() - y[i].as_dvec3()).length_squared();
                    *sum += 0.5 * f64::from(held[i].dot(d)).powi(2);
                }
            }
        }
    }
    member.wait();
    let tet_chunks = member.block(tets.len().div_ceil(CHUNK));
    // SAFETY: nobody writes the trial positions; these chunks' sums are this member's.
    unsafe {
        let trial = cg.trial.whole();
        let sums = cg.tet_sums.part(tet_chunks.clone());
        for (c, sum) in tet_chunks.clone().zip(sums) {
            *sum = (c * CHUNK..((c + 1) * CHUNK).min(tets.len()))
                .map(|t| {
                    let corners = tets[t].map(|k| trial[k as usize].as_dvec3());
                    elastic_energy(&widen(&family.tets[t]), corners)
                })
                .sum();
        }
    }
    member.wait();
    // SAFETY: after a wait nobody writes the sums until the next phase.
    let total =
        unsafe { cg.sums.whole().iter().sum::<f64>() + cg.tet_sums.whole().iter().sum::<f64>() };
    member.wait();
    total
}

/// A tet's element constants in double precision.
fn widen(t: &ElasticTet<f32>) -> ElasticTet<f64> {
    ElasticTet {
        shape: t.shape.map(|row| row.map(f64::from)),
        volume: f64::from(t.volume),
        mu: f64::from(t.mu),
        lambda: f64::from(t.lambda),
        alpha: f64::from(t.alpha),
    }
}

/// Whether `x` is a positive number (not NaN): the conjugate gradients go on only then.
fn positive(x: f64) -> bool {
    x > 0.0
}
