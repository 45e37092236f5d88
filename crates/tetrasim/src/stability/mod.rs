//! Where the edge of stability is: the stable-step estimate ([`estimate`]), the divergence
//! speed limit and the likely cause of a divergence. Every backend uses them, so they depend
//! on the model and the parameters only; the dt x ks sweep that measures the edge is in
//! the command line (`tetrasim stability`, `tetrasim_cli::bench::stability_map`).

pub mod estimate;

pub use estimate::{estimate, speed_limit, StepEstimate};

use crate::model::Model;
use crate::params::{ConstraintCombine, Method, SimParams};

/// The likely cause of a divergence of `model` under `params`, with advice: the step against
/// the stable-step estimate, else the constraint settings or the elements. Settings are
/// named as scenes and Python name them, `` `name = value` ``; the command line shows them
/// as its flags (`tetrasim_cli::cli::in_flags`).
pub fn likely_cause(model: &Model, params: &SimParams) -> String {
    let e = estimate(model, params);
    if !params.has_springs() {
        return format!("likely cause: {}", e.describe(params));
    }
    if e.exceeded_by(params.dt) {
        // Explicit springs too stiff for the step: implicit springs take any step at the
        // same cost, a material is better served by the finite elements, and only then a
        // smaller step.
        let material = match params.youngs_modulus {
            Some(_) => ", or `method = \"neo-hookean\"` for the material's own elasticity",
            None => "",
        };
        format!(
            "likely cause: the step is too large for the stiffness ({}); set `springs = \"implicit\"`, \
             stable at any step{material}; or `dt = {:.2e}` or less, or `substeps = {}` for the \
             same frame time",
            e.describe(params),
            0.9 * e.dt_max,
            (params.dt / (0.9 * e.dt_max)).ceil() as u64 * u64::from(params.substeps)
        )
    } else {
        let constraint = match (params.method, params.combine) {
            (Method::Distance | Method::Volume, ConstraintCombine::Sum) => {
                "the summed constraint forces (`combine = \"sum\"`) overshoot: set `combine = \"scaled\"` or a smaller `omega`"
            }
            (Method::Distance | Method::Volume, ConstraintCombine::Scaled | ConstraintCombine::Average) => {
                "the constraint forces overshoot (omega, iterations, or collapsed/inverted elements): \
                 try a smaller `omega`, a smaller `dt` or more `substeps`"
            }
            _ => "a large initial velocity or deformation, or a mesh with collapsed elements: try a smaller `dt`",
        };
        format!(
            "likely cause: {constraint} (the step is within the springs' {})",
            e.describe(params)
        )
    }
}
