//! Property tests for the mesh readers and writers: random bytes, random truncations and
//! random byte changes of valid files never panic a reader (a panic fails the test), and
//! random valid meshes round-trip through every writer/reader pair.

#[path = "common/io.rs"]
mod io_fixtures;

use glam::DVec3;
use io_fixtures::*;
use proptest::prelude::*;
use std::path::Path;
use tetrasim::mesh::io::{self, ply::PlyEncoding, tetgen, SurfaceFormat};
use tetrasim::mesh::{grid, SurfaceMesh, TetMesh};

const FORMATS: [SurfaceFormat; 4] = [
    SurfaceFormat::Ply,
    SurfaceFormat::Obj,
    SurfaceFormat::Off,
    SurfaceFormat::Stl,
];

/// Runs every reader on `bytes` (as each surface format, and as each of the three TetGen
/// files); any panic fails the property.
fn read_everything(bytes: &[u8]) {
    let path = Path::new("fuzz");
    for f in FORMATS {
        let _ = io::parse_surface(bytes, f, path);
    }
    let node = b"4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
    let ele = b"1 4 0\n0 0 1 2 3\n";
    let _ = tetgen::parse_tetgen(bytes, ele, None, path);
    let _ = tetgen::parse_tetgen(node, bytes, None, path);
    let _ = tetgen::parse_tetgen(node, ele, Some(bytes), path);
    for f in TET_FORMATS {
        let _ = io::parse_tet_mesh(bytes, f, path);
    }
}

const TET_FORMATS: [io::TetFormat; 4] = [
    io::TetFormat::Vtk,
    io::TetFormat::Vtu,
    io::TetFormat::Gmsh,
    io::TetFormat::Medit,
];

/// The meshio fixtures of tests/mesh_readers.rs (every tet format, ASCII and binary).
fn tet_fixtures() -> &'static [(String, Vec<u8>)] {
    static FILES: std::sync::OnceLock<Vec<(String, Vec<u8>)>> = std::sync::OnceLock::new();
    FILES.get_or_init(|| {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/meshio");
        let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| {
                io::TetFormat::from_extension(p).is_some_and(|f| f != io::TetFormat::TetGen)
            })
            .map(|p| {
                (
                    p.file_name().unwrap().to_string_lossy().into_owned(),
                    std::fs::read(&p).unwrap(),
                )
            })
            .collect();
        v.sort();
        v
    })
}

type Sample = (String, Vec<u8>, Option<SurfaceFormat>);

/// Valid files of every format, as (label, bytes, format or None for TetGen's .node), made
/// once.
fn valid_files() -> &'static [Sample] {
    static FILES: std::sync::OnceLock<Vec<Sample>> = std::sync::OnceLock::new();
    FILES.get_or_init(make_valid_files)
}

fn make_valid_files() -> Vec<Sample> {
    let dir = tempfile::tempdir().unwrap();
    let mesh = octahedron();
    let mut out = Vec::new();
    for (name, enc) in [
        ("a.ply", PlyEncoding::Ascii),
        ("le.ply", PlyEncoding::BinaryLittleEndian),
        ("be.ply", PlyEncoding::BinaryBigEndian),
    ] {
        let p = dir.path().join(name);
        io::ply::write(&p, &mesh, enc).unwrap();
        out.push((
            name.to_string(),
            std::fs::read(&p).unwrap(),
            Some(SurfaceFormat::Ply),
        ));
    }
    for (name, f) in [
        ("m.obj", SurfaceFormat::Obj),
        ("m.off", SurfaceFormat::Off),
        ("m.stl", SurfaceFormat::Stl),
    ] {
        let p = dir.path().join(name);
        io::write_surface(&p, &mesh).unwrap();
        out.push((name.to_string(), std::fs::read(&p).unwrap(), Some(f)));
    }
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    out.push((
        "ascii.stl".into(),
        format!("solid a\n{facet}{facet}endsolid a\n").into_bytes(),
        Some(SurfaceFormat::Stl),
    ));
    let p = dir.path().join("t");
    io::write_tetgen(&p, &grid::box_tets(DVec3::ZERO, 1.0, [1, 1, 1])).unwrap();
    out.push((
        "t.node".into(),
        std::fs::read(dir.path().join("t.node")).unwrap(),
        None,
    ));
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn truncated_and_mutated_tet_files_never_panic(which in 0usize..64, cut in 0.0..1.0f64, at in 0.0..1.0f64, value: u8) {
        let files = tet_fixtures();
        let (name, bytes) = &files[which % files.len()];
        let format = io::TetFormat::from_extension(Path::new(name)).unwrap();
        let path = Path::new(name);
        let cut_at = (bytes.len() as f64 * cut) as usize;
        let _ = io::parse_tet_mesh(&bytes[..cut_at], format, path);
        let mut changed = bytes.clone();
        let i = ((changed.len() - 1) as f64 * at) as usize;
        changed[i] = value;
        let _ = io::parse_tet_mesh(&changed, format, path);
        read_everything(&changed);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
        read_everything(&bytes);
    }

    #[test]
    fn random_text_headers_never_panic(
        head in prop::sample::select(vec!["ply\nformat ascii 1.0\n", "ply\nformat binary_big_endian 1.0\n", "OFF\n", "solid x\n", "v 0 0 0\n"]),
        tail in "[ -~\n]{0,300}",
    ) {
        read_everything(format!("{head}{tail}").as_bytes());
    }

    #[test]
    fn truncated_and_mutated_valid_files_never_panic(cut in 0.0..1.0f64, at in 0.0..1.0f64, value: u8) {
        for (name, bytes, format) in valid_files() {
            let n = (cut * bytes.len() as f64) as usize;
            let truncated = &bytes[..n];
            read_everything(truncated);
            // Binary files with a size rule or counts must reject any truncation.
            if name.ends_with("le.ply") || name.ends_with("be.ply") || name == "m.stl" {
                let r = io::parse_surface(truncated, format.unwrap(), Path::new(name));
                prop_assert!(r.is_err(), "{name} cut to {n} of {} bytes was accepted", bytes.len());
            }
            let mut changed = bytes.to_vec();
            let i = ((at * bytes.len() as f64) as usize).min(bytes.len() - 1);
            changed[i] = value;
            read_everything(&changed);
        }
    }
}

/// Finite coordinates of any magnitude single precision can hold (so STL can store them).
fn coord() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e3..1e3f64,
        (-1e30..1e30f64),
        prop::num::f64::NORMAL.prop_filter("fits in f32", |x| x.abs() < 1e38),
        Just(0.0),
        Just(-0.0),
    ]
}

fn surface() -> impl Strategy<Value = SurfaceMesh> {
    proptest::collection::vec((coord(), coord(), coord()), 1..24).prop_flat_map(|pts| {
        let n = pts.len() as u32;
        let vertices: Vec<DVec3> = pts
            .into_iter()
            .map(|(x, y, z)| DVec3::new(x, y, z))
            .collect();
        proptest::collection::vec([0..n, 0..n, 0..n], 1..40).prop_map(move |triangles| {
            SurfaceMesh {
                vertices: vertices.clone(),
                triangles,
            }
        })
    })
}

fn tet_mesh() -> impl Strategy<Value = TetMesh> {
    proptest::collection::vec((coord(), coord(), coord()), 1..24).prop_flat_map(|pts| {
        let n = pts.len() as u32;
        let nodes: Vec<DVec3> = pts
            .into_iter()
            .map(|(x, y, z)| DVec3::new(x, y, z))
            .collect();
        (
            proptest::collection::vec([0..n, 0..n, 0..n, 0..n], 1..30),
            proptest::collection::vec([0..n, 0..n, 0..n], 1..20),
        )
            .prop_map(move |(tets, faces)| TetMesh {
                nodes: nodes.clone(),
                tets,
                faces,
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_surfaces_round_trip(mesh in surface()) {
        let dir = tempfile::tempdir().unwrap();
        for name in ["m.ply", "m.obj", "m.off"] {
            let p = dir.path().join(name);
            io::write_surface(&p, &mesh).unwrap();
            prop_assert_eq!(&io::read_surface(&p).unwrap(), &mesh, "{}", name);
        }
        for enc in [PlyEncoding::Ascii, PlyEncoding::BinaryBigEndian] {
            let p = dir.path().join("e.ply");
            io::ply::write(&p, &mesh, enc).unwrap();
            prop_assert_eq!(&io::read_surface(&p).unwrap(), &mesh, "{:?}", enc);
        }
        // STL welds and re-indexes: compare each triangle's corners, rounded to f32.
        let p = dir.path().join("m.stl");
        io::write_surface(&p, &mesh).unwrap();
        let back = io::read_surface(&p).unwrap();
        let rounded = rounded_to_f32(&mesh);
        let corners = |m: &SurfaceMesh| -> Vec<[DVec3; 3]> {
            m.triangles.iter().map(|t| t.map(|i| m.vertices[i as usize])).collect()
        };
        prop_assert_eq!(corners(&back), corners(&rounded));
        prop_assert!(back.vertices.len() <= mesh.vertices.len());
    }

    #[test]
    fn random_tet_meshes_round_trip(mesh in tet_mesh()) {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t");
        io::write_tetgen(&p, &mesh).unwrap();
        prop_assert_eq!(io::read_tetgen(&p).unwrap(), mesh);
    }
}
