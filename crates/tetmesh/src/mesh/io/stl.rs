//! STL, ASCII and binary. Vertices are welded on read (STL stores every triangle's corners
//! separately): corners with bit-identical coordinates become one vertex.
//!
//! A file is binary when its size is exactly `84 + 50 * count` for the facet count stored at
//! byte 80 (the rule most readers use, since many binary files also start with `solid`),
//! ASCII when it starts with `solid` and holds no NUL byte, and otherwise an error that says
//! which rule failed. Binary errors name the facet; ASCII errors name the line.
//! Writing is binary, single precision, through the `stl_io` crate.

use super::text::{finite_point, show, Ctx, Lines};
use super::{check_surface, read_bytes, write_atomic};
use crate::error::{Error, Result};
use crate::mesh::SurfaceMesh;
use glam::DVec3;
use std::collections::HashMap;
use std::path::Path;

/// Reads an STL file (ASCII or binary).
pub fn read(path: impl AsRef<Path>) -> Result<SurfaceMesh> {
    let path = path.as_ref();
    parse(&read_bytes(path)?, path)
}

/// Parses the bytes of an STL file; `path` is used in error messages only.
pub fn parse(bytes: &[u8], path: &Path) -> Result<SurfaceMesh> {
    let ctx = Ctx { path };
    let count = bytes
        .get(80..84)
        .and_then(|b| <[u8; 4]>::try_from(b).ok())
        .map(u32::from_le_bytes);
    let binary_size = count.map(|c| 84 + 50 * c as u64);
    let starts_solid = {
        let start = bytes
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .unwrap_or(bytes.len());
        bytes
            .get(start..start + 5)
            .is_some_and(|w| w.eq_ignore_ascii_case(b"solid"))
    };
    let mut weld = Welder::default();
    if binary_size == Some(bytes.len() as u64) {
        parse_binary(bytes, &mut weld, ctx)?;
    } else if starts_solid && !bytes.contains(&0) {
        parse_ascii(bytes, &mut weld, ctx)?;
    } else if let (Some(count), Some(size)) = (count, binary_size) {
        return Err(ctx.err(
            None,
            format!(
                "binary STL with a wrong size: the header declares {count} facets ({size} bytes), \
                 the file has {} bytes (truncated?)",
                bytes.len()
            ),
        ));
    } else {
        return Err(ctx.err(
            None,
            format!(
                "not an STL file: {} bytes, too short for a binary STL (84-byte header) and not \
                 starting with `solid`",
                bytes.len()
            ),
        ));
    }
    if weld.mesh.triangles.is_empty() {
        return Err(ctx.err(None, "empty mesh: no facets"));
    }
    Ok(weld.mesh)
}

/// Builds the indexed mesh, merging bit-identical corners.
#[derive(Default)]
struct Welder {
    mesh: SurfaceMesh,
    index: HashMap<[u64; 3], u32>,
}

impl Welder {
    fn add(&mut self, corners: [DVec3; 3]) -> std::result::Result<(), String> {
        let mut tri = [0; 3];
        for (k, p) in corners.iter().enumerate() {
            // `+ 0.0` turns -0.0 into 0.0 so the two weld together.
            let key = (*p + DVec3::ZERO).to_array().map(f64::to_bits);
            let next = self.mesh.vertices.len();
            tri[k] = match self.index.get(&key) {
                Some(&i) => i,
                None => {
                    let i = u32::try_from(next)
                        .map_err(|_| "more than 2^32 distinct vertices".to_string())?;
                    self.index.insert(key, i);
                    self.mesh.vertices.push(*p);
                    i
                }
            };
        }
        self.mesh.triangles.push(tri);
        Ok(())
    }
}

fn parse_binary(bytes: &[u8], weld: &mut Welder, ctx: Ctx<'_>) -> Result<()> {
    let facets = bytes.get(84..).unwrap_or(&[]).chunks_exact(50);
    for (f, rec) in facets.enumerate() {
        let float = |i: usize| {
            rec.get(i * 4..i * 4 + 4)
                .and_then(|b| <[u8; 4]>::try_from(b).ok())
                .map_or(f64::NAN, |b| f32::from_le_bytes(b) as f64)
        };
        let mut corners = [DVec3::ZERO; 3];
        for (k, c) in corners.iter_mut().enumerate() {
            let at = 3 + 3 * k; // skip the normal
            *c = finite_point([float(at), float(at + 1), float(at + 2)])
                .map_err(|m| ctx.err(None, format!("facet {f} vertex {k} has a {m}")))?;
        }
        weld.add(corners)
            .map_err(|m| ctx.err(None, format!("facet {f}: {m}")))?;
    }
    Ok(())
}

fn parse_ascii(bytes: &[u8], weld: &mut Welder, ctx: Ctx<'_>) -> Result<()> {
    let mut lines = Lines::new(bytes, None);
    let mut facet = 0usize;
    let mut in_solid = false;
    let expect = |lines: &mut Lines<'_>, word: &str| -> Result<()> {
        let at = lines.line_no() + 1;
        match lines.next() {
            Some(l)
                if l.tokens
                    .first()
                    .is_some_and(|t| t.eq_ignore_ascii_case(word.as_bytes())) =>
            {
                Ok(())
            }
            Some(l) => Err(ctx.err(
                Some(l.no),
                format!("expected `{word}`, found `{}`", show(l.head())),
            )),
            None => Err(ctx.err(
                Some(at),
                format!("the file ends where `{word}` is expected (truncated?)"),
            )),
        }
    };
    loop {
        let Some(line) = lines.next() else {
            return match in_solid {
                true => Err(ctx.err(
                    None,
                    "the file ends inside a solid: `endsolid` is missing (truncated?)",
                )),
                false => Ok(()),
            };
        };
        let key = line.head().to_ascii_lowercase();
        match (key.as_slice(), in_solid) {
            (b"solid", false) => in_solid = true,
            (b"endsolid", true) => in_solid = false,
            (b"facet", true) => {
                expect(&mut lines, "outer")?;
                let mut corners = [DVec3::ZERO; 3];
                for (k, c) in corners.iter_mut().enumerate() {
                    let what = format!("facet {facet} vertex {k}");
                    let v = lines
                        .next()
                        .ok_or_else(|| ctx.err(None, format!("the file ends before {what}")))?;
                    if !v.head().eq_ignore_ascii_case(b"vertex") {
                        return Err(ctx.err(
                            Some(v.no),
                            format!("{what}: expected `vertex`, found `{}`", show(v.head())),
                        ));
                    }
                    *c = ctx.point(&v, 1, &what)?;
                }
                expect(&mut lines, "endloop")?;
                expect(&mut lines, "endfacet")?;
                weld.add(corners)
                    .map_err(|m| ctx.err(Some(line.no), format!("facet {facet}: {m}")))?;
                facet += 1;
            }
            _ => {
                let expected = if in_solid {
                    "`facet` or `endsolid`"
                } else {
                    "`solid`"
                };
                return Err(ctx.err(
                    Some(line.no),
                    format!("expected {expected}, found `{}`", show(line.head())),
                ));
            }
        }
    }
}

/// Writes `mesh` as binary STL (single precision, normals from the corner order), atomically.
pub fn write(path: impl AsRef<Path>, mesh: &SurfaceMesh) -> Result<()> {
    check_surface(mesh)?;
    if u32::try_from(mesh.triangles.len()).is_err() {
        return Err(Error::Mesh(format!(
            "{} triangles do not fit in a binary STL",
            mesh.triangles.len()
        )));
    }
    if let Some(i) = mesh
        .vertices
        .iter()
        .position(|v| v.abs().max_element() > f32::MAX as f64)
    {
        return Err(Error::Mesh(format!(
            "vertex {i} ({}) does not fit in single precision",
            mesh.vertices[i]
        )));
    }
    let corner = |i: u32| {
        let p = mesh.vertices.get(i as usize).copied().unwrap_or_default();
        stl_io::Vertex::new(p.as_vec3().to_array())
    };
    let triangles = mesh.triangles.iter().map(|t| {
        let [a, b, c] = t.map(|i| mesh.vertices.get(i as usize).copied().unwrap_or_default());
        let n = (b - a).cross(c - a).normalize_or_zero();
        stl_io::Triangle {
            normal: stl_io::Normal::new(n.as_vec3().to_array()),
            vertices: t.map(corner),
        }
    });
    write_atomic(path.as_ref(), |mut w| stl_io::write_stl(&mut w, triangles))
}
