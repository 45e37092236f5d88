//! The tet-mesh readers (`read_tet_mesh`: legacy VTK, VTU, gmsh 2.2/4.1, Medit, TetGen) on
//! files written by an independent writer, meshio 5.3.5 (`tests/data/meshio/make_fixtures.py`),
//! and on bad input: every failure is an error naming the file and the line or element, never
//! a panic. Also: meshio reads our TetGen output, and `tetrasim run --mesh` takes every format.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

// The readers (crate tetmesh) return its own error type, re-exported here.
use tetrasim::geometry::tet_volume;
use tetrasim::mesh::io::{self, read_tet_mesh, TetFormat};
use tetrasim::mesh::Error;
use tetrasim::mesh::TetMesh;

/// Reference figures printed by make_fixtures.py (computed by meshio/numpy, not by us):
/// 12 nodes, 12 tets, sum of |tet volume| 2.0.
const NODES: usize = 12;
const TETS: usize = 12;
const VOLUME: f64 = 2.0;

/// Every fixture with the box's 12 tets (the mixed ones carry triangles, a vertex cell and an
/// extra node besides).
const FIXTURES: [&str; 18] = [
    "box_ascii.vtk",
    "box_binary.vtk",
    "box_42_ascii.vtk",
    "box_42_binary.vtk",
    "box.vtu",
    "box_ascii.vtu",
    "box_binary_raw.vtu",
    "box_22_ascii.msh",
    "box_22_binary.msh",
    "box.msh",
    "box_41_binary.msh",
    "box.mesh",
    "box.node",
    "mixed_ascii.vtk",
    "mixed.vtu",
    "mixed_22_ascii.msh",
    "mixed_41_binary.msh",
    "mixed.mesh",
];

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/meshio")
        .join(name)
}

fn total_volume(m: &TetMesh) -> f64 {
    m.tets
        .iter()
        .map(|t| {
            let p = t.map(|v| m.nodes[v as usize]);
            tet_volume(p).abs()
        })
        .sum()
}

#[test]
fn every_fixture_reads_to_the_tetgen_original() {
    let original = io::read_tetgen(data("box")).unwrap();
    assert_eq!(original.nodes.len(), NODES);
    assert_eq!(original.tets.len(), TETS);
    for name in FIXTURES {
        let m = read_tet_mesh(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.nodes.len(), NODES, "{name}");
        assert_eq!(m.tets.len(), TETS, "{name}");
        assert!((total_volume(&m) - VOLUME).abs() < 1e-12, "{name}");
        assert_eq!(m.nodes, original.nodes, "{name}");
        // Same tets, same order, same orientation (tet 1 is negative in every file).
        assert_eq!(m.tets, original.tets, "{name}");
        let p = m.tets[1].map(|v| m.nodes[v as usize]);
        assert!(tet_volume(p) < 0.0, "{name}");
    }
}

#[test]
fn format_is_found_by_content_when_the_extension_names_none() {
    let dir = tempfile::tempdir().unwrap();
    for (name, format) in [
        ("box_binary.vtk", TetFormat::Vtk),
        ("box.vtu", TetFormat::Vtu),
        ("box_22_binary.msh", TetFormat::Gmsh),
        ("box.msh", TetFormat::Gmsh),
        ("box.mesh", TetFormat::Medit),
    ] {
        let bytes = std::fs::read(data(name)).unwrap();
        assert_eq!(TetFormat::sniff(&bytes), Some(format), "{name}");
        let copy = dir.path().join(format!("{name}.data"));
        std::fs::write(&copy, &bytes).unwrap();
        assert_eq!(read_tet_mesh(&copy).unwrap().tets.len(), TETS, "{name}");
        let upper = dir.path().join(name.to_ascii_uppercase());
        std::fs::write(&upper, &bytes).unwrap();
        assert_eq!(read_tet_mesh(&upper).unwrap().tets.len(), TETS, "{name}");
    }
}

/// The error of reading `bytes` as file `name`; checks it is a parse error naming the file.
fn error_of(name: &str, bytes: &[u8]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    let err = read_tet_mesh(&path).expect_err(name);
    assert!(matches!(err, Error::Parse { .. }), "{name}: {err:?}");
    let msg = err.to_string();
    assert!(msg.contains(&path.display().to_string()), "{msg}");
    msg
}

fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(data(name)).unwrap()
}

#[test]
fn truncated_files_are_errors_naming_the_file() {
    for name in FIXTURES.iter().filter(|n| !n.ends_with(".node")) {
        let bytes = std::fs::read(data(name)).unwrap();
        for cut in [bytes.len() / 3, bytes.len() / 2, bytes.len() * 4 / 5] {
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join(name);
            std::fs::write(&path, &bytes[..cut]).unwrap();
            // A cut may leave a valid but smaller file (e.g. fewer trailing sections); the
            // point is no panic and, when it fails, the file is named.
            if let Err(e) = read_tet_mesh(&path) {
                assert!(e.to_string().contains(&path.display().to_string()), "{e}");
            }
        }
    }
    let msg = error_of(
        "t.msh",
        &std::fs::read(data("box_22_binary.msh")).unwrap()[..300],
    );
    assert!(msg.contains("truncated"), "{msg}");
    let text = fixture_text("box_ascii.vtk");
    let msg = error_of(
        "t.vtk",
        &text.as_bytes()[..text.find("CELL_TYPES").unwrap() + 14],
    );
    assert!(msg.contains("truncated"), "{msg}");
}

#[test]
fn index_out_of_range_names_the_line() {
    // Medit: tetrahedron 1's first vertex is `1`; make it 99.
    let t = fixture_text("box.mesh");
    let at = t.find("Tetrahedra\n12\n").unwrap() + "Tetrahedra\n12\n".len();
    let bad = format!("{}99{}", &t[..at], &t[at + 1..]);
    let line = t[..at].lines().count() + 1;
    let msg = error_of("bad.mesh", bad.as_bytes());
    assert!(
        msg.contains(&format!("bad.mesh:{line}:")) && msg.contains("99"),
        "{msg}"
    );

    // gmsh 2.2: element 6 (the first tet) refers to node tag 77.
    let t = fixture_text("box_22_ascii.msh");
    let bad = t.replacen("\n1 4 2 0 0 1 2 5 11\n", "\n1 4 2 0 0 1 2 5 77\n", 1);
    assert_ne!(bad, t);
    let line = bad.lines().position(|l| l.ends_with(" 77")).unwrap() + 1;
    let msg = error_of("bad.msh", bad.as_bytes());
    assert!(
        msg.contains(&format!(":{line}:")) && msg.contains("77"),
        "{msg}"
    );

    // Legacy VTK 4.2: the first cell's first node 0 -> 12.
    let t = fixture_text("box_42_ascii.vtk");
    let bad = t.replacen("CELLS 12 60\n4\n0\n", "CELLS 12 60\n4\n12\n", 1);
    assert_ne!(bad, t);
    let line = bad.lines().position(|l| l == "CELLS 12 60").unwrap() + 3;
    let msg = error_of("bad.vtk", bad.as_bytes());
    assert!(
        msg.contains(&format!(":{line}:")) && msg.contains("cell 0"),
        "{msg}"
    );

    // VTU ascii: connectivity value 0 -> 40; the error names the DataArray's line.
    let t = fixture_text("box_ascii.vtu");
    let at = t.find("Name=\"connectivity\"").unwrap();
    let open = at + t[at..].find('>').unwrap() + 1;
    let first = open + t[open..].find(|c: char| c.is_ascii_digit()).unwrap();
    let bad = format!("{}40{}", &t[..first], &t[first + 1..]);
    let line = t[..at].lines().count();
    let msg = error_of("bad.vtu", bad.as_bytes());
    assert!(
        msg.contains(&format!(":{line}:")) && msg.contains("40"),
        "{msg}"
    );
}

#[test]
fn non_finite_coordinates_are_errors() {
    let t = fixture_text("box.mesh");
    let bad = t.replacen("1.0000000000000000e+00", "nan", 1);
    let msg = error_of("nan.mesh", bad.as_bytes());
    assert!(
        msg.contains("non-finite") && msg.contains("nan.mesh:"),
        "{msg}"
    );
    let t = fixture_text("box.msh");
    let bad = t.replacen("1.0000000000000000e+00", "inf", 1);
    let msg = error_of("inf.msh", bad.as_bytes());
    assert!(msg.contains("non-finite"), "{msg}");
    let t = fixture_text("box_ascii.vtk");
    let bad = t.replacen("1.0", "nan", 1);
    let msg = error_of("nan.vtk", bad.as_bytes());
    assert!(
        msg.contains("non-finite") && msg.contains("nan.vtk:6:"),
        "{msg}"
    );
    let t = fixture_text("box_ascii.vtu");
    let bad = t.replacen("0.00000000000e+00", "inf", 1);
    let msg = error_of("inf.vtu", bad.as_bytes());
    assert!(msg.contains("non-finite"), "{msg}");
}

#[test]
fn files_without_tets_are_errors_naming_what_they_have() {
    let msg = error_of("triangles.vtk", fixture_text("triangles.vtk").as_bytes());
    assert!(
        msg.contains("no tetrahedra") && msg.contains("4 x triangle (5)"),
        "{msg}"
    );
    // Quadratic tets: a reason, not a skip.
    let t = fixture_text("box_42_ascii.vtk");
    let bad = t.replace("\n10\n", "\n24\n");
    let msg = error_of("quad.vtk", bad.as_bytes());
    assert!(msg.contains("quadratic"), "{msg}");
    // gmsh with the tets' type changed to a 4-node quad... (type 3): none left.
    let t = fixture_text("box_22_ascii.msh");
    let bad: String = t
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(' ').collect();
            if f.len() == 9 && f[1] == "4" {
                format!("{} 3 {}\n", f[0], f[2..].join(" "))
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    let msg = error_of("quads.msh", bad.as_bytes());
    assert!(
        msg.contains("no tetrahedra") && msg.contains("12 of type 3"),
        "{msg}"
    );
    let t = fixture_text("box.mesh");
    let bad = &t[..t.find("Tetrahedra").unwrap()];
    let msg = error_of("none.mesh", bad.as_bytes());
    assert!(msg.contains("no tetrahedra"), "{msg}");
}

#[test]
fn unknown_and_missing_files_say_so() {
    let msg = error_of("what.dat", b"solid nothing\nendsolid\n");
    assert!(
        msg.contains("unknown tet-mesh format") && msg.contains(".msh"),
        "{msg}"
    );
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nothing");
    let msg = read_tet_mesh(&missing).unwrap_err().to_string();
    assert!(
        msg.contains("does not exist") && msg.contains(".vtu"),
        "{msg}"
    );
}

#[test]
fn meshio_reads_our_tetgen_output() {
    let Some(python) = common::python::python_with_meshio() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mesh = common::ball_mesh(2.5);
    io::write_tetgen(dir.path().join("ball"), &mesh).unwrap();
    let script = "import sys, meshio, numpy as np\n\
m = meshio.read(sys.argv[1])\n\
t = m.get_cells_type('tetra')\n\
p = m.points\n\
a, b, c, d = (p[t[:, k]] for k in range(4))\n\
v = np.abs(np.einsum('ij,ij->i', np.cross(b - a, c - a), d - a)).sum() / 6\n\
print(len(p), len(t), repr(float(v)))\n";
    let stdout = common::python::run(&python, script, &[&dir.path().join("ball.node")]);
    let f: Vec<&str> = stdout.split_whitespace().collect();
    assert_eq!(f[0].parse::<usize>().unwrap(), mesh.nodes.len());
    assert_eq!(f[1].parse::<usize>().unwrap(), mesh.tets.len());
    let v: f64 = f[2].parse().unwrap();
    assert!((v - total_volume(&mesh)).abs() < 1e-9 * v, "{v}");
    // And our reader reads it back unchanged.
    assert_eq!(
        io::read_tetgen(dir.path().join("ball")).unwrap().tets,
        mesh.tets
    );
}

#[test]
fn run_takes_every_format() {
    for name in [
        "box.msh",
        "box_22_binary.msh",
        "box.vtu",
        "box_binary.vtk",
        "box.mesh",
        "mixed_41_binary.msh",
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
            .args([
                "run",
                "--frames",
                "2",
                "--method",
                "volume",
                "--backend",
                "cpu",
                "--mesh",
            ])
            .arg(data(name))
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            stdout.lines().any(|l| l.starts_with("volume")),
            "{name}: no table row in\n{stdout}"
        );
    }
}

#[test]
fn run_says_when_the_mesh_file_is_missing() {
    let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args(["run", "--frames", "2", "--mesh", "no/such/mesh.msh"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("no/such/mesh.msh")
            && stderr.contains("does not exist")
            && stderr.contains(".vtu"),
        "{stderr}"
    );
}

/// Our own VTK writers read back by our readers: the same nodes to the bit and the same tets
/// (the independent check of the writers is meshio's, in tests/frame_outputs.rs).
#[test]
fn our_vtk_and_vtu_files_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let mut mesh = common::ball_mesh(2.5);
    for (i, p) in mesh.nodes.iter_mut().enumerate() {
        *p += common::noise3(i as u64) * 1e-3;
    }
    let ratio: Vec<f64> = (0..mesh.tets.len())
        .map(|t| 1.0 + t as f64 * 1e-3)
        .collect();
    let fields = io::Fields {
        point: vec![io::Field {
            name: "displacement",
            values: io::FieldValues::Vector(&mesh.nodes),
        }],
        cell: vec![io::Field {
            name: "volume_ratio",
            values: io::FieldValues::Scalar(&ratio),
        }],
    };
    let vtu = dir.path().join("m.vtu");
    let vtk = dir.path().join("m.vtk");
    io::write_vtu(&vtu, &mesh, &fields).unwrap();
    io::write_vtk_fields(&vtk, &mesh, &fields).unwrap();
    for path in [vtu, vtk] {
        let back = read_tet_mesh(&path).unwrap();
        assert_eq!(back.nodes, mesh.nodes, "{}", path.display());
        assert_eq!(back.tets, mesh.tets, "{}", path.display());
    }
}
