//! Each repair step on hand-made surfaces, with the counts it must report.

#[path = "common/prep.rs"]
mod prep_fixtures;

use glam::DVec3;
use prep_fixtures::{cube, overlapping_spheres, scan};
use tetrasim::mesh::io::read_surface;
use tetrasim::mesh::repair::{orient::signed_volume, repair, RepairOptions};

fn assert_closed_unit_cube(m: &tetrasim::SurfaceMesh, r: &tetrasim::mesh::repair::RepairReport) {
    assert_eq!(
        (r.boundary_edges, r.non_manifold_edges, r.self_intersections),
        (0, 0, Some(0)),
        "{r:?}"
    );
    assert!(r.is_clean());
    assert!(
        (r.enclosed_volume - 1.0).abs() < 1e-12,
        "{}",
        r.enclosed_volume
    );
    assert!((signed_volume(&m.vertices, &m.triangles) - 1.0).abs() < 1e-12);
}

#[test]
fn clean_cube_is_left_alone() {
    let (m, r) = repair(&cube(), &RepairOptions::default()).unwrap();
    assert_eq!(m, cube());
    assert_eq!(
        (
            r.welded_vertices,
            r.degenerate_faces,
            r.duplicate_faces,
            r.flipped_faces,
            r.holes
        ),
        (0, 0, 0, 0, 0)
    );
    assert_closed_unit_cube(&m, &r);
}

#[test]
fn duplicate_vertex_is_welded() {
    let mut c = cube();
    // A copy of vertex 0, off by 1e-10 (far below the 1e-7 * diagonal tolerance), used by
    // the first face: without welding the cube has a slit.
    c.vertices.push(c.vertices[0] + DVec3::splat(1e-10));
    let f = c.triangles.iter().position(|t| t.contains(&0)).unwrap();
    let k = c.triangles[f].iter().position(|&v| v == 0).unwrap();
    c.triangles[f][k] = 8;
    let (m, r) = repair(&c, &RepairOptions::default()).unwrap();
    assert_eq!(r.welded_vertices, 1);
    assert_eq!(r.unreferenced_vertices, 1);
    assert_eq!((m.vertices.len(), m.triangles.len()), (8, 12));
    assert_closed_unit_cube(&m, &r);
}

#[test]
fn flipped_face_is_turned_back() {
    let mut c = cube();
    c.triangles[5].swap(0, 1);
    let (m, r) = repair(&c, &RepairOptions::default()).unwrap();
    assert_eq!(r.flipped_faces, 1);
    assert_eq!(r.outward_flipped_faces, 0);
    assert_closed_unit_cube(&m, &r);
}

#[test]
fn inside_out_cube_is_turned_outward() {
    let mut c = cube();
    for t in &mut c.triangles {
        t.swap(1, 2);
    }
    let (m, r) = repair(&c, &RepairOptions::default()).unwrap();
    assert_eq!((r.flipped_faces, r.outward_flipped_faces), (0, 12));
    assert_closed_unit_cube(&m, &r);
}

#[test]
fn missing_face_is_filled_and_closed() {
    let mut c = cube();
    c.triangles.remove(3);
    let (m, r) = repair(&c, &RepairOptions::default()).unwrap();
    assert_eq!(
        (r.holes, r.hole_faces_added, r.hole_vertices_added),
        (1, 1, 0)
    );
    assert_eq!(m.triangles.len(), 12);
    assert_closed_unit_cube(&m, &r);
    // Without filling, the hole is reported as boundary edges.
    let (_, r) = repair(
        &c,
        &RepairOptions {
            fill_holes: false,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!((r.holes, r.boundary_edges), (1, 3));
    assert!(
        r.warnings.iter().any(|w| w.contains("not closed")),
        "{:?}",
        r.warnings
    );
}

#[test]
fn degenerate_and_duplicate_faces_are_dropped() {
    let mut c = cube();
    c.triangles.push([0, 0, 1]); // repeated vertex
    c.vertices.push((c.vertices[0] + c.vertices[1]) * 0.5); // on the line 0-1: zero area
    c.triangles.push([0, 1, 8]);
    c.triangles.push(c.triangles[2]); // same face again
    let (m, r) = repair(&c, &RepairOptions::default()).unwrap();
    assert_eq!(
        (
            r.degenerate_faces,
            r.duplicate_faces,
            r.unreferenced_vertices
        ),
        (2, 1, 1)
    );
    assert_eq!(m.triangles.len(), 12);
    assert_closed_unit_cube(&m, &r);
}

#[test]
fn opposite_duplicate_faces_cancel() {
    // A cube plus a double wall (a face and its reverse) hanging off it: both copies go.
    let mut c = cube();
    c.vertices.push(DVec3::new(0.5, 0.5, 2.0));
    c.triangles.push([4, 5, 8]);
    c.triangles.push([5, 4, 8]);
    let (m, r) = repair(&c, &RepairOptions::default()).unwrap();
    assert_eq!(r.duplicate_faces, 2);
    assert_eq!(m.triangles.len(), 12);
    assert_closed_unit_cube(&m, &r);
}

#[test]
fn non_manifold_edge_is_reported_and_cut() {
    // A fin: a third face on the cube edge 0-1, sticking out of the cube.
    let mut c = cube();
    assert!(
        c.triangles.iter().any(|t| t.contains(&0) && t.contains(&1)),
        "0-1 is an edge"
    );
    c.vertices.push(DVec3::new(0.5, -1.0, -1.0));
    c.triangles.push([0, 1, 8]);
    let options = RepairOptions {
        cut_and_refill: false,
        ..Default::default()
    };
    let (_, r) = repair(&c, &options).unwrap();
    assert_eq!(r.non_manifold_edges, 1);
    let warning = r
        .warnings
        .iter()
        .find(|w| w.contains("non-manifold"))
        .expect("a warning");
    assert!(warning.contains("vertices 0-1 (3 faces)"), "{warning}");
    assert!(!r.is_clean());
    // By default the faces on the edge are cut out and the hole refilled.
    let (m, r) = repair(&c, &RepairOptions::default()).unwrap();
    assert_eq!(r.non_manifold_edges_found, 1);
    assert_eq!(r.non_manifold_edges, 0);
    assert!(r.cut_faces_removed >= 3, "{r:?}");
    assert_closed_unit_cube(&m, &r);
}

#[test]
fn pinched_vertex_is_reported() {
    // Two unit cubes touching at one corner, (1, 1, 1), welded into one vertex there.
    let mut c = cube();
    let other = cube();
    let base = c.vertices.len() as u32;
    c.vertices
        .extend(other.vertices.iter().map(|p| *p + DVec3::ONE));
    c.triangles
        .extend(other.triangles.iter().map(|t| t.map(|v| v + base)));
    let (m, r) = repair(&c, &RepairOptions::default()).unwrap();
    assert_eq!(r.welded_vertices, 1, "{r:?}");
    assert_eq!(
        (r.non_manifold_edges, r.non_manifold_vertices),
        (0, 1),
        "{r:?}"
    );
    let corner = m.vertices.iter().position(|p| *p == DVec3::ONE).unwrap();
    let warning = r
        .warnings
        .iter()
        .find(|w| w.contains("non-manifold vertices"))
        .expect("a warning");
    assert!(warning.contains(&format!("vertices {corner}")), "{warning}");
    assert!((r.enclosed_volume - 2.0).abs() < 1e-12);
    // A cube alone has none.
    assert_eq!(
        repair(&cube(), &RepairOptions::default())
            .unwrap()
            .1
            .non_manifold_vertices,
        0
    );
}

#[test]
fn self_intersections_are_reported_in_words() {
    let (_, r) = repair(&overlapping_spheres(), &RepairOptions::default()).unwrap();
    let n = r.self_intersections.unwrap();
    assert!(n >= 20, "{n}");
    assert_eq!(
        r.self_intersections_found,
        Some(n),
        "too many to cut: left alone"
    );
    let warning = r
        .warnings
        .iter()
        .find(|w| w.contains("cross each other"))
        .expect("a warning");
    assert!(
        warning.contains(&format!("{n} pairs")) && warning.contains("face "),
        "{warning}"
    );
    assert!(!r.is_clean());
}

#[test]
fn small_bunny_scan_is_closed_by_repair() {
    let Some(path) = scan("bun_zipper_res4.ply") else {
        return;
    };
    let surface = read_surface(&path).unwrap();
    let (m, r) = repair(&surface, &RepairOptions::default()).unwrap();
    assert_eq!((r.vertices_in, r.faces_in), (453, 948));
    // Decimation left 29 opposite pairs, 2 repeated faces and a 4-copy set; 3 holes in the base.
    assert_eq!(r.duplicate_faces, 64);
    assert_eq!(r.holes, 3);
    assert!(r.non_manifold_edges_found > 0);
    // Cutting out the non-manifold edges and refilling leaves pinched vertices (reported; TetGen
    // takes them, and with -Y they stay on the tet mesh's boundary).
    assert_eq!(r.non_manifold_vertices, 5, "{:?}", r.warnings);
    assert!(r.is_clean(), "{r:?}");
    assert!(
        r.enclosed_volume > 6.5e-4 && r.enclosed_volume < 7.5e-4,
        "{}",
        r.enclosed_volume
    );
    assert_eq!(m.triangles.len(), r.faces_out);
}
