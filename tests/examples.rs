//! The programs under `examples/` run and do what they print: a dropped ball comes to rest
//! on the floor with its volume kept, a pulled bar stretches. `cargo test` builds the
//! examples next to this test (`target/<profile>/examples/`); the test runs those binaries.

use std::path::PathBuf;
use std::process::Command;

/// The binary of example `name`, built by the same `cargo test` as this test.
fn example(name: &str) -> PathBuf {
    // This test is target/<profile>/deps/examples-HASH; the examples are in
    // target/<profile>/examples/.
    let exe = std::env::current_exe().expect("the test's own path");
    let profile_dir = exe
        .parent()
        .and_then(|deps| deps.parent())
        .expect("the test binary lies in target/<profile>/deps");
    let path = profile_dir
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(
        path.is_file(),
        "example binary {} is missing: `cargo test` builds the examples, but a filtered run \
         (`cargo test --test examples`) does not; run `cargo build --examples` (same profile) \
         first, or plain `cargo test`",
        path.display()
    );
    path
}

/// Runs example `name` with `args`; its stdout, after checking that it exited with 0.
fn run(name: &str, args: &[&str]) -> String {
    let out = Command::new(example(name))
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("running example {name}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "example {name} {args:?} failed ({}):\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// The number after `prefix` on the line that starts with it.
fn number_after(stdout: &str, prefix: &str) -> f64 {
    stdout
        .lines()
        .find_map(|l| l.strip_prefix(prefix))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.trim_end_matches(',').parse().ok())
        .unwrap_or_else(|| panic!("no number after `{prefix}` in:\n{stdout}"))
}

#[test]
fn drop_comes_to_rest_on_the_floor() {
    let out = run("drop", &["cpu", "1000"]);
    let lowest = number_after(&out, "final lowest ");
    assert!(lowest.abs() < 1e-3, "lowest node {lowest} m:\n{out}");
    let ratio = number_after(&out, "final volume ratio ");
    assert!((ratio - 1.0).abs() < 0.01, "volume ratio {ratio}:\n{out}");
    let settled = number_after(&out, "final frames on the floor ");
    assert!(
        settled >= 300.0,
        "{settled} frames on the floor at the end:\n{out}"
    );
    // One progress line every 50 frames.
    assert_eq!(out.lines().filter(|l| l.starts_with("frame ")).count(), 20);
    assert!(out.contains("ok: came to rest on the floor"), "{out}");
}

#[test]
fn pull_stretches_the_bar() {
    let out = run("pull", &["cpu", "400"]);
    let stretch = number_after(&out, "final stretch ");
    // The handle moved 3 cm along a 0.4 m bar: the far face follows most of the way.
    assert!(
        stretch > 3.0 && stretch < 8.0,
        "stretch {stretch} %:\n{out}"
    );
    assert!(out.contains("ok: the bar stretched"), "{out}");
}

#[test]
fn grasp_lifts_the_block_and_lets_go() {
    for backend in ["cpu", "cpu-ref"] {
        let out = run("grasp", &[backend, "500"]);
        let peak = number_after(&out, "peak ");
        let last = number_after(&out, "final ");
        // The grab lifts its nodes 100 mm and lets go at 0.3 s; the block sinks back.
        assert!(
            peak > 99.0 && last < 20.0,
            "{backend}: peak {peak} mm, final {last} mm:\n{out}"
        );
        assert!(out.contains("ok: the block was lifted"), "{out}");
    }
}
