//! Fixtures for the mesh reader/writer tests (`mesh_io.rs`, `bad_input.rs`,
//! `mesh_io_props.rs`). Included with `#[path = "common/io.rs"] mod io_fixtures;`.
#![allow(dead_code)]

#[path = "skip.rs"]
mod skip;
use glam::DVec3;
use std::path::{Path, PathBuf};
use tetrasim::mesh::SurfaceMesh;

/// A closed octahedron with awkward coordinates (tiny, huge, negative, non-terminating in
/// binary), vertices listed in order of first use by the triangles, so that an STL round trip
/// (which re-indexes by first use) gives the same indices.
pub fn octahedron() -> SurfaceMesh {
    let vertices = vec![
        DVec3::new(0.1, 0.2, 1.3),
        DVec3::new(1.0e-7, -1.0, 0.25),
        DVec3::new(1.0, 1.0 / 3.0, -0.0),
        DVec3::new(-2.5e5, 0.5, 0.125),
        DVec3::new(-1.0, 1.0e12, 7.0),
        DVec3::new(0.0, 0.0, -1.0),
    ];
    let triangles = vec![
        [0, 1, 2],
        [0, 2, 3],
        [0, 3, 4],
        [0, 4, 1],
        [5, 2, 1],
        [5, 3, 2],
        [5, 4, 3],
        [5, 1, 4],
    ];
    SurfaceMesh {
        vertices,
        triangles,
    }
}

/// `mesh` with every coordinate rounded to `f32` (what an STL round trip keeps).
pub fn rounded_to_f32(mesh: &SurfaceMesh) -> SurfaceMesh {
    SurfaceMesh {
        vertices: mesh
            .vertices
            .iter()
            .map(|v| v.as_vec3().as_dvec3())
            .collect(),
        triangles: mesh.triangles.clone(),
    }
}

/// Writes `bytes` to `dir/name` and returns the path.
pub fn put(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// `../shared/meshes` beside the workspace root, or `None` (with a message saying the tests
/// that need it are skipped).
pub fn shared_meshes() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/meshes");
    if dir.is_dir() {
        Some(dir)
    } else {
        skip::skipped(&format!(
            "{} is missing; the real-scan reading tests did not run",
            dir.display()
        ));
        None
    }
}

/// Asserts that `result` is an error whose message contains the file name of `path` and every
/// string in `needles` (e.g. `":12:"` for a line, `"face 3"` for an element), and returns
/// the message.
#[track_caller]
pub fn assert_err<T: std::fmt::Debug, E: std::fmt::Display>(
    result: Result<T, E>,
    path: &Path,
    needles: &[&str],
) -> String {
    let msg = match result {
        Ok(v) => panic!("expected an error for {}, got Ok({v:?})", path.display()),
        Err(e) => e.to_string(),
    };
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(
        msg.contains(name.as_ref()),
        "message does not name the file `{name}`: {msg}"
    );
    for n in needles {
        assert!(msg.contains(n), "message does not contain `{n}`: {msg}");
    }
    msg
}

/// PLY header text (ASCII) for the given body encoding and element/property lines.
pub fn ply_header(format: &str, lines: &[&str]) -> Vec<u8> {
    let mut s = format!("ply\nformat {format} 1.0\ncomment test\n");
    for l in lines {
        s.push_str(l);
        s.push('\n');
    }
    s.push_str("end_header\n");
    s.into_bytes()
}
