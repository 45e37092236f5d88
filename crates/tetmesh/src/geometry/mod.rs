//! Geometry written once for the mesh tools and the engine: the [`Real`] and [`Vector`]
//! traits that let one copy of a formula serve `f64` and `f32`, and the signed tet volume
//! every part of the project measures with (meshing, quality, outputs, the solvers' volume
//! constraints; `glsl/physics/volume.glsl` has its twin of the same name).

mod real;

pub use real::{Real, Vector};

/// Signed volume of the tetrahedron `p` in the convention of physics.md:
/// `(e1 x e2) . e3 / 6` with `e_k = p_k - p_0`, positive for a positively oriented tet
/// (`p_3` on the side of `(p_0, p_1, p_2)` that their counter-clockwise order faces).
#[inline]
pub fn tet_volume<V: Vector>(p: [V; 4]) -> V::Real {
    let (e1, e2, e3) = (p[1] - p[0], p[2] - p[0], p[3] - p[0]);
    e1.cross(e2).dot(e3) * V::Real::from_f64(1.0 / 6.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};

    #[test]
    fn unit_corner_tet_has_a_sixth_and_flips_sign_with_orientation() {
        let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        assert!((tet_volume(p) - 1.0 / 6.0).abs() < 1e-15);
        assert!((tet_volume([p[0], p[2], p[1], p[3]]) + 1.0 / 6.0).abs() < 1e-15);
        let q = p.map(|v| Vec3::from_dvec3(v * 2.0 + DVec3::splat(5.0)));
        assert!((tet_volume(q) - 8.0 / 6.0).abs() < 1e-5);
    }
}
