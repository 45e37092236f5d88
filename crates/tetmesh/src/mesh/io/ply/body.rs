//! The PLY body: element values from ASCII lines or binary bytes, turned into a surface.

use super::header::{Element, Header, Kind, Scalar};
use crate::error::Result;
use crate::mesh::io::text::{capacity, fan, finite_point, parse_f64, parse_i64, show, Ctx, Lines};
use crate::mesh::SurfaceMesh;

/// Where element values come from: ASCII lines or binary bytes.
pub(super) trait Source {
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
    /// Whether each element takes a line (text) even when it has no properties.
    fn element_per_line(&self) -> bool;
}

pub(super) struct AsciiSource<'a> {
    pub(super) lines: Lines<'a>,
    pub(super) tokens: Vec<&'a [u8]>,
    pub(super) next: usize,
    pub(super) no: usize,
    pub(super) offset: usize,
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
    fn element_per_line(&self) -> bool {
        true
    }
}

pub(super) struct BinarySource<'a> {
    pub(super) data: &'a [u8],
    pub(super) pos: usize,
    pub(super) big: bool,
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
    fn element_per_line(&self) -> bool {
        false
    }
}

/// What one element of the file means to us.
enum Role {
    Vertex([usize; 3]),
    Face(usize),
    Skip,
}

pub(super) fn read_body<S: Source>(
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
        if elem.props.is_empty() && !src.element_per_line() {
            // Binary elements without properties take no bytes: however many the header
            // declares (a fuzzer's 35 trillion took minutes one by one), there is nothing
            // to read.
            continue;
        }
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
