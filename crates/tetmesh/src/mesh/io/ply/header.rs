//! The PLY header: format, elements and their properties.

use super::PlyEncoding;
use crate::error::Result;
use crate::mesh::io::text::{show, Ctx};

/// A PLY scalar type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    pub(super) fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }
    pub(super) fn name(self) -> &'static str {
        match self {
            Self::I8 => "char",
            Self::U8 => "uchar",
            Self::I16 => "short",
            Self::U16 => "ushort",
            Self::I32 => "int",
            Self::U32 => "uint",
            Self::F32 => "float",
            Self::F64 => "double",
        }
    }
    pub(super) fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
    pub(super) fn is_int(self) -> bool {
        !matches!(self, Self::F32 | Self::F64)
    }
}

#[derive(Debug, Clone, Copy)]
pub(super) enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) count: usize,
    pub(super) props: Vec<(String, Kind)>,
}

impl Element {
    /// The fewest bytes one element can take in the binary encoding.
    pub(super) fn min_binary_size(&self) -> usize {
        self.props
            .iter()
            .map(|(_, k)| match k {
                Kind::Scalar(s) => s.size(),
                Kind::List { count, .. } => count.size(),
            })
            .sum()
    }
    pub(super) fn find(&self, names: &[&str]) -> Option<usize> {
        self.props
            .iter()
            .position(|(n, _)| names.contains(&n.as_str()))
    }
}

pub(super) struct Header {
    pub(super) encoding: PlyEncoding,
    pub(super) elements: Vec<Element>,
    /// Byte offset of the body.
    pub(super) body: usize,
    /// Number of header lines (the body's first line is `lines + 1`).
    pub(super) lines: usize,
}

pub(super) fn parse_header(bytes: &[u8], ctx: Ctx<'_>) -> Result<Header> {
    let mut pos = 0;
    let mut no = 0;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some(rest) = bytes.get(pos..).filter(|r| !r.is_empty()) else {
            return Err(ctx.err(
                Some(no.max(1)),
                "PLY header ends without `end_header` (truncated file?)",
            ));
        };
        let end = rest.iter().position(|&b| b == b'\n');
        let line = &rest[..end.unwrap_or(rest.len())];
        pos += end.map_or(rest.len(), |e| e + 1);
        no += 1;
        let words: Vec<&[u8]> = line
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty())
            .collect();
        let word = |i: usize| {
            words
                .get(i)
                .map(|w| String::from_utf8_lossy(w).into_owned())
        };
        let err = |m: String| ctx.err(Some(no), m);
        if no == 1 {
            if words.first() != Some(&&b"ply"[..]) {
                return Err(err("not a PLY file: the first line is not `ply`".into()));
            }
            continue;
        }
        let Some(key) = word(0) else { continue };
        match key.as_str() {
            "comment" | "obj_info" => {}
            "format" => {
                encoding = Some(match word(1).as_deref() {
                    Some("ascii") => PlyEncoding::Ascii,
                    Some("binary_little_endian") => PlyEncoding::BinaryLittleEndian,
                    Some("binary_big_endian") => PlyEncoding::BinaryBigEndian,
                    other => {
                        return Err(err(format!(
                            "unknown PLY format `{}`",
                            other.unwrap_or_default()
                        )))
                    }
                })
            }
            "element" => {
                let (Some(name), Some(count)) = (word(1), word(2)) else {
                    return Err(err("`element` needs a name and a count".into()));
                };
                let count = count.parse::<usize>().map_err(|_| {
                    err(format!(
                        "element `{name}`: count `{count}` is not a non-negative integer"
                    ))
                })?;
                elements.push(Element {
                    name,
                    count,
                    props: Vec::new(),
                });
            }
            "property" => {
                let Some(elem) = elements.last_mut() else {
                    return Err(err("`property` before any `element`".into()));
                };
                let scalar = |i: usize| -> Result<Scalar> {
                    let t = word(i).unwrap_or_default();
                    Scalar::from_name(&t).ok_or_else(|| err(format!("unknown PLY type `{t}`")))
                };
                let (kind, name_at) = if word(1).as_deref() == Some("list") {
                    let (count, item) = (scalar(2)?, scalar(3)?);
                    if !count.is_int() {
                        return Err(err(format!(
                            "list count type must be an integer type, not {count:?}"
                        )));
                    }
                    (Kind::List { count, item }, 4)
                } else {
                    (Kind::Scalar(scalar(1)?), 2)
                };
                let name = word(name_at).ok_or_else(|| err("property without a name".into()))?;
                elem.props.push((name, kind));
            }
            "end_header" => break,
            other => {
                return Err(err(format!(
                    "unknown PLY header keyword `{}`",
                    show(other.as_bytes())
                )))
            }
        }
    }
    let encoding = encoding.ok_or_else(|| ctx.err(Some(no), "PLY header has no `format` line"))?;
    Ok(Header {
        encoding,
        elements,
        body: pos,
        lines: no,
    })
}
