//! The `tetprep` binary end to end: outputs, JSON stats, exit codes, and no files on failure.

use std::path::Path;
use std::process::{Command, Output};

use glam::DVec3;
use tetrasim::mesh::io::{read_tetgen, write_surface};
use tetrasim::mesh::shapes;

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
