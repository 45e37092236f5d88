//! Object File Format (Geomview OFF), ASCII.
//!
//! Accepts the `OFF` keyword with the `C`, `N` and `ST` prefixes (per-vertex colours, normals
//! and texture coordinates after x y z are skipped), counts on the keyword's line or the next,
//! `#` comments, per-face colours after the indices, and polygons (split into triangle fans).
//! 4D (`4OFF`), n-dimensional (`nOFF`) and binary OFF are rejected with a message.

use super::text::{capacity, fan, Ctx, Line, Lines};
use super::{check_surface, fmt_f64, read_bytes, write_atomic};
use crate::error::Result;
use crate::mesh::SurfaceMesh;
use std::io::Write;
use std::path::Path;

/// Reads an OFF file.
pub fn read(path: impl AsRef<Path>) -> Result<SurfaceMesh> {
    let path = path.as_ref();
    parse(&read_bytes(path)?, path)
}

/// Parses the bytes of an OFF file; `path` is used in error messages only.
pub fn parse(bytes: &[u8], path: &Path) -> Result<SurfaceMesh> {
    let ctx = Ctx { path };
    let mut lines = Lines::new(bytes, Some(b'#'));
    let first = lines
        .next()
        .ok_or_else(|| ctx.err(None, "empty file (no OFF header)"))?;
    let keyword = first.tokens.first().copied().unwrap_or_default();
    let is_keyword =
        keyword.len() >= 3 && keyword[keyword.len() - 3..].eq_ignore_ascii_case(b"OFF");
    // The counts follow the keyword on its line, or sit on the next line; some files have no
    // keyword at all.
    let (counts, at): (Line<'_>, usize) = if is_keyword {
        // Prefixes: ST (texture), C (colour), N (normal) are fine; 4 and n change the layout.
        let prefix = &keyword[..keyword.len() - 3];
        if prefix.contains(&b'4') || prefix.contains(&b'n') {
            return Err(ctx.err(
                Some(first.no),
                "only 3D OFF is supported (4OFF/nOFF are not)",
            ));
        }
        if first
            .tokens
            .get(1)
            .is_some_and(|t| t.eq_ignore_ascii_case(b"BINARY"))
        {
            return Err(ctx.err(Some(first.no), "binary OFF is not supported"));
        }
        if first.tokens.len() > 1 {
            (first, 1)
        } else {
            (
                lines.next().ok_or_else(|| {
                    ctx.err(None, "the file ends before the vertex and face counts")
                })?,
                0,
            )
        }
    } else {
        (first, 0)
    };
    let nv = ctx.count(&counts, at, "vertex count")?;
    let nf = ctx.count(&counts, at + 1, "face count")?;
    if u32::try_from(nv).is_err() {
        return Err(ctx.err(
            Some(counts.no),
            format!("{nv} vertices do not fit in 32-bit indices"),
        ));
    }
    if nv == 0 || nf == 0 {
        return Err(ctx.err(
            Some(counts.no),
            format!("empty mesh: the header declares {nv} vertices and {nf} faces"),
        ));
    }
    let mut mesh = SurfaceMesh::default();
    mesh.vertices.reserve(capacity(nv, bytes.len(), 6));
    mesh.triangles.reserve(capacity(nf, bytes.len(), 8));
    let ends = |what: &str, i: usize, n: usize| {
        ctx.err(
            None,
            format!("the file ends after {i} of the {n} {what} the header declares"),
        )
    };
    for i in 0..nv {
        let line = lines.next().ok_or_else(|| ends("vertices", i, nv))?;
        mesh.vertices
            .push(ctx.point(&line, 0, &format!("vertex {i}"))?);
    }
    let mut poly = Vec::new();
    for i in 0..nf {
        let line = lines.next().ok_or_else(|| ends("faces", i, nf))?;
        let what = format!("face {i}");
        let k = ctx.count(&line, 0, &format!("{what}: corner count"))?;
        if k < 3 {
            return Err(ctx.err(
                Some(line.no),
                format!("{what} has {k} vertices; a face needs at least 3"),
            ));
        }
        poly.clear();
        for c in 1..=k {
            let v = ctx.int(&line, c, &format!("{what}: vertex index {c} of {k}"))?;
            let index = u32::try_from(v)
                .ok()
                .filter(|&v| (v as usize) < nv)
                .ok_or_else(|| {
                    ctx.err(
                        Some(line.no),
                        format!(
                            "{what}: vertex index {v} is out of range (the file has {nv} vertices)"
                        ),
                    )
                })?;
            poly.push(index);
        }
        fan(&poly, &mut mesh.triangles);
    }
    if let Some(extra) = lines.next() {
        return Err(ctx.err(
            Some(extra.no),
            format!("data after the {nf} faces the header declares (do the header's counts match the file?)"),
        ));
    }
    Ok(mesh)
}

/// Writes `mesh` as OFF, atomically.
pub fn write(path: impl AsRef<Path>, mesh: &SurfaceMesh) -> Result<()> {
    check_surface(mesh)?;
    write_atomic(path.as_ref(), |w| write_to(w, mesh))
}

fn write_to(w: &mut dyn Write, mesh: &SurfaceMesh) -> std::io::Result<()> {
    writeln!(
        w,
        "OFF\n# written by tetrasim\n{} {} 0",
        mesh.vertices.len(),
        mesh.triangles.len()
    )?;
    for v in &mesh.vertices {
        writeln!(w, "{} {} {}", fmt_f64(v.x), fmt_f64(v.y), fmt_f64(v.z))?;
    }
    for t in &mesh.triangles {
        writeln!(w, "3 {} {} {}", t[0], t[1], t[2])?;
    }
    Ok(())
}
