//! Stanford PLY: ASCII, binary little-endian and binary big-endian.
//!
//! Reading takes any element layout: `x`, `y`, `z` of the `vertex` element in any scalar type,
//! any further vertex properties (skipped, e.g. the Stanford scans' `confidence` and
//! `intensity`), the `face` element's `vertex_indices` (or `vertex_index`) list with any
//! integer count and index types, polygons split into triangle fans, and any other elements
//! (skipped). ASCII bodies are read one element per line, as every writer produces them, so a
//! wrong count in the header shows up as a line with too few or too many values. Errors name
//! the line (ASCII) or the element index (binary).
//!
//! Writing uses `double` coordinates (so values read back exactly) and `list uchar int`
//! faces, the layout every PLY reader accepts.

mod body;
mod header;

use super::text::{Ctx, Lines};
use super::{check_surface, fmt_f64, read_bytes, write_atomic};
use crate::error::{Error, Result};
use crate::mesh::SurfaceMesh;
use body::{read_body, AsciiSource, BinarySource};
use header::parse_header;
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

/// Writes `mesh` as PLY in `encoding`, atomically.
pub fn write(path: impl AsRef<Path>, mesh: &SurfaceMesh, encoding: PlyEncoding) -> Result<()> {
    check_surface(mesh)?;
    write_atomic(path.as_ref(), |w| write_to(w, mesh, encoding, None))
}

/// Writes `mesh` with one `quality` value per vertex (`property float quality`, the vertex
/// property MeshLab colours by with "Colorize by vertex quality"). Values must be finite.
pub fn write_with_quality(
    path: impl AsRef<Path>,
    mesh: &SurfaceMesh,
    encoding: PlyEncoding,
    quality: &[f64],
) -> Result<()> {
    check_surface(mesh)?;
    if quality.len() != mesh.vertices.len() {
        return Err(Error::param(
            "quality",
            format!(
                "{} values for {} vertices",
                quality.len(),
                mesh.vertices.len()
            ),
        ));
    }
    if let Some(i) = quality.iter().position(|q| !q.is_finite()) {
        return Err(Error::param(
            "quality",
            format!("the value of vertex {i} is {}", quality[i]),
        ));
    }
    write_atomic(path.as_ref(), |w| {
        write_to(w, mesh, encoding, Some(quality))
    })
}

fn write_to(
    w: &mut dyn Write,
    mesh: &SurfaceMesh,
    encoding: PlyEncoding,
    quality: Option<&[f64]>,
) -> std::io::Result<()> {
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
         property double x\nproperty double y\nproperty double z\n{}element face {}\n\
         property list uchar {index_type} vertex_indices\nend_header\n",
        mesh.vertices.len(),
        if quality.is_some() {
            "property float quality\n"
        } else {
            ""
        },
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
    for (i, v) in mesh.vertices.iter().enumerate() {
        let q = quality.map(|q| q[i] as f32);
        match encoding {
            PlyEncoding::Ascii => {
                write!(w, "{} {} {}", fmt_f64(v.x), fmt_f64(v.y), fmt_f64(v.z))?;
                if let Some(q) = q {
                    write!(w, " {q}")?;
                }
                writeln!(w)?;
            }
            _ => {
                for c in v.to_array() {
                    w.write_all(&f64_bytes(c))?;
                }
                if let Some(q) = q {
                    w.write_all(&if big {
                        q.to_be_bytes()
                    } else {
                        q.to_le_bytes()
                    })?;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A binary element without properties takes no bytes, so however many the header
    /// declares it is read at once (the surface fuzzer's input declared 35 trillion and ran
    /// for minutes; fuzz/regressions/surface/).
    #[test]
    fn binary_elements_without_properties_cost_nothing() {
        let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement junk 35084971874737\n\
            element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
            element face 1\nproperty list uchar int vertex_indices\nend_header\n"
            .to_vec();
        for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            v.iter().for_each(|c| bytes.extend(c.to_le_bytes()));
        }
        bytes.push(3);
        [0i32, 1, 2]
            .iter()
            .for_each(|i| bytes.extend(i.to_le_bytes()));
        let start = std::time::Instant::now();
        let mesh = parse(&bytes, Path::new("junk.ply")).unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
        assert!(start.elapsed().as_secs() < 1);
    }
}
