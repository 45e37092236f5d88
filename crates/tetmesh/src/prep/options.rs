//! Options of the preprocessing pipeline; they mirror `tetprep`'s command line.

use serde::Serialize;

use crate::error::{Error, Result};
use crate::mesh::repair::RepairOptions;

/// Which mesher fills the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Mesher {
    /// TetGen (constrained Delaunay, quality bound): needs a closed surface without
    /// self-intersections. Requires the `tetgen` feature.
    Tetgen,
    /// Regular grid cells inside the surface, six tets each: works on any surface.
    Voxel,
}

impl Mesher {
    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Mesher::Tetgen => "tetgen",
            Mesher::Voxel => "voxel",
        }
    }
}

/// Tet count the voxel mesher aims at when neither a target nor a max volume is given.
pub const DEFAULT_VOXEL_TETS: usize = 10_000;

/// Everything the pipeline needs to know (see `tetprep --help`).
#[derive(Debug, Clone, PartialEq)]
pub struct PrepOptions {
    /// Radius-edge ratio bound for TetGen (`-q`); `None` meshes without a quality bound.
    pub quality: Option<f64>,
    /// Largest tet volume (`-a`), in the scaled input unit cubed.
    pub max_volume: Option<f64>,
    /// No Steiner points on the surface (TetGen `-Y`).
    pub preserve_surface: bool,
    /// Aim for about this many tets (TetGen: volume bound and simplification chosen to land
    /// within 25 %; voxel: grid size).
    pub target_tets: Option<usize>,
    /// Factor applied to the input coordinates before anything else.
    pub scale: f64,
    /// The mesher to use.
    pub mesher: Mesher,
    /// When TetGen fails, use the voxel mesher (with a warning) instead of failing.
    pub fallback: bool,
    /// Surface repair settings.
    pub repair: RepairOptions,
    /// Keep the mesher's numbering of nodes and tets; `false` (default): renumber both
    /// along a Morton curve for memory locality ([`crate::mesh::order`]).
    pub keep_order: bool,
}

impl Default for PrepOptions {
    fn default() -> Self {
        Self {
            quality: Some(2.0),
            max_volume: None,
            preserve_surface: false,
            target_tets: None,
            scale: 1.0,
            mesher: Mesher::Tetgen,
            fallback: false,
            repair: RepairOptions::default(),
            keep_order: false,
        }
    }
}

impl PrepOptions {
    /// Checks ranges and combinations; errors name the option.
    pub fn validate(&self) -> Result<()> {
        if let Some(q) = self.quality {
            if !(q.is_finite() && q >= 1.0) {
                return Err(Error::param("quality", format!("{q}: the radius-edge ratio must be >= 1.0 (TetGen does not terminate below; 1.2..2 is usual)")));
            }
        }
        if let Some(v) = self.max_volume {
            if !(v.is_finite() && v > 0.0) {
                return Err(Error::param(
                    "max-volume",
                    format!("{v}: must be a positive volume"),
                ));
            }
        }
        if let Some(n) = self.target_tets {
            if n < 6 {
                return Err(Error::param(
                    "target-tets",
                    format!("{n}: must be at least 6"),
                ));
            }
            if self.max_volume.is_some() {
                return Err(Error::param("target-tets", "give either --target-tets or --max-volume, not both (the target chooses the max volume)"));
            }
        }
        if !(self.scale.is_finite() && self.scale > 0.0) {
            return Err(Error::param(
                "scale",
                format!("{}: must be a positive number", self.scale),
            ));
        }
        Ok(())
    }
}
