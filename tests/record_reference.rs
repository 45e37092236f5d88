//! The run record's reference (docs/reference/records.md) is generated from the code, so it
//! cannot drift: this test reads the fields of `RunRecord` (with `RecordFacts` flattened
//! into it, as serde does) and `PassTime` from their source, with their doc comments and
//! serde attributes, renders the page and compares it with the committed one
//! (`TETRASIM_BLESS=1 cargo test --release --test record_reference` rewrites it); and it
//! checks that every key of real records (a drop, a press by a collider, a clamped block)
//! is on the page.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

#[path = "common/source.rs"]
mod source;
use source::{cell, check_page, fields, source, Field};

/// A Rust type as JSON names it.
fn json_type(ty: &str) -> String {
    let inner = |t: &str, wrap: &str| ty[wrap.len()..ty.len() - 1].trim().to_string() + t;
    match ty {
        "String" => "string".into(),
        "usize" | "u32" => "integer".into(),
        "f64" => "number".into(),
        "bool" => "boolean".into(),
        "SimParams" => "object: the parameters ([parameters.md](parameters.md))".into(),
        "[f64; 3]" => "3 numbers".into(),
        t if t.starts_with("Option<") => json_type(&inner("", "Option<")) + " or null",
        t if t.starts_with("Vec<") => format!("array of {}", json_type(&inner("", "Vec<"))),
        "PassTime" => "{name, ms_per_frame}".into(),
        other => format!("`{other}`"),
    }
}

/// When a field is written: serde's `skip_serializing_if` leaves it out when empty.
fn presence(attributes: &str) -> &'static str {
    match attributes {
        a if a.contains("Option::is_none") => "when set",
        a if a.contains("Vec::is_empty") => "when not empty",
        a if a.contains("Not::not") => "when true",
        _ => "always",
    }
}

/// The record's keys in the order serde writes them, with their fields.
fn record_fields() -> Vec<Field> {
    let metrics = source("crates/tetrasim/src/metrics.rs");
    let mut out = Vec::new();
    for field in fields(&metrics, "RunRecord") {
        if field.attributes.contains("flatten") {
            out.extend(fields(&metrics, &field.ty));
        } else {
            out.push(field);
        }
    }
    out
}

/// The page.
fn page() -> String {
    let mut out = String::from(
        "# Run records\n\n\
         `tetrasim run --json FILE` (and a scene's `output.json`) writes a JSON array with one \
         record per method run; Python's `Simulation.record` is the same object as a dict. \
         Each record's keys, in the order they are written, with their type and when they are \
         there (generated from `RunRecord` in `crates/tetrasim/src/metrics.rs` by \
         `tests/record_reference.rs`, which fails when this page drifts; \
         `TETRASIM_BLESS=1 cargo test --release --test record_reference` rewrites it). \
         Per-frame series hold one entry per completed frame, in order; `time_s` is their \
         time axis.\n\n\
         | key | JSON type | written | meaning |\n| --- | --- | --- | --- |\n",
    );
    for f in record_fields() {
        let written = presence(&f.attributes);
        let mut ty = json_type(&f.ty);
        if written == "when set" {
            // Left out when `None`: never null.
            ty = ty.trim_end_matches(" or null").to_string();
        }
        out.push_str(&format!(
            "| `{}` | {ty} | {written} | {} |\n",
            f.name,
            cell(&f.doc)
        ));
    }
    out.push_str(
        "\nEach entry of `passes`:\n\n| key | JSON type | meaning |\n| --- | --- | --- |\n",
    );
    for f in fields(&source("crates/tetrasim/src/gpu/timing.rs"), "PassTime") {
        out.push_str(&format!(
            "| `{}` | {} | {} |\n",
            f.name,
            json_type(&f.ty),
            cell(&f.doc)
        ));
    }
    out
}

#[test]
fn the_record_reference_is_the_records_fields() {
    check_page("docs/reference/records.md", &page(), "record_reference");
}

#[test]
fn every_key_of_real_records_is_on_the_page() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let documented: BTreeSet<String> = record_fields().into_iter().map(|f| f.name).collect();
    let dir = tempfile::tempdir().unwrap();
    let mut seen = BTreeSet::new();
    let runs: [&[&str]; 3] = [
        &[
            "--mesh",
            "meshes/sphere",
            "--method",
            "volume",
            "--frames",
            "20",
        ],
        &[
            "--scene",
            "examples/scenes/capsule_press.toml",
            "--frames",
            "20",
        ],
        &[
            "--scene",
            "examples/scenes/clamped_block.toml",
            "--frames",
            "20",
        ],
    ];
    for (k, args) in runs.iter().enumerate() {
        let json = dir.path().join(format!("run{k}.json"));
        let out = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
            .current_dir(root)
            .args(["run", "--quiet"])
            .args(*args)
            .arg("--json")
            .arg(&json)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let records: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        for record in records.as_array().unwrap() {
            seen.extend(record.as_object().unwrap().keys().cloned());
        }
    }
    let missing: Vec<&String> = seen.difference(&documented).collect();
    assert!(missing.is_empty(), "keys not on the page: {missing:?}");
    for key in [
        "collider_force",
        "clamp_force",
        "deepest_m",
        "params",
        "groups",
    ] {
        assert!(seen.contains(key), "no run wrote `{key}`: {seen:?}");
    }
}
