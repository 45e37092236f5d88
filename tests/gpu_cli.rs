//! The GPU bits of the command line: `tetrasim info`, and `run --backend vulkan` with
//! `--device`, `--atomics` and `--validation`, whose JSON gains `device`, `atomics` and
//! `passes` and whose output prints per-pass GPU times.

mod common;
mod gpu_support;

use std::process::Command;

use tetrasim::mesh::io::write_tetgen;
use tetrasim::metrics::RunRecord;

fn tetrasim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tetrasim"))
}

/// A temporary folder holding a ball of `radius` cells as TetGen files, and their prefix.
fn ball_files(radius: f64) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("ball");
    write_tetgen(&prefix, &common::ball_mesh(radius)).unwrap();
    (dir, prefix)
}

#[test]
fn info_lists_limits_and_atomic_paths() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let output = tetrasim().arg("info").output().unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    let devices = tetrasim::gpu::list_devices().unwrap();
    for d in &devices {
        assert!(stdout.contains(&d.name), "no `{}` in\n{stdout}", d.name);
    }
    for needle in [
        "max invocations",
        "timestamps",
        "shaderBufferFloat32AtomicAdd",
        "auto = ",
        "(default for --backend vulkan)",
    ] {
        assert!(stdout.contains(needle), "no `{needle}` in\n{stdout}");
    }
}

#[test]
fn vulkan_run_reports_device_atomics_and_pass_times() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let (dir, prefix) = ball_files(2.5);
    let metrics = dir.path().join("run.json");
    let output = tetrasim()
        .args([
            "run",
            "--backend",
            "vulkan",
            "--device",
            "0",
            "--atomics",
            "cas",
            "--solver",
            "jacobi",
            "--validation",
        ])
        .args([
            "--method",
            "volume",
            "--frames",
            "30",
            "--quiet",
            "--workgroup-size",
            "64",
        ])
        .arg("--mesh")
        .arg(&prefix)
        .arg("--metrics")
        .arg(&metrics)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "stderr: {stderr}");
    assert!(
        !stderr.contains("validation:"),
        "validation messages:\n{stderr}"
    );
    let records: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&metrics).unwrap()).unwrap();
    assert_eq!(records.len(), 1);
    let r = &records[0];
    assert_eq!((r.backend.as_str(), r.frames_run), ("vulkan", 30));
    assert_eq!(r.atomics.as_deref(), Some("cas"));
    let device = r.device.as_deref().unwrap();
    assert_eq!(device, tetrasim::gpu::list_devices().unwrap()[0].name);
    let passes = r.passes.as_ref().unwrap();
    // In execution order: the springs, the volume constraints and their application, then
    // the integration, the divergence check, the volume measure and the forces out.
    let names: Vec<&str> = passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "spring_scatter",
            "volume",
            "constraint_apply",
            "integrate",
            "check",
            "volume_sum",
            "reactions"
        ]
    );
    assert!(passes.iter().all(|p| p.ms_per_frame > 0.0), "{passes:?}");
    assert!(
        r.min_volume_pct > 90.0 && r.avg_volume_pct <= 100.5,
        "{r:?}"
    );
    // The table is followed by one line per pass with its time and share.
    for name in names {
        assert!(
            stdout
                .lines()
                .any(|l| l.trim_start().starts_with(name) && l.ends_with('%')),
            "no `{name}` row in\n{stdout}"
        );
    }
}

#[test]
fn unknown_device_is_a_clear_error() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let (_dir, prefix) = ball_files(1.5);
    let output = tetrasim()
        .args([
            "run",
            "--backend",
            "vulkan",
            "--device",
            "no-such-gpu",
            "--frames",
            "2",
            "--quiet",
        ])
        .arg("--mesh")
        .arg(&prefix)
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("--device no-such-gpu") && stderr.contains("there are:"),
        "{stderr}"
    );
}

#[test]
fn frames_in_flight_change_nothing_but_the_waiting() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let (dir, prefix) = ball_files(2.5);
    let run = |depth: &str| {
        let metrics = dir.path().join(format!("run{depth}.json"));
        let output = tetrasim()
            .args([
                "run",
                "--backend",
                "vulkan",
                "--method",
                "volume",
                "--quiet",
            ])
            .args([
                "--frames",
                "40",
                "--validation",
                "--frames-in-flight",
                depth,
            ])
            .arg("--mesh")
            .arg(&prefix)
            .arg("--metrics")
            .arg(&metrics)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        (output.status.code(), stderr, metrics)
    };
    // The default solver is deterministic: one, two or three frames in flight give the same
    // run to the last bit.
    let mut series = Vec::new();
    for depth in ["1", "2", "3"] {
        let (code, stderr, metrics) = run(depth);
        assert_eq!(code, Some(0), "{stderr}");
        assert!(!stderr.contains("validation:"), "{stderr}");
        let records: Vec<RunRecord> =
            serde_json::from_str(&std::fs::read_to_string(&metrics).unwrap()).unwrap();
        let r = &records[0];
        assert_eq!(r.frames_run, 40);
        series.push((r.volume_pct.clone(), r.local_error_pct.clone()));
    }
    assert_eq!(series[0], series[1]);
    assert_eq!(series[0], series[2]);
    let (code, stderr, _) = run("0");
    assert_eq!(code, Some(1));
    assert!(
        stderr.contains("frames-in-flight") && stderr.contains("must be 1 to 8"),
        "{stderr}"
    );
}

/// The MiB figure after `label` in `text`.
fn mib_after(text: &str, label: &str) -> f64 {
    let at = text
        .find(label)
        .unwrap_or_else(|| panic!("no `{label}` in {text}"));
    let rest = text[at + label.len()..].trim_start();
    let number: String = rest
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    number
        .parse()
        .unwrap_or_else(|_| panic!("no number after `{label}` in {text}"))
}

#[test]
fn a_problem_larger_than_the_device_memory_is_refused_before_any_output() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let (dir, prefix) = ball_files(2.5);
    let (out, metrics) = (dir.path().join("frames"), dir.path().join("run.json"));
    let run = |limit: &str| {
        tetrasim()
            .args([
                "run",
                "--backend",
                "vulkan",
                "--method",
                "volume",
                "--frames",
                "3",
            ])
            .args(["--quiet", "--device-memory", limit, "--mesh"])
            .arg(&prefix)
            .arg("--out-dir")
            .arg(&out)
            .arg("--json")
            .arg(&metrics)
            .output()
            .unwrap()
    };
    // What the plan allocates on the device, in bytes.
    let plan = tetrasim()
        .args(["plan", "--method", "volume", "--mesh"])
        .arg(&prefix)
        .output()
        .unwrap();
    let plan = String::from_utf8_lossy(&plan.stdout).to_string();
    assert!(plan.contains("the plan fits"), "{plan}");
    let planned = mib_after(&plan, "total device memory") / (1024.0 * 1024.0);

    let refused = run("0.05");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("not enough memory: the vulkan backend needs"),
        "{stderr}"
    );
    assert!(
        stderr.contains("offers 0.05 MiB (the --device-memory limit)"),
        "{stderr}"
    );
    let needs = mib_after(&stderr, "needs");
    assert!(
        needs >= planned && needs > 0.05,
        "needs {needs} MiB, planned {planned} MiB"
    );
    assert!(
        !out.exists() && !metrics.exists(),
        "a refused run wrote output"
    );

    // Given what it needs, the same run goes.
    let limit = format!("{:.2}", needs + 0.01);
    let ran = run(&limit);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    assert!(metrics.exists());
}
