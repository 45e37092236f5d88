//! Cut and refill: the faces of each crossing pair, the faces on non-manifold edges (more
//! than two faces) and faces on the same three vertices are cut out, and the holes left behind are filled again
//! ([`super::holes`]). When a round does not clear them, the next one also cuts the faces
//! around (sharing a vertex with) the bad ones, so the refill spans a wider, flatter hole.
//! Scans have a few folds and fins (decimated ones more); so do hole patches now and then.

use std::collections::{HashMap, HashSet};

use super::{holes, intersect, orient};
use crate::mesh::SurfaceMesh;

/// Largest fraction of faces in crossing pairs that is cut and refilled; beyond it the
/// surface overlaps itself at large (e.g. two interpenetrating parts) and is left as it is.
pub const MAX_CROSSING_FRACTION: f64 = 0.01;

/// Rounds of cutting and refilling before giving up.
pub const MAX_ROUNDS: usize = 4;

/// What [`untangle`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Untangled {
    /// Crossing face pairs and non-manifold edges found at the start.
    pub crossings_before: usize,
    /// Non-manifold edges found at the start.
    pub non_manifold_before: usize,
    /// Faces cut out (all rounds) and faces added by refilling.
    pub faces_removed: usize,
    /// Faces added by refilling.
    pub faces_added: usize,
    /// Crossing face pairs and non-manifold edges left at the end (0 unless it gave up).
    pub crossings_after: usize,
    /// Non-manifold edges left at the end.
    pub non_manifold_after: usize,
    /// Whether crossings were left alone because there were too many (more than
    /// [`MAX_CROSSING_FRACTION`] of the faces cross).
    pub crossings_left: bool,
}

/// The faces to cut: those of crossing pairs (when `crossings`) and those on non-manifold
/// edges; with the counts of both.
fn bad_faces(mesh: &SurfaceMesh, crossings: bool) -> (HashSet<u32>, usize, usize) {
    let pairs = if crossings {
        intersect::self_intersections(&mesh.vertices, &mesh.triangles)
    } else {
        Vec::new()
    };
    let edges = orient::edge_faces(&mesh.triangles);
    let mut bad: HashSet<u32> = pairs.iter().flat_map(|&(f, g)| [f, g]).collect();
    let mut non_manifold = 0;
    for faces in edges.values().filter(|f| f.len() > 2) {
        non_manifold += 1;
        bad.extend(faces);
    }
    // Faces on the same three vertices (hole patches can recreate one): cut every copy.
    let mut by_set: HashMap<[u32; 3], Vec<u32>> = HashMap::new();
    for (f, t) in mesh.triangles.iter().enumerate() {
        let mut key = *t;
        key.sort_unstable();
        by_set.entry(key).or_default().push(f as u32);
    }
    bad.extend(by_set.values().filter(|f| f.len() > 1).flatten());
    (bad, pairs.len(), non_manifold)
}

/// Cuts out crossing faces (when `crossings`) and faces on non-manifold edges and refills
/// the holes, up to [`MAX_ROUNDS`] times. Faces must be consistently oriented (refills take
/// their surroundings' winding). Unused vertices stay.
pub fn untangle(mesh: &mut SurfaceMesh, crossings: bool) -> Untangled {
    let (mut cut, c, n) = bad_faces(mesh, crossings);
    let mut result = Untangled {
        crossings_before: c,
        non_manifold_before: n,
        ..Default::default()
    };
    // Parts overlapping at large are no local defect: leave them (and report them).
    let crossing_faces = if crossings {
        let pairs = intersect::self_intersections(&mesh.vertices, &mesh.triangles);
        pairs
            .iter()
            .flat_map(|&(f, g)| [f, g])
            .collect::<HashSet<u32>>()
            .len()
    } else {
        0
    };
    let crossings = if crossing_faces as f64 > MAX_CROSSING_FRACTION * mesh.triangles.len() as f64 {
        result.crossings_left = true;
        let (bad, _, _) = bad_faces(mesh, false);
        cut = bad;
        false
    } else {
        crossings
    };
    let mut counts = (c, n);
    for round in 0..MAX_ROUNDS {
        if cut.is_empty() {
            break;
        }
        for _ in 0..round {
            let ring: HashSet<u32> = cut
                .iter()
                .flat_map(|&f| mesh.triangles[f as usize])
                .collect();
            cut.extend(
                mesh.triangles
                    .iter()
                    .enumerate()
                    .filter(|(_, t)| t.iter().any(|v| ring.contains(v)))
                    .map(|(f, _)| f as u32),
            );
        }
        let before = mesh.triangles.len();
        let mut index = 0u32;
        mesh.triangles.retain(|_| {
            index += 1;
            !cut.contains(&(index - 1))
        });
        result.faces_removed += before - mesh.triangles.len();
        orient::orient_consistently(mesh);
        let (_, added, _) = holes::fill_holes(mesh);
        result.faces_added += added;
        let (next, c, n) = bad_faces(mesh, crossings);
        cut = next;
        counts = (c, n);
    }
    (result.crossings_after, result.non_manifold_after) = counts;
    if result.crossings_left {
        result.crossings_after =
            intersect::self_intersections(&mesh.vertices, &mesh.triangles).len();
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::repair::orient::edge_faces;
    use glam::DVec3;

    #[test]
    fn vertex_pushed_through_the_far_side_is_cut_and_refilled() {
        // A box whose top-centre vertex is pushed down through the bottom face: the faces
        // around it cross the bottom faces.
        let mut m = crate::mesh::shapes::box_surface(DVec3::ZERO, DVec3::ONE, 12);
        let top = m
            .vertices
            .iter()
            .position(|p| (*p - DVec3::new(0.5, 0.5, 1.0)).length() < 1e-12)
            .unwrap();
        // Off the grid's symmetry lines, so faces cross in general position.
        m.vertices[top] = DVec3::new(0.47, 0.53, -0.5);
        let u = untangle(&mut m, true);
        assert!(u.crossings_before >= 4, "{u:?}");
        assert_eq!(u.crossings_after, 0, "{u:?}");
        assert!(u.faces_removed >= 8, "{u:?}");
        assert!(
            edge_faces(&m.triangles).values().all(|f| f.len() == 2),
            "closed after refill"
        );
        assert!(intersect::self_intersections(&m.vertices, &m.triangles).is_empty());
    }

    #[test]
    fn overlapping_parts_are_left_alone() {
        let mut m = crate::mesh::shapes::sphere(1.0, 2);
        let mut other = crate::mesh::shapes::sphere(1.0, 2);
        for p in &mut other.vertices {
            *p += DVec3::new(0.7, 0.1, 0.05);
        }
        let base = m.vertices.len() as u32;
        m.vertices.extend(other.vertices);
        m.triangles
            .extend(other.triangles.iter().map(|t| t.map(|v| v + base)));
        let faces = m.triangles.len();
        let u = untangle(&mut m, true);
        assert!(u.crossings_left, "{u:?}");
        assert!(u.crossings_before > 0);
        assert_eq!(u.crossings_after, u.crossings_before);
        assert_eq!((u.faces_removed, m.triangles.len()), (0, faces));
    }
}
