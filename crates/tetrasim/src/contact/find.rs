//! The step's contacts: a uniform hash of the surface triangles' bounds (cells of the
//! detection margin's size, at least), then for each surface node the nearest eligible
//! triangle within the margin.

use std::collections::HashMap;

use glam::DVec3;

use super::{BodyContact, Contact};
use crate::model::Model;

/// The closest point to `p` on the triangle `t`: its barycentric weights.
pub fn closest_on_triangle(p: DVec3, t: [DVec3; 3]) -> [f64; 3] {
    // Ericson, Real-Time Collision Detection, 5.1.5.
    let (a, b, c) = (t[0], t[1], t[2]);
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return [1.0 - v, v, 0.0];
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return [1.0 - w, 0.0, w];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - w, w];
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    [1.0 - v - w, v, w]
}

type Cell = (i64, i64, i64);

impl BodyContact {
    /// The contacts of a step whose nodes start at `x` with velocities `v` (`dt` [s]):
    /// positions are predicted as `x + dt v`; each surface node gets the nearest triangle
    /// within [`Self::margin`] of its predicted position that belongs to another object,
    /// or to its own with self-contact when the node is neither a corner of it nor a
    /// neighbour (by a spring) of one. In node order.
    pub fn find(&self, model: &Model, x: &[DVec3], v: &[DVec3], dt: f64) -> Vec<Contact> {
        let predicted: Vec<DVec3> = x.iter().zip(v).map(|(x, v)| *x + *v * dt).collect();
        let reach = self.margin + self.thickness;
        let cell_size = reach.max(1e-9) * 2.0;
        let cell = |p: DVec3| -> Cell {
            let c = (p / cell_size).floor();
            (c.x as i64, c.y as i64, c.z as i64)
        };
        let mut grid: HashMap<Cell, Vec<u32>> = HashMap::new();
        for (t, tri) in self.triangles.iter().enumerate() {
            let p = tri.map(|i| predicted[i as usize]);
            let lo = cell(p[0].min(p[1]).min(p[2]) - reach);
            let hi = cell(p[0].max(p[1]).max(p[2]) + reach);
            for i in lo.0..=hi.0 {
                for j in lo.1..=hi.1 {
                    for k in lo.2..=hi.2 {
                        grid.entry((i, j, k)).or_default().push(t as u32);
                    }
                }
            }
        }
        let mut contacts = Vec::new();
        for &node in &self.nodes {
            let p = predicted[node as usize];
            let Some(candidates) = grid.get(&cell(p)) else {
                continue;
            };
            let object = self.object_of[node as usize];
            let mut best: Option<(f64, Contact)> = None;
            for &t in candidates {
                let tri = self.triangles[t as usize];
                if !self.eligible(model, node, object, tri) {
                    continue;
                }
                let corners = tri.map(|i| predicted[i as usize]);
                let Some(normal) = (corners[1] - corners[0])
                    .cross(corners[2] - corners[0])
                    .try_normalize()
                else {
                    continue;
                };
                let bary = closest_on_triangle(p, corners);
                let q = corners[0] * bary[0] + corners[1] * bary[1] + corners[2] * bary[2];
                let distance = p.distance(q);
                // Roughly in front of or behind the face (within 60 degrees of its normal):
                // a node beside a triangle it shares a plane with is no contact.
                let facing = normal.dot(p - q).abs() >= 0.5 * distance;
                if distance < reach && facing && best.map_or(true, |(d, _)| distance < d) {
                    let contact = Contact {
                        node,
                        triangle: tri,
                        bary,
                        normal,
                    };
                    best = Some((distance, contact));
                }
            }
            contacts.extend(best.map(|(_, c)| c));
        }
        contacts
    }

    /// Whether `node` of `object` may touch the triangle `tri`.
    fn eligible(&self, model: &Model, node: u32, object: u32, tri: [u32; 3]) -> bool {
        let other = self.object_of[tri[0] as usize];
        if other != object {
            return true;
        }
        if !self.self_contact[object as usize] || tri.contains(&node) {
            return false;
        }
        // Not a neighbour of a corner: the node's own surface around it is not a contact.
        !model.node_springs.row(node as usize).iter().any(|&s| {
            let [a, b] = model.springs[s as usize];
            tri.contains(&a) || tri.contains(&b)
        })
    }
}
