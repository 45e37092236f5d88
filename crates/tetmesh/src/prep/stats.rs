//! What `tetprep` reports after every run (printed as a table or as JSON).

use std::fmt;

use serde::Serialize;

use super::quality::tet_quality;
use crate::mesh::repair::RepairReport;
use crate::mesh::{topology, TetMesh};

/// Time spent in one stage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StageTime {
    /// `read`, `repair`, `mesh` or `stats`.
    pub stage: String,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Figures of one preprocessing run. Lengths are in the (scaled) input unit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PrepStats {
    /// The input file, when read from one.
    pub input: Option<String>,
    /// The mesher that produced the mesh (`tetgen` or `voxel`).
    pub mesher: String,
    /// Whether TetGen failed and the voxel mesher stood in (`--fallback`).
    pub fell_back: bool,
    /// TetGen's switch string of the kept run.
    pub tetgen_switches: Option<String>,
    /// Mesher runs (TetGen runs spent reaching the target).
    pub tetgen_runs: usize,
    /// Faces as read, after repair, and as meshed (after simplification).
    pub faces_in: usize,
    /// Faces after repair.
    pub faces_repaired: usize,
    /// Faces handed to the mesher (after simplification).
    pub faces_meshed: usize,
    /// Mesh size.
    pub nodes: usize,
    /// Tets of the mesh.
    pub tets: usize,
    /// Unique tet edges.
    pub springs: usize,
    /// Boundary triangles of the tet mesh.
    pub surface_faces: usize,
    /// Vertices where the tet mesh's boundary surface is pinched (its triangles around the
    /// vertex form more than one fan, e.g. two tets touching at a tip); MeshLab calls them
    /// non-manifold vertices.
    pub surface_non_manifold_vertices: usize,
    /// The same count on the surface handed to the mesher (after simplification).
    pub meshed_non_manifold_vertices: usize,
    /// Dihedral angle range over all tets [degrees].
    pub min_dihedral_deg: f64,
    /// Largest dihedral angle over all tets [degrees].
    pub max_dihedral_deg: f64,
    /// Tets with signed volume <= 0 (0 for a usable mesh).
    pub non_positive_tets: usize,
    /// Median over tets of their node indices' spread, as a fraction of the node count
    /// ([`crate::mesh::order::median_index_spread`]: small when a tet's nodes sit together
    /// in memory).
    pub median_index_spread: f64,
    /// Sum of tet volumes and the repaired surface's enclosed volume (length unit cubed).
    pub tet_volume: f64,
    /// The repaired surface's enclosed volume (length unit cubed).
    pub enclosed_volume: f64,
    /// `100 * tet_volume / enclosed_volume`.
    pub volume_percent: f64,
    /// The requested tet count and how far off the result is [%].
    pub target_tets: Option<usize>,
    /// How far the tet count is from the target [%].
    pub target_error_percent: Option<f64>,
    /// Per-stage wall-clock times and their total [s].
    pub times: Vec<StageTime>,
    /// Total wall-clock time [s].
    pub total_seconds: f64,
    /// What the repair found and did.
    pub repair: RepairReport,
    /// Problems worth a look (repair findings, fallback).
    pub warnings: Vec<String>,
}

impl PrepStats {
    /// Measures `mesh` against the repaired surface described by `report`. Mesher fields and
    /// times are filled in by the pipeline.
    pub fn measure(mesh: &TetMesh, report: &RepairReport, target: Option<usize>) -> Self {
        let q = tet_quality(mesh);
        let tets = mesh.tets.len();
        let derived;
        let boundary = if mesh.faces.is_empty() {
            derived = topology::boundary_faces(&mesh.tets);
            &derived
        } else {
            &mesh.faces
        };
        Self {
            input: None,
            mesher: String::new(),
            fell_back: false,
            tetgen_switches: None,
            tetgen_runs: 0,
            faces_in: report.faces_in,
            faces_repaired: report.faces_out,
            faces_meshed: report.faces_out,
            nodes: mesh.nodes.len(),
            tets,
            springs: topology::unique_edges(&mesh.tets).len(),
            surface_faces: boundary.len(),
            surface_non_manifold_vertices: topology::non_manifold_vertices(boundary).len(),
            meshed_non_manifold_vertices: report.non_manifold_vertices,
            min_dihedral_deg: q.min_dihedral_deg,
            max_dihedral_deg: q.max_dihedral_deg,
            non_positive_tets: q.non_positive,
            median_index_spread: crate::mesh::order::median_index_spread(mesh),
            tet_volume: q.volume,
            enclosed_volume: report.enclosed_volume,
            volume_percent: 100.0 * q.volume / report.enclosed_volume,
            target_tets: target,
            target_error_percent: target.map(|n| 100.0 * (tets as f64 - n as f64) / n as f64),
            times: Vec::new(),
            total_seconds: 0.0,
            repair: report.clone(),
            warnings: Vec::new(),
        }
    }
}

impl fmt::Display for PrepStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.repair;
        if let Some(input) = &self.input {
            writeln!(f, "input            {input}")?;
        }
        writeln!(
            f,
            "repair           {} -> {} faces: welded {} vertices, dropped {} degenerate + {} duplicate faces, flipped {} (+{} outward), filled {} holes with {} faces",
            r.faces_in, r.faces_out, r.welded_vertices, r.degenerate_faces, r.duplicate_faces, r.flipped_faces, r.outward_flipped_faces, r.holes, r.hole_faces_added
        )?;
        let crossing = r
            .self_intersections
            .map_or("not checked".to_string(), |n| n.to_string());
        writeln!(f, "surface checks   {} non-manifold edges, {} non-manifold vertices, {} boundary edges, {crossing} self-intersections", r.non_manifold_edges, r.non_manifold_vertices, r.boundary_edges)?;
        let fallback = if self.fell_back { " (fallback)" } else { "" };
        let switches = self
            .tetgen_switches
            .as_deref()
            .map(|s| format!(", switches -{s}"))
            .unwrap_or_default();
        writeln!(
            f,
            "mesher           {}{fallback}{switches}, {} run(s), {} faces meshed ({} non-manifold vertices)",
            self.mesher, self.tetgen_runs, self.faces_meshed, self.meshed_non_manifold_vertices
        )?;
        writeln!(f, "nodes            {}", self.nodes)?;
        write!(f, "tets             {}", self.tets)?;
        if let (Some(n), Some(e)) = (self.target_tets, self.target_error_percent) {
            write!(f, " (target {n}, {e:+.1} %)")?;
        }
        writeln!(f)?;
        writeln!(f, "springs          {}", self.springs)?;
        writeln!(
            f,
            "surface faces    {} ({} non-manifold vertices)",
            self.surface_faces, self.surface_non_manifold_vertices
        )?;
        writeln!(
            f,
            "dihedral angles  {:.2} .. {:.2} deg",
            self.min_dihedral_deg, self.max_dihedral_deg
        )?;
        writeln!(f, "non-positive     {} tets", self.non_positive_tets)?;
        writeln!(
            f,
            "node order       median index spread {:.4} of the node count",
            self.median_index_spread
        )?;
        writeln!(
            f,
            "volume           {:.6e} of {:.6e} enclosed ({:.3} %)",
            self.tet_volume, self.enclosed_volume, self.volume_percent
        )?;
        let times: Vec<String> = self
            .times
            .iter()
            .map(|t| format!("{} {:.2}", t.stage, t.seconds))
            .collect();
        write!(
            f,
            "time [s]         {} (total {:.2})",
            times.join(", "),
            self.total_seconds
        )?;
        for w in &self.warnings {
            write!(f, "\nwarning: {w}")?;
        }
        Ok(())
    }
}
