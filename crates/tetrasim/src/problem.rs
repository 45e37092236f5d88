//! The problem, prepared once: a [`Model`] and its [`SimParams`], validated, with everything
//! a backend derives from them before its first step (the constraint sweeps and their
//! colour groups, the materials per element, the global volume constraints, the divergence
//! limit). Every backend is built from a [`Problem`] and only executes it; the run record
//! reads its facts from the same value, so nothing is coloured or validated twice.
//!
//! A [`Problem`] is immutable and cheap to clone (one shared allocation): a benchmark that
//! runs three backends on one model prepares it once.

use std::ops::Deref;
use std::sync::Arc;

use crate::contact::BodyContact;
use crate::error::{Error, Result};
use crate::model::{ElementMaterial, GlobalVolume, Model, Sweep};
use crate::params::{SimParams, Solver};

/// A validated model and parameter set with what every backend derives from them.
#[derive(Debug, Clone)]
pub struct Problem(Arc<Prepared>);

/// What a [`Problem`] holds (read through `Deref`; never changes after [`Problem::new`]).
#[derive(Debug)]
pub struct Prepared {
    /// The rest data and the initial state.
    pub model: Model,
    /// The parameters, validated.
    pub params: SimParams,
    /// The constraint sweeps of an iteration, in order, each with its groups
    /// ([`Model::constraint_sweeps`]: implicit springs, then distance or volume constraints;
    /// one group for Jacobi and Chebyshev, the colour groups for Gauss-Seidel).
    pub sweeps: Vec<Sweep>,
    /// The material of every spring and tet (the model's own, or from `ks`, `kd`).
    pub material: ElementMaterial,
    /// The global volume constraints, when the parameters solve them.
    pub global: Option<GlobalVolume>,
    /// Contact between objects and of an object with itself, when two surfaces can meet.
    pub bodies: Option<BodyContact>,
    /// Divergence speed limit [m/s] ([`crate::stability::speed_limit`]).
    pub speed_limit: f64,
    /// The likely cause a divergence report names ([`crate::stability::likely_cause`]).
    pub likely_cause: String,
}

impl Problem {
    /// Validates `params` (the one place they are validated) and derives what the backends
    /// need from `model` under them.
    pub fn new(model: &Model, params: &SimParams) -> Result<Self> {
        params.validate()?;
        let sweeps = model.constraint_sweeps(params);
        if params.solver == Solver::Chebyshev && !sweeps.is_empty() && !model.colliders.is_empty() {
            return Err(Error::Param {
                key: "solver".into(),
                message: "the chebyshev solver does not solve collider contact (its \
                          extrapolation would act on the contact forces); use gauss-seidel \
                          or jacobi with colliders"
                    .into(),
            });
        }
        let bodies = BodyContact::new(model);
        if params.minres > 0 && bodies.is_some() {
            return Err(Error::Param {
                key: "minres".into(),
                message: "does not solve contact between bodies (their contacts are found and \
                          solved by the sweeps only); use minres 0 with body contact"
                    .into(),
            });
        }
        let material = model.element_material(params).into_owned();
        let global = params
            .solves_global_volume()
            .then(|| GlobalVolume::new(model));
        Ok(Problem(Arc::new(Prepared {
            speed_limit: crate::stability::speed_limit(model, params),
            likely_cause: crate::stability::likely_cause(model, params),
            model: model.clone(),
            params: params.clone(),
            sweeps,
            material,
            global,
            bodies,
        })))
    }

    /// Whether runs of it measure contact ([`crate::backend::ContactSample`]): it has
    /// kinematic colliders, grabs or body contact.
    pub fn measures_contact(&self) -> bool {
        !self.model.colliders.is_empty() || !self.model.grabs.is_empty() || self.bodies.is_some()
    }

    /// Constraint groups of the largest sweep (1 without constraints, and for Jacobi and
    /// Chebyshev).
    pub fn groups(&self) -> u32 {
        self.sweeps
            .iter()
            .map(|sweep| sweep.groups.len() as u32)
            .max()
            .unwrap_or(1)
    }
}

impl Deref for Problem {
    type Target = Prepared;

    fn deref(&self) -> &Prepared {
        &self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::grid::box_tets;
    use crate::model::ModelBuilder;
    use crate::params::Method;
    use glam::DVec3;

    fn model() -> Model {
        ModelBuilder::new(&box_tets(DVec3::ZERO, 0.1, [3, 2, 2]))
            .build()
            .expect("a box model")
    }

    #[test]
    fn bad_parameters_are_refused_here() {
        let params = SimParams {
            iterations: 0,
            ..SimParams::default()
        };
        let err = Problem::new(&model(), &params).expect_err("0 iterations are refused");
        assert!(err.to_string().contains("iterations"), "{err}");
    }

    #[test]
    fn the_derived_facts_follow_the_parameters() {
        let model = model();
        let gs = Problem::new(&model, &SimParams::default()).expect("valid");
        assert!(gs.groups() > 1, "Gauss-Seidel colours the tets");
        assert!(gs.global.is_some(), "the default solves the global volume");
        assert_eq!(gs.material.volume_compliance.len(), model.tets.len());
        let jacobi = Problem::new(
            &model,
            &SimParams {
                solver: Solver::Jacobi,
                ..SimParams::default()
            },
        )
        .expect("valid");
        assert_eq!(jacobi.groups(), 1);
        assert!(jacobi.global.is_none());
        let mss = Problem::new(
            &model,
            &SimParams {
                method: Method::Mss,
                ..SimParams::default()
            },
        )
        .expect("valid");
        assert!(
            mss.sweeps.is_empty(),
            "springs alone have no constraint sweep"
        );
    }
}
