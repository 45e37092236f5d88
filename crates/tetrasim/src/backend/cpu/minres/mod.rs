//! MINRES on a step's constraint rows ([`StepRows`]; docs/PHYSICS.md, "MINRES after the
//! sweeps"), run by a [`Team`]: the solve both CPU backends run after the sweeps, `cpu` on
//! its team of threads, `cpu-ref` on a team of one. Its vectors are in double precision;
//! the gradients and the matrix product in the rows' ([`StepRows`]).
//!
//! The sweeps converge the step's system one constraint at a time, so a body's slowest
//! modes (a stiff body squashing on the floor) take hundreds of sweeps. MINRES (Paige and
//! Saunders 1975) converges them in tens of iterations, each one product with the matrix:
//! a pass over the constraints to the nodes and one back. MINRES, not conjugate gradients:
//! both minimise over the same Krylov space, but MINRES the residual `r` (each
//! constraint's violation), which never grows from one iteration to the next. Conjugate
//! gradients minimise the error in the forces' energy norm, and cut short at a single-node
//! contact their intermediate forces threw the rigid sphere off the floor (measured;
//! docs/PHYSICS.md). The preconditioner is the rows' diagonal `A + s`.
//!
//! Before the first iteration each member computes its rows' preconditioner and its
//! nodes' mobility and transposed gradients; after the last, the force the increments take
//! off its nodes. The transpose's shape is kept from step to step while the rows' shape is
//! the same. An iteration is three phases between the team's barriers:
//! 1. the product's pass to the nodes, each member its block of nodes, through the rows'
//!    transpose ([`NodeRows`]), so that no two members add to one node;
//! 2. each member's chunks of [`CHUNK`] rows: the last iteration's update of the search
//!    direction and the solution, the product's pass back to the rows, and the first dot
//!    product;
//! 3. the next Lanczos vector and the second dot product (its norm). Every member then
//!    computes the same scalars: the QR factorisation's rotation.
//!
//! The first two phases share their nodes and chunks out by the entries they sum
//! ([`ROW_WEIGHT`]), the third its rows by count (the same work on each).
//!
//! A dot product is summed per chunk, and every member adds the chunks' sums in order, so
//! the solve gives the same bits on a team of any size. (The norm of phase 3 also follows
//! from phase 2's sums in exact arithmetic, `|av|^2 - alpha^2`, which would save a phase;
//! in floating point its error grew tenfold per iteration, so it is computed.)

use crate::backend::cpu::shared::SharedSlice;
use crate::backend::cpu::team::{Member, Team};
use crate::physics::{Held, Mobility, NodeRows, Real, StepRows, Vector};

/// Rows per chunk of a dot product's partial sums; fixed, so that the sums do not depend
/// on the team's size.
const CHUNK: usize = 256;

/// A row's work in the product's pass back to the rows (its vectors' updates), counted in
/// entries (a gradient and the node vector it multiplies): the rows' chunks are shared out
/// by rows plus entries ([`Member::weighted_block`]), the nodes by their entries. Shared
/// by row count, a team of two gave its second member the four-entry tets and the global
/// constraint: on the horse (docs/PHYSICS.md, "MINRES's work shared by entries") that pass
/// took 12.6 ms per step on one member and 19.9 on the other, 14.5 on both with this
/// weight (2 and 3 measured no better).
const ROW_WEIGHT: usize = 1;

/// A MINRES solve's memory, kept from one step to the next (a step's vectors, allocated
/// anew, paid for their pages; the transpose's shape, built anew, cost the horse a tenth of
/// its step).
#[derive(Debug, Clone, Default)]
pub(super) struct Minres<V: Vector> {
    /// The rows the transpose was built from (their shape is what counts), its shape, and
    /// the running totals of the chunks' and nodes' weights.
    shape: StepRows<V>,
    transpose: NodeRows,
    chunk_ends: Vec<usize>,
    node_ends: Vec<usize>,
    /// The gradient at each position of the transpose.
    grads: Vec<V>,
    mobility: Vec<Held<V>>,
    /// The preconditioner: `1 / (A + s)` of each row, 0 on those left to the sweeps
    /// (whose increments stay 0).
    inverse: Vec<f64>,
    /// The solution.
    x: Vec<f64>,
    /// The last two Lanczos vectors `r1`, `r2`, which swap storage each iteration.
    r: [Vec<f64>; 2],
    /// The preconditioned Lanczos vector `y = M^-1 r2`, and the last iteration's
    /// `v = y / beta`.
    y: Vec<f64>,
    v: Vec<f64>,
    /// The last two search directions `w1`, `w`, which swap storage each iteration.
    w: [Vec<f64>; 2],
    /// The product `A v` less the last-but-one Lanczos vector.
    av: Vec<f64>,
    /// The product's node vector `W J^T v`.
    u: Vec<V>,
    /// Per chunk, the partial sums `v . av` and `r2 . M^-1 r2` of an iteration.
    sums: [Vec<f64>; 2],
    /// The force the increments take off each node ([`Minres::node_force`]).
    forces: Vec<V>,
}

/// The solve's data every member reads.
struct Data<'a, V: Vector> {
    rows: &'a StepRows<V>,
    transpose: &'a NodeRows,
    chunk_ends: &'a [usize],
    node_ends: &'a [usize],
    mobility: &'a [Mobility],
    iterations: u32,
}

/// The solve's vectors, written by the members in parts ([`SharedSlice`]).
struct Vectors<'a, V: Vector> {
    grads: SharedSlice<'a, V>,
    mobility: SharedSlice<'a, Held<V>>,
    inverse: SharedSlice<'a, f64>,
    x: SharedSlice<'a, f64>,
    r: [SharedSlice<'a, f64>; 2],
    y: SharedSlice<'a, f64>,
    v: SharedSlice<'a, f64>,
    w: [SharedSlice<'a, f64>; 2],
    av: SharedSlice<'a, f64>,
    u: SharedSlice<'a, V>,
    sums: [SharedSlice<'a, f64>; 2],
    forces: SharedSlice<'a, V>,
}

impl<V: Vector + Send + Sync> Minres<V> {
    /// `iterations` of preconditioned MINRES on `rows`, each node moving with its
    /// `mobility` (what the floor, colliders and grabs hold taken out), solved by `team`:
    /// the multiplier increments ([`Minres::increments`]) and the forces they take off the
    /// nodes ([`Minres::node_force`]). Rows the holding leaves less than [`HELD_SHARE`](crate::physics::HELD_SHARE) of
    /// their mobility, or none, get 0.
    pub(super) fn solve(
        &mut self,
        team: &Team,
        rows: &StepRows<V>,
        mobility: &[Mobility],
        iterations: u32,
    ) {
        let (m, n) = (rows.len(), mobility.len());
        if self.transpose.nodes() != n || !rows.same_shape(&self.shape) {
            rows.transpose(n, &mut self.transpose);
            self.shape.clone_from(rows);
            weights(
                rows,
                &self.transpose,
                &mut self.chunk_ends,
                &mut self.node_ends,
            );
        }
        // Every vector is written before it is read (the members zero theirs first).
        let [r1, r2] = &mut self.r;
        let [w1, w2] = &mut self.w;
        for vector in [
            &mut self.inverse,
            &mut self.x,
            r1,
            r2,
            &mut self.y,
            &mut self.v,
        ] {
            vector.resize(m, 0.0);
        }
        for vector in [w1, w2, &mut self.av] {
            vector.resize(m, 0.0);
        }
        self.grads
            .resize(self.transpose.entries_of(0..n).len(), V::ZERO);
        self.mobility.resize(n, Mobility::free(0.0).rounded());
        self.u.resize(n, V::ZERO);
        self.forces.resize(n, V::ZERO);
        for sums in &mut self.sums {
            sums.resize(m.div_ceil(CHUNK), 0.0);
        }
        let Minres {
            shape: _,
            transpose,
            chunk_ends,
            node_ends,
            grads,
            mobility: held,
            inverse,
            x,
            r: [r1, r2],
            y,
            v,
            w: [w1, w2],
            av,
            u,
            sums: [sums_a, sums_b],
            forces,
        } = self;
        let data = Data {
            rows,
            transpose,
            chunk_ends,
            node_ends,
            mobility,
            iterations,
        };
        let vectors = Vectors {
            grads: SharedSlice::new(grads),
            mobility: SharedSlice::new(held),
            inverse: SharedSlice::new(inverse),
            x: SharedSlice::new(x),
            r: [SharedSlice::new(r1), SharedSlice::new(r2)],
            y: SharedSlice::new(y),
            v: SharedSlice::new(v),
            w: [SharedSlice::new(w1), SharedSlice::new(w2)],
            av: SharedSlice::new(av),
            u: SharedSlice::new(u),
            sums: [SharedSlice::new(sums_a), SharedSlice::new(sums_b)],
            forces: SharedSlice::new(forces),
        };
        // SAFETY: every member runs `iterate` once, with the same data.
        team.run(|member| unsafe { iterate(member, &data, &vectors) });
    }

    /// Each row's multiplier increment after [`Minres::solve`].
    pub(super) fn increments(&self) -> &[f64] {
        &self.x
    }

    /// The force the increments take off node `i` after [`Minres::solve`]: its share of
    /// `J^T delta` (in the rows' precision) less its part along the direction a contact
    /// holds. The solve leaves that part free: there the node does not move, so the
    /// increments can grow along combinations of rows whose only force is on held nodes,
    /// and the contact, which only pushes, would not take a pull off the node (the sphere
    /// at 1 sweep and 34 iterations: increments of 1e6, the body thrown off the floor).
    /// The contact's own solve, which follows, decides that part.
    pub(super) fn node_force(&self, i: usize) -> V {
        self.forces[i]
    }
}

/// The running totals of the weights of the rows' chunks (`ROW_WEIGHT` a row, one an
/// entry) and of the nodes (their entries) into `chunk_ends` and `node_ends`, each
/// starting at 0.
fn weights<V: Vector>(
    rows: &StepRows<V>,
    transpose: &NodeRows,
    chunk_ends: &mut Vec<usize>,
    node_ends: &mut Vec<usize>,
) {
    let m = rows.len();
    let mut entries = vec![0; m.div_ceil(CHUNK)];
    rows.each(|j, _, _| entries[j as usize / CHUNK] += 1);
    chunk_ends.clear();
    chunk_ends.push(0);
    for (c, entries) in entries.into_iter().enumerate() {
        let chunk_rows = ((c + 1) * CHUNK).min(m) - c * CHUNK;
        chunk_ends.push(chunk_ends[c] + ROW_WEIGHT * chunk_rows + entries);
    }
    node_ends.clear();
    node_ends.extend((0..=transpose.nodes()).map(|i| transpose.entries_of(0..i).end));
}

/// The scalars of MINRES's recurrence: the Lanczos coefficients and the QR factorisation of
/// their tridiagonal matrix, one Givens rotation per iteration. Every member keeps its own,
/// the same.
struct Recurrence {
    beta: f64,
    old_beta: f64,
    dbar: f64,
    epsilon: f64,
    phibar: f64,
    cs: f64,
    sn: f64,
}

/// One iteration's update of the search directions and the solution:
/// `w_new = (v - old_epsilon w1 - delta w) / gamma`, `x += phi w_new`.
struct Update {
    old_epsilon: f64,
    delta: f64,
    over_gamma: f64,
    phi: f64,
}

impl Update {
    /// Applies it to a member's rows, the new direction written over `w1` (so that `w`
    /// becomes the next `w1`).
    fn apply(&self, v: &[f64], w1: &mut [f64], w: &[f64], x: &mut [f64]) {
        for (((v, w1), w), x) in v.iter().zip(w1).zip(w).zip(x) {
            let next = (v - self.old_epsilon * *w1 - self.delta * w) * self.over_gamma;
            *w1 = next;
            *x += self.phi * next;
        }
    }
}

impl Recurrence {
    /// The start, from the first Lanczos vector's norm `beta`.
    fn new(beta: f64) -> Self {
        Recurrence {
            beta,
            old_beta: 0.0,
            dbar: 0.0,
            epsilon: 0.0,
            phibar: beta,
            cs: -1.0,
            sn: 0.0,
        }
    }

    /// The factor of the last-but-one Lanczos vector taken off the product.
    fn back(&self) -> f64 {
        if self.old_beta > 0.0 {
            self.beta / self.old_beta
        } else {
            0.0
        }
    }

    /// The next rotation, from the iteration's `alpha` and next `beta`: the update, or
    /// `None` where the factorisation breaks down.
    fn advance(&mut self, alpha: f64, beta: f64) -> Option<Update> {
        self.old_beta = self.beta;
        self.beta = beta;
        let old_epsilon = self.epsilon;
        let delta = self.cs * self.dbar + self.sn * alpha;
        let gbar = self.sn * self.dbar - self.cs * alpha;
        self.epsilon = self.sn * beta;
        self.dbar = -self.cs * beta;
        let gamma = gbar.hypot(beta);
        if !(gamma > 0.0 && gamma.is_finite()) {
            return None;
        }
        (self.cs, self.sn) = (gbar / gamma, beta / gamma);
        let phi = self.cs * self.phibar;
        self.phibar *= self.sn;
        Some(Update {
            old_epsilon,
            delta,
            over_gamma: 1.0 / gamma,
            phi,
        })
    }
}

/// The sum of a dot product's partial sums, in chunk order.
///
/// # Safety
/// Nobody may write `sums` during the call.
unsafe fn total(sums: &SharedSlice<'_, f64>) -> f64 {
    // SAFETY: the caller's promise.
    unsafe { sums.whole() }.iter().sum()
}

/// One member's part of the solve: its chunks of rows and its block of nodes, phase by
/// phase (the module docs). Between two barriers each member writes only its own rows of
/// the row vectors, its own chunks of the sums and its own nodes of the node vectors; what
/// it reads of the others' nobody writes until the next barrier.
///
/// # Safety
/// Every member of the team calls it at once, with the same `data` and `vectors`.
unsafe fn iterate<V: Vector>(member: Member<'_>, data: &Data<'_, V>, vectors: &Vectors<'_, V>) {
    let m = data.rows.len();
    let chunks = member.weighted_block(data.chunk_ends);
    let own = (chunks.start * CHUNK).min(m)..(chunks.end * CHUNK).min(m);
    let nodes = member.weighted_block(data.node_ends);
    let entries = data.transpose.entries_of(nodes.clone());
    // The member's rows' preconditioner and the vectors that start at 0; its nodes'
    // mobility and the transpose's gradients (read by others only after the first barrier).
    {
        // SAFETY: above.
        let (inverse, x, r1, w1, w2, held, grads) = unsafe {
            (
                vectors.inverse.part(own.clone()),
                vectors.x.part(own.clone()),
                vectors.r[0].part(own.clone()),
                vectors.w[0].part(own.clone()),
                vectors.w[1].part(own.clone()),
                vectors.mobility.part(nodes.clone()),
                vectors.grads.part(entries.clone()),
            )
        };
        data.rows
            .preconditioner(own.clone(), data.mobility, inverse);
        for vector in [x, r1, w1, w2] {
            vector.fill(0.0);
        }
        for (held, mobility) in held.iter_mut().zip(&data.mobility[nodes.clone()]) {
            *held = mobility.rounded();
        }
        for (g, &e) in grads.iter_mut().zip(data.transpose.entries(entries)) {
            *g = data.rows.entry_grad(e);
        }
    }
    // SAFETY: the caller's promise.
    unsafe { lanczos(member, data, vectors, &chunks, &own, &nodes) };
    member.wait();
    // The force the increments take off each of the member's nodes, less the held part.
    {
        // SAFETY: above.
        let (x, grads, held, forces) = unsafe {
            (
                vectors.x.whole(),
                vectors.grads.whole(),
                vectors.mobility.whole(),
                vectors.forces.part(nodes.clone()),
            )
        };
        for (i, force) in nodes.zip(forces) {
            *force = held[i].unheld(data.transpose.sum(grads, i, x));
        }
    }
}

/// The iterations of [`iterate`]: the member's rows `own` (its `chunks`) and `nodes`.
///
/// # Safety
/// As [`iterate`]'s, every member past its first phase.
unsafe fn lanczos<V: Vector>(
    member: Member<'_>,
    data: &Data<'_, V>,
    vectors: &Vectors<'_, V>,
    chunks: &std::ops::Range<usize>,
    own: &std::ops::Range<usize>,
    nodes: &std::ops::Range<usize>,
) {
    let (chunks, own, nodes) = (chunks.clone(), own.clone(), nodes.clone());
    // Phase 3's rows: the same work on each, so shared out by count.
    let m = data.rows.len();
    let even_chunks = member.block(m.div_ceil(CHUNK));
    let even = (even_chunks.start * CHUNK).min(m)..(even_chunks.end * CHUNK).min(m);
    let softness = &data.rows.softness()[own.clone()];
    // Chunk `c` of a member's rows, counted from their first.
    let chunk =
        |c: usize, rows: &std::ops::Range<usize>| c * CHUNK..((c + 1) * CHUNK).min(rows.len());
    // What the members read of the others' parts: `y`, the gradients and the mobility in
    // phase 1, `u` in phase 2, the sums after their phase.
    let [alphas, norms] = &vectors.sums;
    // The first Lanczos vector: r2 = r (r1 = 0), y = M^-1 r2, beta^2 = r2 . y.
    {
        // SAFETY: above; only this member writes its rows of `inverse`, and it no longer does.
        let (inverse, r2, y, norms) = unsafe {
            (
                vectors.inverse.part(own.clone()),
                vectors.r[1].part(own.clone()),
                vectors.y.part(own.clone()),
                norms.part(chunks.clone()),
            )
        };
        let residual = &data.rows.residual()[own.clone()];
        for (c, norm) in (0..chunks.len()).zip(norms) {
            let mut sum = 0.0;
            let range = chunk(c, &own);
            let (r2, y) = (&mut r2[range.clone()], &mut y[range.clone()]);
            let (inverse, residual) = (&inverse[range.clone()], &residual[range]);
            for (((r2, y), &inverse), &residual) in r2.iter_mut().zip(y).zip(inverse).zip(residual)
            {
                *r2 = if inverse > 0.0 { residual } else { 0.0 };
                *y = *r2 * inverse;
                sum += *r2 * *y;
            }
            *norm = sum;
        }
    }
    member.wait();
    // SAFETY: above.
    let beta = unsafe { total(norms) };
    if !(beta > 0.0 && beta.is_finite()) {
        return;
    }
    // SAFETY: nobody writes `inverse` any more.
    let inverse_all: &[f64] = unsafe { vectors.inverse.whole() };
    let inverse = &inverse_all[own.clone()];
    let mut recurrence = Recurrence::new(beta.sqrt());
    // The last iteration's update of the search directions and the solution, made in the
    // next iteration's pass over the rows (or after the last).
    let mut pending: Option<Update> = None;
    // r1 is `r[r_at]`, r2 the other; w1 is `w[w_at]`, w the other.
    let (mut r_at, mut w_at) = (0, 0);
    for _ in 0..data.iterations {
        let over_beta = 1.0 / recurrence.beta;
        // 1. u = W J^T v on the member's nodes, v = y / beta.
        {
            // SAFETY: above.
            let (y, u, grads, held) = unsafe {
                (
                    vectors.y.whole(),
                    vectors.u.part(nodes.clone()),
                    vectors.grads.whole(),
                    vectors.mobility.whole(),
                )
            };
            let scale = V::Real::from_f64(over_beta);
            for (i, u) in nodes.clone().zip(u) {
                *u = held[i].apply(data.transpose.sum(grads, i, y) * scale);
            }
        }
        member.wait();
        // 2. The last iteration's update (with its v), then v = y / beta, av = (J u + s v)
        // on the live rows - back r1, and per chunk v . av.
        let back = recurrence.back();
        {
            // SAFETY: above.
            let (u, y, v, r1, av, w1, w, x, alphas) = unsafe {
                (
                    vectors.u.whole(),
                    vectors.y.part(own.clone()),
                    vectors.v.part(own.clone()),
                    vectors.r[r_at].part(own.clone()),
                    vectors.av.part(own.clone()),
                    vectors.w[w_at].part(own.clone()),
                    vectors.w[1 - w_at].part(own.clone()),
                    vectors.x.part(own.clone()),
                    alphas.part(chunks.clone()),
                )
            };
            if let Some(update) = pending.take() {
                update.apply(v, w1, w, x);
                w_at = 1 - w_at;
            }
            av.fill(0.0);
            data.rows.gather(own.clone(), u, av);
            for (c, alpha) in (0..chunks.len()).zip(alphas) {
                let mut sum = 0.0;
                let range = chunk(c, &own);
                let (v, av) = (&mut v[range.clone()], &mut av[range.clone()]);
                let (y, r1) = (&y[range.clone()], &r1[range.clone()]);
                let (inverse, softness) = (&inverse[range.clone()], &softness[range]);
                let rows = (v.iter_mut().zip(av).zip(y).zip(r1)).zip(inverse.iter().zip(softness));
                for ((((v, av), &y), &r1), (&inverse, &softness)) in rows {
                    *v = y * over_beta;
                    let product = match inverse > 0.0 {
                        true => *av + softness * *v,
                        false => 0.0,
                    };
                    *av = product - back * r1;
                    sum += *v * *av;
                }
                *alpha = sum;
            }
        }
        member.wait();
        // 3. The next Lanczos vector r2' = av - (alpha / beta) r2 (in r1's storage: r2
        // becomes the next r1), y = M^-1 r2', and per chunk r2' . y.
        // SAFETY: above.
        let alpha = unsafe { total(alphas) };
        let along = alpha / recurrence.beta;
        {
            // SAFETY: above.
            let (av, r1, r2, y, norms) = unsafe {
                (
                    vectors.av.part(even.clone()),
                    vectors.r[r_at].part(even.clone()),
                    vectors.r[1 - r_at].part(even.clone()),
                    vectors.y.part(even.clone()),
                    norms.part(even_chunks.clone()),
                )
            };
            let inverse = &inverse_all[even.clone()];
            for (c, norm) in (0..even_chunks.len()).zip(norms) {
                let mut sum = 0.0;
                let range = chunk(c, &even);
                let (r1, y) = (&mut r1[range.clone()], &mut y[range.clone()]);
                let (av, r2, inverse) = (&av[range.clone()], &r2[range.clone()], &inverse[range]);
                for ((((r1, y), &av), &r2), &inverse) in
                    r1.iter_mut().zip(y).zip(av).zip(r2).zip(inverse)
                {
                    *r1 = av - along * r2;
                    *y = *r1 * inverse;
                    sum += *r1 * *y;
                }
                *norm = sum;
            }
        }
        r_at = 1 - r_at;
        member.wait();
        // SAFETY: above.
        let beta = unsafe { total(norms) }.max(0.0).sqrt();
        pending = recurrence.advance(alpha, beta);
        if pending.is_none() || beta == 0.0 {
            break;
        }
    }
    if let Some(update) = &pending {
        // SAFETY: above.
        let (v, w1, w, x) = unsafe {
            (
                vectors.v.part(own.clone()),
                vectors.w[w_at].part(own.clone()),
                vectors.w[1 - w_at].part(own.clone()),
                vectors.x.part(own.clone()),
            )
        };
        update.apply(v, w1, w, x);
    }
}

#[cfg(test)]
mod tests;
