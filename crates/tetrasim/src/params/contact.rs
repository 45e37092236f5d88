//! How a time step turns position corrections into velocity ([`ContactMode`]).

use serde::{Deserialize, Serialize};

/// How contacts and hard constraints turn their position corrections into velocity
/// (physics.md, "Contact that does not bounce back"; docs/PHYSICS.md, "Split contact").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum ContactMode {
    /// One solve: every constraint's `C / dt^2` term moves positions and stays in the
    /// velocity (the implicit framework as the paper has it). A nearly rigid body rebounds by
    /// what the iterations leave of its impact.
    #[default]
    Combined,
    /// Split impulses: each step is solved twice from the same state, once in full (the new
    /// positions) and once with every hard constraint's value at 0 and every contact's
    /// penetration at the step's start ignored (the new velocities), so no position
    /// correction becomes velocity. About twice the cost of a step; no rebound.
    Split,
}

impl ContactMode {
    /// Every mode.
    pub const ALL: [ContactMode; 2] = [ContactMode::Combined, ContactMode::Split];

    /// The name used on the command line, in scene files and in records.
    pub fn name(self) -> &'static str {
        match self {
            ContactMode::Combined => "combined",
            ContactMode::Split => "split",
        }
    }
}

impl std::fmt::Display for ContactMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
