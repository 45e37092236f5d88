//! Mesh readers and writers: round trips for every format, hand-made files that exercise each
//! format's variants (PLY encodings and types, OBJ index forms, OFF prefixes, STL detection,
//! TetGen bases and attributes), VTK output parsed back, and the real scans in
//! `../shared/meshes` when present.

#[path = "common/io.rs"]
mod io_fixtures;

use glam::DVec3;
use io_fixtures::*;
use tetrasim::geometry::tet_volume;
use tetrasim::mesh::io::{self, ply::PlyEncoding};
use tetrasim::mesh::{grid, topology, SurfaceMesh, TetMesh};

#[test]
fn surface_round_trips_are_exact_for_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = octahedron();
    for name in ["m.ply", "m.obj", "m.off", "UPPER.PLY", "m.Obj"] {
        let path = dir.path().join(name);
        io::write_surface(&path, &mesh).unwrap();
        assert_eq!(io::read_surface(&path).unwrap(), mesh, "{name}");
    }
    for enc in [
        PlyEncoding::Ascii,
        PlyEncoding::BinaryLittleEndian,
        PlyEncoding::BinaryBigEndian,
    ] {
        let path = dir.path().join(format!("{enc:?}.ply"));
        io::ply::write(&path, &mesh, enc).unwrap();
        assert_eq!(io::read_surface(&path).unwrap(), mesh, "{enc:?}");
    }
    // STL keeps single precision and re-indexes by first use (the fixture's order).
    let path = dir.path().join("m.stl");
    io::write_surface(&path, &mesh).unwrap();
    assert_eq!(
        std::fs::metadata(&path).unwrap().len(),
        84 + 50 * mesh.triangles.len() as u64
    );
    assert_eq!(io::read_surface(&path).unwrap(), rounded_to_f32(&mesh));
}

#[test]
fn ply_writer_default_is_binary_little_endian() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.ply");
    io::write_surface(&path, &octahedron()).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let text = String::from_utf8_lossy(&bytes[..200]);
    assert!(text.contains("format binary_little_endian 1.0"), "{text}");
    // 6 vertices * 3 doubles + 8 faces * (1 + 3 * 4) bytes after the header.
    let header_end = text.find("end_header\n").unwrap() + "end_header\n".len();
    assert_eq!(bytes.len() - header_end, 6 * 24 + 8 * 13);
}

/// Big- or little-endian byte writer for hand-made binary PLY bodies.
struct Bytes {
    big: bool,
    out: Vec<u8>,
}

impl Bytes {
    fn f32(&mut self, v: f32) -> &mut Self {
        self.out.extend(if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        });
        self
    }
    fn f64(&mut self, v: f64) -> &mut Self {
        self.out.extend(if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        });
        self
    }
    fn i16(&mut self, v: i16) -> &mut Self {
        self.out.extend(if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        });
        self
    }
    fn i32(&mut self, v: i32) -> &mut Self {
        self.out.extend(if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        });
        self
    }
    fn u32(&mut self, v: u32) -> &mut Self {
        self.out.extend(if self.big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        });
        self
    }
    fn u8(&mut self, v: u8) -> &mut Self {
        self.out.push(v);
        self
    }
}

/// Four vertices of a unit square at height z = 2 and a fifth above it.
fn square_points() -> Vec<DVec3> {
    vec![
        DVec3::new(0.0, 0.0, 2.0),
        DVec3::new(1.5, 0.0, 2.0),
        DVec3::new(1.5, -0.25, 2.0),
        DVec3::new(0.0, -0.25, 2.0),
        DVec3::new(0.75, 0.5, 3.0),
    ]
}

#[test]
fn binary_big_endian_ply_with_extra_properties_and_uchar_int_lists() {
    let header = ply_header(
        "binary_big_endian",
        &[
            "element vertex 5",
            "property float x",
            "property double y",
            "property short z",
            "property float confidence",
            "property uchar intensity",
            "element face 2",
            "property uchar flags",
            "property list uchar int vertex_indices",
            "element edge 1",
            "property int vertex1",
            "property list ushort float weights",
        ],
    );
    let mut b = Bytes {
        big: true,
        out: header,
    };
    for (i, p) in square_points().iter().enumerate() {
        b.f32(p.x as f32)
            .f64(p.y)
            .i16(p.z as i16)
            .f32(0.5 + i as f32)
            .u8(200);
    }
    b.u8(7).u8(4).i32(0).i32(1).i32(2).i32(3); // a quad
    b.u8(9).u8(3).i32(4).i32(3).i32(2);
    b.i32(1).out.extend([0, 2]); // edge: ushort count 2 (big-endian), two floats
    b.f32(1.0).f32(2.0);
    let dir = tempfile::tempdir().unwrap();
    let mesh = io::read_surface(put(dir.path(), "be.ply", &b.out)).unwrap();
    assert_eq!(mesh.vertices, square_points());
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [4, 3, 2]]);
}

#[test]
fn binary_little_endian_ply_with_int_uint_lists_and_properties_before_xyz() {
    let header = ply_header(
        "binary_little_endian",
        &[
            "element vertex 5",
            "property float32 intensity",
            "property float64 z",
            "property float64 x",
            "property list uint8 uint8 extra",
            "property float64 y",
            "element face 1",
            "property list int uint vertex_index",
            "property list uchar float texcoord",
        ],
    );
    let mut b = Bytes {
        big: false,
        out: header,
    };
    for p in square_points() {
        b.f32(0.25).f64(p.z).f64(p.x).u8(2).u8(9).u8(9).f64(p.y);
    }
    b.i32(5).u32(0).u32(1).u32(2).u32(3).u32(4); // a pentagon
    b.u8(2).f32(0.5).f32(0.5);
    let dir = tempfile::tempdir().unwrap();
    let mesh = io::read_surface(put(dir.path(), "le.ply", &b.out)).unwrap();
    assert_eq!(mesh.vertices, square_points());
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
}

#[test]
fn ascii_ply_with_crlf_vertex_index_and_polygons() {
    let text = "ply\r\nformat ascii 1.0\r\nobj_info made by hand\r\nelement vertex 5\r\n\
        property float x\r\nproperty float y\r\nproperty float z\r\nproperty uchar red\r\n\
        element face 2\r\nproperty list uchar int vertex_index\r\nend_header\r\n\
        0 0 2 1\r\n1.5 0 2 1\r\n1.5 -0.25 2 1\r\n0 -0.25 2 1\r\n0.75 0.5 3 1\r\n\
        4 0 1 2 3\r\n3 4 3 2\r\n";
    let dir = tempfile::tempdir().unwrap();
    let mesh = io::read_surface(put(dir.path(), "a.ply", text)).unwrap();
    assert_eq!(mesh.vertices, square_points());
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [4, 3, 2]]);
}

#[test]
fn obj_with_index_forms_negative_indices_and_polygons() {
    let text = "# a comment\nmtllib x.mtl\no thing\nv 0 0 2\nv 1.5 0 2\nv 1.5 -0.25 2\n\
        v 0 -0.25 2 1.0\nvt 0 0\nvn 0 0 1\ng group\nusemtl m\ns off\n\
        f 1/1/1 2/1/1 3/1/1 4/1/1\nv 0.75 0.5 3 0.2 0.3 0.4\nf -1//1 -2//1 -3//1\nf 3/1 4/1 5/1\nl 1 2\n";
    let dir = tempfile::tempdir().unwrap();
    let mesh = io::read_surface(put(dir.path(), "a.obj", text)).unwrap();
    assert_eq!(mesh.vertices, square_points());
    assert_eq!(
        mesh.triangles,
        vec![[0, 1, 2], [0, 2, 3], [4, 3, 2], [2, 3, 4]]
    );
}

#[test]
fn obj_written_by_us_reads_the_same_in_tobj() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.obj");
    let mesh = octahedron();
    io::write_surface(&path, &mesh).unwrap();
    let (models, _) = tobj::load_obj(
        &path,
        &tobj::LoadOptions {
            triangulate: true,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(models.len(), 1);
    let m = &models[0].mesh;
    let tris: Vec<[u32; 3]> = m.indices.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    assert_eq!(tris, mesh.triangles);
    let pos: Vec<DVec3> = m
        .positions
        .chunks(3)
        .map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64))
        .collect();
    assert_eq!(pos, rounded_to_f32(&mesh).vertices);
}

#[test]
fn off_with_colour_prefix_counts_on_keyword_line_and_polygons() {
    let text = "COFF 5 2 0\n# comment\n0 0 2 255 0 0 255\n1.5 0 2 255 0 0 255\n\n\
        1.5 -0.25 2 255 0 0 255\n0 -0.25 2 1 1 1 1\n0.75 0.5 3 1 1 1 1\n4 0 1 2 3 0.5 0.5 0.5\n3 4 3 2\n";
    let dir = tempfile::tempdir().unwrap();
    let mesh = io::read_surface(put(dir.path(), "a.off", text)).unwrap();
    assert_eq!(mesh.vertices, square_points());
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [4, 3, 2]]);
}

#[test]
fn ascii_stl_is_welded() {
    let facet = |a: &str, b: &str, c: &str| {
        format!("  facet normal 0 0 1\n    outer loop\n      vertex {a}\n      vertex {b}\n      vertex {c}\n    endloop\n  endfacet\n")
    };
    let text = format!(
        "solid test\n{}{}endsolid test\nsolid second\n{}endsolid\n",
        facet("0 0 2", "1.5 0 2", "1.5 -0.25 2"),
        facet("0 0 2", "1.5 -0.25 2", "0 -0.25 2"),
        facet("0.75 0.5 3", "0 -0.25 2", "-0 -0.25 2")
    );
    let dir = tempfile::tempdir().unwrap();
    let mesh = io::read_surface(put(dir.path(), "a.stl", text)).unwrap();
    assert_eq!(mesh.vertices, square_points());
    // -0 and 0 weld to one vertex.
    assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3], [4, 3, 3]]);
}

#[test]
fn binary_stl_whose_header_starts_with_solid_is_read_as_binary() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.stl");
    let mesh = octahedron();
    io::write_surface(&path, &mesh).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    bytes[..14].copy_from_slice(b"solid exported");
    let patched = put(dir.path(), "solid.stl", &bytes);
    assert_eq!(io::read_surface(patched).unwrap(), rounded_to_f32(&mesh));
}

fn sample_tets() -> TetMesh {
    grid::box_tets(DVec3::new(0.1, -0.2, 1.0 / 3.0), 0.25, [2, 1, 3])
}

#[test]
fn tetgen_round_trip_keeps_nodes_tets_and_faces() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("box.v1");
    let mesh = sample_tets();
    assert!(!mesh.faces.is_empty());
    io::write_tetgen(&prefix, &mesh).unwrap();
    for p in ["box.v1", "box.v1.node", "box.v1.ele", "box.v1.face"] {
        assert_eq!(io::read_tetgen(dir.path().join(p)).unwrap(), mesh, "{p}");
    }
    // 0-based and saying so.
    let node = std::fs::read_to_string(dir.path().join("box.v1.node")).unwrap();
    assert!(node.starts_with("# written by tetrasim"), "{node}");
    assert!(node.contains("numbered from 0"));
    let first_record = node.lines().filter(|l| !l.starts_with('#')).nth(1).unwrap();
    assert!(first_record.starts_with("0 "), "{first_record}");
}

#[test]
fn tetgen_writer_derives_boundary_faces_when_the_mesh_has_none() {
    let dir = tempfile::tempdir().unwrap();
    let mut mesh = sample_tets();
    let expected = topology::boundary_faces(&mesh.tets);
    mesh.faces.clear();
    io::write_tetgen(dir.path().join("b"), &mesh).unwrap();
    let back = io::read_tetgen(dir.path().join("b")).unwrap();
    assert_eq!(back.faces, expected);
    assert_eq!((back.nodes, back.tets), (mesh.nodes, mesh.tets));
}

#[test]
fn tetgen_one_based_with_attributes_markers_and_comments() {
    let dir = tempfile::tempdir().unwrap();
    let node = "# 1-based, 2 attributes, boundary markers\n5  3  2  1\n\n\
        1  0 0 0   7.5 8.5  1\n2  1 0 0   7.5 8.5  1\n3  0 1 0   7.5 8.5  0   # comment\n\
        4  0 0 1   7.5 8.5  1\n5  1 1 1   7.5 8.5  1\n";
    put(dir.path(), "t.node", node);
    put(
        dir.path(),
        "t.ele",
        "2 4 1\n1  1 2 3 4  10\n2  2 3 4 5  20.5\n",
    );
    let expected_nodes = vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z, DVec3::ONE];
    let mesh = io::read_tetgen(dir.path().join("t.ele")).unwrap();
    assert_eq!(mesh.nodes, expected_nodes);
    assert_eq!(mesh.tets, vec![[0, 1, 2, 3], [1, 2, 3, 4]]);
    assert!(mesh.faces.is_empty(), "no .face file, no faces");
    put(
        dir.path(),
        "t.face",
        "3 1\n1  1 2 3  -1\n2  1 2 4  -1\n3  2 3 5  -1\n",
    );
    let mesh = io::read_tetgen(dir.path().join("t")).unwrap();
    assert_eq!(mesh.faces, vec![[0, 1, 2], [0, 1, 3], [1, 2, 4]]);
}

#[test]
fn vtk_output_parses_back() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = sample_tets();
    let volumes: Vec<f64> = mesh
        .tets
        .iter()
        .map(|t| tet_volume(t.map(|i| mesh.nodes[i as usize])))
        .collect();
    let path = dir.path().join("m.vtk");
    io::write_vtk(&path, &mesh, Some(("volume", &volumes))).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let find = |head: &str| lines.iter().position(|l| l.starts_with(head)).unwrap();
    let (n, m) = (mesh.nodes.len(), mesh.tets.len());
    let p = find("POINTS ");
    assert_eq!(lines[p], format!("POINTS {n} double"));
    let points: Vec<DVec3> = lines[p + 1..p + 1 + n]
        .iter()
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            DVec3::new(v[0], v[1], v[2])
        })
        .collect();
    assert_eq!(points, mesh.nodes);
    let c = find("CELLS ");
    assert_eq!(lines[c], format!("CELLS {m} {}", 5 * m));
    let cells: Vec<[u32; 4]> = lines[c + 1..c + 1 + m]
        .iter()
        .map(|l| {
            let v: Vec<u32> = l.split_whitespace().map(|t| t.parse().unwrap()).collect();
            assert_eq!(v[0], 4);
            [v[1], v[2], v[3], v[4]]
        })
        .collect();
    assert_eq!(cells, mesh.tets);
    let t = find("CELL_TYPES ");
    assert_eq!(lines[t], format!("CELL_TYPES {m}"));
    assert!(lines[t + 1..t + 1 + m].iter().all(|l| *l == "10"));
    let d = find("CELL_DATA ");
    assert_eq!(
        lines[d..d + 3],
        [
            format!("CELL_DATA {m}"),
            "SCALARS volume double 1".into(),
            "LOOKUP_TABLE default".into()
        ]
    );
    let back: Vec<f64> = lines[d + 3..].iter().map(|l| l.parse().unwrap()).collect();
    assert_eq!(back, volumes);
    // Without scalars there is no CELL_DATA section.
    io::write_vtk(&path, &mesh, None).unwrap();
    assert!(!std::fs::read_to_string(&path)
        .unwrap()
        .contains("CELL_DATA"));
}

#[test]
fn failed_write_leaves_old_file_and_no_temporary_files() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.ply");
    io::write_surface(&path, &octahedron()).unwrap();
    let before = std::fs::read(&path).unwrap();
    let mut bad = octahedron();
    bad.triangles.push([0, 1, 6]);
    let err = io::write_surface(&path, &bad).unwrap_err().to_string();
    assert!(
        err.contains("triangle 8") && err.contains("index 6"),
        "{err}"
    );
    let scalars_err = io::write_vtk(
        dir.path().join("v.vtk"),
        &sample_tets(),
        Some(("q", &[1.0, 2.0])),
    )
    .unwrap_err()
    .to_string();
    assert!(
        scalars_err.contains("2 values for 36 tets"),
        "{scalars_err}"
    );
    // A TetGen write that fails leaves none of its three files.
    let mut tets = sample_tets();
    tets.tets[3][2] = 999;
    assert!(io::write_tetgen(dir.path().join("t"), &tets).is_err());
    assert_eq!(std::fs::read(&path).unwrap(), before);
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["keep.ply".to_string()]);
    // A missing folder is an I/O error naming the destination.
    let missing = dir.path().join("no/such/dir/m.obj");
    let msg = io::write_surface(&missing, &octahedron())
        .unwrap_err()
        .to_string();
    assert!(msg.contains("no/such/dir/m.obj"), "{msg}");
}

#[cfg(unix)]
#[test]
fn written_files_are_readable_by_others() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.off");
    io::write_surface(&path, &octahedron()).unwrap();
    assert_eq!(
        std::fs::metadata(&path).unwrap().permissions().mode() & 0o777,
        0o644
    );
}

/// Reads a scan from `../shared/meshes` and checks its counts and that every index is valid.
fn check_scan(name: &str, vertices: usize, triangles: usize) -> Option<SurfaceMesh> {
    let dir = shared_meshes()?;
    let start = std::time::Instant::now();
    let mesh = io::read_surface(dir.join(name)).unwrap();
    eprintln!("{name}: read in {:.3} s", start.elapsed().as_secs_f64());
    assert_eq!(
        (mesh.vertices.len(), mesh.triangles.len()),
        (vertices, triangles),
        "{name}"
    );
    assert!(mesh
        .triangles
        .iter()
        .flatten()
        .all(|&i| (i as usize) < vertices));
    Some(mesh)
}

#[test]
fn reads_bunny_res4_ascii_scan() {
    if let Some(mesh) = check_scan("bun_zipper_res4.ply", 453, 948) {
        let (lo, hi) = mesh.bounds().unwrap();
        // The bunny is about 15 cm across, in metres.
        assert!(
            (hi - lo).max_element() > 0.1 && (hi - lo).max_element() < 0.2,
            "{lo} {hi}"
        );
    }
}

#[test]
fn reads_bunny_res2_and_res3_ascii_scans() {
    check_scan("bun_zipper_res2.ply", 8171, 16301);
    check_scan("bun_zipper_res3.ply", 1889, 3851);
}

#[test]
fn reads_horse_binary_little_endian_scan() {
    check_scan("horse.ply", 24228, 48452);
}

/// The 3 MB full-resolution scan: about 0.08 s to read in the dev profile, so it runs always.
#[test]
fn reads_full_bunny_with_confidence_and_intensity() {
    if let Some(mesh) = check_scan("bun_zipper.ply", 35947, 69451) {
        // First vertex line of the file: -0.0378297 0.12794 0.00447467 0.850855 0.5
        assert_eq!(
            mesh.vertices[0],
            DVec3::new(-0.0378297, 0.12794, 0.00447467)
        );
    }
}
