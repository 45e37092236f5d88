//! Surfaces and options the pipeline must refuse with a clear error (no panic, no output).

#[path = "common/prep.rs"]
mod prep_fixtures;

use glam::DVec3;
use prep_fixtures::cube;
use tetrasim::mesh::voxel::voxel_mesh;
// The pipeline (crate tetmesh) returns its own error type, re-exported here.
use tetrasim::prep::{prep_file, prep_surface, Error, Mesher, PrepOptions};
use tetrasim::SurfaceMesh;

fn prep_err(surface: &SurfaceMesh, options: &PrepOptions) -> String {
    match prep_surface(surface, options, &mut |_: &str| {}) {
        Ok(out) => panic!("expected an error, got {} tets", out.mesh.tets.len()),
        Err(e) => e.to_string(),
    }
}

fn both_meshers() -> [PrepOptions; 2] {
    [
        PrepOptions::default(),
        PrepOptions {
            mesher: Mesher::Voxel,
            ..Default::default()
        },
    ]
}

#[test]
fn empty_surface() {
    for options in both_meshers() {
        let err = prep_err(&SurfaceMesh::default(), &options);
        assert!(
            err.contains("empty") && err.contains("0 vertices, 0 faces"),
            "{err}"
        );
        let no_faces = SurfaceMesh {
            vertices: cube().vertices,
            triangles: vec![],
        };
        assert!(prep_err(&no_faces, &options).contains("8 vertices, 0 faces"));
    }
    let err = voxel_mesh(&SurfaceMesh::default(), 100)
        .unwrap_err()
        .to_string();
    assert!(err.contains("no vertices"), "{err}");
}

#[test]
fn all_degenerate_surface() {
    let points = SurfaceMesh {
        vertices: vec![DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0), DVec3::Y],
        triangles: vec![[0, 1, 2], [0, 0, 3], [1, 3, 3]],
    };
    for options in both_meshers() {
        let err = prep_err(&points, &options);
        assert!(err.contains("all 3 faces are degenerate"), "{err}");
    }
}

#[test]
fn nan_and_infinite_coordinates() {
    let mut c = cube();
    c.vertices[2].y = f64::NAN;
    for options in both_meshers() {
        let err = prep_err(&c, &options);
        assert!(
            err.contains("vertex 2") && err.contains("non-finite"),
            "{err}"
        );
    }
    let mut c = cube();
    c.vertices[5].z = f64::INFINITY;
    assert!(prep_err(&c, &PrepOptions::default()).contains("vertex 5"));
}

#[test]
fn index_out_of_range() {
    let mut c = cube();
    c.triangles[7][1] = 99;
    let err = prep_err(&c, &PrepOptions::default());
    assert!(
        err.contains("face 7") && err.contains("out of range") && err.contains("8 vertices"),
        "{err}"
    );
}

#[test]
fn flat_surface_encloses_no_volume() {
    // Two triangles forming a square, both sides: a closed but flat shell.
    let flat = SurfaceMesh {
        vertices: vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    };
    for options in both_meshers() {
        let err = prep_err(&flat, &options);
        assert!(err.contains("no volume") || err.contains("empty"), "{err}");
    }
}

#[test]
fn bad_options_name_the_option() {
    let cases: [(PrepOptions, &str); 5] = [
        (
            PrepOptions {
                quality: Some(0.5),
                ..Default::default()
            },
            "`quality`",
        ),
        (
            PrepOptions {
                max_volume: Some(-1.0),
                ..Default::default()
            },
            "`max-volume`",
        ),
        (
            PrepOptions {
                target_tets: Some(3),
                ..Default::default()
            },
            "`target-tets`",
        ),
        (
            PrepOptions {
                target_tets: Some(100),
                max_volume: Some(0.1),
                ..Default::default()
            },
            "`target-tets`",
        ),
        (
            PrepOptions {
                scale: f64::NAN,
                ..Default::default()
            },
            "`scale`",
        ),
    ];
    for (options, key) in cases {
        let err = prep_err(&cube(), &options);
        assert!(err.contains(key), "{key}: {err}");
    }
}

#[test]
fn unreadable_path_names_the_file() {
    let path = std::path::Path::new("/nonexistent/dir/surface.ply");
    let err = prep_file(path, &PrepOptions::default(), &mut |_: &str| {}).unwrap_err();
    assert!(matches!(err, Error::Io { .. }), "{err:?}");
    assert!(
        err.to_string().contains("/nonexistent/dir/surface.ply"),
        "{err}"
    );
}
