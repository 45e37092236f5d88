//! A run ended by SIGTERM (issue 54, "nothing half-written"): `tetrasim run` finishes the
//! frames it has started, writes its record marked `"interrupted": true` with the frames it
//! completed, leaves every frame file whole (each written to a temporary name and renamed)
//! and a checkpoint a later run resumes from, and exits with status 130. Without the signal
//! handler SIGTERM kills the process: no record, status from the signal.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use tetrasim::mesh::io::read_tet_mesh;
use tetrasim::metrics::RunRecord;

/// `tetrasim run` of the bundled sphere, `volume` on `cpu`, for `frames` frames, quiet.
fn run_sphere(frames: u32) -> Command {
    let sphere = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    let mut command = Command::new(env!("CARGO_BIN_EXE_tetrasim"));
    command
        .args([
            "run",
            "--method",
            "volume",
            "--backend",
            "cpu",
            "--quiet",
            "--mesh",
        ])
        .arg(sphere)
        .args(["--frames", &frames.to_string()])
        .stdout(Stdio::null());
    command
}

/// The frame files in `dir`, once there are at least `least` of them (or after 60 s).
fn frames_once(dir: &Path, least: usize) -> Vec<std::path::PathBuf> {
    let started = Instant::now();
    loop {
        let files: Vec<_> = std::fs::read_dir(dir)
            .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        if files.len() >= least || started.elapsed() > Duration::from_secs(60) {
            return files;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn sigterm_ends_a_run_with_its_record_frames_and_checkpoint_whole() {
    let dir = tempfile::tempdir().unwrap();
    let (json, frames, checkpoint) = (
        dir.path().join("run.json"),
        dir.path().join("frames"),
        dir.path().join("run.ckpt"),
    );
    let total = 1_000_000;
    let child = run_sphere(total)
        .args(["--format", "vtk", "--every", "5", "--json"])
        .arg(&json)
        .arg("--out-dir")
        .arg(&frames)
        .arg("--checkpoint")
        .arg(&checkpoint)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Some frames written, and the run still going: the signal comes mid-run.
    assert!(frames_once(&frames, 4).len() >= 4, "no frames after 60 s");
    let pid = libc::pid_t::try_from(child.id()).unwrap();
    // SAFETY: kill(2) with a child's pid and a valid signal touches no memory of ours.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGTERM) }, 0);
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.contains("interrupted: volume ended after frame"),
        "{stderr}"
    );

    let records: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let record = &records[0];
    assert!(record.interrupted && !record.diverged);
    assert!(
        record.frames_run >= 15 && record.frames_run < total,
        "{}",
        record.frames_run
    );
    assert_eq!(record.volume_pct.len(), record.frames_run as usize);
    assert!(record.min_volume_pct > 99.0);

    // Every frame file is a whole mesh; no temporary file is left.
    let files = frames_once(&frames, 0);
    assert!(
        files.len() as u32 >= record.frames_run / 5,
        "{} files",
        files.len()
    );
    for file in &files {
        assert_eq!(
            file.extension().and_then(|e| e.to_str()),
            Some("vtk"),
            "{file:?}"
        );
        let mesh = read_tet_mesh(file).unwrap_or_else(|e| panic!("{file:?}: {e}"));
        assert_eq!((mesh.nodes.len(), mesh.tets.len()), (823, 2857), "{file:?}");
    }

    // The checkpoint is at the frame the run ended on, and a later run resumes from it.
    let resumed = dir.path().join("resumed.json");
    let more = record.frames_run + 10;
    let status = run_sphere(more)
        .arg("--resume")
        .arg(&checkpoint)
        .arg("--json")
        .arg(&resumed)
        .status()
        .unwrap();
    assert!(status.success());
    let resumed: Vec<RunRecord> =
        serde_json::from_str(&std::fs::read_to_string(&resumed).unwrap()).unwrap();
    assert!(!resumed[0].interrupted);
    assert_eq!(resumed[0].volume_pct.len(), more as usize);
    assert_eq!(
        resumed[0].volume_pct[..record.frames_run as usize],
        record.volume_pct[..]
    );
}
