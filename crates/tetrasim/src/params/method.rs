//! The simulation methods: the paper's three (and `mss-node`) and the finite elements.

use serde::{Deserialize, Serialize};

/// The simulation method (physics.md, "Methods").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Springs only, spring-centric scatter.
    Mss,
    /// Springs only, node-centric gather (same physics as `mss`).
    MssNode,
    /// Springs plus an implicit distance constraint on every spring.
    Distance,
    /// Springs plus an implicit volume constraint on every tetrahedron.
    Volume,
    /// Finite elements: stable Neo-Hookean tets with the material's Young's modulus and
    /// Poisson's ratio, solved each step by one Newton step whose linear system gets
    /// `iterations` iterations of two-level preconditioned conjugate gradients
    /// (docs/PHYSICS.md, "Finite elements"). No springs.
    NeoHookean,
}

impl Method {
    /// The paper's methods, in its order (`--method all`).
    pub const ALL: [Method; 4] = [
        Method::Mss,
        Method::MssNode,
        Method::Distance,
        Method::Volume,
    ];

    /// Whether the method runs springs (every method but the finite elements).
    pub fn has_springs(self) -> bool {
        self != Method::NeoHookean
    }

    /// The name used on the command line, in JSON and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Mss => "mss",
            Method::MssNode => "mss-node",
            Method::Distance => "distance",
            Method::Volume => "volume",
            Method::NeoHookean => "neo-hookean",
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
