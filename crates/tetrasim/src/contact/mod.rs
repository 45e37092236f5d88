//! Contact between bodies and of a body with itself (physics.md, third edition, "Contact
//! between bodies and with itself"): once per step a broad phase (a uniform hash of the
//! surface triangles' bounds) and a narrow phase pair each surface node with the nearest
//! surface triangle of another object (or a non-adjacent triangle of its own object, with
//! self-contact) that it is inside of or within the detection margin of; in every iteration
//! each such contact is a one-sided constraint
//!
//! ```text
//! C = n . (x_p - sum_k b_k x_k) - r >= 0
//! ```
//!
//! (`n` the triangle's outward normal and `b` the closest point's barycentric weights, both
//! fixed for the step, `r` the contact thickness) on the node and the triangle's three
//! nodes, solved in the implicit framework like every other constraint, its multiplier
//! accumulated over the iterations and kept pushing (never pulling). Its gradients sum to
//! zero, so linear momentum is conserved and the push is shared by inverse masses.

mod find;

pub use find::closest_on_triangle;

use glam::DVec3;

use crate::model::Model;
use crate::params::SimParams;
use crate::physics::{implicit_accumulate, implicit_multiplier, Solve};

/// One contact of a step: a surface node against a surface triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The node.
    pub node: u32,
    /// The triangle's nodes (outward order).
    pub triangle: [u32; 3],
    /// Barycentric weights of the closest point on the triangle.
    pub bary: [f64; 3],
    /// The triangle's outward unit normal.
    pub normal: DVec3,
}

impl Contact {
    /// The four nodes of the constraint: the node, then the triangle's.
    pub fn nodes(&self) -> [u32; 4] {
        [
            self.node,
            self.triangle[0],
            self.triangle[1],
            self.triangle[2],
        ]
    }

    /// The constraint's gradients on [`Self::nodes`]: `n`, then `-b_k n`.
    pub fn gradients(&self) -> [DVec3; 4] {
        let n = self.normal;
        [n, -n * self.bary[0], -n * self.bary[1], -n * self.bary[2]]
    }

    /// `C = n . (x_p - sum_k b_k x_k) - thickness` at the positions `x` of
    /// [`Self::nodes`].
    pub fn value(&self, x: [DVec3; 4], thickness: f64) -> f64 {
        let on_triangle = x[1] * self.bary[0] + x[2] * self.bary[1] + x[3] * self.bary[2];
        self.normal.dot(x[0] - on_triangle) - thickness
    }
}

/// What body contact needs from the model, prepared once: which surface nodes meet which
/// surface triangles, the thickness and the detection margin.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyContact {
    /// Contact thickness `r` [m]: 5 % of the median surface edge.
    pub thickness: f64,
    /// A node is paired with triangles within this distance of it at its predicted position
    /// [m]: half the median surface edge.
    pub margin: f64,
    /// Surface nodes, ascending.
    pub nodes: Vec<u32>,
    /// Surface triangles (the model's `surface`).
    pub triangles: Vec<[u32; 3]>,
    /// The object of every model node.
    pub object_of: Vec<u32>,
    /// Per object, whether its surface collides with itself.
    pub self_contact: Vec<bool>,
}

impl BodyContact {
    /// The body contact of `model`: `None` when no two surfaces can meet (one object
    /// without self-contact).
    pub fn new(model: &Model) -> Option<Self> {
        let objects = model.objects.len().saturating_sub(1);
        let self_contact: Vec<bool> = (0..objects)
            .map(|k| model.self_contact.get(k).copied().unwrap_or(false))
            .collect();
        if objects < 2 && !self_contact.iter().any(|&s| s) || model.surface.is_empty() {
            return None;
        }
        let mut object_of = vec![0u32; model.node_count()];
        for k in 0..objects {
            let range = model.objects[k] as usize..model.objects[k + 1] as usize;
            object_of[range].fill(k as u32);
        }
        let mut nodes: Vec<u32> = model.surface.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        let mut edges: Vec<f64> = (model.surface.iter())
            .flat_map(|t| (0..3).map(move |e| (t[e], t[(e + 1) % 3])))
            .map(|(a, b)| model.positions[a as usize].distance(model.positions[b as usize]))
            .collect();
        edges.sort_unstable_by(f64::total_cmp);
        let median = edges[edges.len() / 2];
        Some(BodyContact {
            thickness: 0.05 * median,
            margin: 0.5 * median,
            nodes,
            triangles: model.surface.clone(),
            object_of,
            self_contact,
        })
    }
}

/// The deepest any node is inside a collider of `colliders` at time step `step`'s start
/// (their poses then) or behind the triangle of one of `contacts` that pushes, at the
/// positions `x` [m] (0 when none is).
pub fn deepest(
    colliders: &[crate::collider::Collider],
    step: u64,
    dt: f64,
    contacts: &[(Contact, f64)],
    x: impl Fn(usize) -> DVec3,
    nodes: usize,
) -> f64 {
    let at = crate::collider::at_step(colliders, step, dt);
    let mut deepest: f64 = 0.0;
    for i in 0..nodes {
        let p = x(i);
        for c in at.iter().filter(|c| c.may_touch_at_start(p)) {
            deepest = deepest.max(-c.collider.shape.distance(c.start.invert(p)).0);
        }
    }
    for (c, _) in contacts.iter().filter(|(_, lambda)| *lambda < 0.0) {
        let positions = c.nodes().map(|i| x(i as usize));
        deepest = deepest.max(-c.value(positions, 0.0));
    }
    deepest
}

impl BodyContact {
    /// One Jacobi sweep of the step's `contacts` (each with its multiplier so far, `<= 0`)
    /// against the nodes' start positions `x`, velocities `v` and current forces `f`
    /// (closures over node indices, so that either precision can call it), under `params`
    /// for `model`: each contact's increment ([`implicit_multiplier`], each node's inverse
    /// mass scaled by the combine mode for its number of contacts), the total kept at or
    /// below 0 (a contact pushes, never pulls); in split contact's velocity solve (`solve`)
    /// a contact keeps the penetration it starts with ([`Solve::slack`]). Returns the force
    /// to add to each touched node, `-delta grad C` times `omega` and the combine mode's
    /// weight, in node order.
    #[allow(clippy::too_many_arguments)]
    pub fn sweep(
        &self,
        contacts: &mut [(Contact, f64)],
        model: &Model,
        params: &SimParams,
        solve: Solve,
        x: impl Fn(usize) -> DVec3,
        v: impl Fn(usize) -> DVec3,
        f: impl Fn(usize) -> DVec3,
    ) -> Vec<(usize, DVec3)> {
        let mut degree: std::collections::BTreeMap<usize, (u32, DVec3)> = Default::default();
        for (c, _) in contacts.iter() {
            for i in c.nodes() {
                degree.entry(i as usize).or_default().0 += 1;
            }
        }
        for (c, lambda) in contacts.iter_mut() {
            let ids = c.nodes().map(|i| i as usize);
            let grad = c.gradients();
            let value = c.value(ids.map(&x), self.thickness);
            let value = value + solve.slack(value);
            let (mut a, mut b) = (0.0, 0.0);
            for k in 0..4 {
                let i = ids[k];
                let w = model.inv_mass[i];
                let scale = params.combine.node_factors(degree[&i].0).0;
                implicit_accumulate(&mut a, &mut b, grad[k], w, scale, v(i), f(i), params.dt);
            }
            let Some(delta) =
                implicit_multiplier(value, a, b, params.dt, params.constraint_epsilon)
            else {
                continue;
            };
            let total = (*lambda + delta).min(0.0);
            let delta = total - *lambda;
            *lambda = total;
            for k in 0..4 {
                degree.get_mut(&ids[k]).expect("counted").1 -= grad[k] * delta;
            }
        }
        degree
            .into_iter()
            .map(|(i, (d, sum))| (i, sum * (params.combine.node_factors(d).1 * params.omega)))
            .collect()
    }
}

#[cfg(test)]
mod tests;
