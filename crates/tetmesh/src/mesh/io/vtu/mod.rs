//! XML VTK unstructured grids (`.vtu`): the points and the linear tetrahedra.
//!
//! Read: every `Piece` of the `UnstructuredGrid` (pieces are concatenated), its `Points` and
//! its `Cells` (`connectivity`, `offsets`, `types`). Data arrays may be `ascii`, inline
//! `binary` (base64) or `appended` (`raw` or `base64` `AppendedData`), uncompressed or
//! compressed with `vtkZLibDataCompressor` (meshio's default is inline binary + zlib), with
//! `UInt32` or `UInt64` headers, little- or big-endian. Cell type 10 (tetra) is kept, other
//! cell types are skipped, quadratic tets (24) are an error, a file without tets is an error
//! naming the cell types it has. Nodes that no tet uses are dropped; the tets keep the file's
//! orientation. Errors name the file and the line of the `DataArray` (or the XML error's
//! line). Not read: the LZ4 and LZMA compressors, polyhedron cells' face streams (polyhedra
//! are skipped like any non-tet cell), `PUnstructuredGrid` (`.pvtu`).
//!
//! The XML is parsed by `roxmltree` (already built for `shaderc-sys`, fuzzed, no panics on bad
//! input); zlib by `flate2`. The raw appended section is binary, not XML, so it is cut out
//! before the XML is parsed. `vtkio` 0.6.3 was considered: it cannot read meshio's legacy VTK
//! 5.1 files, builds `nom` 3 and C compression libraries by default, and its errors carry
//! no line; 0.7 is a release candidate.
//!
//! Written: linear tetrahedra with point and cell fields ([`write_vtu`]), and ParaView data
//! collections (`.pvd`, [`write_pvd`]) that tie a series of them to simulated times.
//!
//! Arrays are written inline as `format="binary"`: little-endian values, preceded by a
//! `UInt64` byte count, base64-encoded together (the layout VTK, ParaView and meshio read
//! for uncompressed inline data). Points and fields are `Float64`, connectivity and offsets
//! `Int64`, cell types and flags `UInt8`.

mod read;
mod write;

pub use read::{parse, read_vtu};
pub use write::{write_pvd, write_vtu};
