//! The command line without surprises: negative numbers are values, every output flag either
//! acts or is refused with the reason, output folders are made (or refused) before any work,
//! the JSON records carry a time axis, and a run that ends before the body reaches the floor
//! says so next to the paper's column.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::ball_mesh;
use tetrasim::mesh::io::write_tetgen;
use tetrasim::metrics::RunRecord;

fn tetrasim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ball(dir: &Path) -> String {
    let prefix = dir.join("ball");
    write_tetgen(&prefix, &ball_mesh(2.5)).unwrap();
    prefix.to_string_lossy().into_owned()
}

/// Fails unless `o` failed, saying something that contains every one of `words`, and ran
/// nothing (no table on stdout).
fn assert_refused(o: &Output, words: &[&str]) {
    let err = stderr(o);
    assert!(!o.status.success(), "not refused; stderr: {err}");
    for w in words {
        assert!(err.contains(w), "`{w}` not in: {err}");
    }
    assert!(
        o.stdout.is_empty(),
        "it ran: {}",
        String::from_utf8_lossy(&o.stdout)
    );
}

#[test]
fn records_have_a_time_axis_and_short_runs_are_flagged() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ball(dir.path());
    let json = dir.path().join("deep/er/run.json");
    let json_s = json.to_string_lossy().into_owned();
    let common = ["run", "--method", "volume", "--backend", "cpu", "--quiet"];
    let mut args = common.to_vec();
    args.extend(["--mesh", &mesh, "--frames", "30", "--json", &json_s]);
    let short = tetrasim(&args);
    assert!(short.status.success(), "{}", stderr(&short));
    let table = String::from_utf8_lossy(&short.stdout);
    assert!(table.contains("ended before its first contact"), "{table}");
    let warning = stderr(&short);
    assert!(
        warning.contains("warning: volume on cpu (") && warning.contains(") ran 30 frames"),
        "{warning}"
    );
    let records: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let r = &records[0];
    assert_eq!(r.time_s.len(), 30);
    for (k, t) in r.time_s.iter().enumerate() {
        assert!((t - (k + 1) as f64 * 1e-3).abs() < 1e-15, "{t}");
    }
    // Lowest node 0.1 m above the floor, at rest: free fall takes sqrt(2 h / g).
    let contact = r.contact_time_s.unwrap();
    assert!(
        (contact - (2.0 * 0.1 / 9.81f64).sqrt()).abs() < 1e-12,
        "{contact}"
    );

    let mut args = common.to_vec();
    args.extend(["--mesh", &mesh, "--frames", "160"]);
    let long = tetrasim(&args);
    assert!(long.status.success(), "{}", stderr(&long));
    assert!(!String::from_utf8_lossy(&long.stdout).contains("ended before"));
    assert!(!stderr(&long).contains("warning: volume"));

    // No floor, no contact: nothing to warn about.
    let mut args = common.to_vec();
    args.extend(["--mesh", &mesh, "--frames", "5", "--no-floor"]);
    let free = tetrasim(&args);
    assert!(!String::from_utf8_lossy(&free.stdout).contains("ended before"));
}

#[test]
fn a_run_that_ends_before_landing_on_a_collider_is_flagged() {
    // No floor: a plane collider 0.3 m below it, so the lowest node (0.1 m up, at rest)
    // falls 0.4 m.
    let dir = tempfile::tempdir().unwrap();
    let mesh = ball(dir.path());
    let json = dir.path().join("run.json");
    let scene = dir.path().join("plane.toml");
    let write = |frames: u32| {
        let text = format!(
            "[solver]\nframes = {frames}\n\n[[object]]\nmesh = \"{mesh}\"\nmethod = \"volume\"\n\
             drop_height = 0.1\n\n[[collider]]\ntype = \"plane\"\nnormal = [0.0, 1.0, 0.0]\n\
             distance = -0.3\n\n[output]\njson = \"{}\"\n",
            json.display()
        );
        std::fs::write(&scene, text).unwrap();
    };
    let run = |frames: u32| {
        write(frames);
        tetrasim(&[
            "run",
            "--scene",
            scene.to_str().unwrap(),
            "--backend",
            "cpu",
        ])
    };
    let short = run(30);
    assert!(short.status.success(), "{}", stderr(&short));
    let table = String::from_utf8_lossy(&short.stdout);
    assert!(
        table.contains("ended before its first contact (at 0.286 s)"),
        "{table}"
    );
    assert!(
        stderr(&short).contains("ended before the body first reached the floor or a collider"),
        "{}",
        stderr(&short)
    );
    let records: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let contact = records[0].contact_time_s.unwrap();
    assert!(
        (contact - (2.0 * 0.4 / 9.81f64).sqrt()).abs() < 1e-8,
        "{contact}"
    );

    let long = run(300);
    assert!(long.status.success(), "{}", stderr(&long));
    assert!(!String::from_utf8_lossy(&long.stdout).contains("ended before"));
    assert!(!stderr(&long).contains("warning: volume"));
}

#[test]
fn negative_numbers_are_values() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ball(dir.path());
    let json = dir.path().join("up.json");
    let o = tetrasim(&[
        "run",
        "--method",
        "volume",
        "--quiet",
        "--frames",
        "10",
        "--no-floor",
        "--gravity",
        "-9.81",
        "--mesh",
        &mesh,
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let records: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(records[0].frames_run, 10);
    // The camera takes a comma list that starts with a minus sign (parsed before any GPU
    // work: a bad value is refused naming the camera, a good one is not taken for a flag).
    let o = tetrasim(&["render", "--camera", "-1,0.5,2,0,0.3", "--frames", "1"]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(!err.contains("unexpected argument"), "{err}");
    assert!(err.to_lowercase().contains("camera"), "{err}");
}

#[test]
fn flags_that_would_do_nothing_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ball(dir.path());
    let run = |extra: &[&str]| {
        let mut args = vec!["run", "--quiet", "--frames", "2", "--mesh", &mesh];
        args.extend(extra);
        tetrasim(&args)
    };
    assert_refused(&run(&["--every", "2"]), &["every", "--out-dir"]);
    assert_refused(&run(&["--format", "vtu"]), &["format", "--out-dir"]);
    assert_refused(&run(&["--units", "input"]), &["units", "--out-dir"]);
    assert_refused(
        &run(&["--target-tets", "100"]),
        &["target_tets", "surface", "tet mesh"],
    );
    for gpu_flag in [
        &["--validation"][..],
        &["--atomics", "cas"],
        &["--device", "0"],
        &["--workgroup-size", "64"],
    ] {
        assert_refused(&run(gpu_flag), &["--backend vulkan", "cpu"]);
    }
    // `render --backend cpu` steps on the CPU and draws on the GPU; without an output it
    // still has nothing to write.
    assert_refused(
        &tetrasim(&[
            "render",
            "--backend",
            "cpu",
            "--frames",
            "1",
            "--mesh",
            &mesh,
        ]),
        &["nothing to write", "--frames-dir", "--sheet"],
    );
    assert_refused(
        &tetrasim(&["render", "--every", "2", "--frames", "1", "--mesh", &mesh]),
        &["every", "--frames-dir"],
    );
    assert_refused(
        &tetrasim(&["plan", "--out-dir", "x", "--mesh", &mesh]),
        &["out-dir", "plan"],
    );
    assert_refused(
        &tetrasim(&["plan", "--backend", "cpu", "--mesh", &mesh]),
        &["backend", "vulkan"],
    );
    // A scene gives the period of its mesh files itself.
    let scene = dir.path().join("s.toml");
    std::fs::write(
        &scene,
        "[[object]]\nmesh = \"ball\"\nmethod = \"volume\"\n[output]\nevery = 5\n",
    )
    .unwrap();
    assert_refused(
        &tetrasim(&["run", "--scene", scene.to_str().unwrap()]),
        &["output.every", "output.out_dir"],
    );
}

#[test]
fn output_folders_are_made_or_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ball(dir.path());
    let file = dir.path().join("a-file");
    std::fs::write(&file, "x").unwrap();
    let under_file = file.join("run.json");
    // A JSON file whose folder cannot exist: refused before the run (nothing on stdout).
    let o = tetrasim(&[
        "run",
        "--quiet",
        "--frames",
        "400",
        "--method",
        "all",
        "--mesh",
        &mesh,
        "--json",
        under_file.to_str().unwrap(),
    ]);
    assert_refused(&o, &["a-file"]);
    // A JSON path that is a folder.
    assert_refused(
        &tetrasim(&[
            "run",
            "--quiet",
            "--frames",
            "2",
            "--mesh",
            &mesh,
            "--json",
            dir.path().to_str().unwrap(),
        ]),
        &["is a folder"],
    );
    // A mesh folder where a file is.
    assert_refused(
        &tetrasim(&[
            "run",
            "--quiet",
            "--frames",
            "2",
            "--mesh",
            &mesh,
            "--out-dir",
            file.to_str().unwrap(),
        ]),
        &["not a folder"],
    );
    // The report folders of the other subcommands, refused before they mesh or sweep.
    for sub in ["tradeoff", "stability"] {
        assert_refused(
            &tetrasim(&[sub, "--mesh", &mesh, "--out-dir", file.to_str().unwrap()]),
            &["not a folder"],
        );
    }
    // Nested folders are made.
    let nested = dir.path().join("x/y/z");
    let o = tetrasim(&[
        "run",
        "--quiet",
        "--frames",
        "2",
        "--method",
        "volume",
        "--mesh",
        &mesh,
        "--out-dir",
        nested.to_str().unwrap(),
        "--every",
        "1",
        "--format",
        "vtu",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for name in ["volume_00000.vtu", "volume_00002.vtu", "volume.pvd"] {
        assert!(nested.join(name).is_file(), "{name}");
    }
}

#[test]
fn frames_beyond_the_disk_are_refused_before_any_output() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = ball(dir.path());
    let out = dir.path().join("frames");
    let json = dir.path().join("run.json");
    // Four billion frame files of a few kB each: terabytes, more than any test machine has.
    let o = tetrasim(&[
        "run",
        "--quiet",
        "--method",
        "volume",
        "--frames",
        "4000000000",
        "--every",
        "1",
        "--mesh",
        &mesh,
        "--out-dir",
        out.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_refused(
        &o,
        &["the run would write about", "4000000001 files of", "free"],
    );
    assert!(!out.exists() && !json.exists(), "a refused run made output");
}
