//! Stanford PLY: ASCII, binary little-endian and binary big-endian.
//!
//! Reading takes any element layout: `x`, `y`, `z` of the `vertex` element in any scalar type,
//! any further vertex properties (skipped, e.g. the Stanford scans' `confidence` and
//! `intensity`), the `face` element's `vertex_indices` (or `vertex_index`) list with any
//! integer count and index types, polygons split into triangle fans, and any other elements
//! (skipped). Errors name the line (ASCII) or the element index (binary).
//!
//! Writing uses `double` coordinates (so values read back exactly) and `list uchar int`
//! faces, the layout every PLY reader accepts.

use super::text::{capacity, fan, finite_point, parse_f64, parse_i64, show, Ctx, Lines};
use super::{check_surface, fmt_f64, read_bytes, write_atomic};
use crate::error::Result;
use crate::mesh::SurfaceMesh;
use std::io::Write;
use std::path::Path;

/// How a PLY file is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlyEncoding {
    /// Text, one element per line.
    Ascii,
    /// Binary, little-endian (the usual choice).
    BinaryLittleEndian,
    /// Binary, big-endian.
    BinaryBigEndian,
}

/// A PLY scalar type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
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
    fn from_name(name: &str) -> Option<Self> {
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
    fn name(self) -> &'static str {
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
    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
    fn is_int(self) -> bool {
        !matches!(self, Self::F32 | Self::F64)
    }
}

#[derive(Debug, Clone, Copy)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<(String, Kind)>,
}

impl Element {
    /// The fewest bytes one element can take in the binary encoding.
    fn min_binary_size(&self) -> usize {
        self.props
            .iter()
            .map(|(_, k)| match k {
                Kind::Scalar(s) => s.size(),
                Kind::List { count, .. } => count.size(),
            })
            .sum()
    }
    fn find(&self, names: &[&str]) -> Option<usize> {
        self.props
            .iter()
            .position(|(n, _)| names.contains(&n.as_str()))
    }
}

struct Header {
    encoding: PlyEncoding,
    elements: Vec<Element>,
    /// Byte offset of the body.
    body: usize,
    /// Number of header lines (the body's first line is `lines + 1`).
    lines: usize,
}

/// Reads a PLY file.
pub fn read(path: impl AsRef<Path>) -> Result<SurfaceMesh> {
    let path = path.as_ref();
    parse(&read_bytes(path)?, path)
}

/// Parses the bytes of a PLY file; `path` is used in error messages only.
pub fn parse(bytes: &[u8], path: &Path) -> Result<SurfaceMesh> {
    let ctx = Ctx { path };
    let header = parse_header(bytes, ctx)?;
    let body = bytes.get(header.body..).unwrap_or(&[]);
    match header.encoding {
        PlyEncoding::Ascii => {
            let lines = Lines::new(body, None);
            let mut src = AsciiSource {
                lines,
                tokens: Vec::new(),
                next: 0,
                no: 0,
                offset: header.lines,
            };
            read_body(&mut src, &header, body.len(), ctx)
        }
        enc => {
            let mut src = BinarySource {
                data: body,
                pos: 0,
                big: enc == PlyEncoding::BinaryBigEndian,
            };
            read_body(&mut src, &header, body.len(), ctx)
        }
    }
}

fn parse_header(bytes: &[u8], ctx: Ctx<'_>) -> Result<Header> {
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

/// Where element values come from: ASCII lines or binary bytes.
trait Source {
    /// Starts the next element.
    fn begin(&mut self) -> std::result::Result<(), String>;
    /// The next value, converted to `f64` (exact for every PLY integer type).
    fn value(&mut self, ty: Scalar) -> std::result::Result<f64, String>;
    /// Ends an element.
    fn end(&mut self) -> std::result::Result<(), String>;
    /// The current line, for text.
    fn line(&self) -> Option<usize>;
    /// The fewest bytes an element can take.
    fn min_size(&self, e: &Element) -> usize;
}

struct AsciiSource<'a> {
    lines: Lines<'a>,
    tokens: Vec<&'a [u8]>,
    next: usize,
    no: usize,
    offset: usize,
}

impl Source for AsciiSource<'_> {
    fn begin(&mut self) -> std::result::Result<(), String> {
        let line = self
            .lines
            .next()
            .ok_or("the file ends here (fewer elements than the header declares)")?;
        self.no = line.no + self.offset;
        self.tokens = line.tokens;
        self.next = 0;
        Ok(())
    }
    fn value(&mut self, ty: Scalar) -> std::result::Result<f64, String> {
        let t = self
            .tokens
            .get(self.next)
            .ok_or("the line has fewer values than the header declares")?;
        self.next += 1;
        let v = if ty.is_int() {
            parse_i64(t).map(|i| i as f64)
        } else {
            parse_f64(t)
        };
        v.ok_or_else(|| format!("`{}` is not a valid {}", show(t), ty.name()))
    }
    fn end(&mut self) -> std::result::Result<(), String> {
        match self.tokens.len() - self.next.min(self.tokens.len()) {
            0 => Ok(()),
            n => Err(format!(
                "the line has {n} more values than the header declares"
            )),
        }
    }
    fn line(&self) -> Option<usize> {
        Some(self.no)
    }
    fn min_size(&self, e: &Element) -> usize {
        2 * e.props.len()
    }
}

struct BinarySource<'a> {
    data: &'a [u8],
    pos: usize,
    big: bool,
}

impl BinarySource<'_> {
    fn take<const N: usize>(&mut self) -> std::result::Result<[u8; N], String> {
        let bytes = self
            .data
            .get(self.pos..self.pos.saturating_add(N))
            .and_then(|b| <[u8; N]>::try_from(b).ok())
            .ok_or_else(|| {
                format!(
                    "binary PLY too short: data ends at byte {} of the body",
                    self.data.len()
                )
            })?;
        self.pos += N;
        Ok(bytes)
    }
}

impl Source for BinarySource<'_> {
    fn begin(&mut self) -> std::result::Result<(), String> {
        Ok(())
    }
    fn value(&mut self, ty: Scalar) -> std::result::Result<f64, String> {
        macro_rules! num {
            ($t:ty) => {{
                let b = self.take()?;
                (if self.big {
                    <$t>::from_be_bytes(b)
                } else {
                    <$t>::from_le_bytes(b)
                }) as f64
            }};
        }
        Ok(match ty {
            Scalar::I8 => num!(i8),
            Scalar::U8 => num!(u8),
            Scalar::I16 => num!(i16),
            Scalar::U16 => num!(u16),
            Scalar::I32 => num!(i32),
            Scalar::U32 => num!(u32),
            Scalar::F32 => num!(f32),
            Scalar::F64 => num!(f64),
        })
    }
    fn end(&mut self) -> std::result::Result<(), String> {
        Ok(())
    }
    fn line(&self) -> Option<usize> {
        None
    }
    fn min_size(&self, e: &Element) -> usize {
        e.min_binary_size()
    }
}

/// What one element of the file means to us.
enum Role {
    Vertex([usize; 3]),
    Face(usize),
    Skip,
}

fn read_body<S: Source>(
    src: &mut S,
    header: &Header,
    body_len: usize,
    ctx: Ctx<'_>,
) -> Result<SurfaceMesh> {
    let vertex_elems: Vec<&Element> = header
        .elements
        .iter()
        .filter(|e| e.name == "vertex")
        .collect();
    let [vertex_elem] = vertex_elems[..] else {
        return Err(ctx.err(
            None,
            format!(
                "expected one `vertex` element, found {}",
                vertex_elems.len()
            ),
        ));
    };
    let n_vertices = vertex_elem.count;
    if u32::try_from(n_vertices).is_err() {
        return Err(ctx.err(
            None,
            format!("{n_vertices} vertices do not fit in 32-bit indices"),
        ));
    }
    let mut mesh = SurfaceMesh::default();
    let mut saw_faces = false;
    let mut coords = [0.0; 3];
    let mut poly: Vec<u32> = Vec::new();
    for elem in &header.elements {
        let role = match elem.name.as_str() {
            "vertex" => {
                let mut idx = [0; 3];
                for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                    idx[k] = match elem.find(&[axis]) {
                        Some(j) if matches!(elem.props[j].1, Kind::Scalar(_)) => j,
                        _ => {
                            return Err(ctx.err(
                                None,
                                format!("the vertex element has no scalar property `{axis}`"),
                            ))
                        }
                    };
                }
                mesh.vertices
                    .reserve(capacity(elem.count, body_len, src.min_size(elem)));
                Role::Vertex(idx)
            }
            "face" => {
                let j = elem.find(&["vertex_indices", "vertex_index"]);
                let Some(j) = j.filter(|&j| matches!(elem.props[j].1, Kind::List { .. })) else {
                    return Err(ctx.err(
                        None,
                        "the face element has no list property `vertex_indices` or `vertex_index`",
                    ));
                };
                saw_faces = true;
                mesh.triangles
                    .reserve(capacity(elem.count, body_len, src.min_size(elem)));
                Role::Face(j)
            }
            _ => Role::Skip,
        };
        for i in 0..elem.count {
            let at = |src: &S, m: String| {
                ctx.err(
                    src.line(),
                    format!("{} {i} of {}: {m}", elem.name, elem.count),
                )
            };
            src.begin().map_err(|m| at(src, m))?;
            poly.clear();
            for (j, (name, kind)) in elem.props.iter().enumerate() {
                match *kind {
                    Kind::Scalar(ty) => {
                        let v = src
                            .value(ty)
                            .map_err(|m| at(src, format!("property `{name}`: {m}")))?;
                        if let Role::Vertex(idx) = &role {
                            if let Some(k) = idx.iter().position(|&x| x == j) {
                                coords[k] = v;
                            }
                        }
                    }
                    Kind::List { count, item } => {
                        let n = src
                            .value(count)
                            .map_err(|m| at(src, format!("list `{name}` count: {m}")))?;
                        if n < 0.0 {
                            return Err(at(src, format!("list `{name}` has a negative count {n}")));
                        }
                        let keep = matches!(role, Role::Face(f) if f == j);
                        for _ in 0..n as u64 {
                            let v = src
                                .value(item)
                                .map_err(|m| at(src, format!("list `{name}`: {m}")))?;
                            if keep {
                                if !(v >= 0.0 && v < n_vertices as f64 && v.fract() == 0.0) {
                                    return Err(at(
                                        src,
                                        format!("vertex index {v} is out of range (the file has {n_vertices} vertices)"),
                                    ));
                                }
                                poly.push(v as u32);
                            }
                        }
                    }
                }
            }
            src.end().map_err(|m| at(src, m))?;
            match role {
                Role::Vertex(_) => mesh
                    .vertices
                    .push(finite_point(coords).map_err(|m| at(src, m))?),
                Role::Face(_) if poly.len() < 3 => {
                    return Err(at(
                        src,
                        format!(
                            "a face needs at least 3 vertices, this one has {}",
                            poly.len()
                        ),
                    ))
                }
                Role::Face(_) => fan(&poly, &mut mesh.triangles),
                Role::Skip => {}
            }
        }
    }
    if !saw_faces {
        return Err(ctx.err(
            None,
            "the file has no `face` element: a point cloud is not a surface",
        ));
    }
    if mesh.vertices.is_empty() || mesh.triangles.is_empty() {
        return Err(ctx.err(
            None,
            format!(
                "empty mesh: {} vertices, {} triangles",
                mesh.vertices.len(),
                mesh.triangles.len()
            ),
        ));
    }
    Ok(mesh)
}

/// Writes `mesh` as PLY in `encoding`, atomically.
pub fn write(path: impl AsRef<Path>, mesh: &SurfaceMesh, encoding: PlyEncoding) -> Result<()> {
    check_surface(mesh)?;
    write_atomic(path.as_ref(), |w| write_to(w, mesh, encoding))
}

fn write_to(w: &mut dyn Write, mesh: &SurfaceMesh, encoding: PlyEncoding) -> std::io::Result<()> {
    let format = match encoding {
        PlyEncoding::Ascii => "ascii",
        PlyEncoding::BinaryLittleEndian => "binary_little_endian",
        PlyEncoding::BinaryBigEndian => "binary_big_endian",
    };
    let index_type = if mesh.vertices.len() <= i32::MAX as usize {
        "int"
    } else {
        "uint"
    };
    write!(
        w,
        "ply\nformat {format} 1.0\ncomment written by tetrasim\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\nelement face {}\n\
         property list uchar {index_type} vertex_indices\nend_header\n",
        mesh.vertices.len(),
        mesh.triangles.len()
    )?;
    let big = encoding == PlyEncoding::BinaryBigEndian;
    let f64_bytes = |x: f64| {
        if big {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    let u32_bytes = |x: u32| {
        if big {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    for v in &mesh.vertices {
        match encoding {
            PlyEncoding::Ascii => {
                writeln!(w, "{} {} {}", fmt_f64(v.x), fmt_f64(v.y), fmt_f64(v.z))?
            }
            _ => {
                for c in v.to_array() {
                    w.write_all(&f64_bytes(c))?;
                }
            }
        }
    }
    for t in &mesh.triangles {
        match encoding {
            PlyEncoding::Ascii => writeln!(w, "3 {} {} {}", t[0], t[1], t[2])?,
            _ => {
                w.write_all(&[3])?;
                for i in t {
                    w.write_all(&u32_bytes(*i))?;
                }
            }
        }
    }
    Ok(())
}
