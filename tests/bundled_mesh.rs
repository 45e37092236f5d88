//! The default mesh is compiled into the binary: a copy of `tetrasim` run from an empty
//! folder, away from the source tree, still finds `meshes/sphere` (and `meshes/box`).

use std::process::Command;

#[test]
fn installed_binary_runs_the_bundled_meshes_from_anywhere() {
    let dir = tempfile::tempdir().unwrap();
    let bin = dir.path().join("tetrasim");
    std::fs::copy(env!("CARGO_BIN_EXE_tetrasim"), &bin).unwrap();
    let cwd = dir.path().join("elsewhere");
    std::fs::create_dir(&cwd).unwrap();
    for mesh in [None, Some("meshes/box")] {
        let mut cmd = Command::new(&bin);
        cmd.current_dir(&cwd).args([
            "run",
            "--frames",
            "2",
            "--method",
            "volume",
            "--backend",
            "cpu",
        ]);
        if let Some(m) = mesh {
            cmd.args(["--mesh", m]);
        }
        let out = cmd.output().unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{mesh:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            stdout.lines().any(|l| l.starts_with("volume")),
            "{mesh:?}: no table row in\n{stdout}"
        );
    }
}
