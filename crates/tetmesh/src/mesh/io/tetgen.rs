//! TetGen's `.node`, `.ele` and `.face` files.
//!
//! Reading follows TetGen's own rules: the first node's number sets the base (0 or 1) for
//! every index in the three files; node attributes, boundary markers and region attributes
//! are counted from the headers and skipped; `#` starts a comment; blank lines are ignored;
//! missing header fields take TetGen's defaults (3 dimensions, 0 attributes, 0 markers, 4 nodes
//! per tet). Only 4-node tets are read (a 10-node `.ele` from `-o2` is an error). Errors name the
//! file and the line.
//!
//! Writing is 0-based, with comments saying so, and no attributes or markers. The comments
//! all come before the header line: readers that skip comments only there (meshio 5.3's
//! `np.fromfile` after the header) read the data to its end.

use super::text::{Ctx, Line, Lines};
use super::{check_indices, PendingFile};
use crate::error::{Error, Result};
use crate::mesh::{topology, TetMesh};
use glam::DVec3;
use std::ffi::OsString;
use std::io::Write;
use std::path::{Path, PathBuf};

/// `prefix` without a trailing `.node`, `.ele` or `.face`.
pub fn strip_prefix_ext(prefix: &Path) -> PathBuf {
    match prefix.extension().and_then(|e| e.to_str()) {
        Some("node" | "ele" | "face") => prefix.with_extension(""),
        _ => prefix.to_path_buf(),
    }
}

/// `prefix` + `.ext` (appended, so `a.b` gives `a.b.node`).
pub fn with_ext(prefix: &Path, ext: &str) -> PathBuf {
    let mut s: OsString = prefix.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Reads `PREFIX.node`, `PREFIX.ele` and, if it exists, `PREFIX.face`. `prefix` may also end
/// in `.node`, `.ele` or `.face`. Indices come back 0-based whatever the files' base.
pub fn read_tetgen(prefix: impl AsRef<Path>) -> Result<TetMesh> {
    let prefix = strip_prefix_ext(prefix.as_ref());
    let node_path = with_ext(&prefix, "node");
    let ele_path = with_ext(&prefix, "ele");
    let face_path = with_ext(&prefix, "face");
    let node = std::fs::read(&node_path).map_err(|e| Error::io(&node_path, e))?;
    let ele = std::fs::read(&ele_path).map_err(|e| Error::io(&ele_path, e))?;
    let face = match std::fs::read(&face_path) {
        Ok(b) => Some(b),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(Error::io(&face_path, e)),
    };
    parse_tetgen(&node, &ele, face.as_deref(), &prefix)
}

/// Parses the contents of `.node`, `.ele` and (optionally) `.face` files; `prefix` names
/// them in error messages.
pub fn parse_tetgen(
    node: &[u8],
    ele: &[u8],
    face: Option<&[u8]>,
    prefix: &Path,
) -> Result<TetMesh> {
    let (nodes, base) = parse_node(node, &with_ext(prefix, "node"))?;
    let tets = parse_elements::<4>(ele, &with_ext(prefix, "ele"), base, nodes.len())?;
    let faces = match face {
        Some(f) => parse_elements::<3>(f, &with_ext(prefix, "face"), base, nodes.len())?,
        None => Vec::new(),
    };
    Ok(TetMesh { nodes, tets, faces })
}

/// Header field `i` of `line`, or TetGen's default when absent.
fn field(ctx: Ctx<'_>, line: &Line<'_>, i: usize, what: &str, default: usize) -> Result<usize> {
    if i < line.tokens.len() {
        ctx.count(line, i, what)
    } else {
        Ok(default)
    }
}

/// Error if `lines` has anything left after the `n` records of `what` the header declared.
fn no_more(ctx: Ctx<'_>, lines: &mut Lines<'_>, n: usize, what: &str) -> Result<()> {
    match lines.next() {
        Some(extra) => Err(ctx.err(
            Some(extra.no),
            format!("data after the {n} {what} the header declares (does the header's count match the file?)"),
        )),
        None => Ok(()),
    }
}

fn parse_node(bytes: &[u8], path: &Path) -> Result<(Vec<DVec3>, i64)> {
    let ctx = Ctx { path };
    let mut lines = Lines::new(bytes, Some(b'#'));
    let head = lines
        .next()
        .ok_or_else(|| ctx.err(None, "empty .node file (no header line)"))?;
    let n = ctx.count(&head, 0, "node count")?;
    let dim = field(ctx, &head, 1, "dimension", 3)?;
    let n_attr = field(ctx, &head, 2, "attribute count", 0)?;
    let n_mark = field(ctx, &head, 3, "boundary marker flag", 0)?;
    if dim != 3 {
        return Err(ctx.err(
            Some(head.no),
            format!("dimension is {dim}; only 3D meshes are supported"),
        ));
    }
    if n == 0 {
        return Err(ctx.err(Some(head.no), "empty mesh: the header declares 0 nodes"));
    }
    if u32::try_from(n).is_err() {
        return Err(ctx.err(
            Some(head.no),
            format!("{n} nodes do not fit in 32-bit indices"),
        ));
    }
    let width = 4usize.saturating_add(n_attr).saturating_add(n_mark.min(1));
    let mut nodes = Vec::with_capacity(n.min(bytes.len() / 8));
    let mut base = 0;
    for i in 0..n {
        let line = lines.next().ok_or_else(|| {
            ctx.err(
                None,
                format!(
                    "the file ends after {i} of the {n} nodes the header declares (truncated?)"
                ),
            )
        })?;
        let number = ctx.int(&line, 0, &format!("node {i} number"))?;
        if i == 0 {
            if number != 0 && number != 1 {
                return Err(ctx.err(
                    Some(line.no),
                    format!("the first node is numbered {number}; TetGen numbers from 0 or 1"),
                ));
            }
            base = number;
        } else if number != base + i as i64 {
            return Err(ctx.err(
                Some(line.no),
                format!(
                    "node numbered {number}, expected {} (nodes must be numbered consecutively)",
                    base + i as i64
                ),
            ));
        }
        if line.tokens.len() < width {
            return Err(ctx.err(
                Some(line.no),
                format!(
                    "node {number} has {} values; the header declares number, x, y, z, {n_attr} attributes and {} markers",
                    line.tokens.len(),
                    n_mark.min(1)
                ),
            ));
        }
        nodes.push(ctx.point(&line, 1, &format!("node {number}"))?);
    }
    no_more(ctx, &mut lines, n, "nodes")?;
    Ok((nodes, base))
}

/// Reads `.ele` (`K = 4`) or `.face` (`K = 3`) records, converting node numbers to 0-based
/// indices below `n_nodes`.
fn parse_elements<const K: usize>(
    bytes: &[u8],
    path: &Path,
    base: i64,
    n_nodes: usize,
) -> Result<Vec<[u32; K]>> {
    let ctx = Ctx { path };
    let what = if K == 4 { "tetrahedra" } else { "faces" };
    let one = if K == 4 { "tet" } else { "face" };
    let mut lines = Lines::new(bytes, Some(b'#'));
    let head = lines
        .next()
        .ok_or_else(|| ctx.err(None, format!("empty file (no header line for {what})")))?;
    let m = ctx.count(&head, 0, &format!("{one} count"))?;
    // .ele: <count> <nodes per tet> <region attribute flag>; .face: <count> <marker flag>.
    let extra = if K == 4 {
        let per = field(ctx, &head, 1, "nodes per tetrahedron", 4)?;
        if per == 10 {
            return Err(ctx.err(
                Some(head.no),
                "10-node (second-order) tetrahedra are not supported; mesh without TetGen's -o2",
            ));
        }
        if per != 4 {
            return Err(ctx.err(
                Some(head.no),
                format!("{per} nodes per tetrahedron; only 4 is supported"),
            ));
        }
        field(ctx, &head, 2, "region attribute flag", 0)?
    } else {
        field(ctx, &head, 1, "boundary marker flag", 0)?
    };
    if K == 4 && m == 0 {
        return Err(ctx.err(
            Some(head.no),
            "empty mesh: the header declares 0 tetrahedra",
        ));
    }
    let width = (1 + K).saturating_add(extra.min(1));
    let mut out = Vec::with_capacity(m.min(bytes.len() / (2 * K + 2)));
    for i in 0..m {
        let line = lines.next().ok_or_else(|| {
            ctx.err(
                None,
                format!(
                    "the file ends after {i} of the {m} {what} the header declares (truncated?)"
                ),
            )
        })?;
        if line.tokens.len() < width {
            return Err(ctx.err(
                Some(line.no),
                format!(
                    "{one} {i} has {} values, expected at least {width}",
                    line.tokens.len()
                ),
            ));
        }
        let mut e = [0u32; K];
        for (k, slot) in e.iter_mut().enumerate() {
            let v = ctx.int(&line, 1 + k, &format!("{one} {i} node {k}"))?;
            *slot = v
                .checked_sub(base)
                .and_then(|x| u32::try_from(x).ok())
                .filter(|&x| (x as usize) < n_nodes)
                .ok_or_else(|| {
                    ctx.err(
                        Some(line.no),
                        format!(
                            "{one} {i}: node index {v} is out of range (nodes are numbered {base} to {})",
                            base + n_nodes as i64 - 1
                        ),
                    )
                })?;
        }
        out.push(e);
    }
    no_more(ctx, &mut lines, m, what)?;
    Ok(out)
}

/// Writes `PREFIX.node`, `PREFIX.ele` and `PREFIX.face` (0-based, no attributes or markers).
/// The faces are `mesh.faces`, or the boundary faces of the tets when that is empty. All
/// three files are written to temporary files first and renamed only when all succeeded.
pub fn write_tetgen(prefix: impl AsRef<Path>, mesh: &TetMesh) -> Result<()> {
    let prefix = strip_prefix_ext(prefix.as_ref());
    super::check_tet_mesh(mesh)?;
    check_indices(&mesh.faces, mesh.nodes.len(), "face")?;
    let derived;
    let faces = if mesh.faces.is_empty() {
        derived = topology::boundary_faces(&mesh.tets);
        &derived
    } else {
        &mesh.faces
    };
    let mut files = Vec::new();
    for ext in ["node", "ele", "face"] {
        let path = with_ext(&prefix, ext);
        let mut file = PendingFile::create(&path)?;
        let w = file.writer();
        let written = match ext {
            "node" => write_node(w, mesh),
            "ele" => write_records(
                w,
                "tetrahedra",
                "<tet count> <nodes per tet> <region attribute flag>",
                "4 0",
                &mesh.tets,
            ),
            _ => write_records(
                w,
                "boundary faces",
                "<face count> <boundary marker flag>",
                "0",
                faces,
            ),
        };
        written.map_err(|e| Error::io(&path, e))?;
        files.push(file);
    }
    files.into_iter().try_for_each(PendingFile::commit)
}

fn write_node(w: &mut impl Write, mesh: &TetMesh) -> std::io::Result<()> {
    writeln!(
        w,
        "# written by tetrasim: {} nodes, numbered from 0",
        mesh.nodes.len()
    )?;
    writeln!(
        w,
        "# <node count> <dimension> <attribute count> <boundary marker flag>"
    )?;
    writeln!(w, "# then one line per node: <node number> <x> <y> <z>")?;
    writeln!(w, "{} 3 0 0", mesh.nodes.len())?;
    for (i, p) in mesh.nodes.iter().enumerate() {
        writeln!(
            w,
            "{i} {} {} {}",
            super::fmt_f64(p.x),
            super::fmt_f64(p.y),
            super::fmt_f64(p.z)
        )?;
    }
    Ok(())
}

fn write_records<const K: usize>(
    w: &mut impl Write,
    what: &str,
    header: &str,
    flags: &str,
    records: &[[u32; K]],
) -> std::io::Result<()> {
    writeln!(
        w,
        "# written by tetrasim: {} {what}, node indices numbered from 0",
        records.len()
    )?;
    writeln!(w, "# {header}")?;
    writeln!(w, "# then one line per record: <number> <node indices>")?;
    writeln!(w, "{} {flags}", records.len())?;
    for (i, r) in records.iter().enumerate() {
        write!(w, "{i}")?;
        for v in r {
            write!(w, " {v}")?;
        }
        writeln!(w)?;
    }
    Ok(())
}
