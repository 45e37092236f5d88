//! The stable-step estimate brackets the measured edge for springs, and `tetrasim
//! stability` writes its maps and tables, implicit springs included (stable on the whole
//! map, where explicit ones blow up).

mod common;

use std::process::Command;

use common::box_mesh;
use tetrasim::mesh::io::write_tetgen;
use tetrasim::params::{Method, SimParams};
use tetrasim::ModelBuilder;
use tetrasim_cli::runner::{run, RunOptions};

#[test]
fn springs_are_stable_below_the_estimate_and_diverge_well_above_it() {
    let model = ModelBuilder::new(&box_mesh([3, 3, 3])).build().unwrap();
    for ks in [5e3, 5e4, 5e5] {
        let base = SimParams {
            method: Method::Mss,
            ks,
            ..SimParams::default()
        };
        let estimate = tetrasim::stability::estimate(&model, &base).dt_max;
        for (factor, diverges) in [(0.9, false), (4.0, true)] {
            let dt = factor * estimate;
            let options = RunOptions {
                backend: "cpu-ref".into(),
                frames: 300,
                mesh_label: "box".into(),
                progress: false,
                output: None,
                gpu: Default::default(),
                checkpoint: Default::default(),
            };
            let r = run(&model, &SimParams { dt, ..base.clone() }, &options).unwrap();
            assert_eq!(
                r.diverged, diverges,
                "ks {ks}: dt {dt:e} = {factor} x estimate {estimate:e}: {:?}",
                r.divergence
            );
        }
    }
}

#[test]
fn stability_command_writes_maps_csv_json_and_the_edge() {
    let dir = tempfile::tempdir().unwrap();
    let prefix = dir.path().join("box");
    write_tetgen(&prefix, &box_mesh([2, 2, 2])).unwrap();
    let out = dir.path().join("maps");
    let output = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
        .args(["stability", "--quick", "--mesh"])
        .arg(&prefix)
        .arg("--out-dir")
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    for method in [
        "mss",
        "distance",
        "volume",
        "mss-implicit",
        "volume-implicit",
    ] {
        let png = std::fs::read(out.join(format!("stability_{method}.png"))).unwrap();
        assert_eq!(&png[1..4], b"PNG", "{method}");
        assert!(stdout.contains(&format!("{method}: max |volume - 100| %")));
    }
    let csv = std::fs::read_to_string(out.join("stability.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 5 * 5 * 4);
    let json: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(out.join("stability.json")).unwrap())
            .unwrap();
    assert_eq!(json.len(), 100);
    let find = |method: &str, dt: f64, ks: f64| {
        json.iter()
            .find(|c| c["method"] == method && c["dt"] == dt && c["ks"] == ks)
            .unwrap()
    };
    // Stiff springs at a large step blow up; soft ones at a small step do not.
    assert_eq!(find("mss", 1e-2, 5e5)["diverged"], true);
    assert_eq!(find("mss", 1e-4, 500.0)["diverged"], false);
    // Implicit springs do not, anywhere on the map, and have no explicit step bound.
    for c in json.iter().filter(|c| c["method"] == "mss-implicit") {
        assert_eq!(c["diverged"], false, "{c}");
    }
    assert_eq!(
        find("mss-implicit", 1e-2, 5e5)["dt_estimate"],
        serde_json::Value::Null
    );
    // The volume constraint keeps the volume within 1 % at the paper's step.
    let v = find("volume", 1e-3, 5000.0);
    assert_eq!(v["diverged"], false);
    assert!(v["max_volume_error_pct"].as_f64().unwrap() < 1.0, "{v}");
    assert!(
        stdout.contains("largest stable dt at ks 5000 N/m"),
        "{stdout}"
    );
}
