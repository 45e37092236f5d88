//! Where a mesh is put before a run ([`Placement`]).

use serde::{Deserialize, Serialize};

/// Where the mesh is put before the run (physics.md, preset `seed`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    /// Uniformly scale so the bounding box's largest side is this many metres
    /// (`None` keeps the mesh's own size).
    pub fit_size: Option<f64>,
    /// Put the lowest node this high above `y = 0`, and, when the mesh is fitted, centre it
    /// over the origin in X and Z (`None` keeps the mesh where it is).
    pub drop_height: Option<f64>,
}

impl Default for Placement {
    fn default() -> Self {
        Placement {
            fit_size: Some(1.0),
            drop_height: Some(0.1),
        }
    }
}
