//! Wavefront OBJ: the geometry subset (`v` and `f` statements).
//!
//! Faces may use the `v`, `v/vt`, `v//vn` and `v/vt/vn` forms (only the vertex index is kept),
//! negative (relative) indices, and any number of corners (split into triangle fans). Texture
//! coordinates, normals, groups, materials, lines and points are ignored. Errors name the line.

use super::text::{fan, parse_i64, show, Ctx, Lines};
use super::{check_surface, fmt_f64, read_bytes, write_atomic};
use crate::error::Result;
use crate::mesh::SurfaceMesh;
use std::io::Write;
use std::path::Path;

/// Reads an OBJ file.
pub fn read(path: impl AsRef<Path>) -> Result<SurfaceMesh> {
    let path = path.as_ref();
    parse(&read_bytes(path)?, path)
}

/// Parses the bytes of an OBJ file; `path` is used in error messages only.
pub fn parse(bytes: &[u8], path: &Path) -> Result<SurfaceMesh> {
    let ctx = Ctx { path };
    let mut mesh = SurfaceMesh::default();
    let mut faces = 0usize;
    // Indices that point past the vertices read so far (legal if defined later):
    // (line, face number, 1-based index).
    let mut forward: Vec<(usize, usize, usize)> = Vec::new();
    let mut poly: Vec<u32> = Vec::new();
    for line in Lines::new(bytes, Some(b'#')) {
        match line.tokens.first().copied() {
            Some(b"v") => {
                let what = format!("vertex {}", mesh.vertices.len() + 1);
                mesh.vertices.push(ctx.point(&line, 1, &what)?);
            }
            Some(b"f") => {
                faces += 1;
                poly.clear();
                let n = mesh.vertices.len();
                for token in line.tokens.iter().skip(1) {
                    let head = token.split(|&b| b == b'/').next().unwrap_or(token);
                    let bad = |m: String| ctx.err(Some(line.no), format!("face {faces}: {m}"));
                    let v = parse_i64(head)
                        .ok_or_else(|| bad(format!("`{}` is not a vertex index", show(token))))?;
                    // OBJ indices are 1-based; negative ones count back from the last vertex.
                    let index = match v {
                        0 => return Err(bad("vertex index 0 (OBJ indices start at 1)".into())),
                        v if v < 0 => n as i64 + v,
                        v => v - 1,
                    };
                    let index = usize::try_from(index)
                        .ok()
                        .filter(|&i| u32::try_from(i).is_ok())
                        .ok_or_else(|| {
                            bad(format!(
                                "vertex index {v} is out of range ({n} vertices so far)"
                            ))
                        })?;
                    if index >= n {
                        forward.push((line.no, faces, index + 1));
                    }
                    poly.push(index as u32);
                }
                if poly.len() < 3 {
                    return Err(ctx.err(
                        Some(line.no),
                        format!(
                            "face {faces} has {} vertices; a face needs at least 3",
                            poly.len()
                        ),
                    ));
                }
                fan(&poly, &mut mesh.triangles);
            }
            _ => {}
        }
    }
    let n = mesh.vertices.len();
    if let Some(&(line, face, index)) = forward.iter().find(|f| f.2 > n) {
        return Err(ctx.err(
            Some(line),
            format!(
                "face {face}: vertex index {index} is out of range (the file has {n} vertices)"
            ),
        ));
    }
    if n == 0 || mesh.triangles.is_empty() {
        return Err(ctx.err(None, format!("empty mesh: {n} vertices, {} faces", faces)));
    }
    Ok(mesh)
}

/// Writes `mesh` as OBJ (`v` and `f` lines, 1-based indices), atomically.
pub fn write(path: impl AsRef<Path>, mesh: &SurfaceMesh) -> Result<()> {
    check_surface(mesh)?;
    write_atomic(path.as_ref(), |w| write_to(w, mesh))
}

fn write_to(w: &mut dyn Write, mesh: &SurfaceMesh) -> std::io::Result<()> {
    writeln!(
        w,
        "# written by tetrasim: {} vertices, {} triangles",
        mesh.vertices.len(),
        mesh.triangles.len()
    )?;
    for v in &mesh.vertices {
        writeln!(w, "v {} {} {}", fmt_f64(v.x), fmt_f64(v.y), fmt_f64(v.z))?;
    }
    for t in &mesh.triangles {
        writeln!(
            w,
            "f {} {} {}",
            t[0] as u64 + 1,
            t[1] as u64 + 1,
            t[2] as u64 + 1
        )?;
    }
    Ok(())
}
