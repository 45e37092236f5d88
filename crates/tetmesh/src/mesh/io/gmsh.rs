//! gmsh `.msh` files, versions 2.2 and 4.1, ASCII and binary (what gmsh and meshio write).
//!
//! Read: `$MeshFormat`, `$Nodes` and `$Elements`; every other section (`$Entities`,
//! `$PhysicalNames`, `$NodeData`, ...) is skipped to its `$End...` line. Elements of type 4
//! (4-node tetrahedra) are kept; other types (points, lines, triangles, ...) are skipped;
//! 10-node tets (type 11) are an error. Node tags may be any positive numbers, in any order
//! and with gaps; nodes that no tet uses are dropped, the others keep their order in the file.
//! Binary files may be little- or big-endian (gmsh writes the machine's order; the `1` after
//! the format line tells which). Errors name the file and the line (ASCII) or the node or
//! element (binary). Not read: 4.1's parametric coordinates (skipped), partitioned files'
//! ghost entities, `$Periodic` (skipped), versions before 2.2 and 4.0.
//!
//! The `mshio` crate (0.4.2) reads 4.1 only, is built on `nom` 5, and has `unwrap`/`expect`
//! in its number parsers; 2.2 is the version meshio's `gmsh22` and many tools write, so the
//! parser here handles both.

use super::cursor::{decode_f64, decode_i64, Cursor, Endian, Num};
use super::text::{show, Ctx, Line};
use crate::error::Result;
use crate::mesh::TetMesh;
use glam::DVec3;
use std::collections::HashMap;
use std::path::Path;

/// gmsh's element type number of a 4-node tetrahedron.
pub const GMSH_TET4: i64 = 4;

/// Nodes per element of gmsh's element types (needed to skip binary element blocks).
fn nodes_per_element(t: i64) -> Option<usize> {
    Some(match t {
        1 => 2,
        2 => 3,
        3 => 4,
        4 => 4,
        5 => 8,
        6 => 6,
        7 => 5,
        8 => 3,
        9 => 6,
        10 => 9,
        11 => 10,
        12 => 27,
        13 => 18,
        14 => 14,
        15 => 1,
        16 => 8,
        17 => 20,
        18 => 15,
        19 => 13,
        20 => 9,
        21 => 10,
        22 => 12,
        23 => 15,
        24 => 15,
        25 => 21,
        26 => 4,
        27 => 5,
        28 => 6,
        29 => 20,
        30 => 35,
        31 => 56,
        92 => 64,
        93 => 125,
        _ => return None,
    })
}

/// Reads a gmsh `.msh` file (2.2 or 4.1, ASCII or binary): its nodes and 4-node tets.
pub fn read_msh(path: impl AsRef<Path>) -> Result<TetMesh> {
    let path = path.as_ref();
    parse(&super::read_bytes(path)?, path)
}

struct Format {
    v41: bool,
    binary: bool,
    /// `sizeof(size_t)` for 4.1 binary.
    size_t: Num,
    endian: Endian,
}

struct Reader<'a> {
    c: Cursor<'a>,
    f: Format,
    nodes: Vec<DVec3>,
    tags: HashMap<u64, u32>,
    /// Tets as node tags, with the line (ASCII) or element number for messages.
    tets: Vec<([u64; 4], Option<usize>, usize)>,
    /// Element counts by type, of the elements skipped.
    skipped: std::collections::BTreeMap<i64, usize>,
    elements: usize,
}

/// Parses the bytes of a `.msh` file; `path` names it in errors.
pub fn parse(bytes: &[u8], path: &Path) -> Result<TetMesh> {
    let ctx = Ctx { path };
    let mut c = Cursor::new(bytes, ctx);
    let head = c.need_line("$MeshFormat")?;
    if head.head() != b"$MeshFormat" {
        return Err(ctx.err(
            Some(head.no),
            "not a gmsh file: it does not start with `$MeshFormat`",
        ));
    }
    let fl = c.need_line("the format line")?;
    let version = ctx.f64(&fl, 0, "version")?;
    let file_type = ctx.int(&fl, 1, "file type")?;
    let data_size = ctx.int(&fl, 2, "data size")?;
    let v41 = if version == 2.2 {
        false
    } else if version == 4.1 {
        true
    } else {
        return Err(ctx.err(
            Some(fl.no),
            format!("msh version {version} is not supported; write version 2.2 or 4.1 (gmsh -format msh22 / msh41)"),
        ));
    };
    let binary = match file_type {
        0 => false,
        1 => true,
        t => {
            return Err(ctx.err(
                Some(fl.no),
                format!("file type {t}; expected 0 (ASCII) or 1 (binary)"),
            ))
        }
    };
    let size_t = match data_size {
        8 => Num::U64,
        4 => Num::U32,
        d => return Err(ctx.err(Some(fl.no), format!("data size {d}; expected 8 (or 4)"))),
    };
    let mut endian = Endian::Little;
    if binary {
        let one = c.take(4, &|| "the binary `1` of $MeshFormat".to_string())?;
        endian = match one {
            [1, 0, 0, 0] => Endian::Little,
            [0, 0, 0, 1] => Endian::Big,
            _ => {
                return Err(ctx.err(
                    Some(fl.no + 1),
                    "the binary `1` after the format line is neither little- nor big-endian 1",
                ))
            }
        };
        c.skip_newline();
    }
    let end = c.need_line("$EndMeshFormat")?;
    if end.head() != b"$EndMeshFormat" {
        return Err(ctx.err(
            Some(end.no),
            format!("expected `$EndMeshFormat`, found `{}`", show(end.head())),
        ));
    }
    let mut r = Reader {
        c,
        f: Format {
            v41,
            binary,
            size_t,
            endian,
        },
        nodes: Vec::new(),
        tags: HashMap::new(),
        tets: Vec::new(),
        skipped: Default::default(),
        elements: 0,
    };
    let mut seen_nodes = false;
    while let Some(line) = r.c.line() {
        let name = line.head();
        match name {
            b"$Nodes" => {
                if seen_nodes {
                    return Err(ctx.err(Some(line.no), "a second $Nodes section"));
                }
                seen_nodes = true;
                if r.f.v41 {
                    r.nodes41()?
                } else {
                    r.nodes22()?
                }
                r.end_section(b"$EndNodes")?;
            }
            b"$Elements" => {
                if r.f.v41 {
                    r.elements41()?
                } else {
                    r.elements22()?
                }
                r.end_section(b"$EndElements")?;
            }
            _ if name.starts_with(b"$") && !name.starts_with(b"$End") => {
                let mut marker = b"$End".to_vec();
                marker.extend_from_slice(&name[1..]);
                r.c.skip_past_line(&marker, line.no)?;
            }
            _ => {
                return Err(ctx.err(
                    Some(line.no),
                    format!("expected a section (`$Name`), found `{}`", show(name)),
                ))
            }
        }
    }
    r.finish()
}

impl<'a> Reader<'a> {
    fn ctx(&self) -> Ctx<'a> {
        self.c.ctx
    }

    fn end_section(&mut self, marker: &[u8]) -> Result<()> {
        let line = self
            .c
            .need_line(&format!("`{}`", String::from_utf8_lossy(marker)))?;
        if line.head() != marker {
            return Err(self.ctx().err(
                Some(line.no),
                format!(
                    "expected `{}`, found `{}` (does a count match the data?)",
                    String::from_utf8_lossy(marker),
                    show(line.head())
                ),
            ));
        }
        Ok(())
    }

    /// Registers node `tag` at `p`.
    fn add_node(&mut self, tag: i64, p: [f64; 3], at: Option<usize>, i: usize) -> Result<()> {
        let what = format!("node {i} (tag {tag})");
        let p = super::text::finite_point(p)
            .map_err(|m| self.ctx().err(at, format!("{what} has a {m}")))?;
        let tag = u64::try_from(tag).ok().filter(|&t| t > 0).ok_or_else(|| {
            self.ctx()
                .err(at, format!("{what}: node tags must be positive"))
        })?;
        let index = u32::try_from(self.nodes.len())
            .map_err(|_| self.ctx().err(at, "more nodes than 32-bit indices hold"))?;
        if self.tags.insert(tag, index).is_some() {
            return Err(self
                .ctx()
                .err(at, format!("{what}: tag {tag} is used twice")));
        }
        self.nodes.push(p);
        Ok(())
    }

    /// A count read from an ASCII header line field.
    fn count(&self, line: &Line<'_>, i: usize, what: &str) -> Result<usize> {
        self.ctx().count(line, i, what)
    }

    fn nodes22(&mut self) -> Result<()> {
        let head = self.c.need_line("the node count")?;
        let n = self.count(&head, 0, "node count")?;
        self.nodes.reserve(n.min(self.c.left() / 8));
        for i in 0..n {
            if self.f.binary {
                let what = || format!("node {i} of {n}");
                let b = self.c.take(28, &what)?;
                let tag = decode_i64(&b[..4], Num::I32, self.f.endian)[0];
                let x = decode_f64(&b[4..], Num::F64, self.f.endian);
                self.add_node(tag, [x[0], x[1], x[2]], None, i)?;
            } else {
                let line = self.c.need_line(&format!("node {i} of {n}"))?;
                let tag = self.ctx().int(&line, 0, &format!("node {i} tag"))?;
                let mut p = [0.0; 3];
                for (k, v) in p.iter_mut().enumerate() {
                    *v = self.ctx().f64(
                        &line,
                        1 + k,
                        &format!("node {i} {}", ["x", "y", "z"][k]),
                    )?;
                }
                self.add_node(tag, p, Some(line.no), i)?;
            }
        }
        if self.f.binary {
            self.c.skip_newline();
        }
        Ok(())
    }

    /// One `size_t` (binary) or an error naming `what`.
    fn size_t(&mut self, what: &dyn Fn() -> String) -> Result<u64> {
        let b = self.c.take(self.f.size_t.size(), what)?;
        Ok(decode_i64(b, self.f.size_t, self.f.endian)[0].max(0) as u64)
    }

    fn int(&mut self, what: &dyn Fn() -> String) -> Result<i64> {
        let b = self.c.take(4, what)?;
        Ok(decode_i64(b, Num::I32, self.f.endian)[0])
    }

    /// A 4.1 header: four numbers (ASCII line, or `ints` i32 then size_t's in binary).
    fn header41(&mut self, ints: usize, what: &str) -> Result<([u64; 4], Option<usize>)> {
        let mut h = [0u64; 4];
        if self.f.binary {
            for (k, slot) in h.iter_mut().enumerate() {
                let w = || format!("the {what} header");
                *slot = if k < ints {
                    self.int(&w)? as u64
                } else {
                    self.size_t(&w)?
                };
            }
            return Ok((h, None));
        }
        let line = self.c.need_line(&format!("the {what} header"))?;
        for (k, slot) in h.iter_mut().enumerate() {
            let v = self
                .ctx()
                .int(&line, k, &format!("{what} header field {}", k + 1))?;
            // Entity dimensions and tags may be negative (orientation); keep the magnitude.
            *slot = if k < ints {
                v.unsigned_abs()
            } else {
                u64::try_from(v).map_err(|_| {
                    self.ctx()
                        .err(Some(line.no), format!("{what} count is {v}"))
                })?
            };
        }
        Ok((h, Some(line.no)))
    }

    fn nodes41(&mut self) -> Result<()> {
        let ([blocks, total, _, _], at) = self.header41(0, "$Nodes")?;
        let total = usize::try_from(total).unwrap_or(usize::MAX);
        self.nodes.reserve(total.min(self.c.left() / 8));
        let mut i = 0usize;
        for b in 0..blocks {
            let ([dim, _tag, parametric, count], bat) =
                self.header41(3, &format!("node block {b}"))?;
            let count = usize::try_from(count).unwrap_or(usize::MAX);
            if count > total - i.min(total) {
                return Err(self.ctx().err(bat.or(at), format!("node block {b} has {count} nodes; the $Nodes header declares {total} in all")));
            }
            let extra = if parametric != 0 {
                dim.min(3) as usize
            } else {
                0
            };
            let mut tags = Vec::with_capacity(count.min(self.c.left()));
            if self.f.binary {
                self.c.fits(count, self.f.size_t.size(), "node tags")?;
                for k in 0..count {
                    tags.push((
                        self.size_t(&|| format!("node tag {k} of block {b}"))? as i64,
                        None,
                    ));
                }
                self.c.fits(count, 8 * (3 + extra), "node coordinates")?;
                for (k, &(tag, _)) in tags.iter().enumerate() {
                    let bytes = self
                        .c
                        .take(8 * (3 + extra), &|| format!("node {} coordinates", i + k))?;
                    let x = decode_f64(bytes, Num::F64, self.f.endian);
                    self.add_node(tag, [x[0], x[1], x[2]], None, i + k)?;
                }
            } else {
                for k in 0..count {
                    let line = self.c.need_line(&format!("node tag {k} of block {b}"))?;
                    tags.push((self.ctx().int(&line, 0, "node tag")?, Some(line.no)));
                }
                for (k, &(tag, _)) in tags.iter().enumerate() {
                    let line = self
                        .c
                        .need_line(&format!("the coordinates of node {}", i + k))?;
                    let mut p = [0.0; 3];
                    for (a, v) in p.iter_mut().enumerate() {
                        *v = self.ctx().f64(
                            &line,
                            a,
                            &format!("node {} {}", i + k, ["x", "y", "z"][a]),
                        )?;
                    }
                    self.add_node(tag, p, Some(line.no), i + k)?;
                }
            }
            i += count;
        }
        if i != total {
            return Err(self.ctx().err(
                at,
                format!("the node blocks hold {i} nodes; the header declares {total}"),
            ));
        }
        if self.f.binary {
            self.c.skip_newline();
        }
        Ok(())
    }

    /// Records element `e` of `etype` with node tags `ids`.
    fn element(&mut self, etype: i64, ids: &[u64], at: Option<usize>, e: usize) -> Result<()> {
        self.elements += 1;
        match etype {
            GMSH_TET4 => {
                let t: [u64; 4] = ids.try_into().map_err(|_| {
                    self.ctx().err(at, format!("element {e}: a tet (type 4) with {} nodes", ids.len()))
                })?;
                self.tets.push((t, at, e));
            }
            11 => {
                return Err(self.ctx().err(
                    at,
                    format!("element {e} is a 10-node tetrahedron (type 11); only linear tets (type 4) can be simulated: mesh with gmsh -order 1"),
                ))
            }
            t => *self.skipped.entry(t).or_default() += 1,
        }
        Ok(())
    }

    fn elements22(&mut self) -> Result<()> {
        let head = self.c.need_line("the element count")?;
        let m = self.count(&head, 0, "element count")?;
        let mut e = 0usize;
        if self.f.binary {
            while e < m {
                let w = || format!("the element block header after element {e}");
                let etype = self.int(&w)?;
                let follow = self.int(&w)?;
                let ntags = self.int(&w)?;
                let nn = nodes_per_element(etype).ok_or_else(|| {
                    self.ctx()
                        .err(None, format!("element {e}: unknown element type {etype}"))
                })?;
                let (Ok(follow), Ok(ntags)) = (usize::try_from(follow), usize::try_from(ntags))
                else {
                    return Err(self.ctx().err(
                        None,
                        format!("element {e}: negative count in the block header"),
                    ));
                };
                if follow == 0 || follow > m - e {
                    return Err(self.ctx().err(
                        None,
                        format!(
                            "element {e}: a block of {follow} elements, with {} of {m} left",
                            m - e
                        ),
                    ));
                }
                if ntags > 1 << 20 {
                    return Err(self
                        .ctx()
                        .err(None, format!("element {e}: {ntags} tags per element")));
                }
                let per = 1 + ntags + nn;
                self.c.fits(follow, 4 * per, "elements")?;
                for _ in 0..follow {
                    let b = self.c.take(4 * per, &|| format!("element {e}"))?;
                    let v = decode_i64(b, Num::I32, self.f.endian);
                    let ids: Vec<u64> = v[1 + ntags..].iter().map(|&x| x.max(0) as u64).collect();
                    self.element(etype, &ids, None, e)?;
                    e += 1;
                }
            }
            self.c.skip_newline();
            return Ok(());
        }
        for e in 0..m {
            let line = self.c.need_line(&format!("element {e} of {m}"))?;
            let etype = self.ctx().int(&line, 1, &format!("element {e} type"))?;
            let ntags = self
                .ctx()
                .count(&line, 2, &format!("element {e} tag count"))?;
            let first = 3usize.saturating_add(ntags);
            if first > line.tokens.len() {
                return Err(self.ctx().err(
                    Some(line.no),
                    format!(
                        "element {e}: {ntags} tags but only {} values on the line",
                        line.tokens.len()
                    ),
                ));
            }
            let mut ids = Vec::with_capacity(line.tokens.len() - first);
            for k in first..line.tokens.len() {
                let v = self
                    .ctx()
                    .int(&line, k, &format!("element {e} node {}", k - first))?;
                ids.push(v.max(0) as u64);
            }
            self.element(etype, &ids, Some(line.no), e)?;
        }
        Ok(())
    }

    fn elements41(&mut self) -> Result<()> {
        let ([blocks, total, _, _], at) = self.header41(0, "$Elements")?;
        let total = usize::try_from(total).unwrap_or(usize::MAX);
        let mut e = 0usize;
        for b in 0..blocks {
            let ([_dim, _tag, etype, count], bat) =
                self.header41(3, &format!("element block {b}"))?;
            let etype = etype as i64;
            let count = usize::try_from(count).unwrap_or(usize::MAX);
            if count > total - e.min(total) {
                return Err(self.ctx().err(bat.or(at), format!("element block {b} has {count} elements; the $Elements header declares {total} in all")));
            }
            if self.f.binary {
                let nn = nodes_per_element(etype).ok_or_else(|| {
                    self.ctx().err(
                        None,
                        format!("element block {b}: unknown element type {etype}"),
                    )
                })?;
                let size = self.f.size_t.size();
                self.c.fits(count, size * (1 + nn), "elements")?;
                for _ in 0..count {
                    let bytes = self.c.take(size * (1 + nn), &|| format!("element {e}"))?;
                    let v = decode_i64(bytes, self.f.size_t, self.f.endian);
                    let ids: Vec<u64> = v[1..].iter().map(|&x| x.max(0) as u64).collect();
                    self.element(etype, &ids, None, e)?;
                    e += 1;
                }
            } else {
                for _ in 0..count {
                    let line = self.c.need_line(&format!("element {e}"))?;
                    let mut ids = Vec::with_capacity(line.tokens.len().saturating_sub(1));
                    for k in 1..line.tokens.len() {
                        ids.push(
                            self.ctx()
                                .int(&line, k, &format!("element {e} node {}", k - 1))?
                                .max(0) as u64,
                        );
                    }
                    self.element(etype, &ids, Some(line.no), e)?;
                    e += 1;
                }
            }
        }
        if e != total {
            return Err(self.ctx().err(
                at,
                format!("the element blocks hold {e} elements; the header declares {total}"),
            ));
        }
        if self.f.binary {
            self.c.skip_newline();
        }
        Ok(())
    }

    fn finish(self) -> Result<TetMesh> {
        let ctx = self.ctx();
        if self.nodes.is_empty() {
            return Err(ctx.err(None, "no nodes (no $Nodes section, or an empty one)"));
        }
        if self.tets.is_empty() {
            let found = if self.skipped.is_empty() {
                "no elements at all".to_string()
            } else {
                self.skipped
                    .iter()
                    .map(|(t, n)| format!("{n} of type {t}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(ctx.err(
                None,
                format!("no tetrahedra (element type 4) in the file; it has {found}"),
            ));
        }
        let mut tets = Vec::with_capacity(self.tets.len());
        for (ids, at, e) in &self.tets {
            let mut t = [0u32; 4];
            for (k, (id, slot)) in ids.iter().zip(&mut t).enumerate() {
                *slot = *self.tags.get(id).ok_or_else(|| {
                    ctx.err(
                        *at,
                        format!("element {e} node {k}: there is no node with tag {id}"),
                    )
                })?;
            }
            tets.push(t);
        }
        super::finish_tets(self.nodes, tets)
    }
}
