//! A signed distance sampled on a regular grid (the `mesh` collider): built once from a closed
//! surface, read by trilinear interpolation (physics.md, "Kinematic colliders"). The GLSL twin
//! of [`DistanceGrid::sample`] is `grid_distance` in glsl/physics/contact.glsl.

use glam::DVec3;

/// Signed distances [m] (negative inside) at the nodes of a regular grid.
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceGrid {
    /// Position of sample `(0, 0, 0)` [m], in the collider's local frame.
    pub origin: DVec3,
    /// Spacing of the samples [m].
    pub cell: f64,
    /// Samples along X, Y and Z (each at least 2).
    pub dims: [u32; 3],
    /// `dims[0] * dims[1] * dims[2]` distances, X fastest, then Y, then Z.
    pub values: Vec<f64>,
}

impl DistanceGrid {
    /// The sample at integer coordinates `(i, j, k)`.
    pub fn at(&self, i: u32, j: u32, k: u32) -> f64 {
        let [nx, ny, _] = self.dims;
        self.values[(i + nx * (j + ny * k)) as usize]
    }

    /// The far corner of the sampled box [m].
    pub fn end(&self) -> DVec3 {
        self.origin
            + (DVec3::new(
                self.dims[0] as f64,
                self.dims[1] as f64,
                self.dims[2] as f64,
            ) - 1.0)
                * self.cell
    }

    /// Signed distance and outward unit normal at `p` (local frame): trilinear in the cell
    /// holding `p`, the normal the normalised gradient of that interpolant. Outside the
    /// sampled box, the distance at the nearest point of the box plus the distance to it.
    pub fn sample(&self, p: DVec3) -> (f64, DVec3) {
        let q = p.clamp(self.origin, self.end());
        let outside = (p - q).length();
        let u = (q - self.origin) / self.cell;
        let top = DVec3::new(
            self.dims[0] as f64 - 2.0,
            self.dims[1] as f64 - 2.0,
            self.dims[2] as f64 - 2.0,
        );
        let base = u.floor().clamp(DVec3::ZERO, top);
        let t = u - base;
        let (i, j, k) = (base.x as u32, base.y as u32, base.z as u32);
        let c = |a: u32, b: u32, d: u32| self.at(i + a, j + b, k + d);
        // Interpolate along X, then Y, then Z, keeping the partial derivatives.
        let x00 = c(0, 0, 0) + (c(1, 0, 0) - c(0, 0, 0)) * t.x;
        let x10 = c(0, 1, 0) + (c(1, 1, 0) - c(0, 1, 0)) * t.x;
        let x01 = c(0, 0, 1) + (c(1, 0, 1) - c(0, 0, 1)) * t.x;
        let x11 = c(0, 1, 1) + (c(1, 1, 1) - c(0, 1, 1)) * t.x;
        let y0 = x00 + (x10 - x00) * t.y;
        let y1 = x01 + (x11 - x01) * t.y;
        let value = y0 + (y1 - y0) * t.z;
        let dx0 = (c(1, 0, 0) - c(0, 0, 0))
            + ((c(1, 1, 0) - c(0, 1, 0)) - (c(1, 0, 0) - c(0, 0, 0))) * t.y;
        let dx1 = (c(1, 0, 1) - c(0, 0, 1))
            + ((c(1, 1, 1) - c(0, 1, 1)) - (c(1, 0, 1) - c(0, 0, 1))) * t.y;
        let gradient = DVec3::new(
            dx0 + (dx1 - dx0) * t.z,
            (x10 - x00) + ((x11 - x01) - (x10 - x00)) * t.z,
            y1 - y0,
        );
        let normal = if outside > 0.0 {
            (p - q) / outside
        } else {
            gradient.try_normalize().unwrap_or(DVec3::Y)
        };
        (value + outside, normal)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of the exact distance to a sphere of radius 0.5 at the origin.
    fn sphere_grid(n: u32) -> DistanceGrid {
        let cell = 2.0 / (n - 1) as f64;
        let origin = DVec3::splat(-1.0);
        let mut values = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let p = origin + DVec3::new(i as f64, j as f64, k as f64) * cell;
                    values.push(p.length() - 0.5);
                }
            }
        }
        DistanceGrid {
            origin,
            cell,
            dims: [n; 3],
            values,
        }
    }

    #[test]
    fn trilinear_distance_follows_the_sampled_field() {
        let grid = sphere_grid(41);
        for p in [
            DVec3::new(0.3, 0.1, -0.2),
            DVec3::new(0.0, 0.55, 0.0),
            DVec3::new(-0.7, 0.2, 0.4),
        ] {
            let (phi, n) = grid.sample(p);
            assert!((phi - (p.length() - 0.5)).abs() < 3e-3, "{p}: {phi}");
            assert!(n.angle_between(p) < 0.1, "{p}: normal {n}");
        }
        let (phi, n) = grid.sample(DVec3::new(3.0, 0.0, 0.0));
        assert!(
            (phi - 2.5).abs() < 1e-9 && n == DVec3::X,
            "outside the box: {phi} {n}"
        );
    }
}
