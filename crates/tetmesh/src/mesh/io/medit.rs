//! Medit `.mesh` files (ASCII), as written by meshio, MMG, fTetWild and TetGen (`-g`).
//!
//! Read: `MeshVersionFormatted`, `Dimension 3`, `Vertices` (x y z ref) and `Tetrahedra`
//! (four 1-based vertex numbers and a ref); every other section (`Triangles`, `Edges`,
//! `Corners`, ...) is skipped, from its keyword to the next keyword. `#` starts a comment.
//! Nodes that no tet uses are dropped; the tets keep the file's orientation. Errors name the
//! file and the line. Not read: the binary `.meshb` variant, 2D meshes, `Dimension` other
//! than 3.
//!
//! No crate was considered: the format is a handful of keywords followed by counts and
//! numbers, and none of the Rust crates found reads it with line-numbered errors.

use super::text::{parse_f64, parse_i64, show, Ctx, Lines};
use crate::error::Result;
use crate::mesh::TetMesh;
use std::path::Path;

/// Reads a Medit `.mesh` file: its vertices and tetrahedra.
pub fn read_medit(path: impl AsRef<Path>) -> Result<TetMesh> {
    let path = path.as_ref();
    parse(&super::read_bytes(path)?, path)
}

/// The whitespace tokens of a file, each with its line.
struct Tokens<'a> {
    lines: Lines<'a>,
    line: std::vec::IntoIter<&'a [u8]>,
    no: usize,
}

impl<'a> Tokens<'a> {
    fn next(&mut self) -> Option<(usize, &'a [u8])> {
        loop {
            if let Some(t) = self.line.next() {
                return Some((self.no, t));
            }
            let l = self.lines.next()?;
            self.no = l.no;
            self.line = l.tokens.into_iter();
        }
    }

    /// The next token without taking it.
    fn peek(&mut self) -> Option<&'a [u8]> {
        while self.line.as_slice().is_empty() {
            let l = self.lines.next()?;
            self.no = l.no;
            self.line = l.tokens.into_iter();
        }
        self.line.as_slice().first().copied()
    }
}

fn is_keyword(t: &[u8]) -> bool {
    t.first().is_some_and(|b| b.is_ascii_alphabetic())
        && !matches!(
            t.to_ascii_lowercase().as_slice(),
            b"nan" | b"inf" | b"infinity"
        )
}

/// Parses the bytes of a Medit file; `path` names it in errors.
pub fn parse(bytes: &[u8], path: &Path) -> Result<TetMesh> {
    let ctx = Ctx { path };
    let mut t = Tokens {
        lines: Lines::new(bytes, Some(b'#')),
        line: Vec::new().into_iter(),
        no: 0,
    };
    let eof = |what: &str| ctx.err(None, format!("the file ends before {what} (truncated?)"));
    let int = |t: &mut Tokens<'_>, what: &dyn Fn() -> String| -> Result<(usize, i64)> {
        let (no, tok) = t.next().ok_or_else(|| eof(&what()))?;
        let v = parse_i64(tok).ok_or_else(|| {
            ctx.err(
                Some(no),
                format!("{}: `{}` is not an integer", what(), show(tok)),
            )
        })?;
        Ok((no, v))
    };
    let count = |t: &mut Tokens<'_>, what: &str| -> Result<(usize, usize)> {
        let (no, v) = int(t, &|| what.to_string())?;
        let n = usize::try_from(v)
            .map_err(|_| ctx.err(Some(no), format!("{what} is {v}; it must be 0 or more")))?;
        Ok((no, n))
    };
    let (no, first) = t.next().ok_or_else(|| ctx.err(None, "empty file"))?;
    if first != b"MeshVersionFormatted" {
        return Err(ctx.err(
            Some(no),
            "not a Medit file: it does not start with `MeshVersionFormatted`",
        ));
    }
    int(&mut t, &|| "the MeshVersionFormatted number".into())?;
    let mut nodes: Option<Vec<glam::DVec3>> = None;
    let mut tets: Vec<([i64; 4], usize)> = Vec::new();
    let mut skipped: Vec<String> = Vec::new();
    while let Some((no, key)) = t.next() {
        if !is_keyword(key) {
            return Err(ctx.err(
                Some(no),
                format!("expected a keyword, found `{}`", show(key)),
            ));
        }
        match key {
            b"End" => break,
            b"Dimension" => {
                let (dno, d) = int(&mut t, &|| "the dimension".into())?;
                if d != 3 {
                    return Err(ctx.err(
                        Some(dno),
                        format!("dimension {d}; only 3D meshes hold tets"),
                    ));
                }
            }
            b"Vertices" => {
                if nodes.is_some() {
                    return Err(ctx.err(Some(no), "a second Vertices section"));
                }
                let (_, n) = count(&mut t, "vertex count")?;
                let mut v = Vec::with_capacity(n.min(bytes.len() / 8));
                for i in 0..n {
                    let mut c = [0.0; 3];
                    let mut line = 0;
                    for (k, slot) in c.iter_mut().enumerate() {
                        let what = || format!("vertex {} {}", i + 1, ["x", "y", "z"][k]);
                        let (lno, tok) = t.next().ok_or_else(|| eof(&what()))?;
                        line = lno;
                        *slot = parse_f64(tok).ok_or_else(|| {
                            ctx.err(
                                Some(lno),
                                format!("{}: `{}` is not a number", what(), show(tok)),
                            )
                        })?;
                    }
                    int(&mut t, &|| format!("vertex {} reference", i + 1))?;
                    let p = super::text::finite_point(c)
                        .map_err(|m| ctx.err(Some(line), format!("vertex {} has a {m}", i + 1)))?;
                    v.push(p);
                }
                nodes = Some(v);
            }
            b"Tetrahedra" => {
                let (_, m) = count(&mut t, "tetrahedron count")?;
                tets.reserve(m.min(bytes.len() / 10));
                for i in 0..m {
                    let mut e = [0i64; 4];
                    let mut line = 0;
                    for (k, slot) in e.iter_mut().enumerate() {
                        let (lno, v) =
                            int(&mut t, &|| format!("tetrahedron {} vertex {k}", i + 1))?;
                        line = lno;
                        *slot = v;
                    }
                    int(&mut t, &|| format!("tetrahedron {} reference", i + 1))?;
                    tets.push((e, line));
                }
            }
            other => {
                // Any other section: its numbers, up to the next keyword.
                skipped.push(String::from_utf8_lossy(other).into_owned());
                while t.peek().is_some_and(|n| !is_keyword(n)) {
                    t.next();
                }
            }
        }
    }
    let nodes = nodes.ok_or_else(|| ctx.err(None, "no Vertices section"))?;
    if tets.is_empty() {
        return Err(ctx.err(
            None,
            format!(
                "no tetrahedra (no Tetrahedra section, or an empty one); sections found: Vertices{}",
                skipped.iter().map(|s| format!(", {s}")).collect::<String>()
            ),
        ));
    }
    let n = nodes.len();
    let mut out = Vec::with_capacity(tets.len());
    for (i, (e, line)) in tets.iter().enumerate() {
        let mut tet = [0u32; 4];
        for (k, (&v, slot)) in e.iter().zip(&mut tet).enumerate() {
            *slot = v
                .checked_sub(1)
                .and_then(|x| u32::try_from(x).ok())
                .filter(|&x| (x as usize) < n)
                .ok_or_else(|| {
                    ctx.err(
                        Some(*line),
                        format!("tetrahedron {} vertex {k}: {v} is out of range (vertices are numbered 1 to {n})", i + 1),
                    )
                })?;
        }
        out.push(tet);
    }
    super::finish_tets(nodes, out)
}
