//! A step's constraint iterations on a [`Team`](crate::backend::cpu::team::Team): every member runs the
//! schedule's per-iteration dispatches ([`crate::schedule::Schedule::step`]) in order, its
//! share of each (its block of a group's constraints, its block of nodes, its chunks of the
//! surfaces), and waits for the others after each. Each result is computed by one member
//! with the same arithmetic and in the same order as on one thread, so the states are
//! bit-identical for any team size.

use super::*;
use crate::backend::cpu::shared::SharedSlice;
use crate::backend::cpu::team::Member;
use crate::contact::{BodyContact, Contact};

/// What the constraints of a step read and never write.
#[derive(Clone, Copy)]
pub(super) struct Inputs<'a> {
    pub x: &'a [Vec3A],
    pub v: &'a [Vec3A],
    pub inv_mass: &'a [f32],
    /// Per tet: its rest volume.
    pub rest_volume: &'a [f32],
    /// Per tet: its nodes.
    pub tets: &'a [[u32; 4]],
    pub k: Coefficients,
    pub floor: bool,
    /// The step's index, counted from the backend's start (its clock).
    pub step: u64,
    /// The colliders of the step, when there are any.
    pub colliders: Option<Colliders<'a>>,
    /// Body contact and the problem it belongs to, when two surfaces can meet.
    pub bodies: Option<(&'a BodyContact, &'a Problem)>,
    /// The sweeps of an iteration, in order.
    pub sweeps: &'a [Sweep],
    /// The global volume constraints, prepared for this step.
    pub global: Option<&'a Global>,
    /// The Chebyshev weights, one per iteration (solver `chebyshev`).
    pub chebyshev_weights: Option<&'a [f32]>,
    /// Anderson acceleration's memory (0: off).
    pub anderson: u32,
    /// Whether it mixes the volume constraints' multipliers ([`Schedule::anderson_volumes`]).
    pub anderson_volumes: bool,
    /// The pass of each stage of the schedule.
    pub stages: &'a [PassKind],
    /// The step's per-iteration dispatches, in order.
    pub dispatches: &'a [Dispatch],
}

/// What the members write, each its own part in each phase.
pub(super) struct Outputs<'a> {
    /// Total force per node.
    pub f: SharedSlice<'a, Vec3A>,
    /// Floor force per node.
    pub floor_force: SharedSlice<'a, f32>,
    /// Collider force per node (empty without colliders).
    pub contact: SharedSlice<'a, Vec3A>,
    /// The step's body contacts and their multipliers.
    pub body_contacts: SharedSlice<'a, (Contact, f64)>,
    /// Per sweep, per constraint in group order: the compliant multiplier so far.
    pub multipliers: Vec<SharedSlice<'a, f32>>,
    /// Per spring or distance constraint, in group order: force on end 0.
    pub pair_out: SharedSlice<'a, Vec3A>,
    /// Per volume constraint, in group order: force on each corner.
    pub tet_out: SharedSlice<'a, [Vec3A; 4]>,
    /// Finite elements: per node, in group order, its step's force increment.
    pub node_out: SharedSlice<'a, Vec3A>,
    /// Finite elements: the conjugate gradients' vectors.
    pub newton: super::newton::NewtonShared<'a>,
    /// The Chebyshev forces two iterations back (total, floor).
    pub chebyshev: Option<(SharedSlice<'a, Vec3A>, SharedSlice<'a, f32>)>,
    /// Per chunk of every object's surface nodes, object after object (global
    /// constraints): the chunk's partial sums of `B` and of the floor's held terms.
    pub partial: SharedSlice<'a, [f32; 2]>,
    /// Anderson acceleration's history planes, per-chunk sums and multipliers' history
    /// (`anderson > 0`).
    pub anderson: Option<(
        SharedSlice<'a, Vec3A>,
        SharedSlice<'a, f64>,
        SharedSlice<'a, f32>,
    )>,
}

/// Runs all iterations as `member`. Every member must run it, with the same inputs.
pub(super) fn run(member: Member<'_>, inputs: &Inputs<'_>, outputs: &Outputs<'_>) {
    let n = inputs.x.len();
    let nodes = member.block(n);
    let surface = inputs.global.map_or(Vec::new(), |g| surface_in(g, &nodes));
    let reach = reach(inputs, nodes.clone());
    let mut newton = super::elastic::NewtonScalars::default();
    for dispatch in inputs.dispatches {
        let iteration = dispatch.iteration.unwrap_or(0) as usize;
        match (inputs.stages[dispatch.stage], dispatch.group) {
            (PassKind::SpringConstraint | PassKind::Distance | PassKind::Volume, Some(at))
                if inputs.sweeps[at.sweep].blocks.is_some() =>
            {
                let blocks = inputs.sweeps[at.sweep]
                    .blocks
                    .as_ref()
                    .map_or(0, |b| b.len());
                // SAFETY: solve phase: the members solve disjoint runs of whole blocks
                // (their results and multipliers) and nobody writes `f`.
                unsafe { super::blocks::solve(inputs, outputs, at.sweep, member.block(blocks)) };
            }
            (PassKind::SpringConstraint | PassKind::Distance | PassKind::Volume, Some(at)) => {
                let range = inputs.sweeps[at.sweep].range(at.group);
                let block = member.block(range.len());
                let block = range.start + block.start..range.start + block.end;
                // SAFETY: solve phase (after the last wait, before the next): the members
                // write disjoint blocks of the group's constraint results and multipliers
                // and nobody writes `f`.
                unsafe { solve(inputs, outputs, at.sweep, at.group, block) };
            }
            (PassKind::Elastic, Some(at)) => {
                if newton.linearises(iteration) {
                    // The contacts as the forces so far leave them: the nodes they hold.
                    // SAFETY: each member solves only its own block of nodes.
                    unsafe { resolve_contacts(inputs, outputs, &nodes, reach.as_deref()) };
                    member.wait();
                }
                // SAFETY: every member calls it with the same arguments, and nobody else
                // touches the forces, the node results or the vectors meanwhile.
                unsafe {
                    super::elastic::iteration(
                        &member,
                        inputs,
                        outputs,
                        at.sweep,
                        iteration,
                        &mut newton,
                    )
                };
            }
            (PassKind::InversionFloor, Some(at)) if inputs.sweeps[at.sweep].blocks.is_some() => {
                let blocks = inputs.sweeps[at.sweep]
                    .blocks
                    .as_ref()
                    .map_or(0, |b| b.len());
                // SAFETY: solve phase: the members take disjoint runs of whole blocks (their
                // results) and nobody writes `f`.
                unsafe {
                    super::inversion::floor_blocks(inputs, outputs, at.sweep, member.block(blocks))
                };
            }
            (PassKind::InversionFloor, Some(at)) => {
                let range = inputs.sweeps[at.sweep].range(at.group);
                let block = member.block(range.len());
                let block = range.start + block.start..range.start + block.end;
                // SAFETY: solve phase, as for the constraints: the members write disjoint
                // blocks of the group's results and nobody writes `f`.
                unsafe { super::inversion::floor(inputs, outputs, at.sweep, at.group, block) };
            }
            (PassKind::ConstraintApply, Some(at)) => {
                let sweep = &inputs.sweeps[at.sweep];
                let reach = reach.as_deref();
                // SAFETY: apply phase: each member writes only its own block of nodes
                // (forces, floor forces, Chebyshev state) and nobody writes the results.
                unsafe {
                    apply(
                        inputs,
                        outputs,
                        sweep,
                        at.group,
                        iteration,
                        nodes.clone(),
                        reach,
                    )
                };
            }
            (PassKind::GlobalVolumeSum, _) => {
                if let Some(global) = inputs.global {
                    // SAFETY: partial-sum phase: nobody writes `f`; the members write
                    // disjoint chunks of `partial`.
                    unsafe { global_sums(member, inputs, outputs, global) };
                }
            }
            (PassKind::ContactSolve, _) => {
                if let Some(bodies) = inputs.bodies {
                    if member.leads() {
                        // SAFETY: serial phase: the other members wait at the barrier.
                        unsafe { contact_sweep(inputs, outputs, bodies) };
                    }
                    member.wait();
                    // SAFETY: apply phase: each member writes only its own block of nodes.
                    unsafe { resolve_contacts(inputs, outputs, &nodes, reach.as_deref()) };
                }
            }
            (PassKind::AndersonSum, _) => {
                let iteration = iteration as u32;
                // SAFETY: sum phase: nobody writes the forces; the members write their own
                // chunks' history and sums.
                unsafe { super::anderson::sum(member, inputs, outputs, iteration) };
            }
            (PassKind::AndersonMix, _) => {
                let iteration = iteration as u32;
                // SAFETY: mix phase, after the sums and a wait: nobody writes the sums; the
                // members write their own chunks' nodes.
                unsafe { super::anderson::mix(member, inputs, outputs, iteration) };
            }
            // The GPU's application of the contact sums: `contact_solve` applies here.
            (PassKind::ContactApply, _) => continue,
            (PassKind::GlobalVolume, _) => {
                if let Some(global) = inputs.global {
                    // SAFETY: apply phase: nobody writes `partial`; each member writes
                    // only its own block of nodes.
                    unsafe { global_apply(inputs, outputs, global, &nodes, &surface) };
                }
            }
            _ => continue,
        }
        member.wait();
    }
}

/// Per object: the positions (in [`GlobalVolume::nodes`], in order) of its surface nodes
/// that lie in `nodes`.
fn surface_in(global: &Global, nodes: &std::ops::Range<usize>) -> Vec<Vec<u32>> {
    (global.data.objects.iter())
        .map(|object| {
            let first = object.node_first as usize;
            (first..first + object.node_count as usize)
                .filter(|&k| nodes.contains(&(global.data.nodes[k] as usize)))
                .map(|k| k as u32)
                .collect()
        })
        .collect()
}

/// The solve of constraints `block` (positions in `members.items`) of group `g` of sweep
/// `s` against the current forces.
///
/// # Safety
/// No other thread may touch `block` of the results and multipliers, or write `f`,
/// during the call.
unsafe fn solve(
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    s: usize,
    g: usize,
    block: std::ops::Range<usize>,
) {
    let sweep = &inputs.sweeps[s];
    let n = inputs.x.len();
    let on = Nodes {
        x: inputs.x,
        v: inputs.v,
        // SAFETY: nobody writes `f` (the caller's promise).
        f: unsafe { outputs.f.whole() },
        w: inputs.inv_mass,
        a_scale: &sweep.a_scale[g * n..(g + 1) * n],
        k: inputs.k,
    };
    let members = &sweep.members.items[block.clone()];
    let (pairs, tets) = (&sweep.pair_nodes, &sweep.tet_nodes);
    // SAFETY: `block` is this thread's alone (the caller's promise).
    let so_far = unsafe { outputs.multipliers[s].part(block.clone()) };
    match &sweep.family {
        Family::Springs(family) => {
            // SAFETY: `block` of the results is this thread's alone, as `so_far`.
            let out = unsafe { outputs.pair_out.part(block.clone()) };
            solve_block(out, so_far, members, &pairs[block], on, family);
        }
        Family::Distances(family) => {
            // SAFETY: as above.
            let out = unsafe { outputs.pair_out.part(block.clone()) };
            solve_block(out, so_far, members, &pairs[block], on, family);
        }
        Family::Volumes(family) => {
            // SAFETY: as above.
            let out = unsafe { outputs.tet_out.part(block.clone()) };
            solve_block(out, so_far, members, &tets[block], on, family);
        }
        // Solved by `elastic` (its own pass).
        Family::Elastic(_) => {}
    }
}

/// One Jacobi sweep of the step's body contacts ([`BodyContact::sweep`] in double
/// precision), its forces added to the nodes they touch.
///
/// # Safety
/// No other thread may touch the forces or the body contacts during the call.
unsafe fn contact_sweep(
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    (bodies, problem): (&BodyContact, &Problem),
) {
    let (x, v) = (inputs.x, inputs.v);
    // SAFETY: the caller's promise.
    let (contacts, f) = unsafe {
        (
            outputs.body_contacts.part(0..outputs.body_contacts.len()),
            outputs.f.part(0..x.len()),
        )
    };
    let forces = {
        let f = &*f;
        bodies.sweep(
            contacts,
            &problem.model,
            &problem.params,
            inputs.k.solve,
            |i| x[i].to_dvec3(),
            |i| v[i].to_dvec3(),
            |i| f[i].to_dvec3(),
        )
    };
    for (i, force) in forces {
        f[i] += Vec3A::from_dvec3(force);
    }
}

/// The floor's and the colliders' solve of the nodes `nodes` (`reach`: their
/// [`floor_reach`], when there is a floor), after the body contacts moved their forces.
///
/// # Safety
/// No other thread may touch `nodes` of the forces, floor forces and collider forces.
unsafe fn resolve_contacts(
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    nodes: &std::ops::Range<usize>,
    reach: Option<&[f32]>,
) {
    // SAFETY: the caller's promise.
    let (f, floor_force) = unsafe {
        (
            outputs.f.part(nodes.clone()),
            outputs.floor_force.part(nodes.clone()),
        )
    };
    let contact = match inputs.colliders {
        // SAFETY: as above.
        Some(_) => unsafe { outputs.contact.part(nodes.clone()) },
        None => &mut [][..],
    };
    for (k, (f, n)) in f.iter_mut().zip(floor_force.iter_mut()).enumerate() {
        if let Some(reach) = reach {
            (*f, *n) = floor_solve_reach(*f, *n, reach[k]);
        }
        if let Some(colliders) = &inputs.colliders {
            colliders.solve(nodes.start + k, f, &mut contact[k]);
        }
    }
}

/// Each node's [`floor_reach`] for `nodes`, when there is a floor.
fn reach(inputs: &Inputs<'_>, nodes: std::ops::Range<usize>) -> Option<Vec<f32>> {
    let (x, v, w, dt) = (inputs.x, inputs.v, inputs.inv_mass, inputs.k.dt);
    (inputs.floor).then(|| {
        nodes
            .map(|i| floor_reach(x[i].y + inputs.k.solve.slack(x[i].y), v[i].y, w[i], dt))
            .collect()
    })
}

/// Group `g`'s results applied to the nodes `nodes` ([`apply_block`]).
///
/// # Safety
/// No other thread may touch `nodes` of the forces, floor forces and Chebyshev state, or
/// write the results, during the call.
unsafe fn apply(
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    sweep: &Sweep,
    g: usize,
    iteration: usize,
    nodes: std::ops::Range<usize>,
    reach: Option<&[f32]>,
) {
    let first = nodes.start;
    // SAFETY: `nodes` is this thread's alone (the caller's promise), here and below.
    let f = unsafe { outputs.f.part(nodes.clone()) };
    // SAFETY: as `f`.
    let floor_force = unsafe { outputs.floor_force.part(nodes.clone()) };
    let contact = inputs.colliders.map(|colliders| {
        // SAFETY: as `f`.
        (colliders, unsafe { outputs.contact.part(nodes.clone()) })
    });
    let chebyshev = match (&outputs.chebyshev, inputs.chebyshev_weights) {
        (Some((before_f, before_n)), Some(weights)) => Some((
            // SAFETY: as `f`.
            unsafe { before_f.part(nodes.clone()) },
            // SAFETY: as `f`.
            unsafe { before_n.part(nodes) },
            // 1 after the iterations (the inversion sweeps' applies).
            weights.get(iteration).copied().unwrap_or(1.0),
        )),
        _ => None,
    };
    match sweep.kind {
        ConstraintKind::Volume => {
            // SAFETY: nobody writes the results (the caller's promise).
            let out = unsafe { outputs.tet_out.whole() };
            apply_block(
                first,
                f,
                floor_force,
                reach,
                contact,
                chebyshev,
                sweep,
                g,
                gather::<4, _>(out),
            );
        }
        ConstraintKind::Elastic => {
            // SAFETY: nobody writes the results (the caller's promise).
            let out = unsafe { outputs.node_out.whole() };
            apply_block(
                first,
                f,
                floor_force,
                reach,
                contact,
                chebyshev,
                sweep,
                g,
                gather::<1, _>(out),
            );
        }
        _ => {
            // SAFETY: as above.
            let out = unsafe { outputs.pair_out.whole() };
            apply_block(
                first,
                f,
                floor_force,
                reach,
                contact,
                chebyshev,
                sweep,
                g,
                gather::<2, _>(out),
            );
        }
    }
}

/// The global volume constraints' chunks: per object, its first chunk in the partial sums
/// and its chunk count (chunks of [`CHUNK`] surface nodes).
pub(super) fn global_chunks(global: &Global) -> Vec<(usize, usize)> {
    let mut first = 0;
    (global.data.objects.iter())
        .map(|object| {
            let chunks = (object.node_count as usize).div_ceil(CHUNK);
            first += chunks;
            (first - chunks, chunks)
        })
        .collect()
}

/// The partial sums of `B` of every object's global volume constraint against the current
/// forces, and of the contacts' held terms ([`contact_held`]: the floor's and the
/// colliders'), over fixed chunks of [`CHUNK`] surface nodes split among the members.
///
/// # Safety
/// Nobody may write `f`, the floor forces or the collider forces during the call, and every
/// member must call it at the same point (each writes its own chunks of `partial`).
unsafe fn global_sums(
    member: Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    global: &Global,
) {
    let (v, w, dt) = (inputs.v, inputs.inv_mass, inputs.k.dt);
    let chunks: Vec<(usize, usize)> = (global_chunks(global).into_iter().enumerate())
        .flat_map(|(o, (_, count))| (0..count).map(move |c| (o, c)))
        .collect();
    let mine = member.block(chunks.len());
    // SAFETY: nobody writes `f`, the floor forces or the collider forces; the members write
    // disjoint chunks of `partial` (the caller's promise).
    let (f, floor_force, contact, partial) = unsafe {
        (
            outputs.f.whole(),
            outputs.floor_force.whole(),
            outputs.contact.whole(),
            outputs.partial.part(mine.clone()),
        )
    };
    for (&(o, c), partial) in chunks[mine].iter().zip(partial) {
        let object = &global.data.objects[o];
        let range = object.node_first as usize..(object.node_first + object.node_count) as usize;
        let (surface, grad) = (&global.data.nodes[range.clone()], &global.grad[range]);
        let chunk = c * CHUNK..((c + 1) * CHUNK).min(surface.len());
        let (mut a, mut b, mut held) = (0.0f32, 0.0f32, 0.0f32);
        for (&i, &g) in surface[chunk.clone()].iter().zip(&grad[chunk]) {
            let i = i as usize;
            implicit_accumulate(&mut a, &mut b, g, w[i], 1.0, v[i], f[i], dt);
            let push = contact.get(i).copied().unwrap_or(Vec3A::ZERO);
            held += contact_held(g, w[i], held_direction(floor_force[i] > 0.0, push));
        }
        *partial = [b, held];
    }
}

/// Every object's global volume multiplier from its partial sums (added in chunk order, as
/// on one thread), applied to the member's surface nodes `mine` (per object, positions in
/// [`GlobalVolume::nodes`] of those in its block of nodes `nodes`), then the floor's and the
/// colliders' solve of those nodes.
///
/// # Safety
/// Nobody may write `partial` during the call, or touch `nodes` of the forces and floor
/// forces but this member.
unsafe fn global_apply(
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    global: &Global,
    nodes: &std::ops::Range<usize>,
    mine: &[Vec<u32>],
) {
    let (v, w, dt) = (inputs.v, inputs.inv_mass, inputs.k.dt);
    // SAFETY: the caller's promise.
    let (partial, f, floor_force, contact) = unsafe {
        (
            outputs.partial.whole(),
            outputs.f.part(nodes.clone()),
            outputs.floor_force.part(nodes.clone()),
            match inputs.colliders {
                Some(_) => outputs.contact.part(nodes.clone()),
                None => &mut [][..],
            },
        )
    };
    for (o, (first, chunks)) in global_chunks(global).into_iter().enumerate() {
        let sums = &partial[first..first + chunks];
        let b: f32 = sums.iter().map(|s| s[0]).sum();
        let held: f32 = sums.iter().map(|s| s[1]).sum();
        let (c, a) = global.c_and_a[o];
        let c = inputs.k.solve.hard(c);
        let lambda = global_multiplier(c, a, b, held, dt, inputs.k.epsilon).unwrap_or(0.0);
        for &k in &mine[o] {
            let (i, g) = (
                global.data.nodes[k as usize] as usize,
                global.grad[k as usize],
            );
            let (f, n) = (&mut f[i - nodes.start], &mut floor_force[i - nodes.start]);
            *f -= g * lambda;
            if inputs.floor {
                let y = inputs.x[i].y + inputs.k.solve.slack(inputs.x[i].y);
                (*f, *n) = floor_solve(*f, *n, y, v[i].y, w[i], dt);
            }
            if let Some(colliders) = &inputs.colliders {
                colliders.solve(i, f, &mut contact[i - nodes.start]);
            }
        }
    }
}
