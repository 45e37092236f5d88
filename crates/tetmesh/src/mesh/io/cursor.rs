//! A position in a file that mixes text lines and binary blocks (legacy VTK, gmsh `.msh`):
//! keyword lines are read as text, data either as whitespace tokens (with their line numbers)
//! or as fixed-size binary records. Every read is checked against the bytes left, so a count
//! in a header can never make a reader allocate or read past the end.

use super::text::{parse_f64, parse_i64, show, Ctx, Line};
use crate::error::{Error, Result};

/// Byte order of binary data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Endian {
    Little,
    Big,
}

/// A cursor over `bytes`, counting lines (1-based) as it passes newlines.
#[derive(Clone)]
pub(crate) struct Cursor<'a> {
    pub bytes: &'a [u8],
    pub pos: usize,
    /// The number of newlines before `pos`.
    newlines: usize,
    pub ctx: Ctx<'a>,
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8], ctx: Ctx<'a>) -> Self {
        Self {
            bytes,
            pos: 0,
            newlines: 0,
            ctx,
        }
    }

    /// The 1-based line number at the cursor.
    pub fn line_no(&self) -> usize {
        self.newlines + 1
    }

    /// Bytes left.
    pub fn left(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// An error at line `line`.
    pub fn err(&self, line: Option<usize>, message: impl Into<String>) -> Error {
        self.ctx.err(line, message)
    }

    /// The next line as it is (without `\n` and a trailing `\r`), blank or not; `None` at the
    /// end of the file.
    pub fn raw_line(&mut self) -> Option<(usize, &'a [u8])> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.pos..];
        let end = rest.iter().position(|&b| b == b'\n');
        let no = self.line_no();
        let line = &rest[..end.unwrap_or(rest.len())];
        self.pos += end.map_or(rest.len(), |e| e + 1);
        if end.is_some() {
            self.newlines += 1;
        }
        Some((no, line.strip_suffix(b"\r").unwrap_or(line)))
    }

    /// The next non-blank line, split into tokens.
    pub fn line(&mut self) -> Option<Line<'a>> {
        while let Some((no, raw)) = self.raw_line() {
            let tokens: Vec<&[u8]> = raw
                .split(|b| b.is_ascii_whitespace())
                .filter(|t| !t.is_empty())
                .collect();
            if !tokens.is_empty() {
                return Some(Line { no, tokens });
            }
        }
        None
    }

    /// The next non-blank line, or an error saying the file ends before `what`.
    pub fn need_line(&mut self, what: &str) -> Result<Line<'a>> {
        self.line()
            .ok_or_else(|| self.err(None, format!("the file ends before {what} (truncated?)")))
    }

    /// The next whitespace-separated token and its line, crossing line ends.
    pub fn token(&mut self) -> Option<(usize, &'a [u8])> {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            if self.bytes[self.pos] == b'\n' {
                self.newlines += 1;
            }
            self.pos += 1;
        }
        if self.pos >= self.bytes.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        Some((self.line_no(), &self.bytes[start..self.pos]))
    }

    /// The next token parsed by `parse`, or an error naming `what` and saying it is not
    /// `kind` (`a number`, `an integer`).
    fn parsed_token<T>(
        &mut self,
        what: &dyn Fn() -> String,
        parse: fn(&[u8]) -> Option<T>,
        kind: &str,
    ) -> Result<(usize, T)> {
        let (no, t) = self.token().ok_or_else(|| {
            self.err(
                None,
                format!("the file ends before {} (truncated?)", what()),
            )
        })?;
        let v = parse(t).ok_or_else(|| {
            self.err(Some(no), format!("{}: `{}` is not {kind}", what(), show(t)))
        })?;
        Ok((no, v))
    }

    /// The next token as a number, or an error naming `what`.
    pub fn f64_token(&mut self, what: &dyn Fn() -> String) -> Result<(usize, f64)> {
        self.parsed_token(what, parse_f64, "a number")
    }

    /// The next token as an integer, or an error naming `what`.
    pub fn int_token(&mut self, what: &dyn Fn() -> String) -> Result<(usize, i64)> {
        self.parsed_token(what, parse_i64, "an integer")
    }

    /// The next `n` bytes, or an error saying the file ends inside `what`.
    pub fn take(&mut self, n: usize, what: &dyn Fn() -> String) -> Result<&'a [u8]> {
        if n > self.left() {
            return Err(self.err(
                None,
                format!(
                    "the file ends inside {} ({n} bytes needed, {} left; truncated?)",
                    what(),
                    self.left()
                ),
            ));
        }
        let out = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        self.newlines += out.iter().filter(|&&b| b == b'\n').count();
        Ok(out)
    }

    /// Checks that `count` records of `size` bytes fit in what is left, before reading them.
    pub fn fits(&self, count: usize, size: usize, what: &str) -> Result<()> {
        match count.checked_mul(size) {
            Some(n) if n <= self.left() => Ok(()),
            _ => Err(self.err(
                None,
                format!(
                    "{count} {what} of {size} bytes do not fit in the {} bytes left (truncated, or a wrong count?)",
                    self.left()
                ),
            )),
        }
    }

    /// Skips the line end that follows a binary block, if there is one.
    pub fn skip_newline(&mut self) {
        if self.bytes.get(self.pos) == Some(&b'\r') {
            self.pos += 1;
        }
        if self.bytes.get(self.pos) == Some(&b'\n') {
            self.pos += 1;
            self.newlines += 1;
        }
    }

    /// Moves to just after the next line that is exactly `marker` (e.g. `$EndNodes`), or errors.
    pub fn skip_past_line(&mut self, marker: &[u8], section_line: usize) -> Result<()> {
        loop {
            let Some(at) = find(&self.bytes[self.pos..], marker) else {
                return Err(self.err(
                    Some(section_line),
                    format!(
                        "the section has no `{}` (truncated?)",
                        String::from_utf8_lossy(marker)
                    ),
                ));
            };
            let start = self.pos + at;
            let line_start = start == 0 || self.bytes[start - 1] == b'\n';
            let end = start + marker.len();
            let line_end = matches!(self.bytes.get(end), None | Some(b'\n' | b'\r'));
            let skipped = &self.bytes[self.pos..end];
            self.newlines += skipped.iter().filter(|&&b| b == b'\n').count();
            self.pos = end;
            if line_start && line_end {
                self.raw_line();
                return Ok(());
            }
        }
    }
}

/// Position of `needle` in `hay`.
pub(crate) fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    if needle.is_empty() || needle.len() > hay.len() {
        return None;
    }
    hay.windows(needle.len()).position(|w| w == needle)
}

/// A numeric type of binary data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Num {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
}

impl Num {
    /// Size in bytes.
    pub fn size(self) -> usize {
        match self {
            Num::I8 | Num::U8 => 1,
            Num::I16 | Num::U16 => 2,
            Num::I32 | Num::U32 | Num::F32 => 4,
            Num::I64 | Num::U64 | Num::F64 => 8,
        }
    }

    /// Whether the type is a floating-point type.
    pub fn is_float(self) -> bool {
        matches!(self, Num::F32 | Num::F64)
    }

    fn raw<const N: usize>(b: &[u8], e: Endian) -> [u8; N] {
        let mut a = [0u8; N];
        a.copy_from_slice(&b[..N]);
        if e == Endian::Big {
            a.reverse();
        }
        a
    }

    /// Decodes one value from the first `self.size()` bytes of `b` as `f64`.
    pub fn f64(self, b: &[u8], e: Endian) -> f64 {
        match self {
            Num::F32 => f32::from_le_bytes(Self::raw(b, e)) as f64,
            Num::F64 => f64::from_le_bytes(Self::raw(b, e)),
            _ => self.i128(b, e) as f64,
        }
    }

    /// Decodes one integer value (floats are truncated; callers reject non-integer types).
    pub fn i128(self, b: &[u8], e: Endian) -> i128 {
        match self {
            Num::I8 => b[0] as i8 as i128,
            Num::U8 => b[0] as i128,
            Num::I16 => i16::from_le_bytes(Self::raw(b, e)) as i128,
            Num::U16 => u16::from_le_bytes(Self::raw(b, e)) as i128,
            Num::I32 => i32::from_le_bytes(Self::raw(b, e)) as i128,
            Num::U32 => u32::from_le_bytes(Self::raw(b, e)) as i128,
            Num::I64 => i64::from_le_bytes(Self::raw(b, e)) as i128,
            Num::U64 => u64::from_le_bytes(Self::raw(b, e)) as i128,
            Num::F32 | Num::F64 => self.f64(b, e) as i128,
        }
    }
}

/// Decodes all values of `bytes` (a multiple of `num.size()`) as `f64`.
pub(crate) fn decode_f64(bytes: &[u8], num: Num, e: Endian) -> Vec<f64> {
    bytes
        .chunks_exact(num.size())
        .map(|c| num.f64(c, e))
        .collect()
}

/// Decodes all values of `bytes` as integers; values beyond `i64` become `i64::MAX` (out of
/// any index range, so reported as such).
pub(crate) fn decode_i64(bytes: &[u8], num: Num, e: Endian) -> Vec<i64> {
    bytes
        .chunks_exact(num.size())
        .map(|c| i64::try_from(num.i128(c, e)).unwrap_or(i64::MAX))
        .collect()
}
