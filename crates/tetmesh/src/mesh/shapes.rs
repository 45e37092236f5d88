//! Closed, outward-oriented surfaces made by code: the project's own test and demo meshes
//! (no third-party data needed).

use std::f64::consts::PI;

use glam::DVec3;

use super::SurfaceMesh;

/// The shapes the project ships (`meshes/`), at the size they are shipped: about 1 m across.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Shape {
    /// Sphere of radius 0.5 m, 1280 faces.
    Sphere,
    /// Box 1 x 0.5 x 0.5 m, 4 x 4 squares per side (192 faces).
    Box,
    /// Torus: tube centre 0.35 m from the axis, tube radius 0.15 m, 32 x 16 (1024 faces).
    Torus,
}

impl Shape {
    /// The surface of this shape.
    pub fn surface(self) -> SurfaceMesh {
        match self {
            Shape::Sphere => sphere(0.5, 3),
            Shape::Box => box_surface(
                DVec3::new(-0.5, -0.25, -0.25),
                DVec3::new(0.5, 0.25, 0.25),
                4,
            ),
            Shape::Torus => torus(0.35, 0.15, 32, 16),
        }
    }
}

/// A sphere of `radius` centred at the origin: an icosahedron subdivided `subdivisions`
/// times, vertices projected onto the sphere (`20 * 4^subdivisions` faces).
pub fn sphere(radius: f64, subdivisions: u32) -> SurfaceMesh {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices: Vec<DVec3> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .iter()
    .map(|p| DVec3::from_array(*p).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoint = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, vertices: &mut Vec<DVec3>| -> u32 {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                vertices.push(((vertices[a as usize] + vertices[b as usize]) * 0.5).normalize());
                vertices.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let (ab, bc, ca) = (
                mid(a, b, &mut vertices),
                mid(b, c, &mut vertices),
                mid(c, a, &mut vertices),
            );
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    SurfaceMesh {
        vertices: vertices.into_iter().map(|p| p * radius).collect(),
        triangles,
    }
}

/// The surface of the box `[min, max]`, each face split into `n x n` squares of two
/// triangles (`12 n^2` faces).
pub fn box_surface(min: DVec3, max: DVec3, n: usize) -> SurfaceMesh {
    let n = n.max(1);
    let mut mesh = SurfaceMesh::default();
    let mut index = std::collections::HashMap::new();
    // Each face: a fixed axis and side; (u, v) span the other two so that u x v points out.
    for axis in 0..3 {
        for side in [0.0, 1.0] {
            let (u, v) = if side > 0.0 {
                ((axis + 1) % 3, (axis + 2) % 3)
            } else {
                ((axis + 2) % 3, (axis + 1) % 3)
            };
            let mut id = |i: usize, j: usize, mesh: &mut SurfaceMesh| -> u32 {
                let mut g = [0usize; 3];
                g[axis] = if side > 0.0 { n } else { 0 };
                (g[u], g[v]) = (i, j);
                *index.entry(g).or_insert_with(|| {
                    let t = DVec3::new(g[0] as f64, g[1] as f64, g[2] as f64) / n as f64;
                    mesh.vertices.push(min + (max - min) * t);
                    mesh.vertices.len() as u32 - 1
                })
            };
            for j in 0..n {
                for i in 0..n {
                    let a = id(i, j, &mut mesh);
                    let b = id(i + 1, j, &mut mesh);
                    let c = id(i + 1, j + 1, &mut mesh);
                    let d = id(i, j + 1, &mut mesh);
                    mesh.triangles.extend([[a, b, c], [a, c, d]]);
                }
            }
        }
    }
    mesh
}

/// A torus around the z axis: tube centre at distance `major` from the axis, tube radius
/// `minor`, `segments` steps around the axis and `sides` around the tube.
pub fn torus(major: f64, minor: f64, segments: usize, sides: usize) -> SurfaceMesh {
    let (segments, sides) = (segments.max(3), sides.max(3));
    let mut vertices = Vec::with_capacity(segments * sides);
    for i in 0..segments {
        let phi = 2.0 * PI * i as f64 / segments as f64;
        for j in 0..sides {
            let theta = 2.0 * PI * j as f64 / sides as f64;
            let r = major + minor * theta.cos();
            vertices.push(DVec3::new(
                r * phi.cos(),
                r * phi.sin(),
                minor * theta.sin(),
            ));
        }
    }
    let id = |i: usize, j: usize| ((i % segments) * sides + (j % sides)) as u32;
    let mut triangles = Vec::with_capacity(2 * segments * sides);
    for i in 0..segments {
        for j in 0..sides {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            triangles.extend([[a, b, c], [a, c, d]]);
        }
    }
    SurfaceMesh {
        vertices,
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::repair::orient::signed_volume;

    #[test]
    fn shapes_are_closed_outward_with_expected_volume() {
        let s = sphere(2.0, 3);
        assert_eq!(s.triangles.len(), 20 * 64);
        let v = signed_volume(&s.vertices, &s.triangles);
        let exact = 4.0 / 3.0 * PI * 8.0;
        assert!(v > 0.97 * exact && v < exact, "{v} vs {exact}");

        let b = box_surface(DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0), 3);
        assert_eq!(b.triangles.len(), 12 * 9);
        assert_eq!(b.vertices.len(), 6 * 16 - 12 * 4 + 8);
        assert!((signed_volume(&b.vertices, &b.triangles) - 6.0).abs() < 1e-12);

        let t = torus(2.0, 0.5, 48, 24);
        let exact = 2.0 * PI * PI * 2.0 * 0.25;
        let v = signed_volume(&t.vertices, &t.triangles);
        assert!(v > 0.97 * exact && v < exact, "{v} vs {exact}");
        for m in [&s, &b, &t] {
            let edges = crate::mesh::repair::orient::edge_faces(&m.triangles);
            assert!(edges.values().all(|f| f.len() == 2));
        }
    }
}
