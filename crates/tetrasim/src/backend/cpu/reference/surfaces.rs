//! The constraints of `cpu-ref` that act on surfaces and contacts: the global volume
//! constraints, the contacts between bodies, and the floor's and the colliders' solve.

use glam::DVec3;

use super::{ReferenceBackend, StepForces};
use crate::collider;
use crate::model::{GlobalObject, GlobalVolume};
use crate::physics::{
    contact_held, face_volume, floor_solve, global_multiplier, held_direction, implicit_accumulate,
};

impl ReferenceBackend {
    /// Per object of the global volume constraints: `C_g` and the gradient on each of its
    /// surface nodes (in [`GlobalVolume::nodes`] order from the object's first) at the
    /// step's positions, the multiplier still 0. The reference point of the face volumes is
    /// the object's first surface node.
    pub(super) fn global_prepare(&self) -> Vec<(f64, Vec<DVec3>, f64)> {
        let Some(global) = &self.problem.global else {
            return Vec::new();
        };
        (global.objects.iter())
            .map(|object| {
                let (c, grad) = self.global_gradients(global, object);
                (c, grad, 0.0)
            })
            .collect()
    }

    /// `C_g` of `object` and its gradient on each of its surface nodes.
    pub(super) fn global_gradients(
        &self,
        global: &GlobalVolume,
        object: &GlobalObject,
    ) -> (f64, Vec<DVec3>) {
        let nodes = &global.nodes[object.node_first as usize..][..object.node_count as usize];
        let faces = &global.faces[object.face_first as usize..][..object.face_count as usize];
        let o = self.x[nodes[0] as usize];
        let mut c = -object.rest_volume;
        let mut face_grad = Vec::with_capacity(faces.len());
        for face in faces {
            let (v, g) = face_volume(face.map(|i| self.x[i as usize]), o);
            c += v;
            face_grad.push(g);
        }
        let first_face = 3 * object.face_first as usize;
        let grad = (0..nodes.len())
            .map(|k| {
                let row = global.node_faces.row(object.node_first as usize + k);
                row.iter()
                    .map(|&e| face_grad[(e as usize - first_face) / 3][e as usize % 3])
                    .sum()
            })
            .collect();
        (c, grad)
    }

    /// Every object's global volume multiplier against the step's forces so far.
    pub(super) fn global_multipliers(&self, step: &mut StepForces) {
        let Some(global) = &self.problem.global else {
            return;
        };
        let p = &self.problem.params;
        for (object, (c, grad, lambda)) in global.objects.iter().zip(&mut step.global) {
            let nodes = &global.nodes[object.node_first as usize..][..object.node_count as usize];
            let (mut a, mut b, mut held) = (0.0, 0.0, 0.0);
            for (&i, &g) in nodes.iter().zip(grad.iter()) {
                let i = i as usize;
                let w = self.problem.model.inv_mass[i];
                implicit_accumulate(&mut a, &mut b, g, w, 1.0, self.v[i], step.total[i], p.dt);
                let along = held_direction(step.floor[i] > 0.0, step.contacts[i].force);
                held += contact_held(g, w, along);
            }
            let c = step.solve.hard(*c);
            *lambda = global_multiplier(c, a, b, held, p.dt, p.constraint_epsilon).unwrap_or(0.0);
        }
    }

    /// One Jacobi sweep of the step's body contacts against the forces so far
    /// ([`crate::contact::BodyContact::sweep`]), its forces added, then the floor and the
    /// colliders again.
    pub(super) fn contact_iteration(&self, step: &mut StepForces) {
        let Some(bodies) = &self.problem.bodies else {
            return;
        };
        let (model, params) = (&self.problem.model, &self.problem.params);
        let total = &step.total;
        let forces = bodies.sweep(
            &mut step.bodies,
            model,
            params,
            step.solve,
            |i| self.x[i],
            |i| self.v[i],
            |i| total[i],
        );
        for (i, force) in forces {
            step.total[i] += force;
        }
        self.contact_solve(step);
    }

    /// Solves every node's contacts against the step's total force (which includes the
    /// contact forces found so far) and updates both: the floor's, then the colliders' in
    /// their order ([`collider::solve_node`]).
    pub(super) fn contact_solve(&self, step: &mut StepForces) {
        let (model, dt) = (&self.problem.model, self.problem.params.dt);
        if self.problem.params.floor {
            for (i, (f, n)) in step.total.iter_mut().zip(step.floor.iter_mut()).enumerate() {
                let y = self.x[i].y + step.solve.slack(self.x[i].y);
                (*f, *n) = floor_solve(*f, *n, y, self.v[i].y, model.inv_mass[i], dt);
            }
        }
        if model.colliders.is_empty() && model.grabs.is_empty() {
            return;
        }
        let at = collider::at_step(&model.colliders, self.steps, dt);
        if step.clearance.is_empty() {
            step.clearance = self
                .x
                .iter()
                .map(|&x| collider::clearance(&at, x))
                .collect();
            let t = self.steps as f64 * dt;
            step.attached = collider::attachments(&model.grabs, &model.positions, t, dt);
        }
        let nodes = step.total.iter_mut().zip(step.contacts.iter_mut());
        for (i, (f, c)) in nodes.enumerate() {
            let (x, v, w, clear) = (self.x[i], self.v[i], model.inv_mass[i], step.clearance[i]);
            let solve = step.solve;
            (*f, *c) = match step.attached[i] {
                Some(a) => {
                    collider::solve_node_attached(&at, Some(a), solve, *f, c.force, x, v, w, dt)
                }
                None => collider::solve_node_clear(&at, clear, solve, *f, c.force, x, v, w, dt),
            };
        }
    }
}
