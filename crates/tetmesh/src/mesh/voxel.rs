//! The voxel mesher: keeps the cells of a regular grid whose centres lie inside a surface and
//! splits them into tetrahedra ([`grid_tets`]). Works on surfaces TetGen rejects.
//!
//! Inside test: from each cell centre, six axis-aligned rays (+-x, +-y, +-z) count signed
//! crossings (+1 leaving through an outward face, -1 entering): the winding number along that
//! ray, exact for a closed surface. A centre is inside when at least three of the six rays say
//! so (winding >= 1). A hole spoils only the rays that pass through it, and overlapping parts
//! of a self-intersecting surface add up (winding 2 is still inside), so the test holds up on
//! both. Rays for a whole grid column are cast at once.

use glam::DVec3;

use super::grid::grid_tets;
use super::repair::orient::signed_volume;
use super::{SurfaceMesh, TetMesh};
use crate::error::{Error, Result};

/// Tetrahedra per grid cell (Kuhn split).
const TETS_PER_CELL: usize = 6;

/// A regular grid: `cells` cubes of edge `h` from `origin`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoxelGrid {
    /// Lowest corner.
    pub origin: DVec3,
    /// Cell edge length (length unit of the surface).
    pub h: f64,
    /// Cells along x, y, z.
    pub cells: [usize; 3],
}

impl VoxelGrid {
    /// A grid of cell size `h` covering the bounds `(lo, hi)`, centred on them.
    pub fn covering(lo: DVec3, hi: DVec3, h: f64) -> Self {
        let extent = hi - lo;
        let cells = [0, 1, 2].map(|a| ((extent[a] / h).ceil() as usize).max(1));
        let size = DVec3::new(cells[0] as f64, cells[1] as f64, cells[2] as f64) * h;
        Self {
            origin: (lo + hi) * 0.5 - size * 0.5,
            h,
            cells,
        }
    }

    fn index(&self, c: [usize; 3]) -> usize {
        c[0] + self.cells[0] * (c[1] + self.cells[1] * c[2])
    }
}

/// Which cells of `grid` have their centre inside `surface` (indexed `x + nx * (y + ny * z)`).
pub fn inside_cells(surface: &SurfaceMesh, grid: &VoxelGrid) -> Vec<bool> {
    let n = grid.cells;
    let mut votes = vec![0u8; n[0] * n[1] * n[2]];
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        // Small irrational-looking offsets keep rays off edges and vertices that lie on the
        // grid (e.g. a box surface meshed with the grid's own spacing).
        let jitter = [1.234_567e-4, 7.654_321e-5];
        let col_center =
            |i: usize, a: usize, j: f64| grid.origin[a] + (i as f64 + 0.5 + j) * grid.h;
        let mut hits: Vec<Vec<(f64, i32)>> = vec![Vec::new(); n[u] * n[v]];
        for t in &surface.triangles {
            let p = t.map(|i| surface.vertices[i as usize]);
            let normal = (p[1] - p[0]).cross(p[2] - p[0]);
            if normal[axis] == 0.0 {
                continue;
            }
            let sign = if normal[axis] > 0.0 { 1 } else { -1 };
            let lo = p[0].min(p[1]).min(p[2]);
            let hi = p[0].max(p[1]).max(p[2]);
            let range = |a: usize, j: f64| {
                let first = ((lo[a] - grid.origin[a]) / grid.h - 0.5 - j)
                    .ceil()
                    .max(0.0) as usize;
                let last = ((hi[a] - grid.origin[a]) / grid.h - 0.5 - j).floor();
                (
                    first,
                    if last < 0.0 {
                        None
                    } else {
                        Some((last as usize).min(n[a] - 1))
                    },
                )
            };
            let (iu0, iu1) = range(u, jitter[0]);
            let (iv0, iv1) = range(v, jitter[1]);
            let (Some(iu1), Some(iv1)) = (iu1, iv1) else {
                continue;
            };
            for iv in iv0..=iv1 {
                for iu in iu0..=iu1 {
                    let (cu, cv) = (col_center(iu, u, jitter[0]), col_center(iv, v, jitter[1]));
                    if let Some(s) = ray_hit(&p, axis, u, v, cu, cv) {
                        hits[iu + n[u] * iv].push((s, sign));
                    }
                }
            }
        }
        for iv in 0..n[v] {
            for iu in 0..n[u] {
                let column = &mut hits[iu + n[u] * iv];
                column.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
                let total: i32 = column.iter().map(|h| h.1).sum();
                let mut before = 0; // sum of signs of hits below the current centre
                let mut next = 0;
                for k in 0..n[axis] {
                    let t = col_center(k, axis, 0.0);
                    while next < column.len() && column[next].0 < t {
                        before += column[next].1;
                        next += 1;
                    }
                    let mut c = [0; 3];
                    (c[axis], c[u], c[v]) = (k, iu, iv);
                    let forward = total - before; // ray towards +axis
                    let backward = -before; // ray towards -axis
                    votes[grid.index(c)] += (forward >= 1) as u8 + (backward >= 1) as u8;
                }
            }
        }
    }
    votes.into_iter().map(|v| v >= 3).collect()
}

/// Where the line `{u = cu, v = cv}` along `axis` meets triangle `p` (coordinate along
/// `axis`), if it passes through it.
fn ray_hit(p: &[DVec3; 3], axis: usize, u: usize, v: usize, cu: f64, cv: f64) -> Option<f64> {
    let e = |a: DVec3, b: DVec3| (b[u] - a[u]) * (cv - a[v]) - (b[v] - a[v]) * (cu - a[u]);
    let w = [e(p[1], p[2]), e(p[2], p[0]), e(p[0], p[1])];
    let all_pos = w.iter().all(|&x| x > 0.0);
    let all_neg = w.iter().all(|&x| x < 0.0);
    if !(all_pos || all_neg) {
        return None;
    }
    let sum = w[0] + w[1] + w[2];
    Some((w[0] * p[0][axis] + w[1] * p[1][axis] + w[2] * p[2][axis]) / sum)
}

/// Meshes the inside of `surface` with about `target_tets` tetrahedra (within about 10 % when
/// the shape allows; the cell size is corrected up to three times). Errors when the surface
/// is empty or no cell centre lies inside it.
pub fn voxel_mesh(surface: &SurfaceMesh, target_tets: usize) -> Result<TetMesh> {
    let (lo, hi) = surface
        .bounds()
        .ok_or_else(|| Error::Meshing("voxel mesher: the surface has no vertices".into()))?;
    if surface.triangles.is_empty() || !(lo.is_finite() && hi.is_finite()) {
        return Err(Error::Meshing(
            "voxel mesher: the surface has no faces or non-finite coordinates".into(),
        ));
    }
    let extent = hi - lo;
    let box_volume = extent.x.max(0.0) * extent.y.max(0.0) * extent.z.max(0.0);
    let volume = signed_volume(&surface.vertices, &surface.triangles).abs();
    let volume = if volume > 1e-3 * box_volume {
        volume
    } else {
        0.5 * box_volume
    };
    if volume.is_nan() || volume <= 0.0 {
        return Err(Error::Meshing(
            "voxel mesher: the surface encloses no volume (it is flat)".into(),
        ));
    }
    let target = target_tets.max(TETS_PER_CELL);
    let mut h = (TETS_PER_CELL as f64 * volume / target as f64).cbrt();
    let mut best: Option<(usize, VoxelGrid, Vec<bool>)> = None;
    for _ in 0..4 {
        let grid = VoxelGrid::covering(lo, hi, h);
        let inside = inside_cells(surface, &grid);
        let tets = TETS_PER_CELL * inside.iter().filter(|&&b| b).count();
        let off = |t: usize| (t as f64 - target as f64).abs();
        if best
            .as_ref()
            .map_or(true, |(bt, _, _)| off(tets) < off(*bt))
        {
            best = Some((tets, grid, inside));
        }
        if tets > 0 && off(tets) <= 0.1 * target as f64 {
            break;
        }
        // Tets scale with h^-3; with no cell inside yet, halve the cell size.
        h *= if tets == 0 {
            0.5
        } else {
            (tets as f64 / target as f64).cbrt()
        };
    }
    let Some((tets, grid, inside)) = best else {
        return Err(Error::Meshing("voxel mesher: no grid was tried".into()));
    };
    if tets == 0 {
        return Err(Error::Meshing(
            "voxel mesher: no grid cell lies inside the surface".into(),
        ));
    }
    Ok(grid_tets(grid.origin, grid.h, grid.cells, |c| {
        inside[grid.index(c)]
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_hit_interpolates() {
        let p = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 2.0),
            DVec3::new(0.0, 1.0, 3.0),
        ];
        let s = ray_hit(&p, 2, 0, 1, 0.25, 0.25).unwrap();
        assert!((s - (1.0 + 0.25 + 0.5)).abs() < 1e-12);
        assert!(ray_hit(&p, 2, 0, 1, 0.75, 0.75).is_none());
    }
}
