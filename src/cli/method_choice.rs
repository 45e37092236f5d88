//! `--method`'s values: one method, or the paper's three.

use tetrasim::params::Method;

/// `--method` values: one method or `all`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodChoice {
    /// Springs only, spring-centric.
    Mss,
    /// Springs only, node-centric.
    MssNode,
    /// Springs and distance constraints.
    Distance,
    /// Springs and volume constraints.
    Volume,
    /// Finite elements (stable Neo-Hookean; needs the material's E, nu and density; the
    /// default for such a material): a Newton step per time step, --iterations
    /// conjugate-gradient iterations with a two-level preconditioner (the default 10 match an
    /// independent FEM within 1.3 % on a 2304-tet beam; docs/PHYSICS.md, "Finite elements").
    NeoHookean,
    /// mss, distance and volume (the paper's three), in that order.
    All,
}

impl MethodChoice {
    /// The methods this choice runs, in order.
    pub fn methods(self) -> Vec<Method> {
        match self {
            MethodChoice::Mss => vec![Method::Mss],
            MethodChoice::MssNode => vec![Method::MssNode],
            MethodChoice::Distance => vec![Method::Distance],
            MethodChoice::Volume => vec![Method::Volume],
            MethodChoice::NeoHookean => vec![Method::NeoHookean],
            MethodChoice::All => vec![Method::Mss, Method::Distance, Method::Volume],
        }
    }
}
