//! Both meshers through the pipeline: TetGen on generated shapes and a small scan, the voxel
//! mesher on a cube and on a surface with a hole, the target count, and a surface TetGen
//! cannot take (self-intersecting) with and without `--fallback`.
#![cfg_attr(not(feature = "tetgen"), allow(unused_imports))]

#[path = "common/prep.rs"]
mod prep_fixtures;

use glam::DVec3;
use prep_fixtures::{cube, overlapping_spheres, scan, tet_volumes};
use tetrasim::mesh::repair::RepairOptions;
use tetrasim::mesh::repair::RepairReport;
use tetrasim::mesh::TetMesh;
use tetrasim::mesh::{shapes, topology, voxel::voxel_mesh};
use tetrasim::prep::{prep_file, prep_surface, Mesher, PrepOptions, PrepOutput, PrepStats};

fn quiet() -> impl FnMut(&str) {
    |_: &str| {}
}

fn assert_valid(out: &PrepOutput) {
    let volumes = tet_volumes(&out.mesh);
    assert!(
        volumes.iter().all(|&v| v > 0.0),
        "{} non-positive tets",
        volumes.iter().filter(|&&v| v <= 0.0).count()
    );
    assert_eq!(out.stats.non_positive_tets, 0);
    assert_eq!(out.stats.tets, out.mesh.tets.len());
    assert_eq!(
        out.stats.springs,
        topology::unique_edges(&out.mesh.tets).len()
    );
    assert_eq!(out.mesh.faces, topology::boundary_faces(&out.mesh.tets));
    let total: f64 = volumes.iter().sum();
    assert!((out.stats.tet_volume - total).abs() < 1e-9 * total);
}

/// Measures a hand-made tet mesh (nodes, tets) as the pipeline's stats would.
fn stats_of(nodes: &[[f64; 3]], tets: Vec<[u32; 4]>) -> PrepStats {
    let mesh = TetMesh {
        nodes: nodes.iter().map(|&p| DVec3::from_array(p)).collect(),
        faces: topology::boundary_faces(&tets),
        tets,
    };
    let report = RepairReport {
        enclosed_volume: 1.0,
        ..Default::default()
    };
    PrepStats::measure(&mesh, &report, None)
}

#[test]
fn pinched_boundary_vertex_is_counted() {
    let nodes = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1.0],
    ];
    // One tet: its boundary (4 faces) is a closed manifold.
    let one = vec![[0, 1, 2, 3]];
    assert!(topology::non_manifold_vertices(&topology::boundary_faces(&one)).is_empty());
    let stats = stats_of(&nodes, one);
    assert_eq!(
        (stats.surface_faces, stats.surface_non_manifold_vertices),
        (4, 0)
    );
    // Two tets touching only at node 0: the boundary is two closed fans around it.
    let two = vec![[0, 1, 2, 3], [0, 5, 4, 6]];
    assert_eq!(
        topology::non_manifold_vertices(&topology::boundary_faces(&two)),
        [0]
    );
    let stats = stats_of(&nodes, two);
    assert_eq!(
        (stats.surface_faces, stats.surface_non_manifold_vertices),
        (8, 1)
    );
    assert_eq!(stats.non_positive_tets, 0);
    // The JSON carries the count.
    let json = serde_json::to_value(&stats).unwrap();
    assert_eq!(json["surface_non_manifold_vertices"], 1);
    assert!(
        stats.to_string().contains("8 (1 non-manifold vertices)"),
        "{stats}"
    );
    // Two tets sharing a face, or an edge, pinch nothing at a vertex (the edge is reported as
    // a non-manifold edge instead).
    let face = vec![[0, 1, 2, 3], [1, 0, 2, 6]];
    assert!(topology::non_manifold_vertices(&topology::boundary_faces(&face)).is_empty());
    let edge = vec![[0, 1, 2, 3], [0, 1, 5, 6]];
    assert_eq!(topology::boundary_faces(&edge).len(), 8);
    assert!(topology::non_manifold_vertices(&topology::boundary_faces(&edge)).is_empty());
}

#[cfg(feature = "tetgen")]
#[test]
fn tetgen_sphere_fills_the_enclosed_volume() {
    let sphere = shapes::sphere(0.5, 3);
    let options = PrepOptions {
        max_volume: Some(5e-4),
        ..Default::default()
    };
    let out = prep_surface(&sphere, &options, &mut quiet()).unwrap();
    assert_valid(&out);
    assert_eq!(out.stats.mesher, "tetgen");
    assert!(
        (out.stats.volume_percent - 100.0).abs() < 2.0,
        "{}",
        out.stats.volume_percent
    );
    // The volume bound holds for every tet.
    assert!(tet_volumes(&out.mesh)
        .iter()
        .all(|&v| v <= 5e-4 * (1.0 + 1e-9)));
    assert!(out.stats.min_dihedral_deg > 0.0 && out.stats.max_dihedral_deg < 180.0);
}

#[cfg(feature = "tetgen")]
#[test]
fn tetgen_lands_near_the_target() {
    for (surface, target) in [
        (shapes::sphere(0.5, 3), 3000),
        (shapes::Shape::Torus.surface(), 1500),
        (cube(), 800),
    ] {
        let options = PrepOptions {
            target_tets: Some(target),
            ..Default::default()
        };
        let out = prep_surface(&surface, &options, &mut quiet()).unwrap();
        assert_valid(&out);
        let err = out.stats.target_error_percent.unwrap();
        assert!(
            err.abs() <= 25.0,
            "target {target}: {} tets ({err:+.1} %)",
            out.stats.tets
        );
        assert!(
            (out.stats.volume_percent - 100.0).abs() < 2.0,
            "{}",
            out.stats.volume_percent
        );
    }
}

#[cfg(feature = "tetgen")]
#[test]
fn self_intersecting_surface_is_refused_with_the_reason_then_voxelized_with_fallback() {
    let options = PrepOptions {
        target_tets: Some(4000),
        ..Default::default()
    };
    let err = prep_surface(&overlapping_spheres(), &options, &mut quiet())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("intersects itself") && err.contains("--fallback"),
        "{err}"
    );

    let mut lines = Vec::new();
    let options = PrepOptions {
        fallback: true,
        ..options
    };
    let out = prep_surface(&overlapping_spheres(), &options, &mut |l: &str| {
        lines.push(l.to_string())
    })
    .unwrap();
    assert_valid(&out);
    assert_eq!(
        (out.stats.mesher.as_str(), out.stats.fell_back),
        ("voxel", true)
    );
    assert!(
        out.stats
            .warnings
            .iter()
            .any(|w| w.contains("TetGen failed")),
        "{:?}",
        out.stats.warnings
    );
    assert!(lines.iter().any(|l| l.starts_with("warning:")), "{lines:?}");
    // The union of two unit spheres whose centres are 1.3 apart.
    let d: f64 = 1.3;
    let lens = std::f64::consts::PI * (4.0 + d) * (2.0 - d).powi(2) / 12.0;
    let union = 2.0 * 4.0 / 3.0 * std::f64::consts::PI - lens;
    let v = out.stats.tet_volume;
    assert!((v / union - 1.0).abs() < 0.15, "{v} vs {union}");
    assert!(
        (out.stats.tets as f64 / 4000.0 - 1.0).abs() <= 0.25,
        "{}",
        out.stats.tets
    );
}

#[cfg(feature = "tetgen")]
#[test]
fn open_surface_is_a_tetgen_error_naming_the_reason() {
    let mut c = cube();
    c.triangles.remove(0);
    let options = PrepOptions {
        repair: RepairOptions {
            fill_holes: false,
            ..Default::default()
        },
        ..Default::default()
    };
    let err = prep_surface(&c, &options, &mut quiet())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("no tetrahedra") && err.contains("not closed"),
        "{err}"
    );
}

#[cfg(not(feature = "tetgen"))]
#[test]
fn tetgen_without_the_feature_is_a_clear_error() {
    let err = prep_surface(&cube(), &PrepOptions::default(), &mut quiet())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("without the `tetgen` feature") && err.contains("--mesher voxel"),
        "{err}"
    );
}

#[test]
fn voxel_cube_is_a_regular_grid() {
    let c = shapes::box_surface(DVec3::ZERO, DVec3::ONE, 3);
    let mesh = voxel_mesh(&c, 6 * 1000).unwrap();
    // A cell of 0.1: exactly 10^3 cells inside, 6 tets each, filling the cube.
    assert_eq!(mesh.tets.len(), 6000);
    assert_eq!(mesh.nodes.len(), 11 * 11 * 11);
    let volumes = tet_volumes(&mesh);
    assert!(volumes.iter().all(|&v| v > 0.0));
    assert!((volumes.iter().sum::<f64>() - 1.0).abs() < 1e-9);
}

#[test]
fn voxel_mesher_fills_a_surface_with_a_hole() {
    // The sphere without 20 faces around one pole: rays through the hole are outvoted.
    let mut s = shapes::sphere(1.0, 3);
    let pole = DVec3::new(0.0, 0.0, 1.0);
    let before = s.triangles.len();
    let vertices = s.vertices.clone();
    s.triangles.retain(|t| {
        t.iter()
            .all(|&v| vertices[v as usize].distance(pole) > 0.25)
    });
    assert!(before - s.triangles.len() >= 6);
    let options = PrepOptions {
        mesher: Mesher::Voxel,
        target_tets: Some(5000),
        repair: RepairOptions {
            fill_holes: false,
            ..Default::default()
        },
        ..Default::default()
    };
    let out = prep_surface(&s, &options, &mut quiet()).unwrap();
    assert_valid(&out);
    assert!(out.stats.repair.boundary_edges > 0);
    let ball = 4.0 / 3.0 * std::f64::consts::PI;
    assert!(
        (out.stats.tet_volume / ball - 1.0).abs() < 0.12,
        "{}",
        out.stats.tet_volume
    );
    assert!(
        (out.stats.tets as f64 / 5000.0 - 1.0).abs() <= 0.25,
        "{}",
        out.stats.tets
    );
    // Nothing sticks out of the sphere by more than a cell diagonal.
    let h = (out.stats.tet_volume / out.stats.tets as f64 * 6.0).cbrt();
    assert!(out.mesh.nodes.iter().all(|p| p.length() < 1.0 + 2.0 * h));
}

#[cfg(feature = "tetgen")]
#[test]
fn small_bunny_scan_meshes_near_the_target() {
    let Some(path) = scan("bun_zipper_res4.ply") else {
        return;
    };
    let options = PrepOptions {
        target_tets: Some(5000),
        ..Default::default()
    };
    let out = prep_file(&path, &options, &mut quiet()).unwrap();
    assert_valid(&out);
    assert!(
        out.stats.target_error_percent.unwrap().abs() <= 25.0,
        "{}",
        out.stats.tets
    );
    assert!(
        (out.stats.volume_percent - 100.0).abs() < 2.0,
        "{}",
        out.stats.volume_percent
    );
    assert_eq!(out.stats.repair.holes, 3);
}

/// The full scans (seconds each in release): `cargo test --release --test meshing -- --ignored`.
#[cfg(feature = "tetgen")]
#[test]
#[ignore]
fn scans_mesh_near_20k_tets() {
    for name in [
        "bun_zipper.ply",
        "horse.ply",
        "bun_zipper_res2.ply",
        "bun_zipper_res3.ply",
    ] {
        let Some(path) = scan(name) else { return };
        let options = PrepOptions {
            target_tets: Some(20_000),
            ..Default::default()
        };
        let out = prep_file(&path, &options, &mut quiet()).unwrap();
        assert_valid(&out);
        assert!(
            out.stats.target_error_percent.unwrap().abs() <= 25.0,
            "{name}: {}",
            out.stats.tets
        );
        assert!(
            (out.stats.volume_percent - 100.0).abs() < 2.0,
            "{name}: {}",
            out.stats.volume_percent
        );
    }
}

/// The pipeline renumbers TetGen's output along a Morton curve unless `keep_order` is set:
/// the same tets, each one's nodes close together in memory.
#[cfg(feature = "tetgen")]
#[test]
fn tetgen_output_is_renumbered_for_locality() {
    use tetrasim::mesh::order::median_index_spread;
    let sphere = shapes::sphere(0.5, 3);
    let options = PrepOptions {
        target_tets: Some(6000),
        ..Default::default()
    };
    let ordered = prep_surface(&sphere, &options, &mut quiet()).unwrap();
    let kept = PrepOptions {
        keep_order: true,
        ..options
    };
    let kept = prep_surface(&sphere, &kept, &mut quiet()).unwrap();
    assert_valid(&ordered);
    assert_eq!(ordered.mesh.tets.len(), kept.mesh.tets.len());
    assert_eq!(ordered.mesh.nodes.len(), kept.mesh.nodes.len());
    let total = |m: &TetMesh| tet_volumes(m).iter().sum::<f64>();
    assert!((total(&ordered.mesh) / total(&kept.mesh) - 1.0).abs() < 1e-12);
    let (before, after) = (
        median_index_spread(&kept.mesh),
        median_index_spread(&ordered.mesh),
    );
    println!("median index spread: TetGen {before:.4}, Morton {after:.4}");
    assert!(before > 0.1 && after < 0.2 * before, "{before} -> {after}");
    assert!(ordered.stats.times.iter().any(|t| t.stage == "order"));
    assert!(!kept.stats.times.iter().any(|t| t.stage == "order"));
}
