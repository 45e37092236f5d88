//! Compiles TetGen 1.5 and our shim with `cc`.
//!
//! The sources are the copy in `tetgen/` next to this file (TetGen 1.5 as shipped in the
//! `tritet` 3.4.0 crate's `c_code`, AGPL-3.0; see `tetgen/README.md`), so the build needs no
//! download and no knowledge of where cargo keeps registry sources (which differs with
//! `cargo vendor`, source replacement and mirrors). `$TETGEN_SRC_DIR`, when set, names another
//! directory holding `tetgen.cxx`, `tetgen.h` and `predicates.cxx` to compile instead.

use std::env;
use std::path::{Path, PathBuf};

const NEEDED: [&str; 3] = ["tetgen.cxx", "tetgen.h", "predicates.cxx"];

fn has_sources(dir: &Path) -> bool {
    NEEDED.iter().all(|f| dir.join(f).is_file())
}

fn find_sources(bundled: &Path) -> Result<PathBuf, String> {
    println!("cargo:rerun-if-env-changed=TETGEN_SRC_DIR");
    let (dir, what) = match env::var_os("TETGEN_SRC_DIR") {
        Some(dir) => (PathBuf::from(dir), "TETGEN_SRC_DIR="),
        None => (bundled.to_path_buf(), "the bundled copy "),
    };
    if has_sources(&dir) {
        Ok(dir)
    } else {
        Err(format!(
            "{what}{} does not contain {}",
            dir.display(),
            NEEDED.join(", ")
        ))
    }
}

fn main() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let bundled = manifest.join("tetgen");
    let src = match find_sources(&bundled) {
        Ok(dir) => dir,
        Err(message) => {
            eprintln!("error: tetgen-sys: {message}");
            panic!("tetgen-sys: {message}");
        }
    };
    for f in NEEDED {
        println!("cargo:rerun-if-changed={}", src.join(f).display());
    }
    println!("cargo:rerun-if-changed=tetgen/auxiliary.h");
    println!("cargo:rerun-if-changed=shim/shim.cpp");
    println!("cargo:rerun-if-changed=shim/tetgen_unit.cpp");

    // Exact predicates and TetGen's robustness rely on IEEE arithmetic without fused
    // multiply-add contraction (GCC contracts by default on some targets).
    let mut build = cc::Build::new();
    build
        .cpp(true)
        .include(&src)
        // `auxiliary.h` (tritet's small helper that its tetgen.cxx includes) when the
        // override directory lacks it.
        .include(&bundled)
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
