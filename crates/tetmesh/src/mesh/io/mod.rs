//! Readers and writers for surface and tet-mesh formats, one file per format.
//!
//! | format | read | write | module |
//! | --- | --- | --- | --- |
//! | PLY (ascii, binary LE/BE) | [`read_surface`] | [`write_surface`] (binary LE), [`ply::write`] | [`ply`] |
//! | Wavefront OBJ | [`read_surface`] | [`write_surface`] | [`obj`] |
//! | OFF | [`read_surface`] | [`write_surface`] | [`off`] |
//! | STL (ascii, binary) | [`read_surface`] | [`write_surface`] (binary) | [`stl`] |
//! | TetGen `.node/.ele/.face` | [`read_tetgen`], [`read_tet_mesh`] | [`write_tetgen`] | [`tetgen`] |
//! | legacy VTK unstructured grid `.vtk` (ASCII, BINARY; 2.0 to 5.1) | [`read_tet_mesh`] | [`write_vtk`], [`write_vtk_fields`] (ASCII) | [`vtk`] |
//! | XML VTK `.vtu` (ascii, base64, appended raw/base64, zlib) | [`read_tet_mesh`] | [`write_vtu`] (base64) | [`vtu`] |
//! | ParaView collection `.pvd` | -- | [`write_pvd`] | [`vtu`] |
//! | gmsh `.msh` 2.2 and 4.1 (ASCII, binary) | [`read_tet_mesh`] | -- | [`gmsh`] |
//! | Medit `.mesh` (ASCII) | [`read_tet_mesh`] | -- | [`medit`] |
//!
//! The VTK writers take point and cell data as [`Fields`]; PLY surfaces can carry a
//! per-vertex quality ([`ply::write_with_quality`]).
//!
//! Surface formats are chosen by the file extension (case-insensitive). Tet-mesh formats are
//! chosen by the extension too, else by the first bytes ([`TetFormat::sniff`]). The tet
//! readers keep linear tets only (other cell types are skipped, quadratic tets are an error
//! with the reason), keep each tet's orientation as in the file (the model flips negative
//! tets when it builds: `tetrasim::model`), and all but TetGen's drop nodes that no tet uses
//! ([`drop_unused_nodes`]). Every reader checks
//! what it reads: counts against headers, finite coordinates, indices in range, at least one
//! element; a failure is an [`Error::Parse`] naming the file and the line (text formats) or the
//! element (binary formats). No reader panics on any input: the property tests in
//! `tests/mesh_io_props.rs` feed them random bytes and truncated files.
//!
//! Every writer goes through [`write_atomic`]: the data goes to a temporary file in the
//! destination folder, which is renamed over the destination only when everything was written,
//! so a failure leaves the old file (or nothing) in place, never half a file.
//!
//! Crates considered, and why most parsing here is our own:
//! - `ply-rs` 0.1.3 reads all encodings and list types, but panics on a header count that does
//!   not fit in 64 bits (`n.parse().unwrap()` in its grammar), stores each element in a
//!   hash map keyed by property name, was last released in 2020, and builds `skeptic` (a dozen
//!   crates) as a build dependency of every user. Its errors carry no element index either.
//!   The PLY reader here is one small module with checked reads.
//! - `tobj` 4 triangulates polygons and handles negative indices, but its errors are a bare
//!   enum (`FaceVertexOutOfBounds`) with neither line nor index, it splits the mesh into models
//!   by group, and reads `f32` unless a feature is set. OBJ's `v`/`f` subset is small, so the
//!   reader here is ours; the tests read our OBJ output back with `tobj` as an independent
//!   check.
//! - `stl_io` 0.11 reads and writes STL with no dependencies, but it takes any binary file whose
//!   80-byte header starts with `solid ` for ASCII (common in CAD exports), and its errors name
//!   neither line nor facet. The reader here decides by the binary size rule first; the binary
//!   writer is `stl_io`'s.
//! - `vtkio` 0.6.3 (VTK legacy and XML) builds `nom` 3 and, by default, the C libraries of
//!   LZMA and LZ4; it cannot read legacy VTK 5.1 (`OFFSETS`/`CONNECTIVITY`), which is what
//!   meshio 5 writes by default; 0.7 reads 5.1 but is a release candidate (0.7.0-rc2). Its
//!   errors name neither line nor cell. The legacy reader here ([`vtk`]) is one small module;
//!   the `.vtu` reader ([`vtu`]) parses the XML with `roxmltree` 0.20 (already built for
//!   `shaderc-sys`, fuzzed, never panics) and inflates zlib arrays with `flate2` 1
//!   (already in the tree through `png`); base64 is a 30-line decoder, since VTK writes a
//!   compressed array's header and data as two base64 runs, which strict decoders refuse.
//! - `mshio` 0.4.2 reads gmsh 4.1 only (not 2.2, which meshio's `gmsh22` and many tools write),
//!   is built on `nom` 5, and has `expect`/`unwrap` in its number parsers; [`gmsh`] reads both
//!   versions with one set of checks.
//! - Medit has no maintained Rust reader; [`medit`] is a keyword/count scanner.
//! - `tempfile` provides the temporary file for [`write_atomic`].

mod cursor;
mod fields;
pub mod fuzzing;
pub mod gmsh;
pub mod medit;
pub mod obj;
pub mod off;
pub mod ply;
pub mod stl;
pub mod tetgen;
mod text;
pub mod vtk;
pub mod vtu;

pub use fields::{Field, FieldValues, Fields};
pub use tetgen::{read_tetgen, write_tetgen};
pub use vtk::{write_vtk, write_vtk_fields};
pub use vtu::{write_pvd, write_vtu};

use crate::error::{Error, Result};
use crate::mesh::{SurfaceMesh, TetMesh};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The surface formats known to [`read_surface`] and [`write_surface`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceFormat {
    /// Stanford PLY.
    Ply,
    /// Wavefront OBJ.
    Obj,
    /// Object File Format.
    Off,
    /// Stereolithography.
    Stl,
}

impl SurfaceFormat {
    /// The format named by `path`'s extension (case-insensitive), or a parse error naming the
    /// file and the extensions that are known.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("ply") => Ok(Self::Ply),
            Some("obj") => Ok(Self::Obj),
            Some("off") => Ok(Self::Off),
            Some("stl") => Ok(Self::Stl),
            other => Err(Error::parse(
                path,
                None,
                format!(
                    "unknown surface format {}; expected .ply, .obj, .off or .stl",
                    other
                        .map(|e| format!("`.{e}`"))
                        .unwrap_or_else(|| "(no extension)".into())
                ),
            )),
        }
    }
}

/// Reads a triangle surface from a `.ply`, `.obj`, `.off` or `.stl` file (chosen by the
/// extension, case-insensitive). Polygons are split into triangle fans; STL vertices are
/// welded. Coordinates are in the file's units.
pub fn read_surface(path: impl AsRef<Path>) -> Result<SurfaceMesh> {
    let path = path.as_ref();
    let format = SurfaceFormat::from_path(path)?;
    let bytes = read_bytes(path)?;
    parse_surface(&bytes, format, path)
}

/// Parses the bytes of a surface file in `format`; `path` is used in error messages only.
pub fn parse_surface(bytes: &[u8], format: SurfaceFormat, path: &Path) -> Result<SurfaceMesh> {
    match format {
        SurfaceFormat::Ply => ply::parse(bytes, path),
        SurfaceFormat::Obj => obj::parse(bytes, path),
        SurfaceFormat::Off => off::parse(bytes, path),
        SurfaceFormat::Stl => stl::parse(bytes, path),
    }
}

/// Writes a triangle surface in the format named by the extension: PLY (binary
/// little-endian; see [`ply::write`] for ASCII), OBJ, OFF or binary STL (single precision).
/// The mesh is checked first (see [`check_surface`]); the file is written atomically.
pub fn write_surface(path: impl AsRef<Path>, mesh: &SurfaceMesh) -> Result<()> {
    let path = path.as_ref();
    match SurfaceFormat::from_path(path)? {
        SurfaceFormat::Ply => ply::write(path, mesh, ply::PlyEncoding::BinaryLittleEndian),
        SurfaceFormat::Obj => obj::write(path, mesh),
        SurfaceFormat::Off => off::write(path, mesh),
        SurfaceFormat::Stl => stl::write(path, mesh),
    }
}

/// Checks that a surface can be written and read back: at least one vertex and one triangle,
/// finite coordinates, indices in range, counts that fit in `u32`.
pub fn check_surface(mesh: &SurfaceMesh) -> Result<()> {
    if mesh.vertices.is_empty() || mesh.triangles.is_empty() {
        return Err(Error::Mesh(format!(
            "surface is empty ({} vertices, {} triangles)",
            mesh.vertices.len(),
            mesh.triangles.len()
        )));
    }
    check_points(&mesh.vertices, "vertex")?;
    check_indices(&mesh.triangles, mesh.vertices.len(), "triangle")
}

/// Checks that a tet mesh can be written: at least one node and one tet, finite
/// coordinates, indices in range.
pub fn check_tet_mesh(mesh: &crate::mesh::TetMesh) -> Result<()> {
    if mesh.nodes.is_empty() || mesh.tets.is_empty() {
        return Err(Error::Mesh(format!(
            "tet mesh is empty ({} nodes, {} tets)",
            mesh.nodes.len(),
            mesh.tets.len()
        )));
    }
    check_points(&mesh.nodes, "node")?;
    check_indices(&mesh.tets, mesh.nodes.len(), "tet")
}

/// Error unless every point is finite; `what` names an element ("vertex", "node").
pub(crate) fn check_points(points: &[glam::DVec3], what: &str) -> Result<()> {
    if u32::try_from(points.len()).is_err() {
        return Err(Error::Mesh(format!(
            "{} {what}s do not fit in 32-bit indices",
            points.len()
        )));
    }
    match points.iter().position(|p| !p.is_finite()) {
        Some(i) => Err(Error::Mesh(format!(
            "{what} {i} has a non-finite coordinate {}",
            points[i]
        ))),
        None => Ok(()),
    }
}

/// Error unless every index of every element is below `n`; `what` names the element.
pub(crate) fn check_indices<const K: usize>(
    elements: &[[u32; K]],
    n: usize,
    what: &str,
) -> Result<()> {
    for (i, e) in elements.iter().enumerate() {
        if let Some(&bad) = e.iter().find(|&&v| v as usize >= n) {
            return Err(Error::Mesh(format!(
                "{what} {i} has index {bad}, but there are only {n} points"
            )));
        }
    }
    Ok(())
}

/// Reads a whole file, naming it in the error.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|e| Error::io(path, e))
}

/// A file being written: a temporary file beside the destination, renamed over it by
/// [`PendingFile::commit`]. Dropped without commit, the temporary file is deleted.
pub struct PendingFile {
    dest: PathBuf,
    writer: BufWriter<tempfile::NamedTempFile>,
}

impl PendingFile {
    /// Opens a temporary file in `dest`'s folder (which must exist).
    pub fn create(dest: &Path) -> Result<Self> {
        let dir = match dest.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let name = dest
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".tmp")
            .tempfile_in(dir)
            .map_err(|e| Error::io(dest, e))?;
        Ok(Self {
            dest: dest.to_path_buf(),
            writer: BufWriter::new(tmp),
        })
    }

    /// The buffered writer into the temporary file.
    pub fn writer(&mut self) -> &mut impl Write {
        &mut self.writer
    }

    /// The destination path.
    pub fn dest(&self) -> &Path {
        &self.dest
    }

    /// Flushes, syncs and renames the temporary file over the destination.
    pub fn commit(self) -> Result<()> {
        let dest = self.dest;
        let tmp = self
            .writer
            .into_inner()
            .map_err(|e| Error::io(&dest, e.into_error()))?;
        tmp.as_file().sync_all().map_err(|e| Error::io(&dest, e))?;
        set_default_permissions(&tmp, &dest);
        tmp.persist(&dest).map_err(|e| Error::io(&dest, e.error))?;
        Ok(())
    }
}

/// Temporary files are created private (0600); give the result what a plain `File::create`
/// would usually give (the old file's mode if there was one, else 0644). Best effort.
#[cfg(unix)]
fn set_default_permissions(tmp: &tempfile::NamedTempFile, dest: &Path) {
    use std::os::unix::fs::PermissionsExt;
    let perms = std::fs::metadata(dest)
        .map(|m| m.permissions())
        .unwrap_or_else(|_| std::fs::Permissions::from_mode(0o644));
    let _ = tmp.as_file().set_permissions(perms);
}

#[cfg(not(unix))]
fn set_default_permissions(_tmp: &tempfile::NamedTempFile, _dest: &Path) {}

/// Writes `path` atomically: `fill` writes into a temporary file in the same folder, which
/// replaces `path` only if `fill` and the final flush succeed. I/O errors name `path`.
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let mut file = PendingFile::create(path)?;
    fill(file.writer()).map_err(|e| Error::io(path, e))?;
    file.commit()
}

/// Formats an `f64` so that it reads back to the same value (shortest round-trip form), in
/// exponent notation for very large or small magnitudes.
pub(crate) fn fmt_f64(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-4..1e15).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// The tet-mesh formats known to [`read_tet_mesh`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TetFormat {
    /// TetGen `.node/.ele` (and `.face`), given as the prefix or any of the three files.
    TetGen,
    /// Legacy VTK unstructured grid (`.vtk`).
    Vtk,
    /// XML VTK unstructured grid (`.vtu`).
    Vtu,
    /// gmsh `.msh` 2.2 or 4.1.
    Gmsh,
    /// Medit `.mesh`.
    Medit,
}

/// The tet-mesh file extensions, for messages.
pub const TET_FORMATS: &str =
    "TetGen prefix (PREFIX.node + PREFIX.ele), .vtk (legacy VTK), .vtu (XML VTK), .msh (gmsh 2.2/4.1), .mesh (Medit)";

impl TetFormat {
    /// The format named by `path`'s extension (case-insensitive), if it names one.
    pub fn from_extension(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "node" | "ele" | "face" => Self::TetGen,
            "vtk" => Self::Vtk,
            "vtu" => Self::Vtu,
            "msh" => Self::Gmsh,
            "mesh" => Self::Medit,
            _ => return None,
        })
    }

    /// The format of a file from its first bytes: `# vtk DataFile`, `<VTKFile` (after an
    /// optional XML declaration), `$MeshFormat`, `MeshVersionFormatted` (after comments).
    pub fn sniff(bytes: &[u8]) -> Option<Self> {
        let head = &bytes[..bytes.len().min(4096)];
        let mut start = head.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(head);
        // Blank lines and `#` comments (Medit) before the first keyword.
        loop {
            let trimmed = start.trim_ascii_start();
            if trimmed.starts_with(b"# vtk DataFile") {
                return Some(Self::Vtk);
            }
            if trimmed.starts_with(b"#") {
                let end = trimmed.iter().position(|&b| b == b'\n');
                start = end.map_or(&[][..], |e| &trimmed[e + 1..]);
                continue;
            }
            start = trimmed;
            break;
        }
        if start.starts_with(b"$MeshFormat") {
            Some(Self::Gmsh)
        } else if start.starts_with(b"MeshVersionFormatted") {
            Some(Self::Medit)
        } else if start.starts_with(b"<") && cursor::find(head, b"<VTKFile").is_some() {
            Some(Self::Vtu)
        } else {
            None
        }
    }
}

/// Reads a tet mesh in any format of [`TetFormat`], chosen by the extension
/// (case-insensitive) or, when that names no tet format, by the content
/// ([`TetFormat::sniff`]); a path that is no file but a TetGen prefix (`PREFIX.node` exists)
/// reads TetGen. Indices come back 0-based; tets keep the file's orientation (the model
/// orients them). The VTK, gmsh and Medit readers drop nodes that no tet uses (see
/// [`drop_unused_nodes`]); TetGen's are kept as they are.
pub fn read_tet_mesh(path: &Path) -> Result<TetMesh> {
    if let Some(format) = TetFormat::from_extension(path) {
        if format == TetFormat::TetGen {
            return read_tetgen(path);
        }
        return parse_tet_mesh(&read_bytes(path)?, format, path);
    }
    if path.is_file() {
        let bytes = read_bytes(path)?;
        let format = TetFormat::sniff(&bytes).ok_or_else(|| {
            Error::parse(
                path,
                None,
                format!("unknown tet-mesh format (neither the extension nor the content says which); tet meshes: {TET_FORMATS}"),
            )
        })?;
        return parse_tet_mesh(&bytes, format, path);
    }
    if tetgen::with_ext(path, "node").is_file() {
        return read_tetgen(path);
    }
    Err(Error::parse(
        path,
        None,
        format!(
            "the file does not exist (nor {}.node); tet meshes: {TET_FORMATS}",
            path.display()
        ),
    ))
}

/// Parses the bytes of a single-file tet mesh in `format` (not [`TetFormat::TetGen`], which
/// is two files: see [`tetgen::parse_tetgen`]); `path` names it in errors.
pub fn parse_tet_mesh(bytes: &[u8], format: TetFormat, path: &Path) -> Result<TetMesh> {
    match format {
        TetFormat::Vtk => vtk::parse_vtk(bytes, path),
        TetFormat::Vtu => vtu::parse(bytes, path),
        TetFormat::Gmsh => gmsh::parse(bytes, path),
        TetFormat::Medit => medit::parse(bytes, path),
        TetFormat::TetGen => Err(Error::parse(
            path,
            None,
            "TetGen meshes are two files (.node and .ele): read them with read_tetgen",
        )),
    }
}

/// Removes the nodes that no tet uses and renumbers the tets, keeping the order of the rest.
/// Returns how many were removed. Files from gmsh and meshio often hold such nodes (geometry
/// points, nodes of other element types); the model would give each one a mass and let it
/// fall alone, unconnected, so the readers of those formats drop them.
pub fn drop_unused_nodes(mesh: &mut TetMesh) -> usize {
    let mut new_index = vec![u32::MAX; mesh.nodes.len()];
    for t in &mesh.tets {
        for &v in t {
            new_index[v as usize] = 0;
        }
    }
    let mut kept = 0u32;
    let mut nodes = Vec::with_capacity(mesh.nodes.len());
    for (i, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = kept;
            kept += 1;
            nodes.push(mesh.nodes[i]);
        }
    }
    let removed = mesh.nodes.len() - nodes.len();
    if removed > 0 {
        for t in &mut mesh.tets {
            for v in t.iter_mut() {
                *v = new_index[*v as usize];
            }
        }
        for f in &mut mesh.faces {
            for v in f.iter_mut() {
                *v = new_index[*v as usize];
            }
        }
        mesh.faces.retain(|f| f.iter().all(|&v| v != u32::MAX));
        mesh.nodes = nodes;
    }
    removed
}

/// A tet mesh from checked nodes and tets (indices in range, at least one tet), with unused
/// nodes dropped and no faces (the model derives the boundary).
pub(crate) fn finish_tets(nodes: Vec<glam::DVec3>, tets: Vec<[u32; 4]>) -> Result<TetMesh> {
    check_points(&nodes, "node")?;
    let mut mesh = TetMesh {
        nodes,
        tets,
        faces: Vec::new(),
    };
    drop_unused_nodes(&mut mesh);
    Ok(mesh)
}
