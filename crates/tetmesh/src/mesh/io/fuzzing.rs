//! The readers on arbitrary bytes, as the fuzz targets (`fuzz/`, `scripts/fuzz.sh`) and
//! their regression test (`tests/fuzz_regressions.rs`) run them: each entry point drops
//! what the reader returns, so a panic, a hang or a runaway allocation is the only failure.

use std::path::Path;

use super::{parse_surface, parse_tet_mesh, tetgen, SurfaceFormat, TetFormat};

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

/// A fuzz target's entry point: the reader on arbitrary bytes.
pub type Target = fn(&[u8]);

/// Every entry point by the name of its fuzz target.
pub const TARGETS: [(&str, Target); 4] = [
    ("surface", surface),
    ("tet_mesh", tet_mesh),
    ("sniffed", sniffed),
    ("tetgen", tetgen),
];
