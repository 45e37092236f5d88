//! The readers (and the Python layer's array checks) on arbitrary bytes, as the fuzz
//! targets (`fuzz/`, `scripts/fuzz.sh`) and their regression test
//! (`tests/fuzz_regressions.rs`) run them: each entry point drops what the reader returns,
//! so a panic, a hang or a runaway allocation is the only failure.

use std::path::Path;

use super::{check_tet_mesh, parse_surface, parse_tet_mesh, tetgen, SurfaceFormat, TetFormat};
use crate::mesh::{arrays, topology, TetMesh};

/// The surface formats, in the order the first byte of [`surface`]'s input picks them.
const SURFACES: [SurfaceFormat; 4] = [
    SurfaceFormat::Ply,
    SurfaceFormat::Obj,
    SurfaceFormat::Off,
    SurfaceFormat::Stl,
];

/// The single-file tet formats, in the order the first byte of [`tet_mesh`]'s input picks
/// them.
const TETS: [TetFormat; 4] = [
    TetFormat::Vtk,
    TetFormat::Vtu,
    TetFormat::Gmsh,
    TetFormat::Medit,
];

/// The byte that parts [`tetgen`]'s input into its `.node`, `.ele` and `.face` files (none
/// of their text holds it).
pub const TETGEN_SEPARATOR: u8 = 0xFF;

/// The path the readers name in their errors.
fn path() -> &'static Path {
    Path::new("fuzz-input")
}

/// A surface reader on `data[1..]`, the format picked by `data[0]` (PLY, OBJ, OFF, STL).
pub fn surface(data: &[u8]) {
    if let Some((&pick, bytes)) = data.split_first() {
        let format = SURFACES[pick as usize % SURFACES.len()];
        let _ = parse_surface(bytes, format, path());
    }
}

/// A tet-mesh reader on `data[1..]`, the format picked by `data[0]` (legacy VTK, VTU, gmsh,
/// Medit).
pub fn tet_mesh(data: &[u8]) {
    if let Some((&pick, bytes)) = data.split_first() {
        let format = TETS[pick as usize % TETS.len()];
        let _ = parse_tet_mesh(bytes, format, path());
    }
}

/// `read_tet_mesh`'s route for a file whose extension names no format: the format sniffed
/// from the first bytes ([`TetFormat::sniff`]), then its reader.
pub fn sniffed(data: &[u8]) {
    if let Some(format) = TetFormat::sniff(data) {
        let _ = parse_tet_mesh(data, format, path());
    }
}

/// The TetGen reader on `data` parted at [`TETGEN_SEPARATOR`] into `.node`, `.ele` and an
/// optional `.face`.
pub fn tetgen(data: &[u8]) {
    let mut files = data.splitn(3, |&b| b == TETGEN_SEPARATOR);
    let node = files.next().unwrap_or_default();
    let ele = files.next().unwrap_or_default();
    let _ = tetgen::parse_tetgen(node, ele, files.next(), path());
}

/// `tetrasim.Mesh(nodes, tets)`'s checks on arrays made of `data` ([`arrays_mesh`]), and
/// the boundary of the mesh they pass, found as `Mesh.faces` finds it.
pub fn arrays(data: &[u8]) {
    if let Some(mesh) = arrays_mesh(data) {
        let _ = topology::boundary_faces(&mesh.tets);
    }
}

/// The mesh `tetrasim.Mesh(nodes, tets)` would make of arrays read from `data`, or `None`
/// where its checks refuse them: `data[0] % 5` columns of nodes (float64, little-endian)
/// and `data[1] % 6` of tets (int64), then the nodes' row count (u16, little-endian), the
/// nodes' values and the tets' values, each array cut to whole rows (numpy's shapes
/// always match their values). [`arrays_input`] writes a mesh this way.
pub fn arrays_mesh(data: &[u8]) -> Option<TetMesh> {
    let [node_columns, tet_columns, rows_low, rows_high, ref rest @ ..] = *data else {
        return None;
    };
    let (node_columns, tet_columns) = (node_columns as usize % 5, tet_columns as usize % 6);
    let node_rows = u16::from_le_bytes([rows_low, rows_high]) as usize;
    let (node_bytes, tet_bytes) = rest.split_at((node_rows * node_columns * 8).min(rest.len()));
    let words = |bytes: &[u8], columns: usize| -> Vec<[u8; 8]> {
        let whole = match columns {
            0 => 0,
            c => bytes.len() / 8 / c * c,
        };
        bytes
            .chunks_exact(8)
            .take(whole)
            .map(|b| b.try_into().unwrap_or_default())
            .collect()
    };
    let nodes: Vec<f64> = words(node_bytes, node_columns)
        .into_iter()
        .map(f64::from_le_bytes)
        .collect();
    let tets: Vec<i64> = words(tet_bytes, tet_columns)
        .into_iter()
        .map(i64::from_le_bytes)
        .collect();
    let shape = |values: usize, columns: usize| [values.checked_div(columns).unwrap_or(0), columns];
    let nodes = arrays::points(shape(nodes.len(), node_columns), &nodes, "nodes", None).ok()?;
    let tets =
        arrays::index_rows::<4>(shape(tets.len(), tet_columns), &tets, "tets", nodes.len()).ok()?;
    let mesh = TetMesh {
        nodes,
        tets,
        faces: Vec::new(),
    };
    check_tet_mesh(&mesh).ok().map(|()| mesh)
}

/// `mesh`'s nodes and tets as [`arrays_mesh`] reads them (at most 65,535 nodes): a seed
/// for the `arrays` target.
pub fn arrays_input(mesh: &TetMesh) -> Vec<u8> {
    let rows = u16::try_from(mesh.nodes.len()).unwrap_or(u16::MAX);
    let mut bytes = vec![3, 4];
    bytes.extend(rows.to_le_bytes());
    for p in mesh.nodes.iter().take(rows as usize) {
        bytes.extend(p.to_array().iter().flat_map(|v| v.to_le_bytes()));
    }
    for t in &mesh.tets {
        bytes.extend(t.iter().flat_map(|&i| i64::from(i).to_le_bytes()));
    }
    bytes
}

/// A fuzz target's entry point: the reader on arbitrary bytes.
pub type Target = fn(&[u8]);

/// Every entry point by the name of its fuzz target.
pub const TARGETS: [(&str, Target); 5] = [
    ("surface", surface),
    ("tet_mesh", tet_mesh),
    ("sniffed", sniffed),
    ("tetgen", tetgen),
    ("arrays", arrays),
];
