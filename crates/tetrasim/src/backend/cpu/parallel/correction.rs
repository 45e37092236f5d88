//! `cpu`'s rigid-part correction of the finite elements' last iteration (`cpu-ref`'s in
//! `backend/cpu/reference/elastic.rs`): each free object's elastic forces lose their rigid
//! part ([`RigidPart`]), at full length on a body nothing holds and, on a body a contact
//! holds, at the length that minimises the Newton step's quadratic model along it
//! ([`correction_length`]). The same bits on a team of any size.

use glam::Vec3A;

use super::iterations::{Inputs, Outputs};
use super::newton::CHUNK;
use crate::backend::cpu::team::Member;
use crate::physics::{correction_length, elastic_product, held_mass, RigidPart};
use crate::schedule::family::ElasticNodes;

/// Removes the rigid parts from the node results (the iteration's increments). Three
/// phases, five where a contact holds a free object; the caller's wait ends the last.
///
/// # Safety
/// As [`super::elastic::iteration`], after a wait that ended the writes of the node
/// results and of the conjugate gradients' `r`.
pub(super) unsafe fn remove_rigid_parts(
    member: &Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    family: &ElasticNodes<f32>,
) {
    let (x, k, cg) = (inputs.x, inputs.k, &outputs.newton);
    // Every member finds the same rigid parts (the same sums in the same order).
    // SAFETY: nobody writes the forces, the node results or `held` until the next wait.
    let (parts, held_objects) = unsafe {
        let (f, out) = (outputs.f.whole(), outputs.node_out.whole());
        let (floor, contact) = (outputs.floor_force.whole(), outputs.contact.whole());
        let held = cg.held.whole();
        let parts: Vec<RigidPart> = (family.free_objects.iter())
            .map(|object| {
                RigidPart::of(object.clone().map(|i| {
                    let pushed = contact.get(i).copied().unwrap_or(Vec3A::ZERO);
                    let phi = f[i] - k.gravity * family.mass[i] - Vec3A::Y * floor[i] - pushed;
                    let m = held_mass(f64::from(family.mass[i]), held[i]);
                    (x[i].as_dvec3(), m, (phi + out[i]).as_dvec3())
                }))
            })
            .collect();
        let held_objects: Vec<bool> = (family.free_objects.iter())
            .map(|object| object.clone().any(|i| held[i] != Vec3A::ZERO))
            .collect();
        (parts, held_objects)
    };
    let lengths = if held_objects.contains(&true) {
        member.wait();
        // SAFETY: the caller's promise.
        unsafe { lengths(member, inputs, outputs, family, &parts, &held_objects) }
    } else {
        vec![1.0; parts.len()]
    };
    member.wait();
    let own = member.block(x.len());
    // SAFETY: these nodes' results are this member's; nobody writes `held`.
    let (out, held) = unsafe { (outputs.node_out.part(own.clone()), cg.held.whole()) };
    for ((object, part), length) in family.free_objects.iter().zip(&parts).zip(lengths) {
        for i in object.start.max(own.start)..object.end.min(own.end) {
            let m = held_mass(f64::from(family.mass[i]), held[i]);
            out[i - own.start] -= (part.force(x[i].as_dvec3(), m) * length).as_vec3a();
        }
    }
}

/// Each free object's correction length (one where no contact holds it): the corrections'
/// moves `d` in the conjugate gradients' `trial` (free now), their products `A d` in `q`,
/// then per held object `r . d` and `d . A d` summed per chunk and the chunks in order.
/// Four phases; the last ends with a wait.
///
/// # Safety
/// As [`remove_rigid_parts`].
unsafe fn lengths(
    member: &Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    family: &ElasticNodes<f32>,
    parts: &[RigidPart],
    held_objects: &[bool],
) -> Vec<f64> {
    let (x, w, tets, dt, cg) = (
        inputs.x,
        inputs.inv_mass,
        inputs.tets,
        inputs.k.dt,
        &outputs.newton,
    );
    let n = x.len();
    let own = member.block(n);
    // SAFETY: these nodes' moves are this member's; nobody writes `held`.
    unsafe {
        let (d, held) = (cg.trial.part(own.clone()), cg.held.whole());
        d.fill(Vec3A::ZERO);
        let objects = family.free_objects.iter().zip(parts).zip(held_objects);
        for ((object, part), _) in objects.filter(|(_, &held)| held) {
            for i in object.start.max(own.start)..object.end.min(own.end) {
                let m = held_mass(f64::from(family.mass[i]), held[i]);
                let force = part.force(x[i].as_dvec3(), m).as_vec3a();
                d[i - own.start] = -force * (w[i] * dt * dt);
            }
        }
    }
    member.wait();
    let own_tets = member.block(tets.len());
    // SAFETY: nobody writes the moves or the stiffnesses; these tets' corners are this
    // member's.
    unsafe {
        let (d, linear) = (cg.trial.whole(), cg.linear.whole());
        let corners = cg.corners.part(own_tets.clone());
        for (corners, t) in corners.iter_mut().zip(own_tets) {
            let moves = tets[t].map(|k| d[k as usize]);
            *corners = elastic_product(&family.tets[t], &linear[t], moves);
        }
    }
    member.wait();
    // SAFETY: nobody writes the moves or the corners; these nodes' products are this
    // member's.
    unsafe {
        let (d, corners, held) = (cg.trial.whole(), cg.corners.whole(), cg.held.whole());
        let q = cg.q.part(own.clone());
        for (j, i) in own.clone().enumerate() {
            let corner = |item: usize| corners[item / 4][item % 4];
            q[j] = family.product(i, w[i], dt, d[i], held[i], corner);
        }
    }
    let mut lengths = vec![1.0; parts.len()];
    let chunks = member.block(n.div_ceil(CHUNK));
    for (o, object) in family.free_objects.iter().enumerate() {
        if !held_objects[o] {
            continue;
        }
        member.wait();
        // SAFETY: nobody writes `r`, the moves or the products; these chunks' sums are
        // this member's.
        unsafe {
            let (r, d, q) = (cg.r.whole(), cg.trial.whole(), cg.q.whole());
            let sums = cg.pair_sums.part(2 * chunks.start..2 * chunks.end);
            for (c, sum) in chunks.clone().zip(sums.chunks_mut(2)) {
                let nodes = (c * CHUNK).max(object.start)..((c + 1) * CHUNK).min(object.end);
                let terms = nodes.map(|i| (f64::from(r[i].dot(d[i])), f64::from(d[i].dot(q[i]))));
                let (gain, curvature) = terms.fold((0.0, 0.0), |s, t| (s.0 + t.0, s.1 + t.1));
                (sum[0], sum[1]) = (gain, curvature);
            }
        }
        member.wait();
        // SAFETY: after a wait nobody writes the sums until the next phase.
        let sums = unsafe { cg.pair_sums.whole() };
        let gain = sums.iter().step_by(2).sum::<f64>();
        let curvature = sums.iter().skip(1).step_by(2).sum::<f64>();
        lengths[o] = correction_length(gain, curvature);
    }
    lengths
}
