//! Optional overrides of [`SimParams`]: the one list of the parameters a user sets. Each
//! struct is both a table of a scene file (serde: `[solver]` and an object's `material`)
//! and, with the `clap` feature, a part of `tetrasim run`'s flags (flattened into `RunArgs`;
//! the doc comments are the `--help` text); `apply` writes the given values onto a
//! [`SimParams`].
//!
//! A new parameter is a field of [`SimParams`] (with its default) and a field here (with its
//! line in `apply`).

use serde::Deserialize;

use tetrasim::params::{
    Accuracy, ConstraintCombine, ContactMode, Gravity, MassMode, SimParams, Solver, SpringKind,
};

/// Time stepping and the constraint solver, shared by all objects: a scene's `[solver]`
/// table and `run`'s solver flags. `None` keeps the base value (the preset's).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(deny_unknown_fields)]
pub struct SolverOverrides {
    /// The speed/accuracy dial: `fast` (0.35 to 0.86 of the default's time, twice its local
    /// volume error), `balanced` (the defaults) or `accurate` (twice the time, half the
    /// error); it sets the solver, groups, iterations, substeps and dt, and any of those
    /// given as well overrides it (docs/guide/accuracy.md).
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    pub accuracy: Option<Accuracy>,
    /// Time step [s].
    #[cfg_attr(feature = "clap", arg(long))]
    pub dt: Option<f64>,
    /// Time steps per frame.
    #[cfg_attr(feature = "clap", arg(long))]
    pub substeps: Option<u32>,
    /// Constraint iterations per time step.
    #[cfg_attr(feature = "clap", arg(long))]
    pub iterations: Option<u32>,
    /// Relaxation factor of the constraint forces.
    #[cfg_attr(feature = "clap", arg(long))]
    pub omega: Option<f64>,
    /// How constraint forces are combined: `scaled` (momentum-conserving, default), `sum`
    /// (the paper's literal reading), `average` (first edition, drifts; for comparison).
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    pub combine: Option<ConstraintCombine>,
    /// How each iteration sweeps the constraints: `gauss-seidel` (colour groups, default),
    /// `jacobi` (the paper's method) or `chebyshev` (Jacobi with Chebyshev semi-iteration).
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    pub solver: Option<Solver>,
    /// Colour groups of the Gauss-Seidel solver (default 8).
    #[cfg_attr(feature = "clap", arg(long))]
    pub groups: Option<u32>,
    /// Block Gauss-Seidel (solver gauss-seidel; 0, off, default): the constraints cut in
    /// index order into blocks of this many, each swept colour by colour while all blocks
    /// run at once, in place of the colour groups; up to 1024 one GPU workgroup each, above
    /// that thread blocks for the cpu backends (docs/PHYSICS.md).
    #[cfg_attr(feature = "clap", arg(long, value_name = "TETS"))]
    pub block_size: Option<u32>,
    /// Sweeps of each block per iteration (block Gauss-Seidel; default 1, up to 8): more
    /// converge further within each block; on the GPU they cost barriers, not dispatches.
    #[cfg_attr(feature = "clap", arg(long, value_name = "N"))]
    pub block_sweeps: Option<u32>,
    /// Sweeps of each block of implicit springs per iteration (0, default: as
    /// block_sweeps): the volume constraints gain more from a second sweep than the
    /// springs, which are the larger sweep.
    #[cfg_attr(feature = "clap", arg(long, value_name = "N"))]
    pub spring_block_sweeps: Option<u32>,
    /// One global volume constraint per object, solved after the local constraints in every
    /// iteration: `true` (`--global-volume` alone) or `false`; default: on for
    /// `gauss-seidel`, off for `jacobi` (the paper's method) and `chebyshev`.
    #[cfg_attr(feature = "clap", arg(long, num_args = 0..=1, default_missing_value = "true", value_name = "BOOL"))]
    pub global_volume: Option<bool>,
    /// Springs as the paper's explicit forces (`explicit`, default) or as compliant
    /// constraints solved with the others (`implicit`: stable for any mass and stiffness;
    /// methods mss and volume).
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    pub springs: Option<SpringKind>,
    /// Implicit springs start each step from the last step's multipliers: stiffness
    /// independent of the iteration count for slow, quasi-static loads (not through impacts;
    /// default false).
    #[cfg_attr(feature = "clap", arg(long, num_args = 0..=1, default_missing_value = "true", value_name = "BOOL"))]
    pub warm_start: Option<bool>,
    /// Spectral radius estimate of the Chebyshev solver, in (0, 1) (default 0.95); lowered
    /// when there are too few iterations for it (to 0.934 at 5 iterations, 0.899 at 4, 0.832
    /// at 3; 0.95 is kept from 6 on), which the run record's `chebyshev_rho` reports.
    #[cfg_attr(feature = "clap", arg(long))]
    pub rho: Option<f64>,
    /// Anderson acceleration of the constraint iterations: the history columns kept, 0 (off,
    /// default) to 8; each iteration's forces are mixed with the last ones' to converge the
    /// slow modes of a stiff body (about 5 % more per iteration on cpu; docs/PHYSICS.md).
    #[cfg_attr(feature = "clap", arg(long, value_name = "MEMORY"))]
    pub anderson: Option<u32>,
    /// MINRES iterations after each step's sweeps, 0 (off, default) to 200, every backend:
    /// converges the slow modes of a stiff body that the sweeps leave (a rigid
    /// body's rebound off the floor), the sweeps finding who touches the floor; 28 after 1
    /// sweep bring the bundled sphere to rest (1.7 mm of rebound) for about 1.3x the
    /// default's step on cpu, 1.2x on lavapipe (docs/PHYSICS.md, "MINRES after the sweeps").
    #[cfg_attr(feature = "clap", arg(long, value_name = "ITERATIONS"))]
    pub minres: Option<u32>,
    /// Inversion sweeps after each step's iterations (method volume; 0, off, default, to
    /// 64): each sweeps the volume constraints' groups once more, pushing every tet whose
    /// volume at the step's end would be below `inversion_floor` of its rest volume back up
    /// to it (docs/PHYSICS.md, "Inversion floor").
    #[cfg_attr(feature = "clap", arg(long, value_name = "SWEEPS"))]
    pub inversion_sweeps: Option<u32>,
    /// The fraction of its rest volume the inversion sweeps restore a tet to, in (0, 1]
    /// (default 0.1).
    #[cfg_attr(feature = "clap", arg(long, value_name = "FRACTION"))]
    pub inversion_floor: Option<f64>,
    /// How contact and hard constraints turn position corrections into velocity:
    /// `combined` (one solve, default) or `split` (split impulses: a nearly rigid body does
    /// not bounce; about twice the solve, a higher local volume error; docs/PHYSICS.md).
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    pub contact: Option<ContactMode>,
    /// Skip a constraint whose denominator A is at or below this (`epsilon` before
    /// 2026-12-06, still read with a warning).
    #[cfg_attr(feature = "clap", arg(long, alias = "epsilon"))]
    #[serde(alias = "epsilon")]
    pub constraint_epsilon: Option<f64>,
    /// Gravity [m/s^2]: a magnitude along -Y (`9.81`, the default) or a vector `x,y,z`
    /// (`--gravity=0,0,-9.81`; the floor stays the plane y = 0, so a body falling along
    /// another axis wants `--no-floor` and a plane collider).
    #[cfg_attr(feature = "clap", arg(long, value_name = "G|X,Y,Z"))]
    pub gravity: Option<Gravity>,
    /// Frames to simulate (the length of the run, not a `SimParams` value).
    #[cfg_attr(feature = "clap", arg(long))]
    pub frames: Option<u32>,
}

impl SolverOverrides {
    /// These values where given, `base`'s elsewhere: flags over a scene's `[solver]`.
    pub fn over(&self, base: &SolverOverrides) -> SolverOverrides {
        SolverOverrides {
            accuracy: self.accuracy.or(base.accuracy),
            dt: self.dt.or(base.dt),
            substeps: self.substeps.or(base.substeps),
            iterations: self.iterations.or(base.iterations),
            omega: self.omega.or(base.omega),
            combine: self.combine.or(base.combine),
            solver: self.solver.or(base.solver),
            groups: self.groups.or(base.groups),
            block_size: self.block_size.or(base.block_size),
            block_sweeps: self.block_sweeps.or(base.block_sweeps),
            spring_block_sweeps: self.spring_block_sweeps.or(base.spring_block_sweeps),
            global_volume: self.global_volume.or(base.global_volume),
            springs: self.springs.or(base.springs),
            warm_start: self.warm_start.or(base.warm_start),
            rho: self.rho.or(base.rho),
            anderson: self.anderson.or(base.anderson),
            minres: self.minres.or(base.minres),
            inversion_sweeps: self.inversion_sweeps.or(base.inversion_sweeps),
            inversion_floor: self.inversion_floor.or(base.inversion_floor),
            contact: self.contact.or(base.contact),
            constraint_epsilon: self.constraint_epsilon.or(base.constraint_epsilon),
            gravity: self.gravity.or(base.gravity),
            frames: self.frames.or(base.frames),
        }
    }

    /// Writes every given value onto `params` (`frames` is the caller's).
    pub fn apply(&self, params: &mut SimParams) {
        // The dial first: every setting given overrides it.
        if let Some(accuracy) = self.accuracy {
            accuracy.apply(params);
        }
        set(&mut params.dt, self.dt);
        set(&mut params.substeps, self.substeps);
        set(&mut params.iterations, self.iterations);
        set(&mut params.omega, self.omega);
        set(&mut params.combine, self.combine);
        set(&mut params.solver, self.solver);
        set(&mut params.groups, self.groups);
        set(&mut params.block_size, self.block_size);
        set(&mut params.block_sweeps, self.block_sweeps);
        set(&mut params.spring_block_sweeps, self.spring_block_sweeps);
        set(&mut params.global_volume, self.global_volume.map(Some));
        set(&mut params.rho, self.rho);
        set(&mut params.anderson, self.anderson);
        set(&mut params.minres, self.minres);
        set(&mut params.inversion_sweeps, self.inversion_sweeps);
        set(&mut params.inversion_floor, self.inversion_floor);
        set(&mut params.springs, self.springs);
        set(&mut params.warm_start, self.warm_start);
        set(&mut params.contact, self.contact);
        set(&mut params.constraint_epsilon, self.constraint_epsilon);
        set(&mut params.gravity, self.gravity.map(Gravity::vector));
    }

    /// Every key (a `[solver]` key, a flag's id).
    pub const KEYS: [&'static str; 23] = [
        "accuracy",
        "dt",
        "substeps",
        "iterations",
        "omega",
        "combine",
        "solver",
        "groups",
        "block_size",
        "block_sweeps",
        "spring_block_sweeps",
        "global_volume",
        "springs",
        "warm_start",
        "rho",
        "anderson",
        "minres",
        "inversion_sweeps",
        "inversion_floor",
        "contact",
        "constraint_epsilon",
        "gravity",
        "frames",
    ];

    /// Whether `key` is one of these values (a flag's id, a `[solver]` key).
    pub fn has(key: &str) -> bool {
        Self::KEYS.contains(&key)
    }

    /// A value given for a solver that does not use it, refused rather than ignored: the
    /// key and the solver it needs (`groups` without Gauss-Seidel, `rho` without
    /// Chebyshev), when `solver` is the one that runs.
    pub fn misplaced(&self, solver: Solver) -> Option<(&'static str, Solver)> {
        [
            ("groups", self.groups.is_some(), Solver::GaussSeidel),
            ("block_size", self.block_size.is_some(), Solver::GaussSeidel),
            (
                "block_sweeps",
                self.block_sweeps.is_some(),
                Solver::GaussSeidel,
            ),
            (
                "spring_block_sweeps",
                self.spring_block_sweeps.is_some(),
                Solver::GaussSeidel,
            ),
            ("rho", self.rho.is_some(), Solver::Chebyshev),
        ]
        .into_iter()
        .find(|&(_, given, needs)| given && solver != needs)
        .map(|(key, _, needs)| (key, needs))
    }
}

/// Spring constants or an elastic material, and mass, of an object: a scene object's
/// `material` table and `run`'s material flags. `None` keeps the base value (the preset's).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
#[serde(deny_unknown_fields)]
pub struct MaterialOverrides {
    /// Spring stiffness [N/m].
    #[cfg_attr(feature = "clap", arg(long))]
    pub ks: Option<f64>,
    /// Spring damping [N s/m].
    #[cfg_attr(feature = "clap", arg(long))]
    pub kd: Option<f64>,
    /// Mass of every node [kg] (the preset: 1).
    #[cfg_attr(feature = "clap", arg(long, conflicts_with = "density"))]
    pub node_mass: Option<f64>,
    /// Lumped masses from this density [kg/m^3] instead of equal node masses.
    #[cfg_attr(feature = "clap", arg(long))]
    pub density: Option<f64>,
    /// Young's modulus [Pa]: spring stiffnesses from the material (Van Gelder) instead of
    /// --ks; use with --density (`--youngs` before 2026-12-06, still read with a warning).
    #[cfg_attr(feature = "clap", arg(long, alias = "youngs", value_name = "PA", conflicts_with_all = ["ks", "kd"]))]
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio in (-1, 0.5] of the --youngs-modulus material: compliant volume
    /// constraints (bulk modulus E / (3 (1 - 2 nu))); default and 0.5: incompressible
    /// (`--poisson` before 2026-12-06, still read with a warning).
    #[cfg_attr(
        feature = "clap",
        arg(
            long,
            alias = "poisson",
            value_name = "NU",
            requires = "youngs_modulus"
        )
    )]
    pub poisson_ratio: Option<f64>,
    /// Damping time [s] of the --youngs-modulus material: each spring's damping is this times its
    /// stiffness (default 0.003, the paper's kd / ks).
    #[cfg_attr(
        feature = "clap",
        arg(long, value_name = "S", requires = "youngs_modulus")
    )]
    pub damping: Option<f64>,
}

impl MaterialOverrides {
    /// These values over `base`'s: flags over a scene object's `material`. A value given
    /// here replaces what excludes it there: a Young's modulus the spring constants (and
    /// only the modulus of a material: its Poisson's ratio and damping stay unless given
    /// too), a spring constant the material (modulus, Poisson's ratio and damping), one
    /// mass the other.
    pub fn over(&self, base: &MaterialOverrides) -> MaterialOverrides {
        let mut out = base.clone();
        if self.youngs_modulus.is_some() {
            (out.ks, out.kd) = (None, None);
        }
        if self.ks.is_some() || self.kd.is_some() {
            out.youngs_modulus = None;
            (out.poisson_ratio, out.damping) = (None, None);
        }
        if self.node_mass.is_some() {
            out.density = None;
        }
        if self.density.is_some() {
            out.node_mass = None;
        }
        MaterialOverrides {
            ks: self.ks.or(out.ks),
            kd: self.kd.or(out.kd),
            node_mass: self.node_mass.or(out.node_mass),
            density: self.density.or(out.density),
            youngs_modulus: self.youngs_modulus.or(out.youngs_modulus),
            poisson_ratio: self.poisson_ratio.or(out.poisson_ratio),
            damping: self.damping.or(out.damping),
        }
    }

    /// Every key (a `material` key, a flag's id).
    pub const KEYS: [&'static str; 7] = [
        "ks",
        "kd",
        "node_mass",
        "density",
        "youngs_modulus",
        "poisson_ratio",
        "damping",
    ];

    /// Whether `key` is one of these values (a flag's id, a `material` key).
    pub fn has(key: &str) -> bool {
        Self::KEYS.contains(&key)
    }

    /// Two given values that exclude each other (the flags refuse them through clap, scenes
    /// through this): a spring constant beside a Young's modulus, or two masses.
    pub fn conflict(&self) -> Option<(&'static str, &'static str)> {
        let e = self.youngs_modulus.is_some();
        [
            (
                "node_mass",
                self.node_mass.is_some(),
                "density",
                self.density.is_some(),
            ),
            ("youngs_modulus", e, "ks", self.ks.is_some()),
            ("youngs_modulus", e, "kd", self.kd.is_some()),
        ]
        .into_iter()
        .find(|&(_, a, _, b)| a && b)
        .map(|(a, _, b, _)| (a, b))
    }

    /// Writes every given value onto `params` (`density` wins over `node_mass`; the flags
    /// and scenes refuse both). A Young's modulus replaces the base's: its Poisson's ratio
    /// and damping are the ones given here, or the defaults.
    pub fn apply(&self, params: &mut SimParams) {
        set(&mut params.ks, self.ks);
        set(&mut params.kd, self.kd);
        if self.youngs_modulus.is_some() {
            params.youngs_modulus = self.youngs_modulus;
            params.poisson_ratio = self.poisson_ratio;
            params.damping = self.damping;
        } else {
            set(&mut params.poisson_ratio, self.poisson_ratio.map(Some));
            set(&mut params.damping, self.damping.map(Some));
        }
        set(
            &mut params.mass,
            self.node_mass.map(|mass| MassMode::PerNode { mass }),
        );
        set(
            &mut params.mass,
            self.density.map(|density| MassMode::Density { density }),
        );
    }
}

/// `*target = value` when there is one.
fn set<T>(target: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *target = v;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_given_changes_nothing_and_each_value_lands() {
        let base = SimParams::default();
        let mut p = base.clone();
        SolverOverrides::default().apply(&mut p);
        MaterialOverrides::default().apply(&mut p);
        assert_eq!(p, base);
        let solver = SolverOverrides {
            constraint_epsilon: Some(1e-9),
            global_volume: Some(false),
            rho: Some(0.5),
            ..SolverOverrides::default()
        };
        solver.apply(&mut p);
        MaterialOverrides {
            density: Some(10.0),
            ..MaterialOverrides::default()
        }
        .apply(&mut p);
        assert_eq!(
            (p.constraint_epsilon, p.global_volume, p.rho, p.mass),
            (1e-9, Some(false), 0.5, MassMode::Density { density: 10.0 })
        );
        assert_eq!(
            solver.misplaced(Solver::GaussSeidel),
            Some(("rho", Solver::Chebyshev))
        );
        assert_eq!(solver.misplaced(Solver::Chebyshev), None);
        assert!(SolverOverrides::has("global_volume") && !SolverOverrides::has("ks"));
        assert!(MaterialOverrides::has("node_mass") && !MaterialOverrides::has("dt"));
    }

    #[test]
    fn a_modulus_over_a_material_keeps_its_ratio_and_damping_and_springs_replace_it() {
        let material = MaterialOverrides {
            youngs_modulus: Some(1e5),
            poisson_ratio: Some(0.45),
            damping: Some(0.01),
            density: Some(1000.0),
            ..MaterialOverrides::default()
        };
        let stiffer = MaterialOverrides {
            youngs_modulus: Some(2e5),
            ..MaterialOverrides::default()
        }
        .over(&material);
        assert_eq!(
            (
                stiffer.youngs_modulus,
                stiffer.poisson_ratio,
                stiffer.damping
            ),
            (Some(2e5), Some(0.45), Some(0.01))
        );
        let springs = MaterialOverrides {
            youngs_modulus: Some(2e5),
            ..MaterialOverrides::default()
        }
        .over(&MaterialOverrides {
            ks: Some(100.0),
            kd: Some(1.0),
            ..MaterialOverrides::default()
        });
        assert_eq!((springs.ks, springs.kd), (None, None));
        let replaced = MaterialOverrides {
            ks: Some(100.0),
            ..MaterialOverrides::default()
        }
        .over(&material);
        assert_eq!(
            (
                replaced.youngs_modulus,
                replaced.poisson_ratio,
                replaced.damping
            ),
            (None, None, None)
        );
        assert_eq!(replaced.density, Some(1000.0));
    }

    /// The key lists are the structs' fields: every key a scene table accepts, and (with
    /// `clap`) every flag's id.
    #[test]
    fn the_key_lists_name_every_field() {
        for key in SolverOverrides::KEYS {
            let text = format!("{key} = 1");
            let err = toml::from_str::<SolverOverrides>(&text)
                .err()
                .map(|e| e.to_string());
            assert!(!err.unwrap_or_default().contains("unknown field"), "{key}");
        }
        for key in MaterialOverrides::KEYS {
            let text = format!("{key} = 1.0");
            let err = toml::from_str::<MaterialOverrides>(&text)
                .err()
                .map(|e| e.to_string());
            assert!(!err.unwrap_or_default().contains("unknown field"), "{key}");
        }
        let unknown = toml::from_str::<SolverOverrides>("nope = 1")
            .unwrap_err()
            .to_string();
        let expected = unknown.split("expected one of").nth(1).unwrap_or_default();
        // The old name `epsilon` is listed beside its new one.
        assert_eq!(
            expected.matches('`').count(),
            2 * (SolverOverrides::KEYS.len() + 1),
            "{unknown}"
        );
        let unknown = toml::from_str::<MaterialOverrides>("nope = 1")
            .unwrap_err()
            .to_string();
        let expected = unknown.split("expected one of").nth(1).unwrap_or_default();
        assert_eq!(
            expected.matches('`').count(),
            2 * MaterialOverrides::KEYS.len(),
            "{unknown}"
        );
        #[cfg(feature = "clap")]
        {
            use clap::Args;
            let ids = |cmd: clap::Command| -> Vec<String> {
                cmd.get_arguments()
                    .map(|a| a.get_id().to_string())
                    .collect()
            };
            assert_eq!(
                ids(SolverOverrides::augment_args(clap::Command::new("s"))),
                SolverOverrides::KEYS
            );
            assert_eq!(
                ids(MaterialOverrides::augment_args(clap::Command::new("m"))),
                MaterialOverrides::KEYS
            );
        }
    }
}
