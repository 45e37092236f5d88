//! The guide's commands run (issue 53): every line of a `sh` block in `docs/guide/*.md`
//! that begins with `target/release/tetrasim` is run from the repository's root with the
//! binary under test and must succeed, and every `toml` block that is a whole scene (it has
//! an `[[object]]`) is run as `tetrasim run --scene` (its paths taken from the repository's
//! root, its outputs written to a temporary folder), so a page cannot drift from the
//! command line. (Lines that name placeholders in capitals, like `--mesh HORSE`, begin with
//! `tetrasim` alone and are the figures' recipes, not run here; the Python blocks run in
//! python/tests/test_guide.py.)

use std::path::Path;
use std::process::Command;

/// The `toml` blocks of `text` that are whole scenes.
fn scenes(text: &str) -> Vec<String> {
    let (mut inside, mut found, mut block) = (false, Vec::new(), String::new());
    for line in text.lines() {
        match line.trim_start() {
            "```toml" => (inside, block) = (true, String::new()),
            "```" if inside => {
                inside = false;
                if block.contains("[[object]]") {
                    found.push(block.clone());
                }
            }
            _ if inside => block.push_str(&format!("{line}\n")),
            _ => {}
        }
    }
    found
}

/// The commands of the `sh` blocks of `text` that begin with `target/release/tetrasim`.
fn commands(text: &str) -> Vec<String> {
    let (mut inside, mut found) = (false, Vec::new());
    for line in text.lines() {
        match line.trim_start() {
            "```sh" => inside = true,
            "```" => inside = false,
            command if inside && command.starts_with("target/release/tetrasim ") => {
                // A trailing comment is the reader's, not the shell's.
                let command = command.split(" # ").next().unwrap_or(command).trim();
                found.push(command.to_string());
            }
            _ => {}
        }
    }
    found
}

#[test]
fn every_command_in_the_guide_runs() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut pages: Vec<_> = std::fs::read_dir(root.join("docs/guide"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    let (mut ran, mut scenes_ran) = (0, 0);
    for page in &pages {
        for command in commands(&std::fs::read_to_string(page).unwrap()) {
            let args: Vec<&str> = command.split_whitespace().skip(1).collect();
            let output = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
                .args(&args)
                .current_dir(root)
                .output()
                .unwrap();
            assert!(
                output.status.success(),
                "{}: `{command}` failed:\n{}",
                page.display(),
                String::from_utf8_lossy(&output.stderr)
            );
            ran += 1;
        }
        for scene in scenes(&std::fs::read_to_string(page).unwrap()) {
            let dir = tempfile::tempdir().unwrap();
            let text = scene
                .replace(
                    "mesh = \"meshes/",
                    &format!("mesh = \"{}/meshes/", root.display()),
                )
                .replace("= \"out/", &format!("= \"{}/", dir.path().display()));
            let file = dir.path().join("scene.toml");
            std::fs::write(&file, text).unwrap();
            let output = Command::new(env!("CARGO_BIN_EXE_tetrasim"))
                .args(["run", "--quiet", "--scene"])
                .arg(&file)
                .output()
                .unwrap();
            assert!(
                output.status.success(),
                "{}: its scene failed:\n{scene}\n{}",
                page.display(),
                String::from_utf8_lossy(&output.stderr)
            );
            scenes_ran += 1;
        }
    }
    assert!(
        ran >= 1 && scenes_ran >= 1,
        "no command or scene found in {pages:?}"
    );
}
