//! What `tetrasim run --out-dir` writes, checked with readers we did not write (Python's
//! meshio for every format, the standard library's XML parser for the `.pvd`), against
//! closed forms: during the free fall before the first contact every node has fallen
//! `g dt^2 n (n + 1) / 2` after `n` frames of symplectic Euler and moves at `g dt n`; the body
//! is not deformed (V/V0 = 1). With `--units input` the files are in the mesh file's units and
//! position, so frame 0 is the input mesh itself.
//!
//! meshio comes from `$TETRASIM_PYTHON` (`scripts/test.sh` sets it to the venv that
//! `scripts/setup.sh` makes) or `python3`; without it the tests say SKIPPED, and fail under
//! `CI=true`.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::ball_mesh;
use common::python::python_with_meshio;
use glam::DVec3;
use tetrasim::geometry::tet_volume;
use tetrasim::mesh::io::write_tetgen;
use tetrasim::mesh::TetMesh;

const G: f64 = 9.81;
const DT: f64 = 1e-3;
const FRAMES: u32 = 20;
const EVERY: u32 = 5;

fn tetrasim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tetrasim"))
}

/// Runs `script` with `args` and parses what it prints as JSON.
fn python_json(python: &Path, script: &str, args: &[&Path]) -> serde_json::Value {
    serde_json::from_str(&common::python::run(python, script, args)).unwrap()
}

/// Reads each file with meshio: points, cells per type, point and cell data.
const READ_WITH_MESHIO: &str = r#"
import json, sys, meshio, numpy as np
out = []
for path in sys.argv[1:]:
    m = meshio.read(path)
    cells = {c.type: c.data.tolist() for c in m.cells}
    out.append({
        "points": m.points.tolist(),
        "cells": cells,
        "point_data": {k: np.asarray(v).tolist() for k, v in m.point_data.items()},
        "cell_data": {k: np.asarray(v[0]).tolist() for k, v in m.cell_data.items()},
    })
print(json.dumps(out))
"#;

/// Reads a `.pvd` with Python's own XML parser: `[time, file]` per data set.
const READ_PVD: &str = r#"
import json, sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
print(json.dumps([[float(d.get("timestep")), d.get("file")] for d in root.iter("DataSet")]))
"#;

/// The test mesh in "millimetres", away from the origin, so `--units input` has a scale
/// and an offset to undo.
fn input_mesh() -> TetMesh {
    let mut mesh = ball_mesh(2.5);
    for p in &mut mesh.nodes {
        *p = *p * 37.0 + DVec3::new(100.0, 250.0, -40.0);
    }
    mesh
}

/// Runs the volume method for [`FRAMES`] frames writing `format` in `units`; returns the
/// output folder and the scale from input units to metres.
fn run(dir: &Path, format: &str, units: &str) -> (PathBuf, f64) {
    let mesh = input_mesh();
    let prefix = dir.join("ball");
    write_tetgen(&prefix, &mesh).unwrap();
    let out_dir = dir.join(format!("frames-{format}-{units}"));
    let output = tetrasim()
        .args([
            "run",
            "--method",
            "volume",
            "--backend",
            "cpu-ref",
            "--quiet",
        ])
        .args([
            "--frames",
            &FRAMES.to_string(),
            "--every",
            &EVERY.to_string(),
        ])
        .args(["--format", format, "--units", units])
        .arg("--mesh")
        .arg(&prefix)
        .arg("--out-dir")
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let (lo, hi) = mesh.bounds().unwrap();
    (out_dir, 1.0 / (hi - lo).max_element())
}

fn vec3(v: &serde_json::Value) -> DVec3 {
    let a: Vec<f64> = serde_json::from_value(v.clone()).unwrap();
    DVec3::new(a[0], a[1], a[2])
}

fn frame_files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    (0..=FRAMES)
        .step_by(EVERY as usize)
        .map(|f| dir.join(format!("volume_{f:05}.{ext}")))
        .collect()
}

/// Fall of every node after `n` frames of symplectic Euler from rest [m].
fn fall(n: u32) -> f64 {
    G * DT * DT * f64::from(n) * f64::from(n + 1) / 2.0
}

#[test]
fn vtu_series_in_input_units_is_the_input_mesh_then_falls_as_computed() {
    let Some(python) = python_with_meshio() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (out, scale) = run(dir.path(), "vtu", "input");
    let mesh = input_mesh();

    let series = python_json(&python, READ_PVD, &[&out.join("volume.pvd")]);
    let series: Vec<(f64, String)> = serde_json::from_value(series).unwrap();
    let frames: Vec<u32> = (0..=FRAMES).step_by(EVERY as usize).collect();
    assert_eq!(series.len(), frames.len(), "{series:?}");
    for ((time, file), f) in series.iter().zip(&frames) {
        assert!((time - f64::from(*f) * DT).abs() < 1e-12, "{series:?}");
        assert_eq!(file, &format!("volume_{f:05}.vtu"));
    }

    let files = frame_files(&out, "vtu");
    let paths: Vec<&Path> = files.iter().map(PathBuf::as_path).collect();
    let read = python_json(&python, READ_WITH_MESHIO, &paths);
    let size = 37.0 * 5.0;
    for (frame, m) in frames.iter().zip(read.as_array().unwrap()) {
        let points: Vec<DVec3> = m["points"].as_array().unwrap().iter().map(vec3).collect();
        let tets: Vec<[u32; 4]> = serde_json::from_value(m["cells"]["tetra"].clone()).unwrap();
        assert_eq!(points.len(), mesh.nodes.len());
        assert_eq!(tets.len(), mesh.tets.len());
        // Every node has fallen by the same closed-form distance, in input units.
        let drop = fall(*frame) / scale;
        for (p, q) in points.iter().zip(&mesh.nodes) {
            let expected = *q - DVec3::Y * drop;
            assert!(
                (*p - expected).length() < 1e-9 * size,
                "frame {frame}: node at {p}, expected {expected}"
            );
        }
        let volume: f64 = tets
            .iter()
            .map(|t| {
                let p = t.map(|i| points[i as usize]);
                tet_volume(p).abs()
            })
            .sum();
        let volume0: f64 = mesh
            .tets
            .iter()
            .map(|t| {
                let p = t.map(|i| mesh.nodes[i as usize]);
                tet_volume(p).abs()
            })
            .sum();
        assert!((volume / volume0 - 1.0).abs() < 1e-9, "frame {frame}");
        let pd = &m["point_data"];
        let cd = &m["cell_data"];
        for (i, d) in pd["displacement"].as_array().unwrap().iter().enumerate() {
            let d = vec3(d);
            assert!(
                (d - DVec3::NEG_Y * drop).length() < 1e-9 * size,
                "node {i}: {d}"
            );
        }
        let speed = G * DT * f64::from(*frame) / scale;
        for v in pd["velocity"].as_array().unwrap() {
            assert!((vec3(v) - DVec3::NEG_Y * speed).length() < 1e-9 * size);
        }
        for key in ["volume_ratio"] {
            for r in pd[key]
                .as_array()
                .unwrap()
                .iter()
                .chain(cd[key].as_array().unwrap())
            {
                assert!((r.as_f64().unwrap() - 1.0).abs() < 1e-9, "{key} {r}");
            }
        }
        let inverted: Vec<u8> = serde_json::from_value(cd["inverted"].clone()).unwrap();
        assert_eq!(inverted.len(), mesh.tets.len());
        assert!(inverted.iter().all(|&x| x == 0));
        let pinned: Vec<u8> = serde_json::from_value(pd["pinned"].clone()).unwrap();
        assert!(pinned.iter().all(|&x| x == 0));
    }
}

#[test]
fn simulation_units_are_metres_above_the_floor() {
    let Some(python) = python_with_meshio() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let (out, _) = run(dir.path(), "vtk", "simulation");
    let files = frame_files(&out, "vtk");
    let read = python_json(&python, READ_WITH_MESHIO, &[&files[0], &files[4]]);
    let lowest = |m: &serde_json::Value| {
        m["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| vec3(p).y)
            .fold(f64::INFINITY, f64::min)
    };
    // The seed placement: largest side 1 m, lowest node 0.1 m above the floor.
    assert!((lowest(&read[0]) - 0.1).abs() < 1e-12);
    assert!((lowest(&read[1]) - (0.1 - fall(FRAMES))).abs() < 1e-12);
    let d = vec3(&read[1]["point_data"]["displacement"][0]);
    assert!((d.y + fall(FRAMES)).abs() < 1e-12, "{d}");
    let names: Vec<&String> = read[1]["cell_data"].as_object().unwrap().keys().collect();
    assert!(names.iter().any(|n| *n == "inverted"), "{names:?}");
}

#[test]
fn ply_frames_carry_a_vertex_quality_and_obj_frames_read() {
    let Some(python) = python_with_meshio() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let surface_nodes = {
        let tets = input_mesh().tets;
        let faces = tetrasim::mesh::topology::boundary_faces(&tets);
        let mut nodes: Vec<u32> = faces.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        (faces.len(), nodes.len())
    };
    for format in ["ply", "obj"] {
        let (out, _) = run(dir.path(), format, "input");
        let files = frame_files(&out, format);
        let read = python_json(&python, READ_WITH_MESHIO, &[&files[4]]);
        let m = &read[0];
        assert_eq!(
            m["cells"]["triangle"].as_array().unwrap().len(),
            surface_nodes.0,
            "{format}"
        );
        assert_eq!(m["points"].as_array().unwrap().len(), surface_nodes.1);
        if format == "ply" {
            let quality = m["point_data"]["quality"].as_array().unwrap();
            assert_eq!(quality.len(), surface_nodes.1);
            for q in quality {
                assert!((q.as_f64().unwrap() - 1.0).abs() < 1e-6, "{q}");
            }
        }
    }
}
