//! Anderson acceleration on the `cpu` team (src/physics/anderson.rs): `anderson_sum` and
//! `anderson_mix` as two phases. Each member takes a block of fixed [`CHUNK`]s of nodes,
//! stores their residuals and history columns and sums the normal equations' products per
//! chunk in double precision; then every member adds the chunks up in chunk order (the same
//! weights on every member, for any team size), mixes its nodes' forces and its block of
//! the multipliers, and solves its nodes' floor and colliders again.

use super::iterations::{Inputs, Outputs};
use super::*;
use crate::backend::cpu::team::Member;
use crate::physics::{
    anderson_weights, floor_solve, gram_index, gram_terms, AndersonIteration, ANDERSON_MAX_MEMORY,
};

/// The Gram terms a chunk keeps room for (those of the largest memory).
const TERMS: usize = gram_terms(ANDERSON_MAX_MEMORY as usize);

/// Anderson acceleration's arrays (`anderson > 0`).
#[derive(Debug, Clone)]
pub(super) struct Anderson {
    /// The history columns kept.
    pub memory: u32,
    /// Planes of one vector per node: `x`, `f`, `g`, then `memory` columns of `df`, then
    /// of `dg`.
    pub history: Vec<Vec3A>,
    /// Per chunk of nodes, its share of each Gram term.
    pub sums: Vec<f64>,
    /// The mixed sweeps' multipliers (one sweep after another) mixed with the same
    /// weights: planes of the last iteration's, then `memory` columns of their differences.
    pub multipliers: Vec<f32>,
    /// Whether the volume constraints' multipliers are mixed ([`mixes`]).
    pub volumes: bool,
}

impl Anderson {
    /// The arrays of memory `memory` for `n` nodes and `constraints` mixed multipliers.
    pub(super) fn new(memory: u32, n: usize, constraints: usize, volumes: bool) -> Self {
        Anderson {
            memory,
            history: vec![Vec3A::ZERO; (3 + 2 * memory as usize) * n],
            sums: vec![0.0; n.div_ceil(CHUNK) * TERMS],
            multipliers: vec![0.0; (1 + memory as usize) * constraints],
            volumes,
        }
    }
}

/// Whether Anderson mixes the multipliers of a sweep of `kind`: implicit springs' (always
/// compliant) and, when `volumes`, the volume constraints' (some are compliant); hard
/// constraints never read theirs.
pub(super) fn mixes(kind: ConstraintKind, volumes: bool) -> bool {
    match kind {
        ConstraintKind::Spring => true,
        ConstraintKind::Volume => volumes,
        _ => false,
    }
}

/// Each mixed sweep's multipliers: the member's block of them, and where that block lies
/// in a plane of [`Anderson::multipliers`].
fn multiplier_blocks<'o>(
    member: Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &'o Outputs<'_>,
) -> Vec<(&'o SharedSliceF32<'o>, std::ops::Range<usize>, usize)> {
    let mut first = 0;
    (outputs.multipliers.iter().zip(inputs.sweeps))
        .filter(|(_, sweep)| mixes(sweep.kind, inputs.anderson_volumes))
        .map(|(m, _)| {
            let block = member.block(m.len());
            first += m.len();
            (m, block, first - m.len())
        })
        .collect()
}

/// The multipliers Anderson mixes, over every mixed sweep.
fn mixed_count(inputs: &Inputs<'_>, outputs: &Outputs<'_>) -> usize {
    (outputs.multipliers.iter().zip(inputs.sweeps))
        .filter(|(_, sweep)| mixes(sweep.kind, inputs.anderson_volumes))
        .map(|(m, _)| m.len())
        .sum()
}

type SharedSliceF32<'a> = crate::backend::cpu::shared::SharedSlice<'a, f32>;

/// The multipliers' part of `anderson_sum`: their last values and history column.
///
/// # Safety
/// As [`sum`]; nobody writes the multipliers during the call.
unsafe fn sum_multipliers(
    member: Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    lambda: &SharedSliceF32<'_>,
    at: AndersonIteration,
) {
    let total = mixed_count(inputs, outputs);
    for (m, block, first) in multiplier_blocks(member, inputs, outputs) {
        // SAFETY: each member's block of each sweep is its own; nobody writes them.
        let (now, last) = unsafe {
            (
                m.part(block.clone()),
                lambda.part(first + block.start..first + block.end),
            )
        };
        if let Some(slot) = at.slot {
            let at = (1 + slot) * total + first;
            // SAFETY: as above, in another plane.
            let column = unsafe { lambda.part(at + block.start..at + block.end) };
            for ((d, now), last) in column.iter_mut().zip(&*now).zip(&*last) {
                *d = now - last;
            }
        }
        last.copy_from_slice(now);
    }
}

/// The member's chunks and the nodes they cover.
fn mine(member: Member<'_>, n: usize) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
    let chunks = member.block(n.div_ceil(CHUNK));
    let nodes = (chunks.start * CHUNK).min(n)..(chunks.end * CHUNK).min(n);
    (chunks, nodes)
}

/// `anderson_sum` of `iteration` for the member's chunks.
///
/// # Safety
/// Every member must call it at the same point of the same iteration, and nobody may
/// write the forces or the multipliers during the call.
pub(super) unsafe fn sum(
    member: Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    iteration: u32,
) {
    let Some((history, sums, lambda)) = &outputs.anderson else {
        return;
    };
    let (n, m) = (inputs.x.len(), inputs.anderson as usize);
    let at = AndersonIteration::of(iteration, inputs.anderson);
    // SAFETY: the caller's promise covers the multipliers too.
    unsafe { sum_multipliers(member, inputs, outputs, lambda, at) };
    let (chunks, nodes) = mine(member, n);
    let plane = |p: usize| {
        // SAFETY: the members' node ranges are disjoint, so are their parts of a plane.
        unsafe { history.part(p * n + nodes.start..p * n + nodes.end) }
    };
    // SAFETY: nobody writes the forces during the call (the caller's promise).
    let f = unsafe { &outputs.f.whole()[nodes.clone()] };
    let g = |k: usize| f[k];
    let x = plane(0);
    if at.first {
        for (k, x) in x.iter_mut().enumerate() {
            *x = g(k);
        }
        return;
    }
    let (f_last, g_last) = (plane(1), plane(2));
    let mut column = at.slot.map(|s| (plane(3 + s), plane(3 + m + s)));
    for k in 0..nodes.len() {
        let (gk, fk) = (g(k), g(k) - x[k]);
        if let Some((df, dg)) = &mut column {
            df[k] = fk - f_last[k];
            dg[k] = gk - g_last[k];
        }
        (f_last[k], g_last[k]) = (fk, gk);
    }
    let columns = at.columns;
    if columns == 0 {
        return;
    }
    let df: Vec<&[Vec3A]> = (0..columns).map(|c| &*plane(3 + c)).collect();
    for chunk in chunks {
        let first = chunk * CHUNK - nodes.start;
        let range = first..(first + CHUNK).min(nodes.len());
        let dot = |a: &[Vec3A], b: &[Vec3A]| -> f64 {
            (a[range.clone()].iter().zip(&b[range.clone()]))
                .map(|(p, q)| f64::from(p.dot(*q)))
                .sum()
        };
        // SAFETY: each chunk's row is its member's alone.
        let row = unsafe { sums.part(chunk * TERMS..(chunk + 1) * TERMS) };
        for i in 0..columns {
            for j in i..columns {
                row[gram_index(i, j, columns)] = dot(df[i], df[j]);
            }
            row[columns * (columns + 1) / 2 + i] = dot(df[i], f_last);
        }
    }
}

/// `anderson_mix` of `iteration` for the member's chunks: the weights from every chunk's
/// sums, the mix, then the floor's and colliders' solve of those nodes.
///
/// # Safety
/// Every member must call it at the same point of the same iteration, after [`sum`] and a
/// wait; nobody may write the sums during the call or touch the multipliers but it.
pub(super) unsafe fn mix(
    member: Member<'_>,
    inputs: &Inputs<'_>,
    outputs: &Outputs<'_>,
    iteration: u32,
) {
    let Some((history, sums, lambda)) = &outputs.anderson else {
        return;
    };
    let at = AndersonIteration::of(iteration, inputs.anderson);
    if at.first {
        return;
    }
    let (n, m) = (inputs.x.len(), inputs.anderson as usize);
    let (_, nodes) = mine(member, n);
    let columns = at.columns;
    let mut total = vec![0.0f64; gram_terms(columns)];
    // SAFETY: nobody writes the sums (the caller's promise).
    let rows = unsafe { sums.whole() };
    for row in rows.chunks(TERMS).take(n.div_ceil(CHUNK)) {
        for (t, s) in total.iter_mut().zip(row) {
            *t += s;
        }
    }
    let gamma = anderson_weights(&total, columns).map(|g| g as f32);
    let constraints = mixed_count(inputs, outputs);
    for (m, block, first) in multiplier_blocks(member, inputs, outputs) {
        // SAFETY: each member's block of each sweep is its own.
        let now = unsafe { m.part(block.clone()) };
        for (j, &gamma) in gamma[..columns].iter().enumerate() {
            let at = (1 + j) * constraints + first;
            // SAFETY: as above; nobody writes the columns in this phase.
            let column = unsafe { &lambda.whole()[at + block.start..at + block.end] };
            for (l, d) in now.iter_mut().zip(column) {
                *l -= d * gamma;
            }
        }
    }
    let plane = |p: usize| {
        // SAFETY: the members' node ranges are disjoint, so are their parts of a plane.
        unsafe { history.part(p * n + nodes.start..p * n + nodes.end) }
    };
    let (x, g) = (plane(0), &*plane(2));
    let dg: Vec<&[Vec3A]> = (0..columns).map(|c| &*plane(3 + m + c)).collect();
    let (v, w, dt) = (inputs.v, inputs.inv_mass, inputs.k.dt);
    // SAFETY: each member writes only its own nodes' forces (the caller's promise).
    let (f, floor_force, contact) = unsafe {
        (
            outputs.f.part(nodes.clone()),
            outputs.floor_force.part(nodes.clone()),
            match inputs.colliders {
                Some(_) => outputs.contact.part(nodes.clone()),
                None => &mut [][..],
            },
        )
    };
    for k in 0..nodes.len() {
        let mut next = g[k];
        for (d, &gamma) in dg.iter().zip(&gamma) {
            next -= d[k] * gamma;
        }
        x[k] = next;
        let i = nodes.start + k;
        let (f, n) = (&mut f[k], &mut floor_force[k]);
        *f = next;
        if inputs.floor {
            let y = inputs.x[i].y + inputs.k.solve.slack(inputs.x[i].y);
            (*f, *n) = floor_solve(*f, *n, y, v[i].y, w[i], dt);
        }
        if let Some(colliders) = &inputs.colliders {
            colliders.solve(i, f, &mut contact[k]);
        }
    }
}
