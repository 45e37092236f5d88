//! Writing `.vtu` files and `.pvd` collections (see the module above for the layout).

use crate::error::{Error, Result};
use crate::mesh::io::fields::{FieldValues, Fields};
use crate::mesh::io::vtk::VTK_TETRA;
use crate::mesh::io::{check_tet_mesh, fmt_f64, write_atomic};
use crate::mesh::TetMesh;
use base64::engine::general_purpose::STANDARD as BASE64;
use base64::Engine as _;
use std::io::Write;
use std::path::Path;

/// Writes `mesh` with `fields` as a `.vtu` file, atomically. The mesh and the fields are
/// checked first ([`Fields::check`]).
pub fn write_vtu(path: impl AsRef<Path>, mesh: &TetMesh, fields: &Fields) -> Result<()> {
    check_tet_mesh(mesh)?;
    fields.check(mesh.nodes.len(), mesh.tets.len())?;
    write_atomic(path.as_ref(), |w| write_to(w, mesh, fields))
}

/// One inline binary `DataArray`: `bytes` holds the little-endian values.
fn data_array(
    w: &mut dyn Write,
    indent: &str,
    vtk_type: &str,
    name: Option<&str>,
    components: usize,
    bytes: &[u8],
) -> std::io::Result<()> {
    let mut raw = Vec::with_capacity(8 + bytes.len());
    raw.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    raw.extend_from_slice(bytes);
    write!(w, "{indent}<DataArray type=\"{vtk_type}\"")?;
    if let Some(name) = name {
        write!(w, " Name=\"{name}\"")?;
    }
    if components != 1 {
        write!(w, " NumberOfComponents=\"{components}\"")?;
    }
    writeln!(w, " format=\"binary\">")?;
    writeln!(w, "{indent}  {}", BASE64.encode(&raw))?;
    writeln!(w, "{indent}</DataArray>")
}

fn f64_bytes(values: impl IntoIterator<Item = f64>) -> Vec<u8> {
    values.into_iter().flat_map(f64::to_le_bytes).collect()
}

fn field_array(w: &mut dyn Write, name: &str, values: FieldValues) -> std::io::Result<()> {
    let indent = "        ";
    match values {
        FieldValues::Scalar(v) => data_array(
            w,
            indent,
            "Float64",
            Some(name),
            1,
            &f64_bytes(v.iter().copied()),
        ),
        FieldValues::Vector(v) => data_array(
            w,
            indent,
            "Float64",
            Some(name),
            3,
            &f64_bytes(v.iter().flat_map(|p| p.to_array())),
        ),
        FieldValues::Flag(v) => data_array(w, indent, "UInt8", Some(name), 1, v),
    }
}

fn write_to(w: &mut dyn Write, mesh: &TetMesh, fields: &Fields) -> std::io::Result<()> {
    let (n, m) = (mesh.nodes.len(), mesh.tets.len());
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <UnstructuredGrid>")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{m}\">"
    )?;
    for (tag, list) in [("PointData", &fields.point), ("CellData", &fields.cell)] {
        if list.is_empty() {
            continue;
        }
        writeln!(w, "      <{tag}>")?;
        for field in list {
            field_array(w, field.name, field.values)?;
        }
        writeln!(w, "      </{tag}>")?;
    }
    writeln!(w, "      <Points>")?;
    data_array(
        w,
        "        ",
        "Float64",
        None,
        3,
        &f64_bytes(mesh.nodes.iter().flat_map(|p| p.to_array())),
    )?;
    writeln!(w, "      </Points>")?;
    writeln!(w, "      <Cells>")?;
    let connectivity: Vec<u8> = mesh
        .tets
        .iter()
        .flatten()
        .flat_map(|&i| i64::from(i).to_le_bytes())
        .collect();
    data_array(
        w,
        "        ",
        "Int64",
        Some("connectivity"),
        1,
        &connectivity,
    )?;
    let offsets: Vec<u8> = (1..=m as i64).flat_map(|k| (4 * k).to_le_bytes()).collect();
    data_array(w, "        ", "Int64", Some("offsets"), 1, &offsets)?;
    data_array(
        w,
        "        ",
        "UInt8",
        Some("types"),
        1,
        &vec![VTK_TETRA; m],
    )?;
    writeln!(w, "      </Cells>")?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")
}

/// Writes a ParaView data collection (`.pvd`) listing `entries` as `(time [s], file)`, the
/// files relative to the `.pvd`'s folder. Times must be finite and increasing.
pub fn write_pvd(path: impl AsRef<Path>, entries: &[(f64, String)]) -> Result<()> {
    if let Some(i) = (0..entries.len())
        .find(|&i| !entries[i].0.is_finite() || (i > 0 && entries[i].0 <= entries[i - 1].0))
    {
        return Err(Error::param(
            "pvd",
            format!(
                "time {} of `{}` is not finite or not after the previous one",
                entries[i].0, entries[i].1
            ),
        ));
    }
    if let Some((_, file)) = entries.iter().find(|(_, f)| f.contains(['"', '<', '&'])) {
        return Err(Error::param(
            "pvd",
            format!("file name `{file}` contains a character XML would need escaped"),
        ));
    }
    write_atomic(path.as_ref(), |w| {
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">"
        )?;
        writeln!(w, "  <Collection>")?;
        for (time, file) in entries {
            writeln!(
                w,
                "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{file}\"/>",
                fmt_f64(*time)
            )?;
        }
        writeln!(w, "  </Collection>")?;
        writeln!(w, "</VTKFile>")
    })
}
