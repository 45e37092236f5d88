//! The guide's commands run (issue 53): every line of a `sh` block in `docs/guide/*.md`
//! that begins with `target/release/tetrasim` is run from the repository's root with the
//! binary under test and must succeed, so a page cannot drift from the command line.
//! (Lines that name placeholders in capitals, like `--mesh HORSE`, begin with `tetrasim`
//! alone and are the figures' recipes, not run here.)

use std::path::Path;
use std::process::Command;

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
    let mut ran = 0;
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
    }
    assert!(ran >= 1, "no command found in {pages:?}");
}
