//! The bundled meshes (`meshes/sphere`, `meshes/box`, `meshes/torus`), compiled into the
//! binary so that `tetrasim run` and `tetrasim bench` work from any folder and after the
//! source tree has moved or been deleted (an installed binary). A file of the same name in the
//! working directory still wins (see [`super::load_mesh`]).

use crate::mesh::io::tetgen::parse_tetgen;
use crate::mesh::TetMesh;
use std::path::Path;

/// `(name, .node, .ele, .face)` of a bundled mesh.
type Bundled = (&'static str, &'static [u8], &'static [u8], &'static [u8]);

/// The bundled meshes.
const MESHES: [Bundled; 3] = [
    (
        "meshes/sphere",
        include_bytes!("../../../../meshes/sphere.node"),
        include_bytes!("../../../../meshes/sphere.ele"),
        include_bytes!("../../../../meshes/sphere.face"),
    ),
    (
        "meshes/box",
        include_bytes!("../../../../meshes/box.node"),
        include_bytes!("../../../../meshes/box.ele"),
        include_bytes!("../../../../meshes/box.face"),
    ),
    (
        "meshes/torus",
        include_bytes!("../../../../meshes/torus.node"),
        include_bytes!("../../../../meshes/torus.ele"),
        include_bytes!("../../../../meshes/torus.face"),
    ),
];

/// The names of the bundled meshes.
pub fn names() -> impl Iterator<Item = &'static str> {
    MESHES.iter().map(|m| m.0)
}

/// The bundled mesh called `name` (`meshes/sphere`, `meshes/box` or `meshes/torus`, with or
/// without a `./` in front), parsed from the copy compiled into the binary.
pub fn bundled(name: &str) -> Option<TetMesh> {
    let name = name.strip_prefix("./").unwrap_or(name);
    let (label, node, ele, face) = MESHES.iter().find(|m| m.0 == name)?;
    // The files are checked by the tests below; a parse failure would be a build mistake.
    parse_tetgen(node, ele, Some(face), Path::new(label)).ok()
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_bundled_mesh_parses() {
        for name in super::names() {
            let m = super::bundled(name).unwrap_or_else(|| panic!("{name}"));
            assert!(m.tets.len() > 1000, "{name}");
        }
        assert!(super::bundled("meshes/none").is_none());
    }
}
