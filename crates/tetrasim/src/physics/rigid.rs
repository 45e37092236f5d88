//! The rigid part of a force field on a free body: the net force and the torque of internal
//! forces are zero, but an iterative solve stopped early leaves a residual that has both
//! (the finite elements' conjugate gradients: their net force is minus the residual's sum).
//! [`RigidPart::of`] finds the uniform acceleration and angular acceleration that the field
//! imparts to the body as a rigid whole; subtracting [`RigidPart::force`] at every node
//! leaves a field with zero net force and zero torque, unchanged in every deformation mode.

use glam::{DMat3, DVec3};

/// The rigid motion a force field imparts to a body: `f_i = m_i (a + alpha x (x_i - c))`
/// at each node has the field's net force and torque about the centre of mass `c`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RigidPart {
    centre: DVec3,
    acceleration: DVec3,
    angular: DVec3,
}

impl RigidPart {
    /// The rigid part of the forces `f` on nodes at `x` with masses `m` (in one pass over
    /// `(x, m, f)`). A body whose inertia tensor is singular (its nodes on one line) keeps
    /// its torque.
    pub fn of(nodes: impl Iterator<Item = (DVec3, f64, DVec3)>) -> Self {
        let (mut mass, mut first, mut second) = (0.0, DVec3::ZERO, DMat3::ZERO);
        let (mut force, mut torque) = (DVec3::ZERO, DVec3::ZERO);
        for (x, m, f) in nodes {
            mass += m;
            first += x * m;
            second += outer(x, x * m);
            force += f;
            torque += x.cross(f);
        }
        if mass <= 0.0 {
            return RigidPart::default();
        }
        let centre = first / mass;
        // Second moment and torque about the centre of mass.
        let about = second - outer(centre, centre * mass);
        let torque = torque - centre.cross(force);
        let trace = about.x_axis.x + about.y_axis.y + about.z_axis.z;
        let inertia = DMat3::from_diagonal(DVec3::splat(trace)) - about;
        let scale = trace * trace * trace;
        let angular = if inertia.determinant().abs() > 1e-12 * scale.abs() {
            inertia.inverse() * torque
        } else {
            DVec3::ZERO
        };
        RigidPart {
            centre,
            acceleration: force / mass,
            angular,
        }
    }

    /// The rigid part's force on a node of mass `m` at `x` [N].
    pub fn force(&self, x: DVec3, m: f64) -> DVec3 {
        (self.acceleration + self.angular.cross(x - self.centre)) * m
    }
}

/// The length of the rigid-part correction on a body a contact holds, from its moves `d`:
/// `gain = r . d` (`r` the Newton step's residual) and `curvature = d . A d`, the length
/// that minimises the step's quadratic model along `d`, kept within [0, 1]; zero where
/// the model has no positive curvature along it (docs/PHYSICS.md, "The correction's
/// length"). A body nothing holds keeps the whole correction, its momentum's balance.
pub fn correction_length(gain: f64, curvature: f64) -> f64 {
    if gain > 0.0 && curvature > 0.0 {
        (gain / curvature).min(1.0)
    } else {
        0.0
    }
}

/// `a b^T`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removing_the_rigid_part_leaves_no_net_force_or_torque_and_keeps_deformation() {
        let x = [
            DVec3::new(0.1, 0.2, -0.3),
            DVec3::new(1.0, 0.0, 0.2),
            DVec3::new(0.0, 1.5, 0.1),
            DVec3::new(0.3, 0.4, 1.2),
            DVec3::new(-0.7, 0.9, 0.5),
        ];
        let m = [1.0, 2.0, 0.5, 3.0, 1.5];
        let f = [
            DVec3::new(1.0, -2.0, 0.5),
            DVec3::new(0.3, 0.1, -0.4),
            DVec3::new(-0.2, 0.8, 0.9),
            DVec3::new(0.0, 0.5, -1.1),
            DVec3::new(2.0, -0.3, 0.2),
        ];
        let part = RigidPart::of((0..5).map(|i| (x[i], m[i], f[i])));
        let rest: Vec<DVec3> = (0..5).map(|i| f[i] - part.force(x[i], m[i])).collect();
        let net: DVec3 = rest.iter().sum();
        let torque: DVec3 = (0..5).map(|i| x[i].cross(rest[i])).sum();
        assert!(net.length() < 1e-12, "net force {net}");
        assert!(torque.length() < 1e-12, "torque {torque}");
        // A field with no rigid part (a pair of opposite forces along their line) is kept.
        let pair = [DVec3::X, -DVec3::X, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO];
        let x_pair = [DVec3::ZERO, DVec3::X * 2.0, x[2], x[3], x[4]];
        let part = RigidPart::of((0..5).map(|i| (x_pair[i], m[i], pair[i])));
        for i in 0..5 {
            assert!(part.force(x_pair[i], m[i]).length() < 1e-12);
        }
    }

    #[test]
    fn the_correction_is_taken_as_far_as_it_lowers_the_model() {
        // The model `-g s + c s^2 / 2` is least at `s = g / c`, kept within [0, 1].
        assert_eq!(correction_length(0.25, 1.0), 0.25);
        assert_eq!(correction_length(3.0, 1.0), 1.0);
        // Uphill, flat, or not a number: none of it.
        assert_eq!(correction_length(-0.5, 1.0), 0.0);
        assert_eq!(correction_length(0.5, 0.0), 0.0);
        assert_eq!(correction_length(f64::NAN, 1.0), 0.0);
    }
}
