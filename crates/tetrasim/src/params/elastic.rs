//! The finite-element method's requirements ([`Method::NeoHookean`]): a material given by
//! its Young's modulus, Poisson's ratio and density, and a solve its per-node steps take.

use super::{MassMode, Method, SimParams, Solver, SpringKind};
use crate::error::{Error, Result};

impl SimParams {
    /// Whether the method has springs (every method but the finite elements).
    pub fn has_springs(&self) -> bool {
        self.method.has_springs()
    }

    /// Checks what the finite-element method needs; the error names the key.
    pub(super) fn validate_elastic(&self) -> Result<()> {
        if self.method != Method::NeoHookean {
            return Ok(());
        }
        let method = self.method;
        if self.youngs_modulus.is_none() {
            return Err(Error::param(
                "youngs_modulus",
                format!("method {method} needs the material's Young's modulus [Pa]"),
            ));
        }
        match self.poisson_ratio {
            None => {
                return Err(Error::param(
                    "poisson_ratio",
                    format!("method {method} needs the material's Poisson's ratio in (-1, 0.5)"),
                ))
            }
            Some(nu) if !(nu > -1.0 && nu < 0.5) => {
                return Err(Error::param(
                    "poisson_ratio",
                    format!(
                        "must be in (-1, 0.5) for method {method} (0.5, incompressible, has \
                         no finite bulk modulus), got {nu}"
                    ),
                ))
            }
            Some(_) => {}
        }
        if !matches!(self.mass, MassMode::Density { .. }) {
            return Err(Error::param(
                "density",
                format!(
                    "method {method} needs the material's density [kg/m^3]: masses of 1 kg per \
                     node would make a body of the wrong weight for its stiffness"
                ),
            ));
        }
        if self.springs == SpringKind::Implicit || self.warm_start {
            return Err(Error::param(
                "springs",
                format!("method {method} has no springs (leave springs and warm_start unset)"),
            ));
        }
        for (key, set) in [
            ("minres", self.minres > 0),
            ("anderson", self.anderson > 0),
            ("block_size", self.block_size > 0),
            ("inversion_sweeps", self.inversion_sweeps > 0),
        ] {
            if set {
                return Err(Error::param(
                    key,
                    format!(
                        "acts on constraint multipliers; method {method} solves per node \
                         (leave {key} at 0)"
                    ),
                ));
            }
        }
        if self.omega != 1.0 {
            return Err(Error::param(
                "omega",
                format!(
                    "relaxes constraint sweeps; method {method} takes each conjugate-gradient \
                     step whole (leave omega at 1, got {})",
                    self.omega
                ),
            ));
        }
        if self.solver != Solver::GaussSeidel {
            return Err(Error::param(
                "solver",
                format!(
                    "method {method} solves each step by preconditioned conjugate gradients, \
                     one iteration per `iterations`; the sweep solvers (jacobi, chebyshev) do \
                     not apply to it (leave solver at its default, gauss-seidel)"
                ),
            ));
        }
        Ok(())
    }
}
