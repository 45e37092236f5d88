//! tetmesh: the meshes of tetrasim and the preprocessing pipeline that makes them.
//!
//! ```text
//! surface file (PLY/OBJ/OFF/STL) --mesh::io--> SurfaceMesh
//!   --prep (scale, repair, simplify, TetGen or voxel mesher)--> TetMesh --mesh::io--> files
//! ```
//!
//! Used by the `tetprep` binary and by the `tetrasim` engine, which re-exports it
//! (`tetrasim::mesh`, `tetrasim::prep`). It needs no GPU and no shader compiler. TetGen
//! (AGPL-3.0) is compiled in only with the `tetgen` feature (on by default).

pub mod error;
pub mod geometry;
pub mod mesh;
pub mod prep;

pub use error::{Error, Result};
pub use mesh::{SurfaceMesh, TetMesh};
