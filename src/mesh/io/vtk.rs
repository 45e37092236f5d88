//! Legacy VTK (`.vtk`, ASCII) unstructured grids of linear tetrahedra (VTK cell type 10),
//! for viewing in ParaView, with an optional per-tet scalar field.

use super::{check_indices, check_points, fmt_f64, write_atomic};
use crate::error::{Error, Result};
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
    if mesh.nodes.is_empty() || mesh.tets.is_empty() {
        return Err(Error::Mesh(format!(
            "tet mesh is empty ({} nodes, {} tets)",
            mesh.nodes.len(),
            mesh.tets.len()
        )));
    }
    check_points(&mesh.nodes, "node")?;
    check_indices(&mesh.tets, mesh.nodes.len(), "tet")?;
    if let Some((name, values)) = cell_scalars {
        if name.is_empty() || name.chars().any(|c| c.is_whitespace() || !c.is_ascii()) {
            return Err(Error::param(
                "cell_scalars",
                format!("field name `{name}` must be non-empty ASCII without spaces"),
            ));
        }
        if values.len() != mesh.tets.len() {
            return Err(Error::param(
                "cell_scalars",
                format!(
                    "`{name}` has {} values for {} tets",
                    values.len(),
                    mesh.tets.len()
                ),
            ));
        }
        // VTK's ASCII reader does not parse `NaN` or `inf`.
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::param(
                "cell_scalars",
                format!("`{name}` value for tet {i} is {}", values[i]),
            ));
        }
    }
    write_atomic(path.as_ref(), |w| write_to(w, mesh, cell_scalars))
}

fn write_to(
    w: &mut dyn Write,
    mesh: &TetMesh,
    cell_scalars: Option<(&str, &[f64])>,
) -> std::io::Result<()> {
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
    if let Some((name, values)) = cell_scalars {
        writeln!(
            w,
            "CELL_DATA {m}\nSCALARS {name} double 1\nLOOKUP_TABLE default"
        )?;
        for v in values {
            writeln!(w, "{}", fmt_f64(*v))?;
        }
    }
    Ok(())
}
