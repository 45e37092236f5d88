//! Data attached to a tet mesh's points and cells for the VTK writers ([`super::vtk`],
//! [`super::vtu`]): named scalar, vector and flag fields, checked once before writing.

use crate::error::{Error, Result};
use glam::DVec3;

/// The values of one field, one per point or per cell.
#[derive(Debug, Clone, Copy)]
pub enum FieldValues<'a> {
    /// One `f64` each (written as VTK `double` / `Float64`).
    Scalar(&'a [f64]),
    /// Three components each (VTK vectors).
    Vector(&'a [DVec3]),
    /// One byte each, 0 or 1 (VTK `unsigned_char` / `UInt8`).
    Flag(&'a [u8]),
}

impl FieldValues<'_> {
    /// Number of values (points or cells).
    pub fn len(&self) -> usize {
        match self {
            FieldValues::Scalar(v) => v.len(),
            FieldValues::Vector(v) => v.len(),
            FieldValues::Flag(v) => v.len(),
        }
    }

    /// Whether there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Index of the first non-finite value, if any.
    fn first_non_finite(&self) -> Option<usize> {
        match self {
            FieldValues::Scalar(v) => v.iter().position(|x| !x.is_finite()),
            FieldValues::Vector(v) => v.iter().position(|x| !x.is_finite()),
            FieldValues::Flag(_) => None,
        }
    }
}

/// A named field.
#[derive(Debug, Clone, Copy)]
pub struct Field<'a> {
    /// Name shown by ParaView (non-empty ASCII, no whitespace).
    pub name: &'a str,
    /// The values.
    pub values: FieldValues<'a>,
}

/// Point data and cell data of a tet mesh.
#[derive(Debug, Clone, Default)]
pub struct Fields<'a> {
    /// One value per node.
    pub point: Vec<Field<'a>>,
    /// One value per tet.
    pub cell: Vec<Field<'a>>,
}

impl Fields<'_> {
    /// Error unless every field has a valid, unique name, one value per point (cell) and
    /// only finite values (VTK's ASCII reader parses neither `NaN` nor `inf`).
    pub fn check(&self, points: usize, cells: usize) -> Result<()> {
        for (fields, n, what, elements) in [
            (&self.point, points, "point", "nodes"),
            (&self.cell, cells, "cell", "tets"),
        ] {
            for (i, f) in fields.iter().enumerate() {
                let name = f.name;
                if name.is_empty() || name.chars().any(|c| c.is_whitespace() || !c.is_ascii()) {
                    return Err(Error::param(
                        "fields",
                        format!(
                            "{what} field name `{name}` must be non-empty ASCII without spaces"
                        ),
                    ));
                }
                if fields[..i].iter().any(|g| g.name == name) {
                    return Err(Error::param(
                        "fields",
                        format!("{what} field `{name}` is given twice"),
                    ));
                }
                if f.values.len() != n {
                    return Err(Error::param(
                        "fields",
                        format!(
                            "{what} field `{name}` has {} values for {n} {elements}",
                            f.values.len()
                        ),
                    ));
                }
                if let Some(k) = f.values.first_non_finite() {
                    return Err(Error::param(
                        "fields",
                        format!("{what} field `{name}` is not finite at {what} {k}"),
                    ));
                }
            }
        }
        Ok(())
    }
}
