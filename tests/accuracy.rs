//! The speed/accuracy dial (`--accuracy`, `[solver] accuracy`): each level's settings
//! reach the run, its header says what it chose, a setting given beside it wins, and on
//! the bundled sphere the local volume error falls from `fast` to `accurate` while the
//! sweeps per frame (the work) rise.

use std::process::Command;

use tetrasim::metrics::RunRecord;

/// `tetrasim run` on the bundled sphere with `args`: its record and its stderr.
fn run(args: &[&str]) -> (RunRecord, String) {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("run.json");
    let output = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args(["run", "--method", "volume", "--quiet", "--json"])
        .arg(&json)
        .args(args)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert!(output.status.success(), "{stderr}");
    let mut records: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    (records.remove(0), stderr)
}

#[test]
fn the_levels_trade_work_for_local_volume_error_on_the_sphere() {
    let mut last: Option<(u32, f64)> = None;
    for level in ["fast", "balanced", "accurate"] {
        let (r, stderr) = run(&["--accuracy", level, "--frames", "300"]);
        assert!(
            stderr.contains(&format!("accuracy {level} (gauss-seidel")),
            "{stderr}"
        );
        let p = &r.params;
        assert!((p.dt * f64::from(p.substeps) - 1e-3).abs() < 1e-15, "{p:?}");
        let sweeps = p.iterations * p.substeps;
        if let Some((fewer, larger)) = last {
            assert!(sweeps > fewer, "{level}: {sweeps} sweeps per frame");
            assert!(
                r.avg_local_error_pct < larger,
                "{level}: {} % local error, the level below {larger} %",
                r.avg_local_error_pct
            );
        }
        last = Some((sweeps, r.avg_local_error_pct));
    }
}

#[test]
fn a_setting_given_beside_the_dial_wins() {
    let (r, stderr) = run(&["--accuracy", "fast", "--iterations", "7", "--frames", "2"]);
    assert_eq!((r.params.iterations, r.params.groups), (7, 4));
    assert!(
        stderr.contains("4 groups + global volume, 7 iterations"),
        "{stderr}"
    );
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/sphere");
    let text =
        format!("[solver]\naccuracy = \"accurate\"\nframes = 2\n[[object]]\nmesh = {mesh:?}\n");
    std::fs::write(&scene, text).unwrap();
    let (r, _) = run(&["--scene", scene.to_str().unwrap()]);
    assert_eq!((r.params.substeps, r.params.dt), (2, 5e-4));
}
