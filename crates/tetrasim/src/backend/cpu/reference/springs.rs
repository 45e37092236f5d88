//! `cpu-ref`'s spring forces: explicit (scattered or gathered) and the warm start of
//! implicit springs.

use glam::DVec3;

use super::ReferenceBackend;
use crate::physics::{spring_constraint, spring_force};

impl ReferenceBackend {
    /// With implicit springs: each spring's warm-start multiplier (zero without
    /// `warm_start`) as the force `-lambda grad C` at the current positions.
    pub(super) fn warm_start_forces(&self) -> Vec<DVec3> {
        let mut f = vec![DVec3::ZERO; self.problem.model.node_count()];
        for (s, &lambda) in self.spring_warm.iter().enumerate() {
            if lambda != 0.0 {
                let ids = self.problem.model.springs[s].map(|i| i as usize);
                let (_, grad) = spring_constraint(
                    self.x[ids[0]],
                    self.x[ids[1]],
                    self.problem.model.rest_length[s],
                );
                for k in 0..2 {
                    f[ids[k]] -= grad[k] * lambda;
                }
            }
        }
        f
    }

    /// Spring forces, one spring at a time, added to both ends.
    pub fn spring_forces_scatter(&self) -> Vec<DVec3> {
        let mut f = vec![DVec3::ZERO; self.problem.model.node_count()];
        for (s, &[i, j]) in self.problem.model.springs.iter().enumerate() {
            let (i, j) = (i as usize, j as usize);
            let fi = self.spring(i, j, s);
            f[i] += fi;
            f[j] -= fi;
        }
        f
    }

    /// Spring forces, one node at a time, gathered over its springs (`node_springs`).
    pub fn spring_forces_gather(&self) -> Vec<DVec3> {
        (0..self.problem.model.node_count())
            .map(|i| {
                let mut f = DVec3::ZERO;
                for &s in self.problem.model.node_springs.row(i) {
                    let [a, b] = self.problem.model.springs[s as usize];
                    let other = if a as usize == i { b } else { a };
                    f += self.spring(i, other as usize, s as usize);
                }
                f
            })
            .collect()
    }

    /// Explicit force on node `i` of spring `s`, whose other end is `j`.
    fn spring(&self, i: usize, j: usize, s: usize) -> DVec3 {
        spring_force(
            self.x[i],
            self.x[j],
            self.v[i],
            self.v[j],
            self.problem.model.rest_length[s],
            self.problem.material.spring_stiffness[s],
            self.problem.material.spring_damping[s],
        )
    }
}
