//! Bad input to the mesh readers: every case is an `Err` (never a panic) whose message names
//! the file and the line (text formats) or the element (binary formats). The mesher's bad
//! inputs are tested in a separate file.

#[path = "common/io.rs"]
mod io_fixtures;

use io_fixtures::*;
use tetrasim::mesh::io;

/// Writes `bytes` as `name` in a fresh folder and reads it as a surface.
fn read_as(
    name: &str,
    bytes: impl AsRef<[u8]>,
) -> (
    tempfile::TempDir,
    std::path::PathBuf,
    tetrasim::mesh::Result<tetrasim::SurfaceMesh>,
) {
    let dir = tempfile::tempdir().unwrap();
    let path = put(dir.path(), name, bytes);
    let result = io::read_surface(&path);
    (dir, path, result)
}

/// Asserts that reading `bytes` as `name` fails with a message containing `needles`; a
/// needle `:N:` must follow the file name (`name:N:`, the line).
#[track_caller]
fn bad(name: &str, bytes: impl AsRef<[u8]>, needles: &[&str]) -> String {
    let (_dir, path, result) = read_as(name, bytes);
    let needles: Vec<String> = needles
        .iter()
        .map(|n| {
            if n.starts_with(':') {
                format!("{name}{n}")
            } else {
                n.to_string()
            }
        })
        .collect();
    let msg = assert_err(
        result,
        &path,
        &needles.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    eprintln!("{msg}");
    msg
}

const TETRA_PLY_VERTICES: &str = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const TETRA_PLY_FACES: &str = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

fn ascii_ply(nv: usize, nf: usize, body: &str) -> String {
    format!(
        "ply\nformat ascii 1.0\nelement vertex {nv}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {nf}\nproperty list uchar int vertex_indices\nend_header\n{body}"
    )
}

#[test]
fn ply_ascii_bad_inputs_name_file_line_and_element() {
    // The valid file reads (so the failures below are caused by the change each makes).
    let (_d, _p, ok) = read_as(
        "ok.ply",
        ascii_ply(4, 4, &format!("{TETRA_PLY_VERTICES}{TETRA_PLY_FACES}")),
    );
    assert_eq!(ok.unwrap().triangles.len(), 4);
    // Header 9 lines; body line k is file line 9 + k.
    // Wrong count: the header says 5 vertices, the file has 4 (a face line is read as vertex 4).
    bad(
        "count.ply",
        ascii_ply(5, 4, &format!("{TETRA_PLY_VERTICES}{TETRA_PLY_FACES}")),
        &[":14:", "vertex 4 of 5", "1 more values"],
    );
    bad(
        "fewer.ply",
        ascii_ply(
            4,
            4,
            &format!("0 0 0\n1 0\n0 1 0\n0 0 1\n{TETRA_PLY_FACES}"),
        ),
        &[":11:", "vertex 1 of 4", "fewer values"],
    );
    // Truncated: the last face is missing.
    let short = &TETRA_PLY_FACES[..TETRA_PLY_FACES.len() - 8];
    bad(
        "trunc.ply",
        ascii_ply(4, 4, &format!("{TETRA_PLY_VERTICES}{short}")),
        &["face 3 of 4", "file ends"],
    );
    // NaN and infinite coordinates name the vertex and the line.
    bad(
        "nan.ply",
        ascii_ply(
            4,
            4,
            &format!("0 0 0\n1 0 0\n0 nan 0\n0 0 1\n{TETRA_PLY_FACES}"),
        ),
        &[":12:", "vertex 2 of 4", "non-finite"],
    );
    bad(
        "inf.ply",
        ascii_ply(
            4,
            4,
            &format!("0 0 0\n1 0 0\n0 1 0\n0 0 -inf\n{TETRA_PLY_FACES}"),
        ),
        &[":13:", "vertex 3", "non-finite"],
    );
    // Out-of-range and negative indices name the face and the index.
    bad(
        "range.ply",
        ascii_ply(
            4,
            4,
            &format!("{TETRA_PLY_VERTICES}3 0 2 1\n3 0 1 7\n3 0 3 2\n3 1 2 3\n"),
        ),
        &[":15:", "face 1 of 4", "index 7", "4 vertices"],
    );
    bad(
        "neg.ply",
        ascii_ply(
            4,
            4,
            &format!("{TETRA_PLY_VERTICES}3 0 2 1\n3 0 1 3\n3 0 -3 2\n3 1 2 3\n"),
        ),
        &[":16:", "face 2 of 4", "index -3"],
    );
    // Polygons with fewer than three corners, non-numbers, extra values.
    bad(
        "two.ply",
        ascii_ply(4, 1, &format!("{TETRA_PLY_VERTICES}2 0 1\n")),
        &[":14:", "face 0 of 1", "at least 3"],
    );
    bad(
        "word.ply",
        ascii_ply(
            4,
            4,
            &format!("0 0 0\n1 zero 0\n0 1 0\n0 0 1\n{TETRA_PLY_FACES}"),
        ),
        &[":11:", "vertex 1 of 4", "`zero`"],
    );
    bad(
        "extra.ply",
        ascii_ply(
            4,
            4,
            &format!("0 0 0 9\n1 0 0\n0 1 0\n0 0 1\n{TETRA_PLY_FACES}"),
        ),
        &[":10:", "vertex 0 of 4", "1 more values"],
    );
    // Empty meshes.
    bad("empty.ply", ascii_ply(0, 0, ""), &["empty mesh"]);
    bad(
        "nofaces.ply",
        ascii_ply(4, 0, TETRA_PLY_VERTICES),
        &["empty mesh", "0 triangles"],
    );
    bad("cloud.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n", &["no `face` element"]);
}

#[test]
fn ply_header_bad_inputs() {
    bad(
        "magic.ply",
        "plyx\nformat ascii 1.0\nend_header\n",
        &[":1:", "not a PLY file"],
    );
    bad(
        "noend.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\n",
        &["without `end_header`"],
    );
    bad(
        "format.ply",
        "ply\nformat binary_middle_endian 1.0\nend_header\n",
        &[":2:", "unknown PLY format"],
    );
    bad(
        "type.ply",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
        &[":4:", "unknown PLY type `float128`"],
    );
    bad(
        "huge.ply",
        "ply\nformat ascii 1.0\nelement vertex 99999999999999999999999999\nend_header\n",
        &[":3:", "not a non-negative integer"],
    );
    bad("noxyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n", &["no scalar property `z`"]);
    bad("floatcount.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n", &[":4:", "list count type"]);
    bad(
        "noformat.ply",
        "ply\nelement vertex 1\nend_header\n",
        &["no `format` line"],
    );
    // A header that promises billions of elements in a tiny file fails without allocating them.
    let huge = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    bad(
        "promise.ply",
        huge,
        &["vertex 0 of 4000000000", "too short"],
    );
}

#[test]
fn ply_binary_bad_inputs_name_the_element() {
    let header = ply_header(
        "binary_little_endian",
        &[
            "element vertex 3",
            "property float x",
            "property float y",
            "property float z",
            "element face 1",
            "property list uchar int vertex_indices",
        ],
    );
    let mut ok = header.clone();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        v.iter().for_each(|c| ok.extend(c.to_le_bytes()));
    }
    ok.push(3);
    [0i32, 1, 2].iter().for_each(|i| ok.extend(i.to_le_bytes()));
    let (_d, _p, good) = read_as("ok.ply", &ok);
    assert_eq!(good.unwrap().triangles, vec![[0, 1, 2]]);
    // Too short: cut inside the face, inside a vertex.
    bad(
        "cut_face.ply",
        &ok[..ok.len() - 2],
        &["face 0 of 1", "binary PLY too short"],
    );
    bad(
        "cut_vertex.ply",
        &ok[..header.len() + 17],
        &["vertex 1 of 3", "binary PLY too short"],
    );
    bad("no_body.ply", &header, &["vertex 0 of 3", "too short"]);
    // NaN in vertex 2, index 9 in face 0, negative count (as char) in a char-count list.
    let mut nan = ok.clone();
    let at = header.len() + 2 * 12 + 4;
    nan[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    bad("nan.ply", &nan, &["vertex 2 of 3", "non-finite"]);
    let mut range = ok.clone();
    let n = range.len();
    range[n - 4..].copy_from_slice(&9i32.to_le_bytes());
    bad(
        "range.ply",
        &range,
        &["face 0 of 1", "index 9", "3 vertices"],
    );
    let mut neg = String::from_utf8(header.clone())
        .unwrap()
        .replace("list uchar int", "list char int")
        .into_bytes();
    neg.extend(&ok[header.len()..header.len() + 36]);
    neg.push(0xfe); // -2 as a signed char
    bad("negcount.ply", &neg, &["face 0 of 1", "negative count -2"]);
}

#[test]
fn obj_bad_inputs_name_file_line_face_and_index() {
    let v = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    bad(
        "range.obj",
        format!("{v}f 1 2 3\nf 1 2 4\n"),
        &[":5:", "face 2", "vertex index 4", "3 vertices"],
    );
    bad(
        "neg.obj",
        format!("{v}f 1 2 -4\n"),
        &[":4:", "face 1", "vertex index -4"],
    );
    bad(
        "zero.obj",
        format!("{v}f 0 1 2\n"),
        &[":4:", "face 1", "vertex index 0"],
    );
    bad(
        "nan.obj",
        "v 0 0 0\nv NaN 0 0\nv 0 1 0\nf 1 2 3\n",
        &[":2:", "vertex 2", "non-finite"],
    );
    bad(
        "short.obj",
        "v 0 0 0\nv 1 0\n",
        &[":2:", "vertex 2 z", "missing"],
    );
    bad(
        "word.obj",
        format!("{v}f 1 two 3\n"),
        &[":4:", "face 1", "`two`"],
    );
    bad(
        "line.obj",
        format!("{v}f 1 2\n"),
        &[":4:", "face 1", "at least 3"],
    );
    bad("empty.obj", "# nothing\n", &["empty mesh"]);
    bad("points.obj", v, &["empty mesh", "3 vertices"]);
}

#[test]
fn off_bad_inputs_name_file_line_and_element() {
    let verts = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    let faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    let (_d, _p, ok) = read_as("ok.off", format!("OFF\n4 4 0\n{verts}{faces}"));
    assert_eq!(ok.unwrap().triangles.len(), 4);
    // Header says 5 vertices, the file has 4: the faces run out.
    bad(
        "more.off",
        format!("OFF\n5 4 0\n{verts}{faces}"),
        &["after 3 of the 4 faces"],
    );
    // Header says 3 vertices, the file has 4: the fourth vertex is read as face 0.
    bad(
        "fewer.off",
        format!("OFF\n3 4 0\n{verts}{faces}"),
        &[":6:", "face 0 has 0 vertices"],
    );
    // Header says 3 faces, the file has 4.
    bad(
        "extra.off",
        format!("OFF\n4 3 0\n{verts}{faces}"),
        &[":10:", "data after the 3 faces"],
    );
    bad(
        "nan.off",
        format!("OFF\n4 4 0\n0 0 0\n1 0 0\n0 nan 0\n0 0 1\n{faces}"),
        &[":5:", "vertex 2", "non-finite"],
    );
    bad(
        "range.off",
        format!("OFF\n4 4 0\n{verts}3 0 2 1\n3 0 1 4\n3 0 3 2\n3 1 2 3\n"),
        &[":8:", "face 1", "vertex index 4"],
    );
    bad(
        "neg.off",
        format!("OFF\n4 4 0\n{verts}3 0 2 1\n3 0 1 3\n3 0 -1 2\n3 1 2 3\n"),
        &[":9:", "face 2", "vertex index -1"],
    );
    bad(
        "corners.off",
        format!("OFF\n4 1 0\n{verts}4 0 1 2\n"),
        &[":7:", "face 0", "vertex index 4 of 4", "missing"],
    );
    bad("empty.off", "OFF\n0 0 0\n", &[":2:", "empty mesh"]);
    bad("nothing.off", "# only a comment\n", &["empty file"]);
    bad(
        "nocounts.off",
        "OFF\n",
        &["before the vertex and face counts"],
    );
    bad("4d.off", "4OFF\n1 1 0\n", &[":1:", "only 3D"]);
    bad("binary.off", "OFF BINARY\n", &[":1:", "binary OFF"]);
    bad(
        "negcount.off",
        "OFF\n-4 4 0\n",
        &[":2:", "vertex count is -4"],
    );
}

#[test]
fn stl_bad_inputs_name_file_line_or_facet() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.stl");
    io::write_surface(&good, &octahedron()).unwrap();
    let bin = std::fs::read(&good).unwrap();
    bad(
        "cut.stl",
        &bin[..bin.len() - 10],
        &["wrong size", "declares 8 facets", "truncated"],
    );
    let mut nan = bin.clone();
    let at = 84 + 3 * 50 + 12 + 12 + 4; // facet 3, vertex 1, y
    nan[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
    bad("inf.stl", &nan, &["facet 3 vertex 1", "non-finite"]);
    let facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
    let (_d, _p, ok) = read_as("ok.stl", format!("solid a\n{facet}endsolid a\n"));
    assert_eq!(ok.unwrap().triangles, vec![[0, 1, 2]]);
    bad(
        "noend.stl",
        format!("solid a\n{facet}"),
        &["`endsolid` is missing"],
    );
    bad(
        "midfacet.stl",
        format!("solid a\n{}", &facet[..facet.len() - 17]),
        &[":7:", "`endloop`", "truncated"],
    );
    bad(
        "nan.stl",
        format!(
            "solid a\n{}",
            facet.replace("vertex 1 0 0", "vertex 1 nan 0")
        ),
        &[":5:", "facet 0 vertex 1", "non-finite"],
    );
    bad(
        "typo.stl",
        format!("solid a\n{}", facet.replace("vertex 1 0 0", "vertx 1 0 0")),
        &[":5:", "facet 0 vertex 1", "`vertx`"],
    );
    bad(
        "four.stl",
        format!(
            "solid a\n{}",
            facet.replace("endloop", "vertex 1 1 1\nendloop")
        ),
        &[":7:", "expected `endloop`"],
    );
    bad(
        "junk.stl",
        format!("solid a\n{facet}bogus\nendsolid\n"),
        &[":9:", "`facet` or `endsolid`", "`bogus`"],
    );
    bad("empty.stl", "solid a\nendsolid a\n", &["empty mesh"]);
    bad("tiny.stl", "hello", &["not an STL file", "5 bytes"]);
    bad("zero.stl", "", &["not an STL file", "0 bytes"]);
}

/// Writes the TetGen files given as (extension, text) into a fresh folder and reads prefix `t`.
#[track_caller]
fn bad_tetgen(files: &[(&str, &str)], needles: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    for (ext, text) in files {
        put(dir.path(), &format!("t.{ext}"), text);
    }
    let result = io::read_tetgen(dir.path().join("t"));
    let msg = match result {
        Ok(m) => panic!("expected an error, got {m:?}"),
        Err(e) => e.to_string(),
    };
    eprintln!("{msg}");
    for n in needles {
        assert!(msg.contains(n), "message does not contain `{n}`: {msg}");
    }
    msg
}

const NODE: &str = "# five nodes\n5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n";
const ELE: &str = "2 4 0\n0 0 1 2 3\n1 1 2 3 4\n";

#[test]
fn tetgen_bad_inputs_name_file_line_and_element() {
    let dir = tempfile::tempdir().unwrap();
    put(dir.path(), "ok.node", NODE);
    put(dir.path(), "ok.ele", ELE);
    assert_eq!(
        io::read_tetgen(dir.path().join("ok")).unwrap().tets.len(),
        2
    );
    bad_tetgen(
        &[("node", NODE), ("ele", "2 4 0\n0 0 1 2 3\n1 1 2 3 9\n")],
        &["t.ele:3:", "tet 1", "node index 9", "0 to 4"],
    );
    bad_tetgen(
        &[("node", NODE), ("ele", "2 4 0\n0 0 1 2 3\n1 1 2 -3 4\n")],
        &["t.ele:3:", "tet 1", "node index -3"],
    );
    bad_tetgen(
        &[("node", NODE), ("ele", "1 10 0\n0 0 1 2 3 4 0 1 2 3 4\n")],
        &["t.ele:1:", "10-node"],
    );
    bad_tetgen(
        &[("node", NODE), ("ele", "3 4 0\n0 0 1 2 3\n1 1 2 3 4\n")],
        &["t.ele", "after 2 of the 3 tetrahedra"],
    );
    bad_tetgen(
        &[("node", NODE), ("ele", "1 4 0\n0 0 1 2 3\n1 1 2 3 4\n")],
        &["t.ele:3:", "data after the 1 tetrahedra"],
    );
    bad_tetgen(
        &[("node", NODE), ("ele", "2 4 1\n0 0 1 2 3 1\n1 1 2 3 4\n")],
        &["t.ele:3:", "tet 1 has 5 values"],
    );
    bad_tetgen(
        &[("node", NODE), ("ele", "0 4 0\n")],
        &["t.ele:1:", "empty mesh"],
    );
    bad_tetgen(
        &[("node", NODE), ("ele", ELE), ("face", "1 0\n0 0 1 5\n")],
        &["t.face:2:", "face 0", "node index 5"],
    );
    bad_tetgen(
        &[("node", &NODE.replace("5 3 0 0", "6 3 0 0")), ("ele", ELE)],
        &["t.node", "after 5 of the 6 nodes"],
    );
    bad_tetgen(
        &[("node", &NODE.replace("5 3 0 0", "4 3 0 0")), ("ele", ELE)],
        &["t.node:7:", "data after the 4 nodes"],
    );
    bad_tetgen(
        &[
            ("node", &NODE.replace("2 0 1 0", "2 0 inf 0")),
            ("ele", ELE),
        ],
        &["t.node:5:", "node 2", "non-finite"],
    );
    bad_tetgen(
        &[("node", &NODE.replace("3 0 0 1", "7 0 0 1")), ("ele", ELE)],
        &["t.node:6:", "numbered 7, expected 3"],
    );
    bad_tetgen(
        &[
            ("node", &NODE.replace("\n0 0 0 0", "\n2 0 0 0")),
            ("ele", ELE),
        ],
        &["t.node:3:", "numbered 2"],
    );
    bad_tetgen(
        &[("node", &NODE.replace("5 3 0 0", "5 3 2 0")), ("ele", ELE)],
        &["t.node:3:", "node 0 has 4 values", "2 attributes"],
    );
    bad_tetgen(
        &[("node", &NODE.replace("5 3 0 0", "5 2 0 0")), ("ele", ELE)],
        &["t.node:2:", "dimension is 2"],
    );
    bad_tetgen(
        &[("node", "0 3 0 0\n"), ("ele", ELE)],
        &["t.node:1:", "empty mesh"],
    );
    bad_tetgen(
        &[("node", "# nothing\n"), ("ele", ELE)],
        &["t.node", "empty .node file"],
    );
    bad_tetgen(
        &[("node", &NODE.replace("1 1 0 0", "1 1 0")), ("ele", ELE)],
        &["t.node:4:", "node 1 has 3 values"],
    );
    // A missing file is an I/O error that names it.
    bad_tetgen(&[("node", NODE)], &["t.ele", "No such file"]);
}

#[test]
fn unreadable_paths_and_unknown_formats() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.ply");
    assert_err(io::read_surface(&missing), &missing, &["No such file"]);
    let folder = dir.path().join("folder.obj");
    std::fs::create_dir(&folder).unwrap();
    assert_err(io::read_surface(&folder), &folder, &[]);
    let xyz = put(dir.path(), "points.xyz", "0 0 0\n");
    assert_err(
        io::read_surface(&xyz),
        &xyz,
        &["unknown surface format `.xyz`", ".ply, .obj, .off or .stl"],
    );
    let bare = put(dir.path(), "noext", "0 0 0\n");
    assert_err(io::read_surface(&bare), &bare, &["(no extension)"]);
    assert_err(
        io::write_surface(&xyz, &octahedron()),
        &xyz,
        &["unknown surface format"],
    );
    assert_eq!(
        std::fs::read_to_string(&xyz).unwrap(),
        "0 0 0\n",
        "a refused write leaves the file alone"
    );
}
