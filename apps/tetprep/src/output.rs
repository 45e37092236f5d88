//! Where `tetprep` writes: the `-o` prefix (a known tet-mesh extension is dropped, so
//! `-o bunny.node` and `-o bunny.vtk` both mean `bunny`) and the output folders, made before
//! any work starts and removed again if the run fails.

use std::path::{Component, Path, PathBuf};

use tetmesh::{Error, Result};

/// Extensions `-o` drops (case-insensitive): TetGen's files and other tet-mesh formats.
pub const TET_EXTENSIONS: [&str; 7] = ["node", "ele", "face", "vtk", "vtu", "msh", "mesh"];

/// The output prefix for `-o PATH`: `PATH` without a known tet-mesh extension. A path that
/// names a folder (empty, ending in `/`, `.` or `..`) is refused: the files need a name.
pub fn output_prefix(path: &Path) -> Result<PathBuf> {
    let text = path.to_string_lossy();
    let names_folder = text.is_empty()
        || text.ends_with(std::path::MAIN_SEPARATOR)
        || text.ends_with('/')
        || text.ends_with("/.")
        || matches!(
            path.components().next_back(),
            None | Some(Component::CurDir | Component::ParentDir | Component::RootDir)
        );
    if names_folder {
        return Err(Error::param(
            "output",
            format!(
                "`{text}` names a folder; -o takes a file prefix such as `{}mesh` (writes mesh.node, mesh.ele, mesh.face)",
                if text.is_empty() || text.ends_with('/') {
                    text.to_string()
                } else {
                    format!("{text}/")
                }
            ),
        ));
    }
    let known = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .is_some_and(|e| TET_EXTENSIONS.contains(&e.as_str()));
    Ok(if known {
        path.with_extension("")
    } else {
        path.to_path_buf()
    })
}

/// `prefix` + `.ext`, appended (`a.b` gives `a.b.vtk`).
pub fn with_ext(prefix: &Path, ext: &str) -> PathBuf {
    let mut s = prefix.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Folders made for the outputs, to be removed again (when still empty) if the run fails.
#[derive(Debug, Default)]
pub struct MadeFolders(Vec<PathBuf>);

impl MadeFolders {
    /// Makes the folder that `file` goes in, with any missing parents, and remembers the ones
    /// it made. A parent that exists as a file is refused, naming it and `option`.
    pub fn make_parent_of(&mut self, file: &Path, option: &str) -> Result<()> {
        let Some(dir) = file.parent().filter(|d| !d.as_os_str().is_empty()) else {
            return Ok(());
        };
        let mut missing = Vec::new();
        let mut at = Some(dir);
        while let Some(d) = at.filter(|d| !d.as_os_str().is_empty()) {
            match std::fs::metadata(d) {
                Ok(m) if m.is_dir() => break,
                Ok(_) => {
                    return Err(Error::param(
                        option,
                        format!(
                            "cannot write {}: {} is a file, not a folder",
                            file.display(),
                            d.display()
                        ),
                    ))
                }
                // Not found, or under a file ("not a directory"): the walk up finds out which;
                // anything else shows when making the folder.
                Err(_) => missing.push(d),
            }
            at = d.parent();
        }
        for d in missing.into_iter().rev() {
            match std::fs::create_dir(d) {
                Ok(()) => self.0.push(d.to_path_buf()),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && d.is_dir() => {}
                Err(e) => {
                    return Err(Error::param(
                        option,
                        format!("cannot make the folder {}: {e}", d.display()),
                    ))
                }
            }
        }
        Ok(())
    }

    /// The folders made, outermost first.
    pub fn made(&self) -> &[PathBuf] {
        &self.0
    }

    /// Removes the folders made, innermost first, where they are still empty.
    pub fn remove_empty(&mut self) {
        for d in self.0.drain(..).rev() {
            let _ = std::fs::remove_dir(d);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prefix(s: &str) -> String {
        output_prefix(Path::new(s))
            .unwrap()
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn known_extensions_are_dropped_once() {
        for ext in TET_EXTENSIONS {
            assert_eq!(prefix(&format!("out/bunny.{ext}")), "out/bunny");
        }
        assert_eq!(prefix("bunny.VTK"), "bunny");
        assert_eq!(prefix("bunny.node.node"), "bunny.node");
        assert_eq!(prefix("bunny"), "bunny");
        assert_eq!(prefix("bunny.v2"), "bunny.v2");
        assert_eq!(prefix("bunny.ply"), "bunny.ply");
        assert_eq!(prefix(".node"), ".node");
    }

    #[test]
    fn folder_names_are_refused() {
        for s in ["", "out/", ".", "..", "out/.", "out/..", "/"] {
            let e = output_prefix(Path::new(s)).unwrap_err().to_string();
            assert!(e.contains("names a folder"), "{s}: {e}");
        }
    }

    #[test]
    fn parents_are_made_and_removed_again() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a/b/mesh");
        let mut made = MadeFolders::default();
        made.make_parent_of(&file, "output").unwrap();
        assert!(dir.path().join("a/b").is_dir());
        assert_eq!(made.made(), [dir.path().join("a"), dir.path().join("a/b")]);
        made.remove_empty();
        assert!(!dir.path().join("a").exists());

        std::fs::write(dir.path().join("f"), "").unwrap();
        let e = made
            .make_parent_of(&dir.path().join("f/g/mesh"), "output")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("is a file, not a folder") && e.contains("/f "),
            "{e}"
        );
        assert!(made.made().is_empty());
    }
}
