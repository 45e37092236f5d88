//! Compiles TetGen 1.5 (sources from the `tritet` registry crate) and our shim with `cc`.
//!
//! The sources are found in `$TETGEN_SRC_DIR` when set, else in
//! `$CARGO_HOME/registry/src/*/tritet-3.4.0/c_code` (CARGO_HOME defaults to `~/.cargo`).

use std::env;
use std::path::{Path, PathBuf};

const TRITET_DIR: &str = "tritet-3.4.0";
const NEEDED: [&str; 3] = ["tetgen.cxx", "tetgen.h", "predicates.cxx"];

fn has_sources(dir: &Path) -> bool {
    NEEDED.iter().all(|f| dir.join(f).is_file())
}

fn cargo_home() -> Option<PathBuf> {
    if let Some(home) = env::var_os("CARGO_HOME") {
        return Some(PathBuf::from(home));
    }
    env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo"))
}

fn find_sources() -> Result<PathBuf, String> {
    println!("cargo:rerun-if-env-changed=TETGEN_SRC_DIR");
    println!("cargo:rerun-if-env-changed=CARGO_HOME");
    if let Some(dir) = env::var_os("TETGEN_SRC_DIR") {
        let dir = PathBuf::from(dir);
        return if has_sources(&dir) {
            Ok(dir)
        } else {
            Err(format!(
                "TETGEN_SRC_DIR={} does not contain {}",
                dir.display(),
                NEEDED.join(", ")
            ))
        };
    }
    let home = cargo_home().ok_or("neither CARGO_HOME nor HOME is set")?;
    let registry = home.join("registry").join("src");
    let mut searched = Vec::new();
    if let Ok(entries) = std::fs::read_dir(&registry) {
        for entry in entries.flatten() {
            let dir = entry.path().join(TRITET_DIR).join("c_code");
            if has_sources(&dir) {
                return Ok(dir);
            }
            searched.push(dir.display().to_string());
        }
    }
    Err(format!(
        "TetGen sources not found: looked for {TRITET_DIR}/c_code under {} (searched: [{}]). \
         Run `cargo fetch` (the `tritet` build-dependency brings them) or set TETGEN_SRC_DIR \
         to a directory holding {}",
        registry.display(),
        searched.join(", "),
        NEEDED.join(", ")
    ))
}

fn main() {
    let src = match find_sources() {
        Ok(dir) => dir,
        Err(message) => {
            eprintln!("error: tetgen-sys: {message}");
            panic!("tetgen-sys: {message}");
        }
    };
    for f in NEEDED {
        println!("cargo:rerun-if-changed={}", src.join(f).display());
    }
    println!("cargo:rerun-if-changed=shim/shim.cpp");
    println!("cargo:rerun-if-changed=shim/tetgen_unit.cpp");

    // Exact predicates and TetGen's robustness rely on IEEE arithmetic without fused
    // multiply-add contraction (GCC contracts by default on some targets).
    let mut build = cc::Build::new();
    build
        .cpp(true)
        .include(&src)
        .file("shim/tetgen_unit.cpp")
        .file(src.join("predicates.cxx"))
        .file("shim/shim.cpp")
        .flag_if_supported("-ffp-contract=off")
        .flag_if_supported("-w")
        .warnings(false);
    // TetGen at -O0/-O1 is several times slower; meshing the scans in tests needs -O2.
    if env::var("OPT_LEVEL")
        .map(|o| o == "0" || o == "1")
        .unwrap_or(true)
    {
        build.opt_level(2);
    }
    build.compile("tetgen_shim");
}
