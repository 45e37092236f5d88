//! A Python with meshio, the independent reader the format tests check our files with:
//! `$TETRASIM_PYTHON` (`scripts/test.sh` points it at the venv `scripts/setup.sh` makes in
//! `target/py`), else `python3`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The Python to use, or `None` after reporting the skip (which fails under `CI=true`) when
/// it cannot import meshio and numpy.
pub fn python_with_meshio() -> Option<PathBuf> {
    let python = std::env::var_os("TETRASIM_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("python3"));
    let ok = Command::new(&python)
        .args(["-c", "import meshio, numpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        Some(python)
    } else {
        super::skip::skipped(&format!(
            "`{}` cannot import meshio (set TETRASIM_PYTHON to a Python with meshio 5.3.5; \
             scripts/setup.sh makes target/py)",
            python.display()
        ));
        None
    }
}

/// Runs `script` with `args` and returns what it printed, failing the test with Python's
/// stderr if it fails.
pub fn run(python: &Path, script: &str, args: &[&Path]) -> String {
    let out = Command::new(python)
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "python failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}
