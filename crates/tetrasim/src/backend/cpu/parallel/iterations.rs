//! A step's constraint iterations on a [`Team`](super::team::Team): every member solves
//! its block of each group's constraints, waits, applies the group's results to its block
//! of nodes, waits, and so on through the groups, the sweeps and the iterations; the
//! global volume constraints are summed in fixed chunks split among the members. Each
//! result is computed by one member with the same arithmetic and in the same order as on
//! one thread, so the states are bit-identical for any team size.

use super::shared::SharedSlice;
use super::team::Member;
use super::*;

/// What the constraints of a step read and never write.
#[derive(Clone, Copy)]
pub(super) struct Inputs<'a> {
    pub x: &'a [Vec3A],
    pub v: &'a [Vec3A],
    pub inv_mass: &'a [f32],
    pub k: Coefficients,
    pub floor: bool,
    pub springs: &'a [[u32; 2]],
    pub rest_length: &'a [f32],
    pub spring_softness: &'a [f32],
    pub spring_damping: &'a [f32],
    pub tets: &'a [[u32; 4]],
    pub rest_volume: &'a [f32],
    pub volume_softness: &'a [f32],
    /// The sweeps of an iteration, in order.
    pub sweeps: &'a [Sweep],
    /// The global volume constraints, prepared for this step.
    pub global: Option<&'a Global>,
    /// The Chebyshev weights, one per iteration (solver `chebyshev`).
    pub chebyshev_weights: Option<&'a [f32]>,
    pub iterations: usize,
}

/// What the members write, each its own part in each phase.
pub(super) struct Outputs<'a> {
    /// Total force per node.
    pub f: SharedSlice<'a, Vec3A>,
    /// Floor force per node.
    pub floor_force: SharedSlice<'a, f32>,
    /// Per sweep, per constraint in group order: the compliant multiplier so far.
    pub multipliers: Vec<SharedSlice<'a, f32>>,
    /// Per spring or distance constraint, in group order: force on end 0.
    pub pair_out: SharedSlice<'a, Vec3A>,
    /// Per volume constraint, in group order: force on each corner.
    pub tet_out: SharedSlice<'a, [Vec3A; 4]>,
    /// The Chebyshev forces two iterations back (total, floor).
    pub chebyshev: Option<(SharedSlice<'a, Vec3A>, SharedSlice<'a, f32>)>,
    /// One partial sum per chunk of an object's surface nodes (global constraints).
    pub partial: SharedSlice<'a, f32>,
}

/// Runs all iterations as `member`. Every member must run it, with the same inputs.
pub(super) fn run(member: Member<'_>, inputs: &Inputs<'_>, outputs: &Outputs<'_>) {
    let n = inputs.x.len();
    let nodes = member.block(n);
    let surface = inputs.global.map_or(Vec::new(), |g| surface_in(g, &nodes));
    let reach = reach(inputs, nodes.clone());
    for iteration in 0..inputs.iterations {
        for (s, sweep) in inputs.sweeps.iter().enumerate() {
            for g in 0..sweep.len() {
                let range = sweep.range(g);
                let block = member.block(range.len());
                let block = range.start + block.start..range.start + block.end;
                // SAFETY: solve phase (after the last wait, before the next): the members
                // write disjoint blocks of the group's constraint results and multipliers
                // and nobody writes `f`.
                unsafe { solve(inputs, outputs, s, g, block) };
                member.wait();
                // SAFETY: apply phase: each member writes only its own block of nodes
                // (forces, floor forces, Chebyshev state) and nobody writes the results.
                unsafe {
                    let reach = reach.as_deref();
                    apply(inputs, outputs, sweep, g, iteration, nodes.clone(), reach)
                };
                member.wait();
            }
        }
        if let Some(global) = inputs.global {
            for (o, mine) in surface.iter().enumerate() {
                // SAFETY: the phases of `global_pass` are separated by its waits.
                unsafe { global_pass(member, inputs, outputs, global, o, &nodes, mine) };
            }
        }
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
    // SAFETY: `block` is this thread's alone (the caller's promise).
    let so_far = unsafe { outputs.multipliers[s].part(block.clone()) };
    let (rest, tets_rest) = (inputs.rest_length, inputs.rest_volume);
    match sweep.kind {
        ConstraintKind::Spring => {
            let (softness, damping) = (inputs.spring_softness, inputs.spring_damping);
            // SAFETY: as `so_far`.
            let out = unsafe { outputs.pair_out.part(block) };
            solve_block(out, so_far, members, inputs.springs, on, |s, [xi, xj]| {
                let (c, grad) = spring_constraint(xi, xj, rest[s]);
                (c, grad, softness[s], damping[s])
            });
        }
        ConstraintKind::Distance => {
            // SAFETY: as `so_far`.
            let out = unsafe { outputs.pair_out.part(block) };
            solve_block(out, so_far, members, inputs.springs, on, |s, [xi, xj]| {
                let (c, grad) = distance_constraint(xi, xj, rest[s]);
                (c, grad, 0.0, 0.0)
            });
        }
        ConstraintKind::Volume => {
            let softness = inputs.volume_softness;
            // SAFETY: as `so_far`.
            let out = unsafe { outputs.tet_out.part(block) };
            solve_block(out, so_far, members, inputs.tets, on, |t, p| {
                let (c, grad) = volume_constraint(p, tets_rest[t]);
                (c, grad, softness[t], 0.0)
            });
        }
    }
}

/// Each node's [`floor_reach`] for `nodes`, when there is a floor.
fn reach(inputs: &Inputs<'_>, nodes: std::ops::Range<usize>) -> Option<Vec<f32>> {
    let (x, v, w, dt) = (inputs.x, inputs.v, inputs.inv_mass, inputs.k.dt);
    (inputs.floor).then(|| {
        nodes
            .map(|i| floor_reach(x[i].y, v[i].y, w[i], dt))
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
    let chebyshev = match (&outputs.chebyshev, inputs.chebyshev_weights) {
        (Some((before_f, before_n)), Some(weights)) => Some((
            // SAFETY: as `f`.
            unsafe { before_f.part(nodes.clone()) },
            // SAFETY: as `f`.
            unsafe { before_n.part(nodes) },
            weights[iteration],
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
                chebyshev,
                sweep,
                g,
                gather(out),
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
                chebyshev,
                sweep,
                g,
                gather(out),
            );
        }
    }
}

/// Object `o`'s global volume constraint against the current forces, then the floor's
/// solve of its surface nodes: the members sum `b` over fixed chunks of [`CHUNK`] surface
/// nodes (the partial sums added in chunk order, as on one thread), each works out the
/// same multiplier and applies it to its surface nodes `mine` (positions in
/// [`GlobalVolume::nodes`]), those in its block of nodes `nodes`.
///
/// # Safety
/// Every member must call it at the same point, between two waits.
unsafe fn global_pass(
    member: Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    global: &Global,
    o: usize,
    nodes: &std::ops::Range<usize>,
    mine: &[u32],
) {
    let (v, w, dt) = (inputs.v, inputs.inv_mass, inputs.k.dt);
    let object = &global.data.objects[o];
    let range = object.node_first as usize..(object.node_first + object.node_count) as usize;
    let surface = &global.data.nodes[range.clone()];
    let grad = &global.grad[range];
    let chunks = surface.len().div_ceil(CHUNK);
    let my_chunks = member.block(chunks);
    {
        // SAFETY: partial-sum phase: nobody writes `f`; the members write disjoint chunks
        // of `partial`.
        let (f, partial) = unsafe { (outputs.f.whole(), outputs.partial.part(my_chunks.clone())) };
        for (c, partial) in my_chunks.zip(partial) {
            let chunk = c * CHUNK..((c + 1) * CHUNK).min(surface.len());
            let (mut a, mut b) = (0.0f32, 0.0f32);
            for (&i, &g) in surface[chunk.clone()].iter().zip(&grad[chunk]) {
                let i = i as usize;
                implicit_accumulate(&mut a, &mut b, g, w[i], 1.0, v[i], f[i], dt);
            }
            *partial = b;
        }
    }
    member.wait();
    // SAFETY: apply phase: nobody writes `partial`; each member writes only its own block
    // of nodes.
    let (partial, f, floor_force) = unsafe {
        (
            outputs.partial.whole(),
            outputs.f.part(nodes.clone()),
            outputs.floor_force.part(nodes.clone()),
        )
    };
    let b: f32 = partial[..chunks].iter().sum();
    let (c, a) = global.c_and_a[o];
    let lambda = implicit_multiplier(c, a, b, dt, inputs.k.epsilon).unwrap_or(0.0);
    for &k in mine {
        let (i, g) = (
            global.data.nodes[k as usize] as usize,
            global.grad[k as usize],
        );
        let (f, n) = (&mut f[i - nodes.start], &mut floor_force[i - nodes.start]);
        *f -= g * lambda;
        if inputs.floor {
            (*f, *n) = floor_solve(*f, *n, inputs.x[i].y, v[i].y, w[i], dt);
        }
    }
    member.wait();
}
