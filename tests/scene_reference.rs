//! The scene format's reference (docs/reference/scene.md) is generated from the code, so it
//! cannot drift: the annotated scene in `crates/tetrascene/src/scene.rs`'s module doc, then
//! every table's keys from the structs and enums serde reads them with (their doc comments,
//! renames and defaults), compared with the committed page
//! (`TETRASIM_BLESS=1 cargo test --release --test scene_reference` rewrites it); and the
//! annotated scene must parse, so the example on the page is a valid scene.

#[path = "common/source.rs"]
mod source;
use source::{cell, check_page, fields, source, variants, Field};

/// A Rust type as TOML names it.
fn toml_type(ty: &str) -> String {
    match ty {
        "PathBuf" => "string (a path, relative to the scene file)".into(),
        "f64" => "float".into(),
        "u32" | "usize" => "integer".into(),
        "bool" => "boolean".into(),
        "[f64; 3]" => "array of 3 floats".into(),
        "[f64; 4]" => "array of 4 floats `[w, x, y, z]`".into(),
        "Method" => "string: a method (`mss`, `distance`, `volume`, `neo-hookean`)".into(),
        "MaterialOverrides" => "table (below)".into(),
        "Pins" => "table, or array of tables (below)".into(),
        "MotionSpec" => "table (below)".into(),
        "Aabb" => "table `{ min, max }`".into(),
        "Vec<KeyframeSpec>" => "array of tables (below)".into(),
        "Vec<u32>" => "array of integers".into(),
        "tetrasim::output::OutputFormat" => "string: `ply`, `obj`, `vtk`, `vtu` or `usd`".into(),
        "tetrasim::output::OutputUnits" => "string: `simulation` or `input`".into(),
        t if t.starts_with("Option<") => toml_type(&t[7..t.len() - 1]),
        other => format!("`{other}`"),
    }
}

/// A table of `fields`: key, type, required, meaning.
fn table(fields: &[Field]) -> String {
    let mut out = String::from("| key | type | | meaning |\n| --- | --- | --- | --- |\n");
    for f in fields
        .iter()
        .filter(|f| !f.attributes.contains("serde(skip)"))
    {
        let needed = if f.optional() { "optional" } else { "required" };
        out.push_str(&format!(
            "| `{}` | {} | {needed} | {} |\n",
            f.key(),
            toml_type(&f.ty),
            cell(&f.doc)
        ));
    }
    out
}

/// The `toml` block of `scene.rs`'s module doc.
fn annotated_scene() -> String {
    let scene = source("crates/tetrascene/src/scene.rs");
    let doc: Vec<&str> = scene
        .lines()
        .filter_map(|l| l.strip_prefix("//!"))
        .map(|l| l.strip_prefix(' ').unwrap_or(l))
        .collect();
    let start = doc.iter().position(|l| *l == "```toml").unwrap() + 1;
    let end = start + doc[start..].iter().position(|l| *l == "```").unwrap();
    doc[start..end].join("\n") + "\n"
}

/// The page.
fn page() -> String {
    let scene = source("crates/tetrascene/src/scene.rs");
    let colliders = source("crates/tetrascene/src/scene/collider.rs");
    let mut out = String::from(
        "# Scene files\n\n\
         A scene is a TOML file that `tetrasim run --scene FILE` runs and \
         `tetrasim.Simulation.from_scene(path)` loads: the objects, the colliders and \
         handles, the solver's settings and the outputs. Paths are relative to the scene \
         file. A key the format does not know, or a value out of range, is refused naming \
         its path (`object[0].material.ks`, `collider[2].motion.keyframes[1].t`; colliders \
         count in file order, the floor included); a key renamed on 2026-12-06 is still \
         read, with a warning naming the new one. Generated from the code by \
         `tests/scene_reference.rs`, which fails when this page drifts \
         (`TETRASIM_BLESS=1 cargo test --release --test scene_reference` rewrites it) and \
         parses the scene below. The guide's [first scene](../guide/first-scene.md) and \
         [contact](../guide/contact.md) pages show scenes at work.\n\n\
         ## Every key in one file\n\n```toml\n",
    );
    out.push_str(&annotated_scene());
    out.push_str(
        "```\n\n## `[solver]`\n\nThe run's parameters, each under its one name: \
        [parameters.md](parameters.md) gives every key with its flag, Python keyword, \
        default and unit (the column \"scene key\").\n\n## `[[object]]`\n\n",
    );
    out.push_str(&table(&fields(&scene, "Object")));
    out.push_str("\n### `material`\n\n");
    out.push_str(&table(&fields(
        &source("crates/tetrascene/src/overrides.rs"),
        "MaterialOverrides",
    )));
    out.push_str(
        "\n### `pin`\n\nOne table, or a list of them (`pin = [{ .. }, { .. }]` or \
         `[[object.pin]]` tables), each fixed or with its own motion.\n\n",
    );
    let pins = source("crates/tetrascene/src/scene/pin.rs");
    out.push_str(&table(&fields(&pins, "Pin")));
    out.push_str("\n`box`:\n\n");
    out.push_str(&table(&fields(&pins, "Aabb")));
    out.push_str("\n## `[[collider]]`\n\n`type` picks the shape; each shape's keys:\n");
    for (variant, keys) in variants(&colliders, "Collider") {
        let name = match variant.attributes.contains("rename = \"") {
            true => variant.key(),
            false => variant.name.to_lowercase(),
        };
        out.push_str(&format!(
            "\n### `type = \"{name}\"`\n\n{}\n\n",
            cell(&variant.doc)
        ));
        out.push_str(&table(&keys));
    }
    out.push_str(
        "\n### `motion`\n\nOf a collider, a moving pin or a grab: a velocity and an \
        angular velocity, or keyframes, not both.\n\n",
    );
    out.push_str(&table(&fields(&colliders, "MotionSpec")));
    out.push_str("\nEach keyframe:\n\n");
    out.push_str(&table(&fields(&colliders, "KeyframeSpec")));
    out.push_str("\n## `[[grab]]`\n\n");
    out.push_str(&table(&fields(
        &source("crates/tetrascene/src/scene/grab.rs"),
        "GrabSpec",
    )));
    out.push_str("\n## `[output]`\n\n");
    out.push_str(&table(&fields(&scene, "Output")));
    out
}

#[test]
fn the_scene_reference_is_the_formats_code() {
    let generated = page();
    check_page("docs/reference/scene.md", &generated, "scene_reference");
    for key in [
        "`fit_size`",
        "`half_extents`",
        "`keyframes`",
        "`release`",
        "`out_dir`",
    ] {
        assert!(generated.contains(key), "{key} is not on the page");
    }
}

#[test]
fn the_annotated_scene_parses() {
    let parsed = tetrascene::scene::Scene::parse(&annotated_scene());
    assert!(parsed.is_ok(), "{:?}", parsed.err());
    let scene = parsed.unwrap();
    assert_eq!(scene.colliders.len(), 6);
    assert_eq!(scene.grabs.len(), 1);
}
