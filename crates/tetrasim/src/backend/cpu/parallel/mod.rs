//! Backend `cpu`: single precision on every core, written to be a fair, strong CPU
//! competitor for the Vulkan engine. No locks and no atomics on the data: each pass computes
//! per-element results in parallel (one spring, one tet), then a per-node pass gathers them
//! through CSR adjacency (node -> spring ends, node -> tet corners). Data is packed in flat
//! arrays of 16-byte SIMD vectors ([`Vec3A`]).
//!
//! The step is the schedule's ([`crate::schedule::Schedule::step`]), dispatch after
//! dispatch. Its constraint iterations (every colour group of every sweep, ten times over,
//! and the global volume constraint) run on a persistent [`team`](super::team) woken once per step: each
//! thread solves a fixed block of each group's constraints ([`solve_block`]), waits at a
//! [`barrier`](super::barrier) (spin, yield, then sleep), applies the group's results to a fixed block of
//! nodes ([`apply_block`]), waits, and so on ([`iterations`]). The step's other stages
//! (springs, the global constraints' gradients, integration) are rayon loops in chunks of
//! at least [`CHUNK`] on the same threads. Every result is computed
//! by one thread with the same arithmetic in the same order whatever the thread count, so
//! the states are bit-identical for any `RAYON_NUM_THREADS` (the unit tests in `tests.rs`).
use glam::Vec3A;
use rayon::prelude::*;

use super::{check_state, diverged, Bad};
use crate::backend::{Backend, State, VolumeSample};
use crate::collider::{self, Attachment, ColliderAt, NodeContact};
use crate::error::Result;
use crate::model::{ConstraintKind, Csr, GlobalVolume, Model};
use crate::params::{chebyshev_weights, ContactMode, Method, SimParams, Solver, SpringKind};
use crate::physics::{
    compliant_multiplier, contact_held, elastic_start, end_position, face_volume, floor_solve,
    global_multiplier, held_direction, implicit_accumulate, implicit_multiplier, integrate_node,
    spring_constraint, spring_force, tet_volume, Solve, Vector,
};
use crate::problem::Problem;
use crate::schedule::family::{ConstraintFamily, Family};
use crate::schedule::{Dispatch, PassKind, Schedule};

mod anderson;
mod backend;
mod blocks;
mod coarse;
mod correction;
mod elastic;
mod inversion;
mod iterations;
mod newton;
#[cfg(test)]
mod tests;

pub use backend::ParallelBackend;

/// Smallest number of elements one parallel task handles.
pub const CHUNK: usize = 1024;

/// The parameters of a step, in single precision.
#[derive(Debug, Clone, Copy)]
struct Coefficients {
    dt: f32,
    /// Iterations per step.
    iterations: u32,
    omega: f32,
    friction: f32,
    epsilon: f32,
    /// The fraction of the rest volume the inversion sweeps restore.
    inversion_floor: f32,
    gravity: Vec3A,
    /// Which of the step's solves runs (split contact's velocity solve, or the full one).
    solve: Solve,
}

/// One constraint sweep of an iteration ([`Model::constraint_sweeps`]): its constraints in
/// the groups solved one after another, with everything they read, in single precision.
#[derive(Debug, Clone)]
struct Sweep {
    kind: ConstraintKind,
    /// The model's node count.
    nodes: usize,
    /// Row `g`: the constraints of group `g` (their positions in `items` index the
    /// per-constraint results).
    members: Csr,
    /// Row `g * n + i`: node `i`'s result slots in group `g` (`2 p + end` for springs,
    /// `4 p + corner` for tets; [`crate::model::ConstraintGroups::node_slots`]).
    slots: Csr,
    /// Per group and node (`g * n + i`): the scale of the node's inverse mass in `A` (its
    /// degree within the group for the momentum-conserving scaling, else 1).
    a_scale: Vec<f32>,
    /// Per group and node: `omega` times the combine mode's apply weight.
    apply: Vec<f32>,
    /// Per constraint (position in `members.items`): the multiplier a compliant constraint
    /// has gathered so far in this step (zero at its start; unused by hard ones).
    multipliers: Vec<f32>,
    /// The constraints' family and its data.
    family: Family<f32>,
    /// Per constraint (position in `members.items`): a spring's or distance constraint's
    /// two nodes, in group order, so that a group's solve reads them in one run instead of
    /// one cache miss per constraint (empty for tets).
    pair_nodes: Vec<[u32; 2]>,
    /// Per constraint, in group order: a tet's four nodes (empty for springs).
    tet_nodes: Vec<[u32; 4]>,
    /// Block Gauss-Seidel's blocks of the one group (`block_size > 0`).
    blocks: Option<blocks::Blocks>,
}

impl Sweep {
    fn new(
        model: &Model,
        params: &SimParams,
        sweep: crate::model::Sweep,
        family: Family<f32>,
    ) -> Self {
        let n = model.node_count();
        let slots = ConstraintKind::node_slots(&sweep, model);
        let (kind, groups) = (sweep.kind, sweep.groups);
        let factors: Vec<(f64, f64)> = groups
            .degree
            .iter()
            .map(|&d| params.combine.node_factors(d))
            .collect();
        let blocks = (sweep.blocks).map(|b| blocks::Blocks::new(b, kind, &factors, params));
        let members = &groups.members.items;
        let (pair_nodes, tet_nodes) = match kind {
            ConstraintKind::Volume => (Vec::new(), in_group_order(members, &model.tets)),
            ConstraintKind::Elastic => (Vec::new(), Vec::new()),
            ConstraintKind::Spring | ConstraintKind::Distance => {
                (in_group_order(members, &model.springs), Vec::new())
            }
        };
        Sweep {
            kind,
            blocks,
            family,
            nodes: n,
            pair_nodes,
            tet_nodes,
            multipliers: vec![0.0; groups.members.items.len()],
            members: groups.members,
            slots,
            a_scale: factors.iter().map(|f| f.0 as f32).collect(),
            apply: factors
                .iter()
                .map(|f| (f.1 * params.omega) as f32)
                .collect(),
        }
    }

    /// The number of groups.
    fn len(&self) -> usize {
        self.members.offsets.len() - 1
    }

    /// Positions (into `members.items`) of group `g`.
    fn range(&self, g: usize) -> std::ops::Range<usize> {
        self.members.offsets[g] as usize..self.members.offsets[g + 1] as usize
    }
}

/// The global volume constraints and what a step's iterations share: positions stay at
/// `x(t)` during the iterations, so each object's `C` and `A` and each surface node's
/// gradient are computed once per step.
#[derive(Debug, Clone)]
struct Global {
    data: GlobalVolume,
    inv_mass: Vec<f32>,
    /// Per surface node (position in `data.nodes`): `grad_k C_g` of its object [m^2].
    grad: Vec<Vec3A>,
    /// Per object: `C_g` [m^3] and `A = sum_k w_k |grad_k C_g|^2`.
    c_and_a: Vec<(f32, f32)>,
}

impl Global {
    fn new(model: &Model, data: GlobalVolume) -> Self {
        Global {
            grad: vec![Vec3A::ZERO; data.nodes.len()],
            c_and_a: vec![(0.0, 0.0); data.objects.len()],
            inv_mass: data
                .nodes
                .iter()
                .map(|&i| model.inv_mass[i as usize] as f32)
                .collect(),
            data,
        }
    }

    /// `C_g`, `A` and the gradients at positions `x`; the reference point of the face
    /// volumes is each object's first surface node.
    fn prepare(&mut self, x: &[Vec3A]) {
        let d = &self.data;
        let face_terms: Vec<(f32, [Vec3A; 3])> = d
            .faces
            .par_iter()
            .enumerate()
            .with_min_len(CHUNK)
            .map(|(f, face)| {
                let object = d.objects.partition_point(|o| o.face_first as usize <= f) - 1;
                let o = x[d.nodes[d.objects[object].node_first as usize] as usize];
                face_volume(face.map(|i| x[i as usize]), o)
            })
            .collect();
        self.grad
            .par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(k, g)| {
                *g = d
                    .node_faces
                    .row(k)
                    .iter()
                    .map(|&e| face_terms[e as usize / 3].1[e as usize % 3])
                    .sum();
            });
        for (o, object) in d.objects.iter().enumerate() {
            let faces =
                object.face_first as usize..(object.face_first + object.face_count) as usize;
            let volume: f64 = face_terms[faces].iter().map(|t| f64::from(t.0)).sum();
            let nodes =
                object.node_first as usize..(object.node_first + object.node_count) as usize;
            let a: f32 = self.grad[nodes.clone()]
                .iter()
                .zip(&self.inv_mass[nodes])
                .map(|(g, &w)| w * g.length_squared())
                .sum();
            self.c_and_a[o] = ((volume - object.rest_volume) as f32, a);
        }
    }
}

/// The part of a node's [`floor_force`](crate::physics::floor_force) fixed for a step, `-(y + dt vy) / (dt^2 w)` at the
/// step's start (minus infinity for a pinned node, which gets no floor force): the floor
/// force is `max(reach - fy_other, 0)`, the same operations in the same order as
/// [`floor_force`](crate::physics::floor_force), without its division in every group's apply.
fn floor_reach(y: f32, vy: f32, w: f32, dt: f32) -> f32 {
    if w <= 0.0 {
        return f32::NEG_INFINITY;
    }
    -(y + dt * vy) / (dt * dt * w)
}

/// The colliders of a step and what their solve reads (none: no colliders).
#[derive(Clone, Copy)]
pub(super) struct Colliders<'a> {
    /// The colliders over the step.
    pub at: &'a [ColliderAt<'a>],
    /// Positions, velocities and inverse masses at the step's start.
    pub x: &'a [Vec3A],
    pub v: &'a [Vec3A],
    pub w: &'a [f32],
    pub dt: f32,
    /// Each node's [`collider::clearance`] in this step.
    pub clear: &'a [f64],
    /// Each node's attachment to a grab in this step (empty without grabs).
    pub attached: &'a [Option<Attachment>],
    /// Which of the step's solves runs.
    pub solve: Solve,
}

impl Colliders<'_> {
    /// Node `i`'s collider contacts re-solved against its total force `f`, which holds
    /// their force so far, `c` ([`collider::solve_node`], in double precision): both
    /// updated; returns the contact.
    #[inline(always)]
    pub fn solve(&self, i: usize, f: &mut Vec3A, c: &mut Vec3A) -> NodeContact {
        let (x, v, w, clear) = (self.x[i], self.v[i], self.w[i], self.clear[i]);
        if self.attached.is_empty() && *c == Vec3A::ZERO && clear > 0.0 {
            // The common case, inline: far from every collider and untouched so far.
            let step = (v + *f * (w * self.dt)) * self.dt;
            if f64::from(step.length_squared()) < clear * clear * (1.0 - 1e-5) {
                return NodeContact::NONE;
            }
        }
        let attached = self.attached.get(i).copied().flatten();
        collide(self.at, clear, attached, self.solve, f, c, x, v, w, self.dt)
    }
}

/// One node's collider contacts re-solved against its total force `f`, which holds their
/// force so far, `c` ([`collider::solve_node`], in double precision): both updated. While
/// its end position stays within its clearance `clear` of `x`, no collider is evaluated
/// ([`collider::solve_node_clear`]).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub(super) fn collide(
    at: &[ColliderAt<'_>],
    clear: f64,
    attached: Option<Attachment>,
    solve: Solve,
    f: &mut Vec3A,
    c: &mut Vec3A,
    x: Vec3A,
    v: Vec3A,
    w: f32,
    dt: f32,
) -> NodeContact {
    let other = *f - *c;
    if attached.is_none()
        && f64::from((end_position(x, v, other, w, dt) - x).length()) < clear * (1.0 - 1e-5)
    {
        *f = other;
        *c = Vec3A::ZERO;
        return NodeContact::NONE;
    }
    let (f1, contact) = collider::solve_node_attached(
        at,
        attached,
        solve,
        f.to_dvec3(),
        c.to_dvec3(),
        x.to_dvec3(),
        v.to_dvec3(),
        f64::from(w),
        f64::from(dt),
    );
    *f = Vec3A::from_dvec3(f1);
    *c = Vec3A::from_dvec3(contact.force);
    contact
}

/// [`floor_solve`] with the node's [`floor_reach`]: bit for bit the same `(f, n)`.
#[inline]
fn floor_solve_reach(f: Vec3A, n: f32, reach: f32) -> (Vec3A, f32) {
    let other = f.y - n;
    let n1 = (reach - other).max(0.0);
    (f + Vec3A::Y * (n1 - n), n1)
}

/// Per node `i` of a block of nodes starting at `first` (`f`, `floor_force`, `reach` and
/// `contact` hold the block): `F += apply * gather(i's slots in group g)`, the Chebyshev
/// extrapolation when it is on, then the floor's solve (`reach`: each node's
/// [`floor_reach`], when there is a floor) and the colliders' (`contact`: each node's
/// collider force, when there are colliders).
#[allow(clippy::too_many_arguments)]
fn apply_block(
    first: usize,
    f: &mut [Vec3A],
    floor_force: &mut [f32],
    reach: Option<&[f32]>,
    contact: Option<(Colliders<'_>, &mut [Vec3A])>,
    chebyshev: Option<ChebyshevState<'_>>,
    sweep: &Sweep,
    g: usize,
    gather: impl Fn(&[u32]) -> Vec3A,
) {
    let n = sweep.nodes;
    let apply = &sweep.apply[g * n..(g + 1) * n];
    let update = |i: usize, f: &mut Vec3A| {
        *f += gather(sweep.slots.row(g * n + i)) * apply[i];
    };
    let (colliders, contact) = match contact {
        Some((colliders, c)) => (Some(colliders), c),
        None => (None, &mut [][..]),
    };
    let mut floor = |i: usize, f: &mut Vec3A, fl: &mut f32| {
        if let Some(reach) = reach {
            (*f, *fl) = floor_solve_reach(*f, *fl, reach[i - first]);
        }
        if let Some(colliders) = &colliders {
            colliders.solve(i, f, &mut contact[i - first]);
        }
    };
    let nodes = f.iter_mut().zip(floor_force.iter_mut());
    match chebyshev {
        None => {
            for (i, (f, fl)) in (first..).zip(nodes) {
                update(i, f);
                floor(i, f, fl);
            }
        }
        Some((before_f, before_n, w)) => {
            let before = before_f.iter_mut().zip(before_n.iter_mut());
            for (i, ((f, fl), (bf, bn))) in (first..).zip(nodes.zip(before)) {
                let (f0, n0) = (*f, *fl);
                update(i, f);
                if w != 1.0 {
                    *f = (*f - *bf) * w + *bf;
                    *fl = (*fl - *bn) * w + *bn;
                }
                (*bf, *bn) = (f0, n0);
                floor(i, f, fl);
            }
        }
    }
}

/// What a group's constraints read: positions, velocities, the current total force and
/// inverse masses of every node, the group's scales of the inverse masses in `A`, and the
/// step's coefficients.
#[derive(Clone, Copy)]
struct Nodes<'a> {
    x: &'a [Vec3A],
    v: &'a [Vec3A],
    f: &'a [Vec3A],
    w: &'a [f32],
    a_scale: &'a [f32],
    k: Coefficients,
}

/// `elements` in the order of `members` (their indices).
fn in_group_order<const K: usize>(members: &[u32], elements: &[[u32; K]]) -> Vec<[u32; K]> {
    members.iter().map(|&e| elements[e as usize]).collect()
}

/// One constraint's forces on its `K` nodes as a per-constraint result array holds them:
/// all four for a tet; for a spring or distance constraint, whose gradients are `[n, -n]`,
/// the force on end 0 (end 1 gets its negation), half the memory the gathers read.
trait NodeForces<const K: usize>: Copy + Send + Sync {
    fn from_forces(forces: [Vec3A; K]) -> Self;
    fn corner(&self, corner: usize) -> Vec3A;
}

impl NodeForces<2> for Vec3A {
    #[inline]
    fn from_forces(forces: [Vec3A; 2]) -> Self {
        forces[0]
    }

    #[inline]
    fn corner(&self, corner: usize) -> Vec3A {
        if corner == 0 {
            *self
        } else {
            -*self
        }
    }
}

impl NodeForces<1> for Vec3A {
    #[inline]
    fn from_forces(forces: [Vec3A; 1]) -> Self {
        forces[0]
    }

    #[inline]
    fn corner(&self, _: usize) -> Vec3A {
        *self
    }
}

impl NodeForces<4> for [Vec3A; 4] {
    #[inline]
    fn from_forces(forces: [Vec3A; 4]) -> Self {
        forces
    }

    #[inline]
    fn corner(&self, corner: usize) -> Vec3A {
        self[corner]
    }
}

/// The per-constraint pass over a block of one group's constraints, for any constraint
/// family on `K` nodes: for the block's `members` (indices into `elements`),
/// [`ConstraintFamily::evaluate`] gives the value `C`, the gradients, the softness and the
/// damping of constraint `e`, and `out` (one entry per member) receives the forces `-delta grad_k C` on its nodes with the compliant
/// multiplier's increment ([`compliant_multiplier`] against `B - softness * so_far`; zero
/// where the constraint is skipped); a compliant constraint's `so_far` grows by
/// `omega delta`.
fn solve_block<const K: usize, R: NodeForces<K>, F: ConstraintFamily<f32, K>>(
    out: &mut [R],
    so_far: &mut [f32],
    members: &[u32],
    nodes: &[[u32; K]],
    on: Nodes<'_>,
    family: &F,
) {
    let Nodes {
        x,
        v,
        f,
        w,
        a_scale,
        k,
    } = on;
    let constraints = members.iter().zip(nodes);
    for ((out, so_far), (&e, ids)) in out.iter_mut().zip(so_far.iter_mut()).zip(constraints) {
        let e = e as usize;
        let ids = ids.map(|a| a as usize);
        let (c, grad, softness, damping) = family.evaluate(e, ids.map(|i| x[i]));
        let c = match softness > 0.0 {
            true => c,
            false => k.solve.hard(c),
        };
        let (mut a, mut b) = (0.0, 0.0);
        for (&i, &g) in ids.iter().zip(&grad) {
            implicit_accumulate(&mut a, &mut b, g, w[i], a_scale[i], v[i], f[i], k.dt);
        }
        let b = b - softness * *so_far;
        let delta = compliant_multiplier(c, a, b, k.dt, softness, damping, k.epsilon);
        if let (Some(d), true) = (delta, softness > 0.0) {
            *so_far += k.omega * d;
        }
        *out = R::from_forces(delta.map_or([Vec3A::ZERO; K], |d| grad.map(|g| g * -d)));
    }
}

/// The gather of per-constraint results `out` over a node's slots (`K * position + corner`;
/// `2 * spring + end` for the explicit springs' results).
fn gather<const K: usize, R: NodeForces<K>>(out: &[R]) -> impl Fn(&[u32]) -> Vec3A + '_ {
    move |slots| {
        let mut sum = Vec3A::ZERO;
        for &e in slots {
            sum += out[e as usize / K].corner(e as usize % K);
        }
        sum
    }
}

/// The Chebyshev state of one iteration: the total and floor forces two iterations back
/// (updated in place) and the iteration's weight.
type ChebyshevState<'a> = (&'a mut [Vec3A], &'a mut [f32], f32);

/// The Chebyshev semi-iteration's weights and the forces two iterations back.
#[derive(Debug, Clone)]
struct Chebyshev {
    weights: Vec<f32>,
    before_f: Vec<Vec3A>,
    before_n: Vec<f32>,
}
