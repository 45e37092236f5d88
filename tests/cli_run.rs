//! `tetrasim run` end to end: a generated mesh written as TetGen files, a short run of every
//! method, the table on stdout, the JSON records, surface output, and clear errors.

mod common;

use std::process::Command;

use common::ball_mesh;
use tetrasim::mesh::io::write_tetgen;
use tetrasim::metrics::RunRecord;
use tetrasim::params::MassMode;

fn tetrasim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tetrasim"))
}

/// The run records in the JSON file `path`.
fn read_records(path: &std::path::Path) -> Vec<RunRecord> {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// `command`'s output, which must be a success (else its stderr is the panic's message).
fn succeeded(command: &mut Command) -> std::process::Output {
    let output = command.output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    output
}

#[test]
fn run_writes_table_metrics_and_surfaces() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    let mesh = ball_mesh(2.5);
    write_tetgen(&prefix, &mesh).unwrap();
    let metrics = dir.path().join("run.json");
    let out_dir = dir.path().join("frames");
    let output = tetrasim()
        .args([
            "run",
            "--preset",
            "seed",
            "--method",
            "all",
            "--backend",
            "cpu-ref",
            "--frames",
            "30",
        ])
        .args(["--ks", "4000", "--quiet", "--every", "10"])
        .arg("--mesh")
        .arg(&prefix)
        .arg("--metrics")
        .arg(&metrics)
        .arg("--out-dir")
        .arg(&out_dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    for method in ["mss", "distance", "volume"] {
        assert!(
            stdout.lines().any(|l| l.starts_with(method)),
            "no `{method}` row in\n{stdout}"
        );
    }
    let records = read_records(&metrics);
    assert_eq!(records.len(), 3);
    for r in &records {
        assert_eq!(
            (
                r.backend.as_str(),
                r.frames,
                r.volume_pct.len(),
                r.params.ks
            ),
            ("cpu-ref", 30, 30, 4000.0)
        );
        assert_eq!((r.nodes, r.tets), (mesh.nodes.len(), mesh.tets.len()));
        // Falling, not yet landed (0.03 s from 0.1 m): the volume is still 100 %.
        assert!(
            (r.min_volume_pct - 100.0).abs() < 0.1,
            "{}: {}",
            r.method,
            r.min_volume_pct
        );
    }
    // Frames 0, 10, 20, 30 for each of the three methods.
    let written = std::fs::read_dir(&out_dir).unwrap().count();
    assert_eq!(written, 12);
    let surface = tetrasim::mesh::io::read_surface(out_dir.join("volume_00030.ply")).unwrap();
    assert_eq!(surface.triangles.len(), mesh.faces.len());
}

#[test]
fn missing_mesh_is_a_clear_error() {
    let output = tetrasim()
        .args(["run", "--mesh", "/nonexistent/thing", "--frames", "1"])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("/nonexistent/thing") && stderr.contains("TetGen prefix"),
        "{stderr}"
    );
}

#[test]
fn bad_parameter_names_the_key() {
    let output = tetrasim()
        .args(["run", "--dt=-1", "--frames", "1"])
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("`dt`"), "{stderr}");
}

#[test]
fn solver_flags_the_solver_does_not_use_are_refused() {
    for (args, key) in [
        (&["--solver", "jacobi", "--groups", "4"][..], "`groups`"),
        (&["--rho", "0.9"][..], "`rho`"),
    ] {
        let output = tetrasim()
            .args(["run", "--frames", "1"])
            .args(args)
            .output()
            .unwrap();
        assert!(!output.status.success(), "{args:?} was accepted");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            stderr.contains(key) && stderr.contains("acts only with"),
            "{stderr}"
        );
    }
}

#[test]
fn unknown_backend_lists_the_known_ones() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    write_tetgen(&prefix, &ball_mesh(1.5)).unwrap();
    let output = tetrasim()
        .args(["run", "--backend", "gpu9000", "--frames", "1"])
        .arg("--mesh")
        .arg(&prefix)
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("gpu9000") && stderr.contains("cpu-ref"),
        "{stderr}"
    );
}

#[test]
fn surface_file_is_meshed_in_process() {
    let surface =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere_surface.off");
    let dir = tempfile::tempdir().unwrap();
    let metrics = dir.path().join("run.json");
    let output = tetrasim()
        .args([
            "run",
            "--method",
            "volume",
            "--frames",
            "3",
            "--quiet",
            "--target-tets",
            "1500",
        ])
        .arg("--mesh")
        .arg(&surface)
        .arg("--metrics")
        .arg(&metrics)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("meshed in-process"), "{stderr}");
    let records = read_records(&metrics);
    // Within tetprep's 25 % of the target.
    assert!(
        (1125..=1875).contains(&records[0].tets),
        "{} tets",
        records[0].tets
    );
}

/// `tetrasim run --scene` takes every flag over the scene's values: the solver, material,
/// method, floor and output flags, placement for every object and `--mesh` for a one-object
/// scene; what cannot apply is refused saying why.
#[test]
fn flags_override_a_scene() {
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/scenes/tilted_plane.toml"
    );
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("run.json");
    succeeded(
        tetrasim()
            .args([
                "run", "--quiet", "--scene", scene, "--frames", "3", "--dt", "5e-4",
            ])
            .args(["--method", "distance", "--density", "900", "--no-floor"])
            .args(["--gravity=0,0,-9.81", "--backend", "cpu-ref", "--json"])
            .arg(&json),
    );
    let records = read_records(&json);
    let [record] = &records[..] else {
        panic!("{} records", records.len())
    };
    let p = &record.params;
    assert_eq!(record.frames, 3, "--frames over solver.frames = 1000");
    assert_eq!((p.dt, p.method.name(), p.floor), (5e-4, "distance", false));
    assert_eq!(p.gravity.to_array(), [0.0, 0.0, -9.81]);
    assert_eq!(p.mass, MassMode::Density { density: 900.0 });
    assert_eq!(record.backend, "cpu-ref");

    let sphere = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/sphere");
    succeeded(
        tetrasim()
            .args([
                "run", "--quiet", "--scene", scene, "--frames", "2", "--mesh", sphere,
            ])
            .args(["--fit-size", "0.3", "--drop-height", "0.5", "--json"])
            .arg(&json),
    );
    let records = read_records(&json);
    assert_eq!(records[0].nodes, 823, "the bundled sphere replaced the box");
    let two = dir.path().join("two.toml");
    let body = format!("[[object]]\nmesh = {sphere:?}\n");
    std::fs::write(&two, format!("[solver]\nframes = 2\n{body}{body}")).unwrap();
    let output = tetrasim()
        .args(["run", "--quiet", "--scene"])
        .arg(&two)
        .args(["--mesh", sphere])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !output.status.success() && stderr.contains("one body's mesh"),
        "{stderr}"
    );
    for (args, says) in [
        (&["--method", "all"][..], "name one method"),
        (&["--dt=-1"][..], "`dt`"),
    ] {
        let output = tetrasim()
            .args(["run", "--quiet", "--scene", scene, "--frames", "1"])
            .args(args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success(), "{args:?} was accepted");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
}

/// Reports fit the run: the paper's column only for its experiment (the `seed` preset's
/// drop from flags), and a held body (pinned or clamped) is not given a free fall's
/// contact time, nor told it ended before one.
#[test]
fn reports_fit_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("r.json");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/scenes/clamped_block.toml"
    );
    let run = |args: &[&str]| {
        let out = succeeded(
            tetrasim()
                .args(["run", "--quiet", "--frames", "5", "--json"])
                .arg(&json)
                .args(args),
        );
        let records = read_records(&json);
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        (text + &String::from_utf8_lossy(&out.stderr), records)
    };
    let (said, records) = run(&["--scene", scene]);
    assert!(
        !said.contains("paper") && !said.contains("free fall"),
        "{said}"
    );
    assert_eq!(
        records[0].contact_time_s, None,
        "a clamped body does not fall freely"
    );
    let (said, records) = run(&["--method", "volume"]);
    assert!(
        said.contains("paper avg") && said.contains("not the paper's experiment"),
        "{said}"
    );
    assert!(records[0].contact_time_s.is_some());
}
