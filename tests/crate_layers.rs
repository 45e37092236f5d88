//! The crates are layered by audience (ARCHITECTURE.md): a program that embeds the engine
//! compiles the engine and the mesh library, and nothing of the application. Checked on the
//! dependency tree Cargo resolves (`cargo tree`, offline, from the lock file), so a new
//! dependency in the wrong crate fails here, naming the crate and the path to it.

use std::path::Path;
use std::process::Command;

/// The crates of the application (command line, plots, images, tables, progress bars,
/// fonts) and TetGen (AGPL): none may reach a program that embeds the engine.
const APPLICATION: [&str; 11] = [
    "clap",
    "plotters",
    "png",
    "gif",
    "csv",
    "toml",
    "indicatif",
    "dejavu",
    "font8x8",
    "tetgen-sys",
    "tetrasim-cli",
];

/// The names of the crates in `package`'s normal dependency tree with `features`.
fn dependencies(package: &str, features: &[&str]) -> Vec<String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut command = Command::new(cargo);
    command
        .current_dir(root)
        .args(["tree", "--offline", "--edges", "normal", "--prefix", "none"])
        .args(["--format", "{p}", "--package", package]);
    if !features.is_empty() {
        command.args(["--features", &features.join(",")]);
    }
    let out = command
        .output()
        .unwrap_or_else(|e| panic!("running cargo tree: {e}"));
    assert!(
        out.status.success(),
        "cargo tree -p {package} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let names: Vec<String> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .map(str::to_string)
        .collect();
    assert!(names.len() > 5, "cargo tree -p {package} listed {names:?}");
    names
}

/// The members of `APPLICATION` that `package` (with `features`) depends on.
fn application_crates_in(package: &str, features: &[&str]) -> Vec<String> {
    let mut found: Vec<String> = dependencies(package, features)
        .into_iter()
        .filter(|name| APPLICATION.contains(&name.as_str()))
        .collect();
    found.sort();
    found.dedup();
    found
}

#[test]
fn the_engine_library_has_no_application_dependency() {
    let deps = dependencies("tetrasim", &[]);
    for needed in ["ash", "gpu-allocator", "glam", "bytemuck", "tetmesh"] {
        assert!(
            deps.iter().any(|d| d == needed),
            "the engine lacks {needed}"
        );
    }
    assert_eq!(application_crates_in("tetrasim", &[]), Vec::<String>::new());
}

#[test]
fn the_mesh_library_has_neither_tetgen_nor_the_engine_by_default() {
    let deps = dependencies("tetmesh", &[]);
    for absent in ["tetgen-sys", "clap", "tetrasim", "ash", "shaderc"] {
        assert!(
            !deps.iter().any(|d| d == absent),
            "tetmesh depends on {absent}"
        );
    }
}

#[test]
fn the_features_bring_what_they_name() {
    // The check above would pass on a tree that lost its dependencies: the features show
    // that `cargo tree` sees them when they are asked for.
    assert_eq!(
        application_crates_in("tetrasim", &["render", "clap"]),
        ["clap", "font8x8", "gif", "png"]
    );
    assert!(dependencies("tetmesh", &["tetgen"])
        .iter()
        .any(|d| d == "tetgen-sys"));
}

#[test]
fn tetprep_builds_without_the_engine() {
    let deps = dependencies("tetprep", &[]);
    for absent in ["tetrasim", "ash", "shaderc", "gpu-allocator"] {
        assert!(
            !deps.iter().any(|d| d == absent),
            "tetprep depends on {absent}"
        );
    }
    assert!(
        deps.iter().any(|d| d == "tetgen-sys"),
        "tetprep meshes with TetGen"
    );
}

/// The scene format is shared by the command line and the Python package: the engine, serde
/// and toml, and no command line unless its `clap` feature asks (then clap alone).
#[test]
fn the_scene_crate_reads_toml_without_the_command_line() {
    assert_eq!(
        application_crates_in("tetrascene", &[]),
        vec!["toml".to_string()]
    );
    assert_eq!(
        application_crates_in("tetrascene", &["clap"]),
        vec!["clap".to_string(), "toml".to_string()]
    );
}

/// The Python package embeds the engine and the scene format, with TetGen (its `prep`) and
/// nothing else of the application: no command line, plots, images or progress bars.
#[test]
fn the_python_package_embeds_the_engine_alone() {
    let deps = dependencies("tetrasim-py", &[]);
    for needed in ["tetrasim", "tetrascene", "pyo3", "numpy"] {
        assert!(
            deps.iter().any(|d| d == needed),
            "the package lacks {needed}"
        );
    }
    assert_eq!(
        application_crates_in("tetrasim-py", &[]),
        vec!["tetgen-sys".to_string(), "toml".to_string()]
    );
}
