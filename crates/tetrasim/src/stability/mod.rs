//! Where the edge of stability is: the stable-step estimate ([`estimate`]), the divergence
//! speed limit and the likely cause of a divergence. Every backend uses them, so they depend
//! on the model and the parameters only; the dt x ks sweep that measures the edge is in
//! the command line (`tetrasim stability`, `tetrasim_cli::bench::stability_map`).

pub mod estimate;

pub use estimate::{estimate, speed_limit, StepEstimate};

use crate::model::Model;
use crate::params::{ConstraintCombine, Method, SimParams};

/// The average local volume error [%] at which a run counts as diverged: the tets' volumes
/// are on average ten times their rest volume off it. No physical motion gets there (a
/// body squashed flat is at 100 %), while a blown-up body may still have no node past the
/// speed limit (a ring pressed by a collider reached 9,239 % 33 frames before one did).
pub const MOST_LOCAL_ERROR_PCT: f64 = 1000.0;

/// Why a frame's sampled volumes mean the run diverged, if they do: the total volume
/// `volume_pct` [% of rest] not finite, or not positive where it `was_positive` at the last
/// sample or the start (the bodies turned inside out; a mesh given inside out is not
/// flagged for staying so), or the average local volume error `local_error_pct` at least
/// [`MOST_LOCAL_ERROR_PCT`].
pub fn volume_divergence(
    volume_pct: f64,
    local_error_pct: f64,
    was_positive: bool,
) -> Option<String> {
    if !volume_pct.is_finite() || !local_error_pct.is_finite() {
        Some("the total volume became non-finite (positions unbounded)".to_string())
    } else if volume_pct <= 0.0 && was_positive {
        Some(format!(
            "the total volume fell to {volume_pct:.1} % of the rest volume (the bodies turned \
             inside out)"
        ))
    } else if local_error_pct >= MOST_LOCAL_ERROR_PCT {
        Some(format!(
            "the average local volume error reached {local_error_pct:.0} % (the tets' volumes \
             are on average {:.0} times their rest volume off it: the mesh has blown up)",
            local_error_pct / 100.0
        ))
    } else {
        None
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn volumes_of_a_blown_up_or_inverted_body_mean_divergence() {
        // A body squashed flat (100 % local error, a sliver of volume left) has not diverged.
        assert_eq!(volume_divergence(0.01, 99.99, true), None);
        assert_eq!(volume_divergence(250.0, 999.0, true), None);
        let inside_out = volume_divergence(-186.0, 300.0, true).unwrap();
        assert!(inside_out.contains("-186.0 %"), "{inside_out}");
        assert!(volume_divergence(0.0, 100.0, true).is_some());
        // A mesh given inside out (its volume -100 % from the start) may stay so.
        assert_eq!(volume_divergence(-100.0, 200.0, false), None);
        let blown = volume_divergence(100.02, 9238.6, true).unwrap();
        assert!(
            blown.contains("9239 %") && blown.contains("92 times"),
            "{blown}"
        );
        assert!(volume_divergence(f64::NAN, 0.0, true).is_some());
        assert!(volume_divergence(100.0, f64::INFINITY, false).is_some());
    }
}
