//! Reads the fields of a struct (or the variants of an enum) from Rust source, with their
//! doc comments and attributes, for the reference pages generated from the code
//! (`tests/record_reference.rs`, `tests/scene_reference.rs`). Included with
//! `#[path = "common/source.rs"] mod source;`.
#![allow(dead_code)]

use std::path::Path;

/// One field (or variant) as its source declares it.
pub struct Field {
    /// Its name in the source.
    pub name: String,
    /// Its type as written (empty for a variant).
    pub ty: String,
    /// Its doc comment, lines joined by spaces.
    pub doc: String,
    /// Its attributes, joined.
    pub attributes: String,
}

impl Field {
    /// The key serde reads it under: its `rename`, else its name.
    pub fn key(&self) -> String {
        let Some(at) = self.attributes.find("rename = \"") else {
            return self.name.clone();
        };
        let rest = &self.attributes[at + "rename = \"".len()..];
        rest[..rest.find('"').unwrap()].to_string()
    }

    /// Whether serde fills it in when the file leaves it out.
    pub fn optional(&self) -> bool {
        self.ty.starts_with("Option<")
            || self
                .attributes
                .split("#[")
                .any(|a| a.starts_with("serde(") && a.contains("default"))
    }
}

/// The source of a file of the workspace.
pub fn source(path: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(path)).unwrap()
}

/// The text between the braces of `pub KIND NAME {` in `source`.
fn body<'a>(source: &'a str, kind: &str, name: &str) -> &'a str {
    let start = source
        .find(&format!("pub {kind} {name} {{"))
        .unwrap_or_else(|| panic!("no {kind} {name}"));
    let body = &source[start..];
    &body[body.find('{').unwrap() + 1..body.find("\n}").unwrap()]
}

/// The declarations at brace depth 0 of `body` (`name: Type,` or `Name {`), each with the
/// doc comment and attributes above it, and for `Name {` the text up to its closing brace.
fn declarations(body: &str) -> Vec<(Field, String)> {
    let (mut out, mut doc, mut attributes) = (Vec::new(), Vec::new(), String::new());
    let mut lines = body.lines().map(str::trim);
    let mut open_attribute = 0i32;
    while let Some(line) = lines.next() {
        if open_attribute > 0 || line.starts_with("#[") {
            attributes.push_str(line);
            open_attribute += balance(line);
            continue;
        }
        if let Some(text) = line.strip_prefix("///") {
            doc.push(text.trim().to_string());
            continue;
        }
        let decl = line.strip_prefix("pub ").unwrap_or(line);
        if decl.is_empty() || decl.starts_with("//") {
            continue;
        }
        let (name, ty, inner) = match decl.split_once(':') {
            Some((name, ty)) if !decl.ends_with('{') => (
                name.trim(),
                ty.trim().trim_end_matches(',').to_string(),
                String::new(),
            ),
            _ => {
                // A variant `Name {`: its fields up to the matching brace.
                let mut inner = String::new();
                let mut depth = 1;
                for line in lines.by_ref() {
                    depth += line.matches('{').count() as i32 - line.matches('}').count() as i32;
                    if depth <= 0 {
                        break;
                    }
                    inner.push_str(line);
                    inner.push('\n');
                }
                (decl.trim_end_matches('{').trim(), String::new(), inner)
            }
        };
        out.push((
            Field {
                name: name.to_string(),
                ty,
                doc: doc.join(" "),
                attributes: std::mem::take(&mut attributes),
            },
            inner,
        ));
        doc.clear();
    }
    out
}

/// Opening less closing brackets of `line`.
fn balance(line: &str) -> i32 {
    let count = |c: &[char]| line.chars().filter(|x| c.contains(x)).count() as i32;
    count(&['(', '[']) - count(&[')', ']'])
}

/// The fields of `pub struct NAME` in `source`, in order.
pub fn fields(source: &str, name: &str) -> Vec<Field> {
    declarations(body(source, "struct", name))
        .into_iter()
        .map(|(f, _)| f)
        .collect()
}

/// The variants of `pub enum NAME` in `source`, each with its fields.
pub fn variants(source: &str, name: &str) -> Vec<(Field, Vec<Field>)> {
    declarations(body(source, "enum", name))
        .into_iter()
        .map(|(variant, inner)| {
            let fields = declarations(&inner).into_iter().map(|(f, _)| f).collect();
            (variant, fields)
        })
        .collect()
}

/// A doc comment as a table cell: intra-doc links as code, pipes escaped.
pub fn cell(doc: &str) -> String {
    doc.replace("[`", "`")
        .replace("`]", "`")
        .replace('|', "\\|")
}

/// Compares the generated page `generated` with the committed one at `path` (relative to
/// the workspace root), rewriting it first under `TETRASIM_BLESS=1`.
pub fn check_page(path: &str, generated: &str, test: &str) {
    let full = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    if std::env::var("TETRASIM_BLESS").is_ok_and(|v| v == "1") {
        std::fs::write(&full, generated).unwrap();
    }
    let committed = std::fs::read_to_string(&full).unwrap_or_default();
    assert!(
        generated == committed,
        "{path} differs from the code: rewrite it with \
         `TETRASIM_BLESS=1 cargo test --release --test {test}`"
    );
}
