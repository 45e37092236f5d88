//! The `tetprep` binary end to end: outputs, JSON stats, exit codes, and no files on failure.
#![cfg_attr(not(feature = "tetgen"), allow(unused_imports))]

use std::path::Path;
use std::process::{Command, Output};

use glam::DVec3;
use tetmesh::mesh::io::{read_surface, read_tetgen, write_surface};
use tetmesh::mesh::shapes;

fn tetprep(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tetprep"))
        .args(args)
        .output()
        .expect("tetprep runs")
}

fn files_with_prefix(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

#[cfg(feature = "tetgen")]
#[test]
fn shape_to_files_with_json_stats() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    let out = tetprep(&[
        "--shape",
        "sphere",
        "-o",
        prefix.to_str().unwrap(),
        "--target-tets",
        "1500",
        "--json",
        "--vtk",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stats: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("stdout is only JSON");
    let tets = stats["tets"].as_u64().unwrap();
    assert!((tets as f64 / 1500.0 - 1.0).abs() <= 0.25, "{tets}");
    assert_eq!(stats["mesher"], "tetgen");
    assert_eq!(stats["non_positive_tets"], 0);
    let mesh = read_tetgen(&prefix).unwrap();
    assert_eq!(mesh.tets.len() as u64, tets);
    assert_eq!(mesh.nodes.len() as u64, stats["nodes"].as_u64().unwrap());
    let mut names = files_with_prefix(dir.path());
    names.sort();
    assert_eq!(names, ["ball.ele", "ball.face", "ball.node", "ball.vtk"]);
    // The .vtk is a mesh `tetrasim run --mesh` takes: the same nodes and tets.
    let vtk = tetmesh::mesh::io::read_tet_mesh(&dir.path().join("ball.vtk")).unwrap();
    assert_eq!(vtk.nodes, mesh.nodes);
    assert_eq!(vtk.tets, mesh.tets);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("tetprep: TetGen run 1"), "{stderr}");
}

#[test]
fn missing_input_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("out");
    let out = tetprep(&["/nonexistent/bunny.ply", "-o", prefix.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("error") && stderr.contains("/nonexistent/bunny.ply"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(files_with_prefix(dir.path()).is_empty());
}

#[cfg(feature = "tetgen")]
#[test]
fn self_intersecting_surface_fails_without_fallback_and_voxelizes_with_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = shapes::sphere(1.0, 2);
    let base = m.vertices.len() as u32;
    let other = shapes::sphere(1.0, 2);
    m.vertices.extend(
        other
            .vertices
            .iter()
            .map(|p| *p + DVec3::new(1.3, 0.1, 0.05)),
    );
    m.triangles
        .extend(other.triangles.iter().map(|t| t.map(|v| v + base)));
    let input = dir.path().join("two.off");
    write_surface(&input, &m).unwrap();
    let prefix = dir.path().join("two");
    let args = |extra: &[&'static str]| {
        let mut a = vec![
            input.to_str().unwrap().to_string(),
            "-o".into(),
            prefix.to_str().unwrap().to_string(),
            "--target-tets".into(),
            "3000".into(),
        ];
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |a: Vec<String>| {
        Command::new(env!("CARGO_BIN_EXE_tetprep"))
            .args(a)
            .output()
            .unwrap()
    };

    let out = run(args(&[]));
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("intersects itself") && stderr.contains("two.off"),
        "{stderr}"
    );
    assert_eq!(files_with_prefix(dir.path()), ["two.off"]);

    let out = run(args(&["--fallback", "--json"]));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("warning: TetGen failed"), "{stderr}");
    let stats: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        (stats["mesher"].as_str(), stats["fell_back"].as_bool()),
        (Some("voxel"), Some(true))
    );
    let mesh = read_tetgen(&prefix).unwrap();
    assert!(mesh.tets.len() > 2000, "{}", mesh.tets.len());
}

fn assert_success(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn assert_clean_failure(out: &Output) -> String {
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

#[cfg(feature = "tetgen")]
#[test]
fn missing_output_folders_are_made_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("new/sub/ball");
    let out = tetprep(&[
        "--shape",
        "sphere",
        "-o",
        prefix.to_str().unwrap(),
        "--target-tets",
        "600",
    ]);
    assert_success(&out);
    let mut names = files_with_prefix(&dir.path().join("new/sub"));
    names.sort();
    assert_eq!(names, ["ball.ele", "ball.face", "ball.node"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let made = stderr.find("made the folder").expect("says so");
    let repairing = stderr.find("repairing").expect("stage line");
    assert!(made < repairing, "{stderr}");
}

#[test]
fn failed_run_removes_the_folders_it_made() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("new/sub/out");
    let out = tetprep(&["/nonexistent/bunny.ply", "-o", prefix.to_str().unwrap()]);
    let stderr = assert_clean_failure(&out);
    assert!(stderr.contains("/nonexistent/bunny.ply"), "{stderr}");
    assert!(files_with_prefix(dir.path()).is_empty());
}

#[test]
fn bad_output_paths_are_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("plain");
    std::fs::write(&file, "not a folder").unwrap();
    // The input does not exist either: the output is checked first, so its error comes.
    let input = "/nonexistent/bunny.ply";
    let cases = [
        (
            vec!["-o".to_string(), format!("{}/out", file.display())],
            "is a file, not a folder",
        ),
        (
            vec!["-o".to_string(), format!("{}/", dir.path().display())],
            "names a folder",
        ),
        (
            vec![
                "-o".to_string(),
                format!("{}/out", dir.path().display()),
                "--save-surface".to_string(),
                format!("{}/s.xyz", dir.path().display()),
            ],
            "unknown surface format",
        ),
        (
            vec![
                "-o".to_string(),
                format!("{}/out", dir.path().display()),
                "--save-surface".to_string(),
                format!("{}/x/s.off", file.display()),
            ],
            "is a file, not a folder",
        ),
    ];
    for (args, reason) in cases {
        let mut all = vec![input.to_string()];
        all.extend(args);
        let out = Command::new(env!("CARGO_BIN_EXE_tetprep"))
            .args(&all)
            .output()
            .unwrap();
        let stderr = assert_clean_failure(&out);
        assert!(
            stderr.contains(reason) && !stderr.contains("reading"),
            "{all:?}: {stderr}"
        );
        assert_eq!(files_with_prefix(dir.path()), ["plain"], "{all:?}");
    }
}

#[cfg(feature = "tetgen")]
#[test]
fn known_extensions_are_dropped_from_the_prefix() {
    let ball = ["ball.ele", "ball.face", "ball.node", "ball.vtk"];
    for (given, names) in [
        ("ball.node", ball),
        ("ball.vtk", ball),
        ("ball.MSH", ball),
        (
            "ball.v2",
            ["ball.v2.ele", "ball.v2.face", "ball.v2.node", "ball.v2.vtk"],
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = tetprep(&[
            "--shape",
            "box",
            "-o",
            dir.path().join(given).to_str().unwrap(),
            "--target-tets",
            "300",
            "--vtk",
        ]);
        assert_success(&out);
        let mut found = files_with_prefix(dir.path());
        found.sort();
        assert_eq!(found, names, "-o {given}");
    }
}

#[cfg(feature = "tetgen")]
#[test]
fn save_surface_writes_the_simplified_surface_that_was_meshed() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    let saved = dir.path().join("surface/meshed.off");
    // 1280 faces and a target of 600 tets: simplified to about 200 faces.
    let out = tetprep(&[
        "--shape",
        "sphere",
        "-o",
        prefix.to_str().unwrap(),
        "--target-tets",
        "600",
        "--scale",
        "2",
        "--save-surface",
        saved.to_str().unwrap(),
        "--json",
    ]);
    assert_success(&out);
    let stats: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let surface = read_surface(&saved).unwrap();
    let faces_in = stats["faces_in"].as_u64().unwrap();
    let faces_meshed = stats["faces_meshed"].as_u64().unwrap();
    assert_eq!(faces_in, 1280);
    assert!(faces_meshed < faces_in / 2, "{faces_meshed}");
    assert_eq!(surface.triangles.len() as u64, faces_meshed);
    // Scaled like the mesh (radius 0.5 x 2), and kept as the mesh's boundary (-Y).
    let radius = surface
        .vertices
        .iter()
        .map(|p| p.length())
        .fold(0.0, f64::max);
    assert!((radius - 1.0).abs() < 1e-9, "{radius}");
    let mesh = read_tetgen(&prefix).unwrap();
    assert_eq!(mesh.faces.len(), surface.triangles.len());
    assert_eq!(
        stats["surface_faces"].as_u64().unwrap(),
        surface.triangles.len() as u64
    );
}

/// `--json FILE` writes the stats there (its folder made first) and keeps the table on
/// stdout; `--json` alone (or `-`) prints them instead of the table.
#[cfg(feature = "tetgen")]
#[test]
fn json_stats_go_to_a_file_or_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    let json = dir.path().join("stats/new/ball.json");
    let out = tetprep(&[
        "--shape",
        "sphere",
        "-o",
        prefix.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(&format!("{}", stats["tets"])), "{stdout}");
    assert!(serde_json::from_slice::<serde_json::Value>(&out.stdout).is_err());
    let out = tetprep(&[
        "--shape",
        "sphere",
        "-o",
        prefix.to_str().unwrap(),
        "--json",
        "-",
    ]);
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(printed["tets"], stats["tets"]);
    // A folder is not a file name: refused before any work.
    let out = tetprep(&[
        "--shape",
        "sphere",
        "-o",
        prefix.to_str().unwrap(),
        "--json",
        dir.path().to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("is a folder") && !err.contains("TetGen"),
        "{err}"
    );
}
