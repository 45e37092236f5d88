//! Line and token helpers shared by the text readers (PLY ascii, OBJ, OFF, STL ascii, TetGen):
//! 1-based line numbers, whitespace tokens, checked number parsing with messages that say
//! what was expected.

use crate::error::Error;
use std::path::Path;

/// One line of a text file: its 1-based number and its whitespace-separated tokens, with
/// anything from `comment` on removed.
pub(crate) struct Line<'a> {
    /// 1-based line number.
    pub no: usize,
    /// The tokens (never empty when returned by [`Lines`]).
    pub tokens: Vec<&'a [u8]>,
}

impl<'a> Line<'a> {
    /// The first token (the keyword, in most formats).
    pub fn head(&self) -> &'a [u8] {
        self.tokens.first().copied().unwrap_or_default()
    }
}

/// Iterator over the non-blank lines of `bytes` (after stripping comments).
pub(crate) struct Lines<'a> {
    rest: &'a [u8],
    no: usize,
    comment: Option<u8>,
}

impl<'a> Lines<'a> {
    /// Lines of `bytes`; `comment` starts a comment that runs to the end of the line.
    pub fn new(bytes: &'a [u8], comment: Option<u8>) -> Self {
        Self {
            rest: bytes,
            no: 0,
            comment,
        }
    }

    /// The number of the last line returned (0 before the first).
    pub fn line_no(&self) -> usize {
        self.no
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = Line<'a>;
    fn next(&mut self) -> Option<Line<'a>> {
        while !self.rest.is_empty() {
            let end = self
                .rest
                .iter()
                .position(|&b| b == b'\n')
                .unwrap_or(self.rest.len());
            let (mut line, rest) = self.rest.split_at(end);
            self.rest = rest.get(1..).unwrap_or(&[]);
            self.no += 1;
            if let Some(c) = self.comment {
                if let Some(p) = line.iter().position(|&b| b == c) {
                    line = &line[..p];
                }
            }
            let tokens: Vec<&[u8]> = line
                .split(|b| b.is_ascii_whitespace())
                .filter(|t| !t.is_empty())
                .collect();
            if !tokens.is_empty() {
                return Some(Line {
                    no: self.no,
                    tokens,
                });
            }
        }
        None
    }
}

/// A token as text for messages (lossy, shortened).
pub(crate) fn show(token: &[u8]) -> String {
    let s = String::from_utf8_lossy(token);
    if s.chars().count() > 40 {
        format!("{}...", s.chars().take(40).collect::<String>())
    } else {
        s.into_owned()
    }
}

/// Parses a token as `f64` (accepting `nan`/`inf`, which callers reject with context).
pub(crate) fn parse_f64(token: &[u8]) -> Option<f64> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// Parses a token as a signed integer.
pub(crate) fn parse_i64(token: &[u8]) -> Option<i64> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// Context for errors in one file: builds [`Error::Parse`] values.
#[derive(Clone, Copy)]
pub(crate) struct Ctx<'p> {
    pub path: &'p Path,
}

impl<'p> Ctx<'p> {
    /// An error at `line` (1-based, when known).
    pub fn err(&self, line: Option<usize>, message: impl Into<String>) -> Error {
        Error::parse(self.path, line, message)
    }

    /// Token `i` of `line`, or an error saying `what` is missing.
    pub fn token<'a>(&self, line: &Line<'a>, i: usize, what: &str) -> Result<&'a [u8], Error> {
        line.tokens.get(i).copied().ok_or_else(|| {
            self.err(
                Some(line.no),
                format!("missing {what} (line has {} values)", line.tokens.len()),
            )
        })
    }

    /// Token `i` of `line` as a finite or non-finite `f64`, naming `what` on error.
    pub fn f64(&self, line: &Line<'_>, i: usize, what: &str) -> Result<f64, Error> {
        let t = self.token(line, i, what)?;
        parse_f64(t).ok_or_else(|| {
            self.err(
                Some(line.no),
                format!("{what}: `{}` is not a number", show(t)),
            )
        })
    }

    /// Token `i` of `line` as an integer, naming `what` on error.
    pub fn int(&self, line: &Line<'_>, i: usize, what: &str) -> Result<i64, Error> {
        let t = self.token(line, i, what)?;
        parse_i64(t).ok_or_else(|| {
            self.err(
                Some(line.no),
                format!("{what}: `{}` is not an integer", show(t)),
            )
        })
    }

    /// Token `i` of `line` as a count (a non-negative integer that fits in `usize`).
    pub fn count(&self, line: &Line<'_>, i: usize, what: &str) -> Result<usize, Error> {
        let v = self.int(line, i, what)?;
        usize::try_from(v).map_err(|_| {
            self.err(
                Some(line.no),
                format!("{what} is {v}; it must be 0 or more"),
            )
        })
    }

    /// Three coordinates from tokens `i..i+3` of `line`, checked finite; `what` names the
    /// point ("vertex 12").
    pub fn point(&self, line: &Line<'_>, i: usize, what: &str) -> Result<glam::DVec3, Error> {
        let mut c = [0.0; 3];
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            c[k] = self.f64(line, i + k, &format!("{what} {axis}"))?;
        }
        finite_point(c).map_err(|m| self.err(Some(line.no), format!("{what} has a {m}")))
    }
}

/// `c` as a point, or a message (to put after an element's name) when a coordinate is NaN or
/// infinite.
pub(crate) fn finite_point(c: [f64; 3]) -> Result<glam::DVec3, String> {
    if c.iter().all(|v| v.is_finite()) {
        Ok(glam::DVec3::from_array(c))
    } else {
        Err(format!(
            "non-finite coordinate ({}, {}, {})",
            c[0], c[1], c[2]
        ))
    }
}

/// Capacity to reserve for `declared` elements when `available` bytes remain and each element
/// takes at least `min_size` bytes: never more than the data could hold, so a lying header
/// cannot make us allocate gigabytes.
pub(crate) fn capacity(declared: usize, available: usize, min_size: usize) -> usize {
    declared.min(available / min_size.max(1))
}

/// Splits a polygon given as vertex indices into a triangle fan around its first vertex.
pub(crate) fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    if let Some((&first, rest)) = poly.split_first() {
        out.extend(rest.windows(2).map(|w| [first, w[0], w[1]]));
    }
}
