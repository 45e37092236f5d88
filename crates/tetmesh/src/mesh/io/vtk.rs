//! Legacy VTK (`.vtk`, ASCII) unstructured grids of linear tetrahedra (VTK cell type 10),
//! for viewing in ParaView, with optional point and cell fields ([`Fields`]).

use super::fields::{FieldValues, Fields};
use super::{check_tet_mesh, fmt_f64, write_atomic};
use crate::error::Result;
use crate::mesh::TetMesh;
use std::io::Write;
use std::path::Path;

/// VTK's cell type number for a linear tetrahedron.
pub const VTK_TETRA: u8 = 10;

/// Writes `mesh` as a legacy ASCII VTK unstructured grid, atomically. `cell_scalars`, when
/// given, is a field name (no whitespace) and one finite value per tet, written as
/// `CELL_DATA`.
pub fn write_vtk(
    path: impl AsRef<Path>,
    mesh: &TetMesh,
    cell_scalars: Option<(&str, &[f64])>,
) -> Result<()> {
    let fields = Fields {
        point: Vec::new(),
        cell: cell_scalars
            .map(|(name, values)| super::Field {
                name,
                values: FieldValues::Scalar(values),
            })
            .into_iter()
            .collect(),
    };
    write_vtk_fields(path, mesh, &fields)
}

/// Writes `mesh` with point and cell fields as a legacy ASCII VTK unstructured grid,
/// atomically. The mesh and the fields are checked first ([`Fields::check`]).
pub fn write_vtk_fields(path: impl AsRef<Path>, mesh: &TetMesh, fields: &Fields) -> Result<()> {
    check_tet_mesh(mesh)?;
    fields.check(mesh.nodes.len(), mesh.tets.len())?;
    write_atomic(path.as_ref(), |w| write_to(w, mesh, fields))
}

fn write_to(w: &mut dyn Write, mesh: &TetMesh, fields: &Fields) -> std::io::Result<()> {
    let (n, m) = (mesh.nodes.len(), mesh.tets.len());
    writeln!(w, "# vtk DataFile Version 3.0")?;
    writeln!(w, "tetrasim tet mesh: {n} nodes, {m} tets")?;
    writeln!(w, "ASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS {n} double")?;
    for p in &mesh.nodes {
        writeln!(w, "{} {} {}", fmt_f64(p.x), fmt_f64(p.y), fmt_f64(p.z))?;
    }
    writeln!(w, "CELLS {m} {}", 5 * m)?;
    for t in &mesh.tets {
        writeln!(w, "4 {} {} {} {}", t[0], t[1], t[2], t[3])?;
    }
    writeln!(w, "CELL_TYPES {m}")?;
    for _ in 0..m {
        writeln!(w, "{VTK_TETRA}")?;
    }
    for (section, count, list) in [
        ("POINT_DATA", n, &fields.point),
        ("CELL_DATA", m, &fields.cell),
    ] {
        if list.is_empty() {
            continue;
        }
        writeln!(w, "{section} {count}")?;
        for field in list {
            let name = field.name;
            match field.values {
                FieldValues::Scalar(values) => {
                    writeln!(w, "SCALARS {name} double 1\nLOOKUP_TABLE default")?;
                    for v in values {
                        writeln!(w, "{}", fmt_f64(*v))?;
                    }
                }
                FieldValues::Vector(values) => {
                    writeln!(w, "VECTORS {name} double")?;
                    for v in values {
                        writeln!(w, "{} {} {}", fmt_f64(v.x), fmt_f64(v.y), fmt_f64(v.z))?;
                    }
                }
                FieldValues::Flag(values) => {
                    writeln!(w, "SCALARS {name} unsigned_char 1\nLOOKUP_TABLE default")?;
                    for v in values {
                        writeln!(w, "{v}")?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// VTK's cell type number for a quadratic (10-node) tetrahedron.
pub const VTK_QUADRATIC_TETRA: u8 = 24;

/// A name for a VTK cell type, for messages.
pub(crate) fn cell_type_name(t: i64) -> String {
    let name = match t {
        1 => "vertex",
        2 => "poly-vertex",
        3 => "line",
        4 => "poly-line",
        5 => "triangle",
        6 => "triangle strip",
        7 => "polygon",
        8 => "pixel",
        9 => "quad",
        10 => "tetra",
        11 => "voxel",
        12 => "hexahedron",
        13 => "wedge",
        14 => "pyramid",
        21 => "quadratic edge",
        22 => "quadratic triangle",
        23 => "quadratic quad",
        24 => "quadratic tetra",
        25 => "quadratic hexahedron",
        42 => "polyhedron",
        _ => return format!("type {t}"),
    };
    format!("{name} ({t})")
}

/// Cells of an unstructured grid (legacy or XML): node lists given by `offsets` (one more
/// than the cells, starting at 0) into `connectivity`, and `types`, all checked here. Keeps
/// the linear tets, skips other types, and errors on quadratic tets or when there are no
/// tets. `where_` names a cell in messages: `(cell index) -> (line, description)`.
pub(crate) fn grid_tets(
    ctx: super::text::Ctx<'_>,
    n_points: usize,
    offsets: &[i64],
    connectivity: &[i64],
    types: &[i64],
    where_: &dyn Fn(usize) -> (Option<usize>, String),
) -> Result<Vec<[u32; 4]>> {
    let n_cells = offsets.len().saturating_sub(1);
    if types.len() != n_cells {
        let (line, _) = where_(0);
        return Err(ctx.err(
            line,
            format!("{} cell types for {n_cells} cells", types.len()),
        ));
    }
    let mut tets = Vec::new();
    let mut other: std::collections::BTreeMap<i64, usize> = Default::default();
    for c in 0..n_cells {
        let (a, b) = (offsets[c], offsets[c + 1]);
        if a < 0 || b < a || b as u64 > connectivity.len() as u64 {
            let (line, what) = where_(c);
            return Err(ctx.err(
                line,
                format!(
                    "{what}: node list {a}..{b} is not within the {} connectivity entries",
                    connectivity.len()
                ),
            ));
        }
        let ids = &connectivity[a as usize..b as usize];
        match types[c] {
            10 => {
                if ids.len() != 4 {
                    let (line, what) = where_(c);
                    return Err(ctx.err(
                        line,
                        format!(
                            "{what} is a tetra (type 10) with {} nodes, not 4",
                            ids.len()
                        ),
                    ));
                }
                let mut t = [0u32; 4];
                for (k, (&id, slot)) in ids.iter().zip(&mut t).enumerate() {
                    *slot = u32::try_from(id)
                        .ok()
                        .filter(|&v| (v as usize) < n_points)
                        .ok_or_else(|| {
                            let (line, what) = where_(c);
                            ctx.err(
                                line,
                                format!("{what} node {k}: index {id} is out of range (there are {n_points} points)"),
                            )
                        })?;
                }
                tets.push(t);
            }
            24 => {
                let (line, what) = where_(c);
                return Err(ctx.err(
                    line,
                    format!(
                        "{what} is a quadratic tetra (VTK type 24, 10 nodes); only linear tets (type 10) \
                         can be simulated: export linear elements (gmsh -order 1, TetGen without -o2)"
                    ),
                ));
            }
            t => *other.entry(t).or_default() += 1,
        }
    }
    if tets.is_empty() {
        let found = if other.is_empty() {
            "no cells at all".to_string()
        } else {
            other
                .iter()
                .map(|(&t, &n)| format!("{n} x {}", cell_type_name(t)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        return Err(ctx.err(
            None,
            format!("no tetrahedra (VTK cell type 10) in the file; it has {found}"),
        ));
    }
    Ok(tets)
}

/// Reads a legacy VTK unstructured grid (`.vtk`, ASCII or BINARY, file versions 2 to 5.1):
/// the points and the linear tetrahedra (cell type 10). Other cell types are skipped;
/// quadratic tets (24) are an error. `POINT_DATA`, `CELL_DATA` and `FIELD` arrays are ignored.
/// Nodes that no tet uses are dropped (see [`super::drop_unused_nodes`]); the tets keep the
/// file's orientation.
pub fn read_vtk(path: impl AsRef<Path>) -> Result<TetMesh> {
    let path = path.as_ref();
    parse_vtk(&super::read_bytes(path)?, path)
}

/// Parses the bytes of a legacy VTK file; `path` names it in errors.
pub fn parse_vtk(bytes: &[u8], path: &Path) -> Result<TetMesh> {
    legacy::parse(bytes, path)
}

mod legacy {
    use super::super::cursor::{decode_f64, decode_i64, Cursor, Endian, Num};
    use super::super::text::{show, Ctx, Line};
    use crate::error::Result;
    use crate::mesh::TetMesh;
    use std::path::Path;

    /// Values read from the file, with the line of each (ASCII) for messages.
    struct Values<T> {
        v: Vec<T>,
        lines: Vec<usize>,
    }

    fn num_type(c: &Cursor<'_>, line: &Line<'_>, i: usize) -> Result<Num> {
        let t = c.ctx.token(line, i, "data type")?;
        Ok(match t.to_ascii_lowercase().as_slice() {
            b"bit" => {
                return Err(c.err(Some(line.no), "data type `bit` is not supported"));
            }
            b"char" | b"vtktypeint8" => Num::I8,
            b"unsigned_char" | b"vtktypeuint8" => Num::U8,
            b"short" | b"vtktypeint16" => Num::I16,
            b"unsigned_short" | b"vtktypeuint16" => Num::U16,
            b"int" | b"vtktypeint32" => Num::I32,
            b"unsigned_int" | b"vtktypeuint32" => Num::U32,
            b"long" | b"vtktypeint64" | b"vtkidtype" => Num::I64,
            b"unsigned_long" | b"vtktypeuint64" => Num::U64,
            b"float" | b"vtktypefloat32" => Num::F32,
            b"double" | b"vtktypefloat64" => Num::F64,
            _ => return Err(c.err(Some(line.no), format!("unknown data type `{}`", show(t)))),
        })
    }

    /// Reads one text value: its line and the value, or an error naming it.
    type TokenReader<'a, T> = fn(&mut Cursor<'a>, &dyn Fn() -> String) -> Result<(usize, T)>;

    struct Reader<'a> {
        c: Cursor<'a>,
        binary: bool,
    }

    impl<'a> Reader<'a> {
        /// `n` values, binary (decoded by `decode`) or text (read by `token`); `what(i)`
        /// names value `i`.
        fn values<T>(
            &mut self,
            n: usize,
            num: Num,
            what: &dyn Fn(usize) -> String,
            decode: fn(&[u8], Num, Endian) -> Vec<T>,
            token: TokenReader<'a, T>,
        ) -> Result<Values<T>> {
            if self.binary {
                self.c.fits(n, num.size(), "values")?;
                let b = self.c.take(n * num.size(), &|| what(0))?;
                self.c.skip_newline();
                return Ok(Values {
                    v: decode(b, num, Endian::Big),
                    lines: Vec::new(),
                });
            }
            let cap = n.min(self.c.left() / 2);
            let mut out = Values {
                v: Vec::with_capacity(cap),
                lines: Vec::with_capacity(cap),
            };
            for i in 0..n {
                let (no, v) = token(&mut self.c, &|| what(i))?;
                out.v.push(v);
                out.lines.push(no);
            }
            Ok(out)
        }

        /// `n` numbers as `f64`; `what(i)` names value `i`.
        fn floats(
            &mut self,
            n: usize,
            num: Num,
            what: &dyn Fn(usize) -> String,
        ) -> Result<Values<f64>> {
            self.values(n, num, what, decode_f64, Cursor::f64_token)
        }

        /// `n` integers.
        fn ints(
            &mut self,
            n: usize,
            num: Num,
            what: &dyn Fn(usize) -> String,
        ) -> Result<Values<i64>> {
            self.values(n, num, what, decode_i64, Cursor::int_token)
        }
    }

    pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<TetMesh> {
        let ctx = Ctx { path };
        let mut c = Cursor::new(bytes, ctx);
        let (no, first) = c.raw_line().ok_or_else(|| ctx.err(None, "empty file"))?;
        if !first.starts_with(b"# vtk DataFile") {
            return Err(ctx.err(
                Some(no),
                "not a legacy VTK file: the first line is not `# vtk DataFile Version ...`",
            ));
        }
        c.raw_line()
            .ok_or_else(|| ctx.err(None, "the file ends before the title line"))?;
        let enc = c.need_line("the ASCII/BINARY line")?;
        let binary = match enc.head().to_ascii_uppercase().as_slice() {
            b"ASCII" => false,
            b"BINARY" => true,
            other => {
                return Err(ctx.err(
                    Some(enc.no),
                    format!("expected ASCII or BINARY, found `{}`", show(other)),
                ))
            }
        };
        let ds = c.need_line("the DATASET line")?;
        let kind = ds.tokens.get(1).copied().unwrap_or_default();
        if !ds.head().eq_ignore_ascii_case(b"DATASET")
            || !kind.eq_ignore_ascii_case(b"UNSTRUCTURED_GRID")
        {
            return Err(ctx.err(
                Some(ds.no),
                format!(
                    "expected `DATASET UNSTRUCTURED_GRID`, found `{}`; only unstructured grids hold tets",
                    show(&ds.tokens.join(&b' '))
                ),
            ));
        }
        let mut r = Reader { c, binary };
        let mut points: Option<Vec<glam::DVec3>> = None;
        // (offsets, connectivity, line of each connectivity value or of each cell's first).
        let mut cells: Option<(Vec<i64>, Values<i64>, usize)> = None;
        let mut types: Option<Values<i64>> = None;
        while let Some(line) = r.c.line() {
            let key = line.head().to_ascii_uppercase();
            match key.as_slice() {
                b"POINTS" => {
                    let n = ctx.count(&line, 1, "point count")?;
                    let num = num_type(&r.c, &line, 2)?;
                    let k = n
                        .checked_mul(3)
                        .ok_or_else(|| ctx.err(Some(line.no), "point count too large"))?;
                    let vals = r.floats(k, num, &|i| {
                        format!("point {} {}", i / 3, ["x", "y", "z"][i % 3])
                    })?;
                    let mut pts = Vec::with_capacity(n);
                    for (i, c3) in vals.v.chunks_exact(3).enumerate() {
                        let p = super::super::text::finite_point([c3[0], c3[1], c3[2]]).map_err(
                            |m| {
                                let at = vals.lines.get(3 * i).copied();
                                ctx.err(at, format!("point {i} has a {m}"))
                            },
                        )?;
                        pts.push(p);
                    }
                    points = Some(pts);
                }
                b"CELLS" => {
                    let a = ctx.count(&line, 1, "cell count")?;
                    let b = ctx.count(&line, 2, "cell list size")?;
                    // Version 5.1 (meshio's default): OFFSETS and CONNECTIVITY arrays follow.
                    let save = r.c.clone();
                    let next = r.c.line();
                    if let Some(off) = next.filter(|l| l.head().eq_ignore_ascii_case(b"OFFSETS")) {
                        let num = num_type(&r.c, &off, 1)?;
                        let offsets = r.ints(a, num, &|i| format!("offset {i}"))?;
                        let con = r.c.need_line("CONNECTIVITY")?;
                        if !con.head().eq_ignore_ascii_case(b"CONNECTIVITY") {
                            return Err(ctx.err(
                                Some(con.no),
                                format!("expected CONNECTIVITY, found `{}`", show(con.head())),
                            ));
                        }
                        let num = num_type(&r.c, &con, 1)?;
                        let conn = r.ints(b, num, &|i| format!("connectivity entry {i}"))?;
                        if offsets.v.first().is_some_and(|&o| o != 0) {
                            return Err(ctx.err(
                                offsets.lines.first().copied(),
                                "the first offset must be 0",
                            ));
                        }
                        cells = Some((offsets.v, conn, line.no));
                    } else {
                        // Restore: the line after CELLS was data, not OFFSETS.
                        r.c = save;
                        let list = r.ints(b, Num::I32, &|i| format!("cell list entry {i}"))?;
                        let mut offsets = Vec::with_capacity(a.min(b) + 1);
                        let mut conn = Values {
                            v: Vec::with_capacity(b),
                            lines: Vec::new(),
                        };
                        let mut at = 0usize;
                        offsets.push(0);
                        for i in 0..a {
                            let k = list.v.get(at).copied().ok_or_else(|| {
                                ctx.err(
                                    list.lines.last().copied().or(Some(line.no)),
                                    format!("the cell list ends before cell {i} of {a}"),
                                )
                            })?;
                            let k = usize::try_from(k).ok().filter(|&k| at + 1 + k <= list.v.len()).ok_or_else(|| {
                                ctx.err(list.lines.get(at).copied().or(Some(line.no)), format!("cell {i}: {k} nodes do not fit in the cell list of {b} entries"))
                            })?;
                            conn.v.extend_from_slice(&list.v[at + 1..at + 1 + k]);
                            if !list.lines.is_empty() {
                                conn.lines
                                    .extend_from_slice(&list.lines[at + 1..at + 1 + k]);
                            }
                            at += 1 + k;
                            offsets.push(conn.v.len() as i64);
                        }
                        if at != b {
                            return Err(ctx.err(Some(line.no), format!("the {a} cells use {at} of the {b} list entries the CELLS line declares")));
                        }
                        cells = Some((offsets, conn, line.no));
                    }
                }
                b"CELL_TYPES" => {
                    let n = ctx.count(&line, 1, "cell type count")?;
                    types = Some(r.ints(n, Num::I32, &|i| format!("cell type {i}"))?);
                }
                b"METADATA" => {
                    // Text up to a blank line (VTK 9 writes it after arrays, also in binary files).
                    while let Some((_, raw)) = r.c.raw_line() {
                        if raw.iter().all(|b| b.is_ascii_whitespace()) {
                            break;
                        }
                    }
                }
                b"FIELD" => {
                    let n = ctx.count(&line, 2, "array count")?;
                    for _ in 0..n {
                        let a = r.c.need_line("a FIELD array")?;
                        let comps = ctx.count(&a, 1, "component count")?;
                        let tuples = ctx.count(&a, 2, "tuple count")?;
                        let num = num_type(&r.c, &a, 3)?;
                        let k = comps
                            .checked_mul(tuples)
                            .ok_or_else(|| ctx.err(Some(a.no), "array too large"))?;
                        let name = show(a.head());
                        r.floats(k, num, &|i| format!("value {i} of array {name}"))?;
                    }
                }
                b"POINT_DATA" | b"CELL_DATA" => break,
                other => {
                    return Err(ctx.err(
                        Some(line.no),
                        format!("unexpected `{}` in an unstructured grid", show(other)),
                    ))
                }
            }
            if points.is_some() && cells.is_some() && types.is_some() {
                break;
            }
        }
        let points = points.ok_or_else(|| ctx.err(None, "no POINTS section"))?;
        let (offsets, conn, cells_line) =
            cells.ok_or_else(|| ctx.err(None, "no CELLS section (no tets)"))?;
        let types = types.ok_or_else(|| ctx.err(None, "no CELL_TYPES section"))?;
        let binary = r.binary;
        let where_ = |c: usize| -> (Option<usize>, String) {
            let line = if binary {
                None
            } else {
                offsets
                    .get(c)
                    .and_then(|&o| conn.lines.get(o as usize))
                    .copied()
                    .or(Some(cells_line))
            };
            (line, format!("cell {c}"))
        };
        if types.v.len() != offsets.len().saturating_sub(1) {
            return Err(ctx.err(
                types.lines.first().copied(),
                format!(
                    "CELL_TYPES has {} entries for {} cells",
                    types.v.len(),
                    offsets.len().saturating_sub(1)
                ),
            ));
        }
        let tets = super::grid_tets(ctx, points.len(), &offsets, &conn.v, &types.v, &where_)?;
        super::super::finish_tets(points, tets)
    }
}
