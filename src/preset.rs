//! Named experiment presets: parameters, placement and frame count in one value, every field
//! of which the command line can override.

use serde::{Deserialize, Serialize};

use tetrasim::params::{Placement, SimParams, SEED_FRAMES};

/// The names accepted by `--preset`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum PresetName {
    /// The paper's experiment as physics.md fixes it: fit to 1 m, 0.1 m above the floor,
    /// 1 kg per node, dt 1 ms, 10 iterations, 1 substep, ks 5000, kd 15, 400 frames.
    Seed,
}

/// A complete experiment setting.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Preset {
    /// Solver parameters.
    pub params: SimParams,
    /// Where the mesh is put.
    pub placement: Placement,
    /// Frames to simulate.
    pub frames: u32,
}

impl Preset {
    /// The `seed` preset (physics.md, "The paper's experiment").
    pub fn seed() -> Self {
        Preset {
            params: SimParams::default(),
            placement: Placement::default(),
            frames: SEED_FRAMES,
        }
    }

    /// The preset called `name`.
    pub fn named(name: PresetName) -> Self {
        match name {
            PresetName::Seed => Preset::seed(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tetrasim::params::MassMode;

    #[test]
    fn seed_matches_physics_md() {
        let p = Preset::named(PresetName::Seed);
        assert_eq!(p.frames, 400);
        assert_eq!(
            (p.params.dt, p.params.substeps, p.params.iterations),
            (1e-3, 1, 10)
        );
        assert_eq!(
            (p.params.ks, p.params.kd, p.params.friction, p.params.omega),
            (5000.0, 15.0, 0.0, 1.0)
        );
        assert_eq!(p.params.mass, MassMode::PerNode { mass: 1.0 });
        assert_eq!(
            (p.placement.fit_size, p.placement.drop_height),
            (Some(1.0), Some(0.1))
        );
        assert!(p.params.floor);
    }
}
