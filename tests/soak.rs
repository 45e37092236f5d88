//! `tetrasim soak` (issue 54, item 4; `scripts/soak.sh` runs the long form): a short soak
//! of the bundled sphere passes on `cpu` and on `vulkan` with its figures on its last line,
//! and fails, naming the energy, where the first edition's per-node averaging gains energy.

mod gpu_support;

use std::process::{Command, Output};

fn soak(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .arg("soak")
        .args(args)
        .output()
        .unwrap()
}

/// The soak's last line, and a figure after `label` on it.
fn figure(line: &str, label: &str) -> f64 {
    let rest = &line[line
        .find(label)
        .unwrap_or_else(|| panic!("no `{label}` in {line}"))
        + label.len()..];
    let number: String = rest
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-' || *c == '+' || *c == 'e')
        .collect();
    number
        .parse()
        .unwrap_or_else(|_| panic!("`{number}` after `{label}` in {line}"))
}

/// The last line of a soak that must pass.
fn passed_line(args: &[&str]) -> String {
    let output = soak(args);
    let line = last_line(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{line}\n{stderr}");
    assert!(line.ends_with("PASS"), "{line}");
    line
}

/// The last line of a soak that must fail (exit 1).
fn failed_line(args: &[&str]) -> String {
    let output = soak(args);
    let line = last_line(&output);
    assert_eq!(output.status.code(), Some(1), "{line}");
    line
}

fn last_line(output: &Output) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout);
    stdout.lines().last().unwrap_or_default().to_string()
}

#[test]
fn a_short_soak_on_cpu_passes_with_its_figures() {
    let line = passed_line(&["--method", "volume", "--frames", "2000", "--samples", "20"]);
    assert_eq!(figure(&line, "cpu volume:"), 2000.0, "{line}");
    assert!(figure(&line, "(+") < 1.0, "{line}");
    assert!(line.contains("no device memory"), "{line}");
    let start = figure(&line, "energy");
    assert!(start > 0.0, "{line}");
    assert!(figure(&line, "J, volume") > 99.9, "{line}");
}

#[test]
fn a_short_soak_on_vulkan_watches_the_device_memory() {
    if !gpu_support::vulkan_available() {
        return;
    }
    let args = [
        "--method",
        "volume",
        "--backend",
        "vulkan",
        "--frames",
        "200",
        "--samples",
        "10",
    ];
    let line = passed_line(&args);
    let device = figure(&line, "device memory");
    assert!(
        device > 0.0,
        "the allocator's report should count the buffers: {line}"
    );
}

#[test]
fn a_soak_fails_where_the_energy_rises() {
    let args = [
        "--method",
        "volume",
        "--combine",
        "average",
        "--frames",
        "400",
        "--samples",
        "20",
    ];
    let line = failed_line(&args);
    assert!(line.contains("FAIL (the energy rose"), "{line}");
    assert!(line.starts_with("soak meshes/sphere cpu volume:"), "{line}");
}

#[test]
fn a_soak_refuses_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("run.json");
    let output = soak(&["--frames", "10", "--json", json.to_str().unwrap()]);
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("invalid parameter `json`"), "{stderr}");
    assert!(!json.exists());
}

#[test]
fn a_soak_that_diverges_ends_and_fails_naming_the_divergence() {
    // Explicit springs at a step 50 times their stable one.
    let args = [
        "--method",
        "mss",
        "--dt",
        "0.05",
        "--frames",
        "400",
        "--samples",
        "20",
    ];
    let line = failed_line(&args);
    assert!(line.contains("FAIL (diverged at frame"), "{line}");
}
