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
