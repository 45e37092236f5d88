//! The modules of each crate depend one way: the graph of `crate::MODULE` references between
//! the top-level modules of the engine (`crates/tetrasim`), of `tetmesh` and of the command
//! line (`src/`), and between the files of the larger modules (tests left out), has no cycle.
//! (The crates themselves depend one way by construction, Cargo refuses a cycle; what each
//! library may depend on is `tests/crate_layers.rs`.) Read
//! from the sources as text, so a new `use` that closes a loop fails here, naming the loop.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
    out
}

/// The source without its test module and comments.
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Names `word` of `PREFIXword` and of `PREFIX{word, ...}` in `code`, for each prefix
/// (`crate::` between a crate's modules, `super::` between a module's files).
fn refs(code: &str, prefixes: &[&str]) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    for (i, prefix) in prefixes
        .iter()
        .flat_map(|p| code.match_indices(p).map(move |(i, _)| (i, *p)))
    {
        let rest = &code[i + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let inner = group.split('}').next().unwrap_or("");
            for part in inner.split(',') {
                out.insert(ident(part.trim()));
            }
        } else {
            out.insert(ident(rest));
        }
    }
    out
}

/// Module -> the other modules of `src` it names through `prefixes`.
fn graph(src: &Path, prefixes: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let mut modules: BTreeMap<String, Vec<PathBuf>> = BTreeMap::new();
    for entry in std::fs::read_dir(src).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            modules.insert(name, rust_files(&path));
        } else if name != "lib" && name != "main" && path.extension().is_some_and(|e| e == "rs") {
            modules.insert(name, vec![path]);
        }
    }
    let names: BTreeSet<String> = modules.keys().cloned().collect();
    modules
        .iter()
        .map(|(m, files)| {
            let deps = files
                .iter()
                .flat_map(|f| refs(&code(f), prefixes))
                .filter(|d| d != m && names.contains(d))
                .collect();
            (m.clone(), deps)
        })
        .collect()
}

/// A cycle of `g`, if it has one (depth-first search).
fn find_cycle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        g: &BTreeMap<String, BTreeSet<String>>,
        m: &str,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|p| p == m) {
            let mut cycle = path[at..].to_vec();
            cycle.push(m.to_string());
            return Some(cycle);
        }
        if done.contains(m) {
            return None;
        }
        path.push(m.to_string());
        for d in g.get(m).into_iter().flatten() {
            if let Some(c) = visit(g, d, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(m.to_string());
        None
    }
    let mut done = BTreeSet::new();
    g.keys()
        .find_map(|m| visit(g, m, &mut Vec::new(), &mut done))
}

#[test]
fn top_level_modules_have_no_cycles() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (src, prefixes) in [
        ("src", &["crate::"][..]),
        ("src/bench", &["super::", "crate::bench::"]),
        ("crates/tetrasim/src", &["crate::"]),
        (
            "crates/tetrasim/src/backend",
            &["super::", "crate::backend::"],
        ),
        (
            "crates/tetrasim/src/backend/vulkan",
            &["super::", "crate::backend::vulkan::"],
        ),
        ("crates/tetrasim/src/sim", &["super::", "crate::sim::"]),
        ("crates/tetrasim/src/gpu", &["super::", "crate::gpu::"]),
        ("crates/tetmesh/src", &["crate::"]),
        ("crates/tetmesh/src/mesh", &["super::", "crate::mesh::"]),
    ] {
        let g = graph(&root.join(src), prefixes);
        assert!(g.len() >= 3, "{src}: only {} modules read", g.len());
        if let Some(cycle) = find_cycle(&g) {
            panic!("{src}: modules depend in a loop: {}", cycle.join(" -> "));
        }
    }
}

/// The most lines a source file may have (ARCHITECTURE.md, "Habits the build enforces").
const MAX_LINES: usize = 600;

#[test]
fn no_source_file_is_longer_than_the_limit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "tests", "crates", "apps"] {
        files.extend(rust_files(&root.join(dir)));
    }
    assert!(files.len() > 100, "only {} source files found", files.len());
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let lines = std::fs::read_to_string(f).unwrap().lines().count();
            (lines > MAX_LINES).then(|| format!("{} ({lines} lines)", f.display()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "split these files (at most {MAX_LINES} lines): {}",
        long.join(", ")
    );
}

#[test]
fn a_loop_is_found() {
    let g: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(m, d)| (m.to_string(), d.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(find_cycle(&g).unwrap(), ["a", "b", "c", "a"]);
    assert_eq!(
        refs("use crate::{x, y::z};\ncrate::w::f()", &["crate::"]).len(),
        3
    );
}
