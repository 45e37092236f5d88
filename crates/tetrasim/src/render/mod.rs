//! Offscreen rendering of the simulation (`tetrasim render`): a Vulkan graphics pipeline on
//! the simulation's own context draws the surface straight from the simulation's position
//! buffer into a multisampled offscreen image; only the finished picture is read back.
//! No window or display is involved, so it runs headless (lavapipe in CI).
//!
//! - [`Renderer`]: one model, one image per call ([`renderer`] has the pass list);
//! - [`sheet`]: contact sheets; [`image`]: PNG files and animated GIFs (the command line's
//!   `tetrasim render` steps every method and writes them);
//! - [`ColourMode`]: flat, volume ratio V/V0 per node (averaged over its tets), spring strain.

pub mod camera;
pub mod colliders;
pub mod geometry;
pub mod gpu_image;
pub mod image;
pub mod layout;
pub mod legend;
pub mod pipelines;
pub mod renderer;
pub mod sheet;
pub mod style;
pub mod target;
pub mod text;

pub use camera::{Camera, SceneFrame};
pub use image::{GifWriter, Image};
pub use renderer::Renderer;

use crate::error::{Error, Result};

/// What colours the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum ColourMode {
    /// One clay colour, lit.
    Flat,
    /// Per node: V/V0 averaged over the tets that share it, on a diverging map (blue: volume
    /// lost, red: gained).
    #[default]
    Volume,
    /// Per node: spring strain (l - l0) / l0 averaged over its springs (blue: compressed).
    Strain,
}

impl ColourMode {
    /// `MODE_*` in glsl/render/common.glsl.
    pub fn shader_mode(self) -> u32 {
        match self {
            ColourMode::Flat => 0,
            ColourMode::Volume => 1,
            ColourMode::Strain => 2,
        }
    }

    /// Default half range of the colour map: V/V0 in [0.5, 1.5], strain in [-0.2, 0.2].
    pub fn default_range(self) -> f32 {
        match self {
            ColourMode::Strain => 0.2,
            _ => 0.5,
        }
    }
}

/// How to draw: image size, anti-aliasing, colours and camera.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Image width [pixels].
    pub width: u32,
    /// Image height [pixels].
    pub height: u32,
    /// Samples per pixel wanted (4, 2 or 1; fewer where the device has fewer).
    pub samples: u32,
    /// Surface colouring.
    pub colour: ColourMode,
    /// Half range of the colour map around its neutral value; `None`: the mode's default.
    pub range: Option<f32>,
    /// Camera; `None`: fitted to the model's starting bounds.
    pub camera: Option<Camera>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 480,
            height: 360,
            samples: 4,
            colour: ColourMode::Volume,
            range: None,
            camera: None,
        }
    }
}

impl RenderOptions {
    /// The colour map's half range.
    pub fn range(&self) -> f32 {
        self.range.unwrap_or_else(|| self.colour.default_range())
    }

    /// Checks sizes and the range.
    pub fn validate(&self) -> Result<()> {
        if !(16..=8192).contains(&self.width) || !(16..=8192).contains(&self.height) {
            return Err(Error::param(
                "size",
                format!(
                    "{}x{}: each side must be 16 to 8192 pixels",
                    self.width, self.height
                ),
            ));
        }
        let range = self.range();
        if !(range.is_finite() && range > 0.0) {
            return Err(Error::param(
                "range",
                format!("{range} must be a positive number"),
            ));
        }
        Ok(())
    }
}

/// Parses `WxH` (e.g. `640x480`).
pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    let bad = || {
        Error::param(
            "size",
            format!("`{s}`: expected WIDTHxHEIGHT in pixels, e.g. 640x480"),
        )
    };
    let (w, h) = s.trim().split_once(['x', 'X']).ok_or_else(bad)?;
    let w = w.trim().parse().map_err(|_| bad())?;
    let h = h.trim().parse().map_err(|_| bad())?;
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_validate() {
        assert_eq!(parse_size("640x480").unwrap(), (640, 480));
        assert_eq!(parse_size(" 32X16 ").unwrap(), (32, 16));
        assert!(parse_size("640").is_err());
        assert!(parse_size("ax4").is_err());
        let small = RenderOptions {
            width: 8,
            ..Default::default()
        };
        assert!(small.validate().unwrap_err().to_string().contains("size"));
        let bad_range = RenderOptions {
            range: Some(0.0),
            ..Default::default()
        };
        assert!(bad_range.validate().is_err());
        assert_eq!(RenderOptions::default().range(), 0.5);
    }
}
