//! Surface repair before meshing: weld duplicate vertices, drop degenerate and duplicate
//! faces and unreferenced vertices, orient faces consistently and outward, fill holes, and
//! report what cannot be fixed here (non-manifold edges and vertices, self-intersections) in
//! words.
//!
//! Order: clean -> consistent orientation -> fill holes -> cut out crossing faces and refill
//! -> outward -> checks. Holes are filled after the orientation walk so each patch takes its
//! surroundings' winding.

pub mod clean;
pub mod holes;
pub mod intersect;
pub mod orient;
pub mod untangle;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::mesh::SurfaceMesh;

/// How many examples of each problem the report spells out.
const EXAMPLES: usize = 5;

/// What [`repair`] does.
#[derive(Debug, Clone, PartialEq)]
pub struct RepairOptions {
    /// Vertices closer than this fraction of the bounding-box diagonal are merged.
    pub weld_tolerance: f64,
    /// Fill boundary loops (holes).
    pub fill_holes: bool,
    /// Look for crossing faces (costs about as much as the rest together on large scans).
    pub check_self_intersections: bool,
    /// Cut out crossing faces (when checked) and faces on non-manifold edges, and refill.
    pub cut_and_refill: bool,
}

impl Default for RepairOptions {
    fn default() -> Self {
        Self {
            weld_tolerance: 1e-7,
            fill_holes: true,
            check_self_intersections: true,
            cut_and_refill: true,
        }
    }
}

/// Counts of everything [`repair`] found and changed.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct RepairReport {
    /// Vertices and faces as given.
    pub vertices_in: usize,
    /// Faces as given.
    pub faces_in: usize,
    /// Vertices merged into a coincident one.
    pub welded_vertices: usize,
    /// Faces dropped for a repeated vertex or zero area.
    pub degenerate_faces: usize,
    /// Faces dropped because an earlier face uses the same three vertices.
    pub duplicate_faces: usize,
    /// Vertices dropped because no face uses them.
    pub unreferenced_vertices: usize,
    /// Faces reversed to agree with their neighbours.
    pub flipped_faces: usize,
    /// Faces reversed so that each component encloses a positive volume.
    pub outward_flipped_faces: usize,
    /// Connected components (over manifold edges).
    pub components: usize,
    /// Edges whose two faces still disagree (non-orientable parts).
    pub orientation_conflicts: usize,
    /// Boundary loops found (and filled when filling is on).
    pub holes: usize,
    /// Faces and vertices the hole filling added.
    pub hole_faces_added: usize,
    /// Vertices the hole filling added.
    pub hole_vertices_added: usize,
    /// Boundary edges left after filling (0 for a closed surface).
    pub boundary_edges: usize,
    /// Edges shared by more than two faces.
    pub non_manifold_edges: usize,
    /// Vertices where the surface is pinched: their faces form more than one fan (see
    /// [`crate::mesh::topology::non_manifold_vertices`]). TetGen takes them; mesh viewers
    /// flag them.
    pub non_manifold_vertices: usize,
    /// Edges shared by more than two faces before cutting and refilling.
    pub non_manifold_edges_found: usize,
    /// Pairs of faces that crossed each other before fixing (`None` when not checked).
    pub self_intersections_found: Option<usize>,
    /// Faces cut out to remove crossings and non-manifold edges, and faces added refilling
    /// the cuts.
    pub cut_faces_removed: usize,
    /// Faces added refilling the cuts.
    pub cut_faces_added: usize,
    /// Pairs of faces that still cross each other (`None` when not checked).
    pub self_intersections: Option<usize>,
    /// Vertices and faces after repair.
    pub vertices_out: usize,
    /// Faces after repair.
    pub faces_out: usize,
    /// Volume enclosed by the repaired surface (length unit cubed).
    pub enclosed_volume: f64,
    /// The problems left, in words, with a few examples each.
    pub warnings: Vec<String>,
}

impl RepairReport {
    /// Whether the repaired surface is closed, manifold and free of crossings (as far as
    /// checked): what TetGen needs.
    pub fn is_clean(&self) -> bool {
        self.boundary_edges == 0
            && self.non_manifold_edges == 0
            && self.self_intersections.unwrap_or(0) == 0
            && self.orientation_conflicts == 0
    }
}

/// Checks that the surface is usable at all: vertices and faces present, finite
/// coordinates, indices in range.
pub fn validate(mesh: &SurfaceMesh) -> Result<()> {
    if mesh.vertices.is_empty() || mesh.triangles.is_empty() {
        return Err(Error::Mesh(format!(
            "the surface is empty ({} vertices, {} faces)",
            mesh.vertices.len(),
            mesh.triangles.len()
        )));
    }
    if let Some((i, p)) = mesh
        .vertices
        .iter()
        .enumerate()
        .find(|(_, p)| !p.is_finite())
    {
        return Err(Error::Mesh(format!(
            "vertex {i} has a non-finite coordinate ({}, {}, {})",
            p.x, p.y, p.z
        )));
    }
    let n = mesh.vertices.len();
    if let Some((f, t)) = mesh
        .triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&v| v as usize >= n))
    {
        return Err(Error::Mesh(format!(
            "face {f} {t:?} uses a vertex index out of range (there are {n} vertices)"
        )));
    }
    Ok(())
}

/// Repairs a surface (see the module doc). Errors: an unusable surface (see [`validate`]),
/// or nothing left after dropping degenerate faces.
pub fn repair(mesh: &SurfaceMesh, options: &RepairOptions) -> Result<(SurfaceMesh, RepairReport)> {
    validate(mesh)?;
    let mut m = mesh.clone();
    let mut r = RepairReport {
        vertices_in: mesh.vertices.len(),
        faces_in: mesh.triangles.len(),
        ..Default::default()
    };
    let diag = mesh
        .bounds()
        .map(|(lo, hi)| (hi - lo).length())
        .unwrap_or(0.0);

    r.welded_vertices = clean::weld(&mut m, options.weld_tolerance * diag);
    r.degenerate_faces = clean::drop_degenerate(&mut m, 1e-14 * diag * diag);
    if m.triangles.is_empty() {
        return Err(Error::Mesh(format!(
            "all {} faces are degenerate (repeated vertices or zero area)",
            mesh.triangles.len()
        )));
    }
    r.duplicate_faces = clean::drop_duplicates(&mut m);
    r.unreferenced_vertices = clean::drop_unreferenced(&mut m);

    let mut orientation = orient::orient_consistently(&mut m);
    r.flipped_faces = orientation.flipped;

    if options.fill_holes {
        let before = m.triangles.len();
        let (holes, faces, vertices) = holes::fill_holes(&mut m);
        (r.holes, r.hole_faces_added, r.hole_vertices_added) = (holes, faces, vertices);
        if m.triangles.len() != before {
            // Patches join components; walk again (no face changes winding on a good patch).
            orientation = orient::orient_consistently(&mut m);
            r.flipped_faces += orientation.flipped;
        }
    } else {
        r.holes = holes::boundary_loops(&m.triangles).len();
    }
    if options.cut_and_refill {
        let u = untangle::untangle(&mut m, options.check_self_intersections);
        r.non_manifold_edges_found = u.non_manifold_before;
        if u.crossings_left {
            r.warnings.push(format!(
                "{} pairs of faces cross: more than {} % of the faces, so parts of the surface overlap at large; left as they are",
                u.crossings_before,
                100.0 * untangle::MAX_CROSSING_FRACTION
            ));
        }
        r.self_intersections_found = options
            .check_self_intersections
            .then_some(u.crossings_before);
        (r.cut_faces_removed, r.cut_faces_added) = (u.faces_removed, u.faces_added);
        if u.faces_removed > 0 {
            orientation = orient::orient_consistently(&mut m);
            r.flipped_faces += orientation.flipped;
        }
        r.unreferenced_vertices += clean::drop_unreferenced(&mut m);
    }
    if r.cut_faces_removed > 0 {
        r.warnings.push(format!(
            "{} pairs of crossing faces and {} non-manifold edges: cut out {} faces, refilled with {}",
            r.self_intersections_found.unwrap_or(0),
            r.non_manifold_edges_found,
            r.cut_faces_removed,
            r.cut_faces_added
        ));
    }
    r.components = orientation.components;
    r.orientation_conflicts = orientation.conflicts;
    r.outward_flipped_faces =
        orient::orient_outward(&mut m, &orientation.component_of, orientation.components);

    let edges = orient::edge_faces(&m.triangles);
    r.boundary_edges = edges.values().filter(|f| f.len() == 1).count();
    let non_manifold = orient::non_manifold_edges(&edges);
    r.non_manifold_edges = non_manifold.len();
    if !non_manifold.is_empty() {
        let examples: Vec<String> = non_manifold
            .iter()
            .take(EXAMPLES)
            .map(|(e, n)| format!("vertices {}-{} ({n} faces)", e[0], e[1]))
            .collect();
        r.warnings.push(format!(
            "{} non-manifold edges (shared by more than two faces), e.g. {}",
            non_manifold.len(),
            examples.join(", ")
        ));
    }
    let pinched = crate::mesh::topology::non_manifold_vertices(&m.triangles);
    r.non_manifold_vertices = pinched.len();
    if !pinched.is_empty() {
        let examples: Vec<String> = pinched
            .iter()
            .take(EXAMPLES)
            .map(|v| v.to_string())
            .collect();
        r.warnings.push(format!(
            "{} non-manifold vertices (the surface is pinched there: their faces form more than one fan), e.g. vertices {}",
            pinched.len(),
            examples.join(", ")
        ));
    }
    if r.orientation_conflicts > 0 {
        r.warnings.push(format!(
            "{} edges where neighbouring faces cannot be oriented alike (non-orientable surface)",
            r.orientation_conflicts
        ));
    }
    if r.boundary_edges > 0 {
        r.warnings.push(format!(
            "{} boundary edges remain: the surface is not closed",
            r.boundary_edges
        ));
    }
    if options.check_self_intersections {
        let pairs = intersect::self_intersections(&m.vertices, &m.triangles);
        r.self_intersections = Some(pairs.len());
        if !pairs.is_empty() {
            let examples: Vec<String> = pairs
                .iter()
                .take(EXAMPLES)
                .map(|&(f, g)| {
                    format!(
                        "face {f} {:?} x face {g} {:?}",
                        m.triangles[f as usize], m.triangles[g as usize]
                    )
                })
                .collect();
            r.warnings.push(format!(
                "{} pairs of faces cross each other (self-intersections), e.g. {}",
                pairs.len(),
                examples.join("; ")
            ));
        }
    }
    r.vertices_out = m.vertices.len();
    r.faces_out = m.triangles.len();
    r.enclosed_volume = orient::signed_volume(&m.vertices, &m.triangles);
    Ok((m, r))
}
