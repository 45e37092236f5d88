//! Solver parameters: one struct with documented units and defaults, shared by the CLI,
//! scene files and every backend (the GPU push-constant block is derived from it). What a
//! user may set is listed once, in the command line's `SolverOverrides` and
//! `MaterialOverrides` (`tetrasim_cli::overrides`: the flags and the scene keys).

use serde::{Deserialize, Serialize};

mod accuracy;
pub use accuracy::Accuracy;
mod blocks;
pub use blocks::{default_block_sweeps, MAX_BLOCK_SIZE, MAX_BLOCK_SWEEPS, MAX_WORKGROUP_BLOCK};
mod contact;
pub use contact::ContactMode;
mod gravity;
pub use gravity::Gravity;
mod placement;
pub use placement::Placement;
mod elastic;
mod method;
pub use method::Method;
mod inversion;
mod minres;
pub use inversion::{default_inversion_floor, MAX_INVERSION_SWEEPS};

use crate::error::{Error, Result};
pub use crate::physics::{
    chebyshev_rho, chebyshev_rho_limit, chebyshev_weights, ANDERSON_MAX_MEMORY,
    MINRES_MAX_ITERATIONS,
};

/// How node masses are assigned.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "mode")]
pub enum MassMode {
    /// Every node has the same mass [kg] (the `seed` preset: 1 kg).
    PerNode {
        /// The mass of every node [kg].
        mass: f64,
    },
    /// Lumped mass from material density [kg/m^3]: each tet gives a quarter of its rest
    /// volume times density to each of its nodes.
    Density {
        /// The material's density [kg/m^3].
        density: f64,
    },
}

/// How the forces of one iteration's constraints are combined per node (physics.md,
/// "Momentum-conserving scaling" and "Iterations, relaxation and substeps").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum ConstraintCombine {
    /// Momentum-conserving scaling (the default): each constraint's `A` weighs node `k`'s
    /// inverse mass by `d_k`, the number of constraints of that kind touching it, and its
    /// forces are applied whole, so they sum to zero and conserve linear and angular momentum.
    Scaled,
    /// Plain Jacobi summation, the paper's literal reading (`d_k = 1`; conserves momentum but
    /// diverges on real meshes at omega 1).
    Sum,
    /// The first edition's per-node averaging: each node's sum is divided by `d_k`. Kept only
    /// as a comparison: it does not conserve momentum (a body on a frictionless floor slides).
    Average,
}

impl ConstraintCombine {
    /// The name used on the command line, in scene files and in records.
    pub fn name(self) -> &'static str {
        match self {
            ConstraintCombine::Scaled => "scaled",
            ConstraintCombine::Sum => "sum",
            ConstraintCombine::Average => "average",
        }
    }

    /// The two per-node factors of a node touched by `degree` constraints of one kind,
    /// `(a_scale, apply_weight)`: node `k`'s inverse mass enters a constraint's
    /// `A = sum_k a_scale_k w_k |grad_k C|^2`, and the node's summed constraint forces are
    /// multiplied by `apply_weight` (before `omega`). Every backend uses this function.
    pub fn node_factors(self, degree: u32) -> (f64, f64) {
        let d = f64::from(degree.max(1));
        match self {
            ConstraintCombine::Scaled => (d, 1.0),
            ConstraintCombine::Sum => (1.0, 1.0),
            ConstraintCombine::Average => (1.0, 1.0 / d),
        }
    }
}

/// How each iteration sweeps the constraints (physics.md, "Faster convergence at equal
/// cost").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum Solver {
    /// The paper's method: every constraint reads the same forces, their sums are added at
    /// the end of the sweep.
    Jacobi,
    /// Gauss-Seidel by colour groups: constraints coloured at load time (no two of a colour
    /// share a node), colours merged into `groups` groups solved one after another, each
    /// against the forces the previous groups left.
    GaussSeidel,
    /// Jacobi sweeps with Chebyshev semi-iteration (Wang 2015): iteration `k`'s forces are
    /// `F_k = w_k (Fhat_k - F_(k-2)) + F_(k-2)`, `Fhat_k` the plain Jacobi update, with
    /// weights from the spectral radius estimate `rho` (see `chebyshev_weights`), lowered to
    /// what the iteration count can take (`chebyshev_rho`).
    Chebyshev,
}

impl Solver {
    /// Every solver.
    pub const ALL: [Solver; 3] = [Solver::Jacobi, Solver::GaussSeidel, Solver::Chebyshev];

    /// The name used on the command line, in scene files and in records.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Jacobi => "jacobi",
            Solver::GaussSeidel => "gauss-seidel",
            Solver::Chebyshev => "chebyshev",
        }
    }
}

impl std::fmt::Display for Solver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How the springs act (physics.md, "Compliant (implicit) springs").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum SpringKind {
    /// The paper's explicit forces `ks (l - L) + kd (relative velocity)`, added before the
    /// constraint iterations; stable only for `dt < ~2 sqrt(m / ks)`.
    Explicit,
    /// Each spring a compliant constraint `C = |x_i - x_j| - L` with compliance `1 / ks` and
    /// first-order implicit damping `kd`, solved in the constraint iterations (before the
    /// method's own constraints in each iteration): stable for any mass and stiffness.
    Implicit,
}

impl SpringKind {
    /// The name used on the command line, in scene files and in records.
    pub fn name(self) -> &'static str {
        match self {
            SpringKind::Explicit => "explicit",
            SpringKind::Implicit => "implicit",
        }
    }
}

impl std::fmt::Display for SpringKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Everything the solver needs besides the model. Units are SI.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimParams {
    /// Method to simulate.
    pub method: Method,
    /// Time step [s].
    pub dt: f64,
    /// Time steps per frame.
    pub substeps: u32,
    /// Constraint iterations per time step (ignored by `mss`, `mss-node`).
    pub iterations: u32,
    /// Relaxation factor applied to each iteration's combined constraint forces.
    pub omega: f64,
    /// Spring stiffness [N/m] (unused, and left out of run records, when the springs come
    /// from a Young's modulus).
    #[serde(default = "default_ks")]
    pub ks: f64,
    /// Spring damping [N s/m] (likewise).
    #[serde(default = "default_kd")]
    pub kd: f64,
    /// Explicit spring forces (the paper) or compliant spring constraints.
    #[serde(default = "default_springs")]
    pub springs: SpringKind,
    /// Implicit springs start each step from their last step's multipliers (their forces
    /// added to `F` at `x(t)`): the stiffness no longer depends on the iteration count in
    /// quasi-static scenes, but a multiplier carried through an impact is wrong (physics.md,
    /// docs/PHYSICS.md "Iterations"). Off by default.
    #[serde(default)]
    pub warm_start: bool,
    /// Young's modulus [Pa]: when given, every spring's stiffness comes from it (Van Gelder:
    /// `k_e = E sum_(t at e) V0_t / L_e^2`) instead of `ks`, and its damping is `damping k_e`
    /// instead of `kd` (physics.md, "Material in physical units").
    #[serde(default)]
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio in `(-1, 0.5]` (needs `youngs_modulus`): the volume constraints become
    /// compliant, `alpha_t = V0_t / K` with the bulk modulus `K = E / (3 (1 - 2 nu))`;
    /// `None` or 0.5 keeps them hard (incompressible), the paper's constraint.
    #[serde(default)]
    pub poisson_ratio: Option<f64>,
    /// Stiffness-proportional (Rayleigh) damping time `beta` [s] of a material given by
    /// `youngs_modulus`: each spring's damping is `beta k_e` [N s/m]. `None`: the paper's
    /// ratio `kd / ks` of the `seed` preset, 3 ms.
    #[serde(default)]
    pub damping: Option<f64>,
    /// Gravity's acceleration [m/s^2] (the up axis is +Y: the floor is `y = 0`); read from
    /// a vector `[x, y, z]` or, as scenes, flags and older records may give it, a magnitude
    /// along -Y ([`Gravity`]).
    #[serde(deserialize_with = "gravity::deserialize", default = "gravity::earth")]
    pub gravity: glam::DVec3,
    /// Whether the floor plane `y = 0` exists.
    pub floor: bool,
    /// Floor friction in `[0, 1]`: a node on the floor loses this fraction of its tangential
    /// velocity per step, but never more than this times the velocity its floor force gave it
    /// (Coulomb's law with `mu = friction`; [`crate::physics::floor_friction`]).
    pub friction: f64,
    /// Node mass assignment.
    pub mass: MassMode,
    /// Per-node combination of constraint forces.
    pub combine: ConstraintCombine,
    /// How each iteration sweeps the constraints.
    #[serde(default = "default_solver")]
    pub solver: Solver,
    /// Colour groups of the Gauss-Seidel solver (at most the number of colours; ignored by
    /// Jacobi).
    #[serde(default = "default_groups")]
    pub groups: u32,
    /// Block Gauss-Seidel (docs/PHYSICS.md, "Block Gauss-Seidel"; 0: off): each sweep cut
    /// into blocks of at most `block_size` constraints, swept colour by colour while the
    /// blocks run at once, in place of the colour groups (solver `gauss-seidel`). Up to
    /// [`MAX_WORKGROUP_BLOCK`] a block is one GPU workgroup; larger blocks (to
    /// [`MAX_BLOCK_SIZE`]) are thread blocks, `cpu` and `cpu-ref` only.
    #[serde(default)]
    pub block_size: u32,
    /// Sweeps of each block per iteration (block Gauss-Seidel; 1 to [`MAX_BLOCK_SWEEPS`]): on
    /// the GPU they cost barriers in the same dispatch, not dispatches.
    #[serde(default = "default_block_sweeps")]
    pub block_sweeps: u32,
    /// The same for the implicit springs' blocks (0: `block_sweeps`; [`Self::spring_sweeps`]).
    #[serde(default)]
    pub spring_block_sweeps: u32,
    /// One global volume constraint per object, solved after the local constraints in
    /// every iteration (methods `distance` and `volume`; ignored by the springs-only ones).
    /// `None`: the solver's default, on for Gauss-Seidel and off for Jacobi (the paper's
    /// method).
    #[serde(default)]
    pub global_volume: Option<bool>,
    /// Spectral radius estimate of the Chebyshev solver, in `(0, 1)` (ignored by the others);
    /// the weights use at most [`chebyshev_rho_limit`] of `iterations`
    /// ([`SimParams::chebyshev_rho`]).
    #[serde(default = "default_rho")]
    pub rho: f64,
    /// Anderson acceleration of the constraint iterations: the history columns kept (0: off,
    /// at most [`ANDERSON_MAX_MEMORY`]). Each iteration's forces are mixed with the last
    /// `anderson` iterations' to cancel the slow modes that sweeps leave (docs/PHYSICS.md,
    /// "Anderson acceleration"); 5 is a good memory.
    #[serde(default)]
    pub anderson: u32,
    /// MINRES iterations on the step's linearised constraints after the sweeps (0: off, at
    /// most [`MINRES_MAX_ITERATIONS`]; every backend, not with contact between bodies). The sweeps find who touches
    /// the floor and colliders; MINRES then converges the slow modes they leave, a stiff
    /// body squashing on the floor (docs/PHYSICS.md, "MINRES after the sweeps"). Without
    /// inversion sweeps after it, the step ends with the global volume constraints once
    /// more, which restore the total that MINRES solves only as far as its iterations go.
    #[serde(default)]
    pub minres: u32,
    /// Inversion sweeps after the constraint iterations of every step (method `volume`;
    /// 0: off): each sweeps the volume constraints' groups once more with the one-sided
    /// floor `V >= inversion_floor V0` measured at the positions the step is about to
    /// reach, so that a tet the iterations left collapsed or inside out is pushed back
    /// before it is integrated (docs/PHYSICS.md, "Inversion floor").
    #[serde(default)]
    pub inversion_sweeps: u32,
    /// The fraction of its rest volume below which the inversion sweeps push a tet back,
    /// in `(0, 1]`.
    #[serde(default = "default_inversion_floor")]
    pub inversion_floor: f64,
    /// How position corrections reach the velocity: one combined solve (default) or split
    /// impulses (`split`: no rebound, twice the solve).
    #[serde(default)]
    pub contact: ContactMode,
    /// A constraint is skipped when its `A = sum_k w_k |grad_k C|^2` is at or below this
    /// (units of `A`: 1/kg m^2 for distance, 1/kg m^4 for volume constraints); guards
    /// collapsed elements, whose multiplier would be unbounded. Not in physics.md.
    #[serde(default = "default_constraint_epsilon")]
    pub constraint_epsilon: f64,
}

impl Default for SimParams {
    /// The `seed` preset's physics (physics.md, "The paper's experiment").
    fn default() -> Self {
        SimParams {
            method: Method::Volume,
            dt: 1e-3,
            substeps: 1,
            iterations: 10,
            omega: 1.0,
            ks: default_ks(),
            kd: default_kd(),
            springs: default_springs(),
            warm_start: false,
            youngs_modulus: None,
            poisson_ratio: None,
            damping: None,
            gravity: gravity::earth(),
            floor: true,
            friction: 0.0,
            mass: MassMode::PerNode { mass: 1.0 },
            combine: ConstraintCombine::Scaled,
            solver: default_solver(),
            groups: default_groups(),
            block_size: 0,
            block_sweeps: 1,
            spring_block_sweeps: 0,
            global_volume: None,
            rho: default_rho(),
            anderson: 0,
            minres: 0,
            inversion_sweeps: 0,
            inversion_floor: default_inversion_floor(),
            contact: ContactMode::Combined,
            constraint_epsilon: default_constraint_epsilon(),
        }
    }
}

impl SimParams {
    /// Simulated time of one frame: `dt * substeps` [s].
    pub fn frame_time(&self) -> f64 {
        self.dt * f64::from(self.substeps)
    }

    /// Whether the time step solves constraints in iterations: a constraint method, or
    /// implicit springs.
    pub fn has_constraints(&self) -> bool {
        matches!(
            self.method,
            Method::Distance | Method::Volume | Method::NeoHookean
        ) || self.springs == SpringKind::Implicit
    }

    /// Whether the global volume constraints are solved: asked for (by default with
    /// Gauss-Seidel), and a method with constraint iterations.
    pub fn solves_global_volume(&self) -> bool {
        self.global_volume_on() && matches!(self.method, Method::Distance | Method::Volume)
    }

    /// Whether the global volume constraints are asked for: `global_volume`, else the
    /// solver's default (on for Gauss-Seidel, off for Jacobi).
    pub fn global_volume_on(&self) -> bool {
        self.global_volume
            .unwrap_or(self.solver == Solver::GaussSeidel)
    }

    /// Whether the constraint sweeps run in blocks (`block_size > 0` with Gauss-Seidel).
    pub fn solves_in_blocks(&self) -> bool {
        self.block_size > 0 && self.solver == Solver::GaussSeidel
    }

    /// The spectral radius estimate the Chebyshev weights use: `rho`, lowered to
    /// [`chebyshev_rho_limit`] when `iterations` are too few for it (physics.md's Chebyshev
    /// section in docs/PHYSICS.md).
    pub fn chebyshev_rho(&self) -> f64 {
        chebyshev_rho(self.rho, self.iterations)
    }

    /// Checks every value's range; the error names the offending key.
    pub fn validate(&self) -> Result<()> {
        fn positive_finite(key: &str, v: f64) -> Result<()> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::param(
                    key,
                    format!("must be a finite number > 0, got {v}"),
                ))
            }
        }
        fn non_negative_finite(key: &str, v: f64) -> Result<()> {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(Error::param(
                    key,
                    format!("must be a finite number >= 0, got {v}"),
                ))
            }
        }
        positive_finite("dt", self.dt)?;
        if self.substeps == 0 {
            return Err(Error::param("substeps", "must be at least 1"));
        }
        if self.iterations == 0 {
            return Err(Error::param("iterations", "must be at least 1"));
        }
        positive_finite("omega", self.omega)?;
        non_negative_finite("ks", self.ks)?;
        non_negative_finite("kd", self.kd)?;
        if !self.gravity.is_finite() {
            return Err(Error::param(
                "gravity",
                format!("must be finite, got {:?}", self.gravity.to_array()),
            ));
        }
        if !(0.0..=1.0).contains(&self.friction) {
            return Err(Error::param(
                "friction",
                format!("must be in [0, 1], got {}", self.friction),
            ));
        }
        if self.groups == 0 {
            return Err(Error::param("groups", "must be at least 1"));
        }
        self.validate_blocks()?;
        if !(self.rho > 0.0 && self.rho < 1.0) {
            return Err(Error::param(
                "rho",
                format!("must be in (0, 1), got {}", self.rho),
            ));
        }

        if self.anderson > ANDERSON_MAX_MEMORY {
            return Err(Error::param(
                "anderson",
                format!(
                    "keeps at most {ANDERSON_MAX_MEMORY} history columns, got {}",
                    self.anderson
                ),
            ));
        }
        if self.anderson > 0 {
            if !self.has_constraints() {
                return Err(Error::param(
                    "anderson",
                    format!(
                        "accelerates constraint iterations; {} with explicit springs has none \
                         (use method volume or distance, or springs = implicit)",
                        self.method
                    ),
                ));
            }
            if self.solver == Solver::Chebyshev {
                return Err(Error::param(
                    "anderson",
                    "does not combine with the chebyshev solver (both extrapolate the \
                     iterations); use jacobi or gauss-seidel",
                ));
            }
        }
        self.validate_minres()?;
        self.validate_inversion()?;
        self.validate_elastic()?;
        if let Some(e) = self.youngs_modulus {
            positive_finite("youngs_modulus", e)?;
        }
        for (key, value) in [
            ("poisson_ratio", self.poisson_ratio),
            ("damping", self.damping),
        ] {
            if value.is_some() && self.youngs_modulus.is_none() {
                return Err(Error::param(
                    key,
                    "describes a material given by its Young's modulus; give youngs_modulus \
                     too (or use ks and kd)",
                ));
            }
        }
        if let Some(nu) = self.poisson_ratio {
            if !(nu > -1.0 && nu <= 0.5) {
                return Err(Error::param(
                    "poisson_ratio",
                    format!("must be in (-1, 0.5], got {nu}"),
                ));
            }
        }
        if let Some(beta) = self.damping {
            non_negative_finite("damping", beta)?;
        }
        if let Some(e) = self.youngs_modulus {
            if !matches!(self.mass, MassMode::Density { .. }) {
                return Err(Error::param(
                    "density",
                    format!(
                        "a material given by its Young's modulus ({e} Pa) needs its density \
                         [kg/m^3]: masses of 1 kg per node would make a body of the wrong \
                         weight for its stiffness"
                    ),
                ));
            }
        }
        if self.warm_start && self.springs != SpringKind::Implicit {
            return Err(Error::param(
                "warm_start",
                "acts only with implicit springs (springs = implicit)",
            ));
        }
        if self.springs == SpringKind::Implicit {
            match self.method {
                Method::MssNode | Method::Distance => {
                    return Err(Error::param(
                        "springs",
                        format!(
                            "implicit springs act with the methods mss and volume; {} {}",
                            self.method,
                            if self.method == Method::Distance {
                                "already holds every spring at its rest length"
                            } else {
                                "gathers explicit spring forces per node (use mss)"
                            }
                        ),
                    ))
                }
                // Refused earlier (`validate_elastic`).
                Method::Mss | Method::Volume | Method::NeoHookean => {}
            }
            if self.solver == Solver::Chebyshev {
                return Err(Error::param(
                    "springs",
                    "implicit springs are solved by jacobi or gauss-seidel, not chebyshev",
                ));
            }
            if self.youngs_modulus.is_none() && self.ks <= 0.0 {
                return Err(Error::param(
                    "ks",
                    "implicit springs need a stiffness > 0 (compliance 1 / ks)",
                ));
            }
        }
        if self.contact == ContactMode::Split {
            if self.warm_start {
                return Err(Error::param(
                    "contact",
                    "split contact solves each step twice from the same multipliers; it does \
                     not combine with warm_start (set warm_start = false)",
                ));
            }
            if self.solver == Solver::Chebyshev {
                return Err(Error::param(
                    "contact",
                    "split contact is solved by jacobi or gauss-seidel, not chebyshev",
                ));
            }
        }
        non_negative_finite("constraint_epsilon", self.constraint_epsilon)?;
        match self.mass {
            MassMode::PerNode { mass } => positive_finite("mass", mass)?,
            MassMode::Density { density } => positive_finite("density", density)?,
        }
        Ok(())
    }
}

/// The paper's spring stiffness [N/m].
fn default_ks() -> f64 {
    5000.0
}

/// The paper's spring damping [N s/m].
fn default_kd() -> f64 {
    15.0
}

/// Default of [`SimParams::springs`]: the paper's explicit springs.
pub fn default_springs() -> SpringKind {
    SpringKind::Explicit
}

/// Default of [`SimParams::damping`] [s]: the `seed` preset's `kd / ks` (15 / 5000).
pub const DEFAULT_DAMPING_TIME: f64 = 15.0 / 5000.0;

/// Default of [`SimParams::solver`].
pub fn default_solver() -> Solver {
    Solver::GaussSeidel
}

/// Default of [`SimParams::rho`] (physics.md's prototype: 0.95 on the bunny).
pub fn default_rho() -> f64 {
    0.95
}

#[cfg(test)]
mod tests;

/// Default of [`SimParams::groups`].
pub fn default_groups() -> u32 {
    8
}

/// Default of [`SimParams::constraint_epsilon`]: far below any real element's `A` at the
/// `seed` scale (about 1e-7 for a tet of 20k at 1 m), representable in f32.
pub fn default_constraint_epsilon() -> f64 {
    1e-20
}

/// Frames of the `seed` preset.
pub const SEED_FRAMES: u32 = 400;
