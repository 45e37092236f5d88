//! Mass-spring force (physics.md, "Mass-spring forces", paper Eq. 1).

use super::{Real, Vector};

/// Force [N] on node `i` of the spring `(i, j)`; the force on `j` is its negation.
///
/// `x_*` are positions [m], `v_*` velocities [m/s], `rest` the rest length [m], `ks` the
/// stiffness [N/m] and `kd` the damping [N s/m]:
/// `f_i = [ks (l - L) + kd ((v_j - v_i) . n)] n` with `d = x_j - x_i`, `l = |d|`, `n = d / l`.
/// A spring of zero length has no direction and returns zero.
#[inline]
pub fn spring_force<V: Vector>(
    xi: V,
    xj: V,
    vi: V,
    vj: V,
    rest: V::Real,
    ks: V::Real,
    kd: V::Real,
) -> V {
    let d = xj - xi;
    let l = d.length();
    if l <= V::Real::ZERO {
        return V::ZERO;
    }
    let n = d * (V::Real::ONE / l);
    n * (ks * (l - rest) + kd * (vj - vi).dot(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn stretched_spring_pulls_ends_together() {
        let f = spring_force(
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::ZERO,
            DVec3::ZERO,
            1.5,
            100.0,
            0.0,
        );
        assert!((f - DVec3::new(50.0, 0.0, 0.0)).length() < 1e-12);
    }

    #[test]
    fn damping_acts_on_relative_normal_velocity_only() {
        let vj = DVec3::new(-1.0, 3.0, 0.0); // approaching along x, sliding along y
        let f = spring_force(DVec3::ZERO, DVec3::X, DVec3::ZERO, vj, 1.0, 100.0, 2.0);
        assert!((f - DVec3::new(-2.0, 0.0, 0.0)).length() < 1e-12);
    }

    #[test]
    fn zero_length_spring_has_no_force() {
        let f = spring_force(
            DVec3::ONE,
            DVec3::ONE,
            DVec3::ZERO,
            DVec3::X,
            1.0,
            100.0,
            2.0,
        );
        assert_eq!(f, DVec3::ZERO);
    }
}
