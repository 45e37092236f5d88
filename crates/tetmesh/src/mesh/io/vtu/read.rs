//! Reading `.vtu` files (see the module above for what is read).

use crate::error::{Error, Result};
use crate::mesh::io::cursor::{decode_f64, decode_i64, find, Endian, Num};
use crate::mesh::io::text::Ctx;
use crate::mesh::TetMesh;
use std::io::Read;
use std::path::Path;

/// Reads a `.vtu` file: its points and linear tets.
pub fn read_vtu(path: impl AsRef<Path>) -> Result<TetMesh> {
    let path = path.as_ref();
    parse(&crate::mesh::io::read_bytes(path)?, path)
}

/// The appended data section: encoding and the bytes after its `_` marker.
struct Appended<'a> {
    base64: bool,
    data: &'a [u8],
    /// All arrays' offsets, sorted (a base64 array runs to the next one).
    offsets: Vec<usize>,
}

struct Grid<'a> {
    ctx: Ctx<'a>,
    endian: Endian,
    header: Num,
    zlib: bool,
    appended: Option<Appended<'a>>,
}

/// Parses the bytes of a `.vtu` file; `path` names it in errors.
pub fn parse(bytes: &[u8], path: &Path) -> Result<TetMesh> {
    let ctx = Ctx { path };
    // Cut the raw appended data out: it is not text.
    let mut xml_bytes = bytes.to_vec();
    let mut appended = None;
    if let Some(start) = find(bytes, b"<AppendedData") {
        let gt = bytes[start..]
            .iter()
            .position(|&b| b == b'>')
            .map(|p| start + p)
            .ok_or_else(|| ctx.err(None, "the <AppendedData> tag is not closed (truncated?)"))?;
        let tag = String::from_utf8_lossy(&bytes[start..gt]);
        let base64 = !tag.contains("\"raw\"");
        let underscore = bytes[gt..]
            .iter()
            .position(|&b| b == b'_')
            .map(|p| gt + p)
            .ok_or_else(|| ctx.err(None, "the appended data has no `_` marker (truncated?)"))?;
        let close = bytes
            .windows(b"</AppendedData>".len())
            .rposition(|w| w == b"</AppendedData>")
            .filter(|&c| c > underscore)
            .ok_or_else(|| ctx.err(None, "the file has no </AppendedData> (truncated?)"))?;
        let mut x = bytes[..=gt].to_vec();
        // Keep the line count of the XML after the cut as it was.
        x.extend(bytes[gt + 1..close].iter().filter(|&&b| b == b'\n'));
        x.extend_from_slice(&bytes[close..]);
        xml_bytes = x;
        appended = Some(Appended {
            base64,
            data: &bytes[underscore + 1..close],
            offsets: Vec::new(),
        });
    }
    let text = std::str::from_utf8(&xml_bytes).map_err(|e| {
        let line = 1 + xml_bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        ctx.err(Some(line), "the XML is not valid UTF-8")
    })?;
    let doc = roxmltree::Document::parse(text)
        .map_err(|e| ctx.err(Some(e.pos().row as usize), format!("not valid XML: {e}")))?;
    let line_of = |n: roxmltree::Node<'_, '_>| Some(doc.text_pos_at(n.range().start).row as usize);
    let root = doc.root_element();
    if root.tag_name().name() != "VTKFile" {
        return Err(ctx.err(
            line_of(root),
            format!(
                "the root element is <{}>, not <VTKFile>",
                root.tag_name().name()
            ),
        ));
    }
    if root.attribute("type") != Some("UnstructuredGrid") {
        return Err(ctx.err(
            line_of(root),
            format!(
                "VTKFile type {:?}; only UnstructuredGrid holds tets",
                root.attribute("type").unwrap_or("(none)")
            ),
        ));
    }
    let endian = match root.attribute("byte_order") {
        None | Some("LittleEndian") => Endian::Little,
        Some("BigEndian") => Endian::Big,
        Some(o) => return Err(ctx.err(line_of(root), format!("byte_order {o:?}"))),
    };
    let header = match root.attribute("header_type") {
        None | Some("UInt32") => Num::U32,
        Some("UInt64") => Num::U64,
        Some(o) => {
            return Err(ctx.err(
                line_of(root),
                format!("header_type {o:?}; expected UInt32 or UInt64"),
            ))
        }
    };
    let zlib = match root.attribute("compressor") {
        None | Some("") => false,
        Some("vtkZLibDataCompressor") => true,
        Some(o) => {
            return Err(ctx.err(
                line_of(root),
                format!("compressor {o}: only vtkZLibDataCompressor (zlib) is supported"),
            ))
        }
    };
    if let Some(a) = &mut appended {
        let mut offs: Vec<usize> = doc
            .descendants()
            .filter(|n| n.has_tag_name("DataArray"))
            .filter_map(|n| n.attribute("offset")?.trim().parse().ok())
            .collect();
        offs.sort_unstable();
        offs.dedup();
        a.offsets = offs;
    }
    let g = Grid {
        ctx,
        endian,
        header,
        zlib,
        appended,
    };
    let grid = root
        .children()
        .find(|n| n.has_tag_name("UnstructuredGrid"))
        .ok_or_else(|| ctx.err(line_of(root), "no <UnstructuredGrid> element"))?;
    let mut nodes = Vec::new();
    let mut tets = Vec::new();
    let mut pieces = 0;
    let mut no_tets: Option<Error> = None;
    for piece in grid.children().filter(|n| n.has_tag_name("Piece")) {
        pieces += 1;
        let count = |name: &str| -> Result<usize> {
            piece
                .attribute(name)
                .ok_or_else(|| ctx.err(line_of(piece), format!("<Piece> has no {name}")))?
                .trim()
                .parse()
                .map_err(|_| ctx.err(line_of(piece), format!("<Piece> {name} is not a count")))
        };
        let (np, nc) = (count("NumberOfPoints")?, count("NumberOfCells")?);
        let array = |parent: &str, name: Option<&str>| -> Result<roxmltree::Node<'_, '_>> {
            let p = piece
                .children()
                .find(|n| n.has_tag_name(parent))
                .ok_or_else(|| ctx.err(line_of(piece), format!("<Piece> has no <{parent}>")))?;
            p.children()
                .filter(|n| n.has_tag_name("DataArray"))
                .find(|n| name.is_none() || n.attribute("Name") == name)
                .ok_or_else(|| {
                    ctx.err(
                        line_of(p),
                        format!(
                            "<{parent}> has no DataArray{}",
                            name.map(|n| format!(" named {n}")).unwrap_or_default()
                        ),
                    )
                })
        };
        let pa = array("Points", None)?;
        if pa
            .attribute("NumberOfComponents")
            .is_some_and(|c| c.trim() != "3")
        {
            return Err(ctx.err(line_of(pa), "the points array must have 3 components"));
        }
        let k = np
            .checked_mul(3)
            .ok_or_else(|| ctx.err(line_of(piece), "too many points"))?;
        let xyz = g.floats(pa, k, line_of(pa))?;
        let base = nodes.len();
        for (i, c) in xyz.chunks_exact(3).enumerate() {
            let p = crate::mesh::io::text::finite_point([c[0], c[1], c[2]])
                .map_err(|m| ctx.err(line_of(pa), format!("point {i} has a {m}")))?;
            nodes.push(p);
        }
        if nc == 0 {
            continue;
        }
        let oa = array("Cells", Some("offsets"))?;
        let ends = g.ints(oa, nc, line_of(oa))?;
        let ca = array("Cells", Some("connectivity"))?;
        let conn_len = usize::try_from(*ends.last().unwrap_or(&0))
            .map_err(|_| ctx.err(line_of(oa), "negative offset"))?;
        let conn = g.ints(ca, conn_len, line_of(ca))?;
        let ta = array("Cells", Some("types"))?;
        let types = g.ints(ta, nc, line_of(ta))?;
        let mut offsets = Vec::with_capacity(nc + 1);
        offsets.push(0);
        offsets.extend_from_slice(&ends);
        let where_ = |c: usize| (line_of(ca), format!("piece {} cell {c}", pieces - 1));
        match crate::mesh::io::vtk::grid_tets(ctx, np, &offsets, &conn, &types, &where_) {
            Ok(t) => tets.extend(t.into_iter().map(|t| t.map(|v| v + base as u32))),
            Err(e @ Error::Parse { line: None, .. }) => no_tets = Some(e),
            Err(e) => return Err(e),
        }
    }
    if pieces == 0 {
        return Err(ctx.err(line_of(grid), "no <Piece> in the UnstructuredGrid"));
    }
    if tets.is_empty() {
        return Err(no_tets.unwrap_or_else(|| ctx.err(None, "no cells: no tetrahedra in the file")));
    }
    if u32::try_from(nodes.len()).is_err() {
        return Err(ctx.err(None, "more points than 32-bit indices hold"));
    }
    crate::mesh::io::finish_tets(nodes, tets)
}

/// The numeric type named by a DataArray's `type`.
fn num_type(name: &str) -> Option<Num> {
    Some(match name {
        "Int8" | "Char" => Num::I8,
        "UInt8" => Num::U8,
        "Int16" => Num::I16,
        "UInt16" => Num::U16,
        "Int32" => Num::I32,
        "UInt32" => Num::U32,
        "Int64" => Num::I64,
        "UInt64" => Num::U64,
        "Float32" => Num::F32,
        "Float64" => Num::F64,
        _ => return None,
    })
}

impl Grid<'_> {
    fn floats(
        &self,
        a: roxmltree::Node<'_, '_>,
        n: usize,
        line: Option<usize>,
    ) -> Result<Vec<f64>> {
        match self.raw(a, n, line)? {
            Data::Text(t) => self.text(t, n, line, |s| s.parse::<f64>().ok()),
            Data::Binary(b, num) => Ok(decode_f64(&b, num, self.endian)),
        }
    }

    fn ints(&self, a: roxmltree::Node<'_, '_>, n: usize, line: Option<usize>) -> Result<Vec<i64>> {
        match self.raw(a, n, line)? {
            Data::Text(t) => self.text(t, n, line, |s| s.parse::<i64>().ok()),
            Data::Binary(b, num) if num.is_float() => Err(self.ctx.err(
                line,
                format!(
                    "{num:?} data where integers are expected ({} bytes)",
                    b.len()
                ),
            )),
            Data::Binary(b, num) => Ok(decode_i64(&b, num, self.endian)),
        }
    }

    fn text<T>(
        &self,
        t: &str,
        n: usize,
        line: Option<usize>,
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<Vec<T>> {
        let mut out = Vec::with_capacity(n.min(t.len() / 2 + 1));
        for (i, tok) in t.split_ascii_whitespace().enumerate() {
            if i == n {
                return Err(self
                    .ctx
                    .err(line, format!("more than the {n} values expected")));
            }
            out.push(parse(tok).ok_or_else(|| {
                self.ctx.err(
                    line,
                    format!(
                        "value {i}: `{}` is not a number of the array's type",
                        crate::mesh::io::text::show(tok.as_bytes())
                    ),
                )
            })?);
        }
        if out.len() != n {
            return Err(self.ctx.err(
                line,
                format!("{} values, expected {n} (truncated?)", out.len()),
            ));
        }
        Ok(out)
    }

    /// The array's data: text, or the decoded bytes (exactly `n` values) and their type.
    fn raw<'d>(
        &self,
        a: roxmltree::Node<'d, 'd>,
        n: usize,
        line: Option<usize>,
    ) -> Result<Data<'d>> {
        let ty = a.attribute("type").unwrap_or("(none)");
        let num = num_type(ty)
            .ok_or_else(|| self.ctx.err(line, format!("unknown DataArray type {ty:?}")))?;
        let bytes = match a.attribute("format").unwrap_or("ascii") {
            "ascii" => return Ok(Data::Text(a.text().unwrap_or(""))),
            "binary" => {
                let text = a.text().unwrap_or("").as_bytes();
                let decoded = base64(text).map_err(|m| self.ctx.err(line, m))?;
                self.block(&decoded, num, n, line)?
            }
            "appended" => {
                let ap = self.appended.as_ref().ok_or_else(|| {
                    self.ctx.err(
                        line,
                        "format=\"appended\" but the file has no <AppendedData>",
                    )
                })?;
                let off: usize = a
                    .attribute("offset")
                    .and_then(|o| o.trim().parse().ok())
                    .filter(|&o| o <= ap.data.len())
                    .ok_or_else(|| {
                        self.ctx.err(
                            line,
                            "the appended array's offset is missing or past the data",
                        )
                    })?;
                if ap.base64 {
                    let end = ap
                        .offsets
                        .iter()
                        .copied()
                        .find(|&o| o > off)
                        .unwrap_or(ap.data.len())
                        .min(ap.data.len());
                    let decoded = base64(&ap.data[off..end]).map_err(|m| self.ctx.err(line, m))?;
                    self.block(&decoded, num, n, line)?
                } else {
                    self.block(&ap.data[off..], num, n, line)?
                }
            }
            f => {
                return Err(self.ctx.err(
                    line,
                    format!("DataArray format {f:?}; expected ascii, binary or appended"),
                ))
            }
        };
        Ok(Data::Binary(bytes, num))
    }

    /// Reads `n` values of `num` from a header-prefixed (and maybe compressed) block.
    fn block(&self, b: &[u8], num: Num, n: usize, line: Option<usize>) -> Result<Vec<u8>> {
        let err = |m: String| self.ctx.err(line, m);
        let want = n
            .checked_mul(num.size())
            .ok_or_else(|| err("array too large".into()))?;
        let hs = self.header.size();
        let word = |i: usize| -> Result<u64> {
            let s = b
                .get(i * hs..(i + 1) * hs)
                .ok_or_else(|| err("the data ends inside its header (truncated?)".into()))?;
            Ok(decode_i64(s, self.header, self.endian)[0].max(0) as u64)
        };
        if !self.zlib {
            let len = word(0)?;
            if len < want as u64 {
                return Err(err(format!(
                    "{len} bytes of data, {want} expected for {n} values"
                )));
            }
            return b.get(hs..hs + want).map(<[u8]>::to_vec).ok_or_else(|| {
                err(format!(
                    "the data ends before its {want} bytes (truncated?)"
                ))
            });
        }
        let blocks = usize::try_from(word(0)?).unwrap_or(usize::MAX);
        let block_size = word(1)?;
        let last = word(2)?;
        if blocks > b.len() / hs {
            return Err(err(format!(
                "{blocks} compressed blocks do not fit in the data"
            )));
        }
        let mut pos = hs * (3 + blocks);
        if pos > b.len() {
            return Err(err(
                "the data ends inside its compression header (truncated?)".into(),
            ));
        }
        // The values' size comes from the file: reserve no more than the compressed bytes
        // can inflate to (zlib's largest ratio); the blocks' own checks bound the rest.
        let mut out = Vec::with_capacity(want.min(b.len().saturating_mul(ZLIB_LARGEST_RATIO)));
        for k in 0..blocks {
            let csize = usize::try_from(word(3 + k)?).unwrap_or(usize::MAX);
            let chunk = b.get(pos..pos.saturating_add(csize)).ok_or_else(|| {
                err(format!(
                    "compressed block {k} ends past the data (truncated?)"
                ))
            })?;
            pos += csize;
            let usize_ = if k + 1 == blocks && last != 0 {
                last
            } else {
                block_size
            };
            // Never inflate more than the values need (a lying header cannot make us allocate).
            let room = (want - out.len().min(want)) as u64;
            if usize_ > room {
                return Err(err(format!(
                    "block {k} inflates to {usize_} bytes; {room} are left of the {want} expected"
                )));
            }
            let before = out.len();
            flate2::read::ZlibDecoder::new(chunk)
                .take(usize_)
                .read_to_end(&mut out)
                .map_err(|e| err(format!("compressed block {k}: {e}")))?;
            if (out.len() - before) as u64 != usize_ {
                return Err(err(format!(
                    "compressed block {k} inflates to {} bytes, not {usize_}",
                    out.len() - before
                )));
            }
        }
        if out.len() != want {
            return Err(err(format!(
                "{} bytes of data, {want} expected for {n} values",
                out.len()
            )));
        }
        Ok(out)
    }
}

/// The most bytes one compressed byte can inflate to with zlib (deflate's limit is about
/// 1032 to 1; a file that claims more values than its blocks can hold is refused by them).
const ZLIB_LARGEST_RATIO: usize = 1032;

enum Data<'d> {
    Text(&'d str),
    Binary(Vec<u8>, Num),
}

/// Decodes base64, skipping whitespace and accepting padding inside the text (VTK encodes a
/// compressed array's header and data as two base64 runs, one after the other).
fn base64(text: &[u8]) -> std::result::Result<Vec<u8>, String> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    let mut quad = [0u8; 4];
    let mut k = 0;
    for (i, &c) in text.iter().enumerate() {
        if c.is_ascii_whitespace() {
            continue;
        }
        if c != b'=' && value(c).is_none() {
            return Err(format!("base64 data: character {i} is `{}`", c as char));
        }
        quad[k] = c;
        k += 1;
        if k == 4 {
            k = 0;
            let pads = quad.iter().rev().take_while(|&&c| c == b'=').count();
            if pads > 2 || quad[..4 - pads].contains(&b'=') {
                return Err(format!("base64 data: misplaced `=` before character {i}"));
            }
            let mut v = 0u32;
            for &q in &quad {
                v = (v << 6) | value(q).unwrap_or(0);
            }
            let b = v.to_be_bytes();
            out.extend_from_slice(&b[1..4 - pads]);
        }
    }
    if k != 0 {
        return Err(
            "base64 data: the text ends inside a group of four characters (truncated?)".into(),
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::base64;

    #[test]
    fn base64_decodes_concatenated_runs() {
        assert_eq!(base64(b"TWFu").unwrap(), b"Man");
        assert_eq!(base64(b"TWE=TQ==").unwrap(), b"MaM");
        assert_eq!(base64(b" TW\nFu ").unwrap(), b"Man");
        assert!(base64(b"TWF").is_err());
        assert!(base64(b"T=Fu").is_err());
        assert!(base64(b"TW*u").is_err());
    }
}
