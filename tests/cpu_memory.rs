//! The CPU backends against the machine's memory (issue 54, "limits, said before they
//! bite"): `tetrasim run --backend cpu` or `cpu-ref` refuses a problem whose memory need
//! ([`tetrasim::backend::cpu::memory::needs`]) exceeds what the machine offers (or the
//! `--device-memory` limit) before it writes anything, and that need is an upper bound on
//! what a run really takes: each run's peak resident memory, read from the kernel
//! (`getrusage(RUSAGE_CHILDREN)`), stays below it and above a third of it. A run whose
//! record would outgrow the machine is refused too, on any backend.
#![cfg(target_os = "linux")]

use std::path::Path;
use std::process::Command;

use tetrasim::mesh::grid::box_tets;
use tetrasim::mesh::io::tetgen::write_tetgen;

/// `tetrasim run` of `mesh` (quiet), then `args`.
fn run(mesh: &Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args(["run", "--quiet", "--mesh"])
        .arg(mesh)
        .args(args)
        .output()
        .unwrap()
}

/// The largest peak resident memory of the children waited for so far [bytes].
fn children_peak() -> u64 {
    // SAFETY: `usage` is a valid out-parameter for getrusage.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: RUSAGE_CHILDREN with a valid pointer.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) };
    assert_eq!(rc, 0, "getrusage failed");
    usage.ru_maxrss as u64 * 1024
}

#[test]
fn a_problem_larger_than_the_memory_limit_is_refused_before_any_output() {
    let sphere = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    let dir = tempfile::tempdir().unwrap();
    let (json, frames) = (dir.path().join("run.json"), dir.path().join("frames"));
    for backend in ["cpu", "cpu-ref"] {
        // Two frames on `backend` with at most `limit` MiB, then `more`.
        let limited = |limit: &str, more: &[&str]| {
            let mut args = vec![
                "--backend",
                backend,
                "--frames",
                "2",
                "--device-memory",
                limit,
            ];
            args.extend(more);
            run(&sphere, &args)
        };
        let outputs = [
            "--json",
            json.to_str().unwrap(),
            "--out-dir",
            frames.to_str().unwrap(),
        ];
        let out = limited("1", &outputs);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        // 16 MiB + 1 KiB for each of the sphere's 2857 tets.
        let expected = format!(
            "the {backend} backend needs up to 18.79 MiB of memory for this problem (2857 tets), \
             the machine offers 1.00 MiB (the --device-memory limit)"
        );
        assert!(stderr.contains(&expected), "{stderr}");
        assert!(!json.exists() && !frames.exists(), "{backend} wrote output");
        // The limit the need names lets the run go.
        let out = limited("18.8", &[]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn the_need_bounds_the_peak_memory_of_every_method_on_both_backends() {
    // A box of 30 x 30 x 24 cubes, 129,600 tets, resting on the floor from the start (so
    // contact is in the peak), 3 frames.
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("box");
    let mesh = box_tets(glam::DVec3::ZERO, 0.01, [30, 30, 24]);
    write_tetgen(&prefix, &mesh).unwrap();
    let tets = mesh.tets.len() as u64;
    let need = (16 << 20) + 1024 * tets;
    let methods = ["mss", "distance", "volume", "neo-hookean"];
    for backend in ["cpu", "cpu-ref"] {
        for method in methods {
            let out = run(
                &prefix,
                &[
                    "--backend",
                    backend,
                    "--method",
                    method,
                    "--frames",
                    "3",
                    "--drop-height",
                    "0",
                    "--youngs-modulus",
                    "1e6",
                    "--poisson-ratio",
                    "0.45",
                    "--density",
                    "1000",
                ],
            );
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            // The running maximum over the children: each run is checked as it ends, and the
            // lower bound is met by the largest so far.
            let peak = children_peak();
            let mib = |b: u64| b as f64 / (1 << 20) as f64;
            println!(
                "{backend} {method}: peak so far {:.1} MiB, need {:.1} MiB",
                mib(peak),
                mib(need)
            );
            assert!(
                peak <= need,
                "{backend} {method} took {:.1} MiB at its peak, above the {:.1} MiB its need \
                 says",
                mib(peak),
                mib(need)
            );
        }
    }
    let peak = children_peak();
    assert!(
        3 * peak >= need,
        "the need ({need} bytes) is over three times the largest peak ({peak} bytes)"
    );
}

#[test]
fn a_record_larger_than_the_machine_is_refused_not_aborted() {
    // Four billion frames: each frame's entries in the record's series (28 bytes of
    // volume figures and more) outgrow any machine. Before the check the record reserved
    // them all at once and the process aborted on the allocation (status 134).
    let sphere = Path::new(env!("CARGO_MANIFEST_DIR")).join("meshes/sphere");
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("run.json");
    let out = run(
        &sphere,
        &[
            "--method",
            "volume",
            "--frames",
            "4000000000",
            "--json",
            json.to_str().unwrap(),
        ],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("the records of a run of 4000000000 frames (1 method) need up to")
            && stderr.contains("run fewer frames"),
        "{stderr}"
    );
    assert!(!json.exists());
}
