//! A solver with its settings as `tradeoff` and `bench` name them on the command line and in
//! records: `gauss-seidel:8+global+anderson5`, parsed and printed.

use tetrasim::error::{Error, Result};
use tetrasim::params::{SimParams, Solver};

/// A solver with its settings: `jacobi`, `chebyshev`, `gauss-seidel:8`,
/// `gauss-seidel:8+global`, `gauss-seidel:8+global+anderson5`,
/// `gauss-seidel:16+global+anderson5+inversion8`, `gauss-seidel:block1024+global`,
/// `gauss-seidel:8+global+minres40`, ...
/// (Chebyshev with the default `rho`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolverSetting {
    /// The solver.
    pub solver: Solver,
    /// Colour groups (Gauss-Seidel; 1 for Jacobi).
    pub groups: u32,
    /// Block Gauss-Seidel's tets per block (0: colour groups).
    pub block_size: u32,
    /// Sweeps of each block per iteration (1 but with blocks).
    pub block_sweeps: u32,
    /// Whether the global volume constraint is solved too.
    pub global_volume: bool,
    /// Anderson acceleration's memory (0: off).
    pub anderson: u32,
    /// MINRES iterations after the sweeps (0: off; every backend).
    pub minres: u32,
    /// Inversion sweeps after the iterations (0: off; method `volume` only, the points of
    /// the other methods skip a setting with them, as one with blocks).
    pub inversion_sweeps: u32,
}

impl SolverSetting {
    /// The settings compared by default: Jacobi (the paper's), Jacobi with the global volume
    /// constraint, Gauss-Seidel with 8 groups, with the global constraint (the default), and
    /// that with Anderson acceleration of memory 5.
    pub const DEFAULTS: [SolverSetting; 5] = [
        SolverSetting::new(Solver::Jacobi, 1, false),
        SolverSetting::new(Solver::Jacobi, 1, true),
        SolverSetting::new(Solver::GaussSeidel, 8, false),
        SolverSetting::new(Solver::GaussSeidel, 8, true),
        SolverSetting::new(Solver::GaussSeidel, 8, true).with_anderson(5),
    ];

    /// A setting without Anderson acceleration.
    pub const fn new(solver: Solver, groups: u32, global_volume: bool) -> Self {
        SolverSetting {
            solver,
            groups,
            block_size: 0,
            block_sweeps: 1,
            global_volume,
            anderson: 0,
            minres: 0,
            inversion_sweeps: 0,
        }
    }

    /// The same setting with Anderson acceleration of memory `memory`.
    pub const fn with_anderson(self, memory: u32) -> Self {
        SolverSetting {
            anderson: memory,
            ..self
        }
    }

    /// The same setting with `iterations` MINRES iterations after the sweeps.
    pub const fn with_minres(self, iterations: u32) -> Self {
        SolverSetting {
            minres: iterations,
            ..self
        }
    }

    /// The same Gauss-Seidel setting in blocks of `tets` (block Gauss-Seidel).
    pub const fn with_blocks(self, tets: u32) -> Self {
        SolverSetting {
            block_size: tets,
            ..self
        }
    }

    /// The same block Gauss-Seidel setting with `sweeps` sweeps of each block.
    pub const fn with_block_sweeps(self, sweeps: u32) -> Self {
        SolverSetting {
            block_sweeps: sweeps,
            ..self
        }
    }

    /// The same setting with `sweeps` inversion sweeps.
    pub const fn with_inversion(self, sweeps: u32) -> Self {
        SolverSetting {
            inversion_sweeps: sweeps,
            ..self
        }
    }

    /// The name in tables, records and on the command line (`gauss-seidel:8+global`).
    pub fn label(&self) -> String {
        let mut out = self.solver.name().to_string();
        if self.solver == Solver::GaussSeidel && self.block_size > 0 {
            out += &format!(":block{}", self.block_size);
            if self.block_sweeps > 1 {
                out += &format!("x{}", self.block_sweeps);
            }
        } else if self.solver == Solver::GaussSeidel {
            out += &format!(":{}", self.groups);
        }
        if self.global_volume {
            out += "+global";
        }
        if self.anderson > 0 {
            out += &format!("+anderson{}", self.anderson);
        }
        if self.minres > 0 {
            out += &format!("+minres{}", self.minres);
        }
        if self.inversion_sweeps > 0 {
            out += &format!("+inversion{}", self.inversion_sweeps);
        }
        out
    }

    /// `base` with this solver.
    pub fn apply(&self, base: &SimParams) -> SimParams {
        SimParams {
            solver: self.solver,
            groups: self.groups,
            block_size: self.block_size,
            block_sweeps: self.block_sweeps,
            global_volume: Some(self.global_volume),
            anderson: self.anderson,
            minres: self.minres,
            inversion_sweeps: self.inversion_sweeps,
            ..base.clone()
        }
    }
}

impl std::str::FromStr for SolverSetting {
    type Err = Error;

    /// `NAME[:GROUPS|:blockB[xS]][+global][+andersonM][+minresK][+inversionN]`, NAME
    /// `jacobi`, `chebyshev` or `gauss-seidel` (groups, for Gauss-Seidel only, default 8; or
    /// blocks of B tets, 1 to 16777216; above 1024 thread blocks, `cpu` backends only), M
    /// Anderson acceleration's memory (1 to 8), K the MINRES iterations after the sweeps (1
    /// to 200, `cpu` backends only), N the inversion sweeps (1 to 64).
    fn from_str(text: &str) -> Result<Self> {
        let limit = tetrasim::params::MAX_INVERSION_SWEEPS;
        let (rest, inversion) = counted_suffix(text, text, "+inversion", "N", limit)?;
        let limit = tetrasim::params::MINRES_MAX_ITERATIONS;
        let (rest, minres) = counted_suffix(text, rest, "+minres", "K", limit)?;
        let limit = tetrasim::params::ANDERSON_MAX_MEMORY;
        let (rest, anderson) = counted_suffix(text, rest, "+anderson", "M", limit)?;
        let (rest, global_volume) = match rest.strip_suffix("+global") {
            Some(rest) => (rest, true),
            None => (rest, false),
        };
        let (rest, block_size, block_sweeps) = match rest.split_once(":block") {
            Some((name, blocks)) => {
                let (blocks, sweeps) = match blocks.split_once('x') {
                    Some((tets, sweeps)) => {
                        let limit = tetrasim::params::MAX_BLOCK_SWEEPS;
                        let x = format!("x{sweeps}");
                        (tets, counted_suffix(text, &x, "x", "S", limit)?.1)
                    }
                    None => (blocks, 1),
                };
                let limit = tetrasim::params::MAX_BLOCK_SIZE;
                let blocks = format!(":block{blocks}");
                let (_, tets) = counted_suffix(text, &blocks, ":block", "B", limit)?;
                (name, tets, sweeps)
            }
            None => (rest, 0, 1),
        };
        let (name, groups) = match rest.split_once(':') {
            Some((name, g)) => {
                let groups = g.parse::<u32>().ok().filter(|&g| g > 0).ok_or_else(|| {
                    Error::param("solvers", format!("`{text}`: groups must be a number >= 1"))
                })?;
                (name, Some(groups))
            }
            None => (rest, None),
        };
        let solver = Solver::ALL
            .into_iter()
            .find(|s| s.name() == name)
            .ok_or_else(|| {
                Error::param(
                    "solvers",
                    format!(
                        "`{text}`: expected jacobi, chebyshev or gauss-seidel, optionally \
                         with :GROUPS or :blockB (gauss-seidel), +global, +andersonM, \
                         +minresK and +inversionN"
                    ),
                )
            })?;
        let groups = match (solver, groups) {
            (Solver::Jacobi | Solver::Chebyshev, Some(_)) => {
                return Err(Error::param(
                    "solvers",
                    format!("`{text}`: {name} has no colour groups"),
                ))
            }
            (Solver::Jacobi | Solver::Chebyshev, None) => 1,
            (Solver::GaussSeidel, g) => g.unwrap_or(tetrasim::params::default_groups()),
        };
        if block_size > 0 && solver != Solver::GaussSeidel {
            return Err(Error::param(
                "solvers",
                format!("`{text}`: {name} has no blocks (gauss-seidel:blockB)"),
            ));
        }
        if anderson > 0 && solver == Solver::Chebyshev {
            return Err(Error::param(
                "solvers",
                format!("`{text}`: anderson does not combine with chebyshev"),
            ));
        }
        Ok(SolverSetting::new(solver, groups, global_volume)
            .with_blocks(block_size)
            .with_block_sweeps(block_sweeps)
            .with_anderson(anderson)
            .with_minres(minres)
            .with_inversion(inversion))
    }
}

/// `rest` without its last `SUFFIX<count>` and the count (1 to `limit`), or `rest` and 0
/// without the suffix; the error names the setting `text` and the count's letter.
fn counted_suffix<'a>(
    text: &str,
    rest: &'a str,
    suffix: &str,
    letter: &str,
    limit: u32,
) -> Result<(&'a str, u32)> {
    let Some((rest, count)) = rest.rsplit_once(suffix) else {
        return Ok((rest, 0));
    };
    let count = (count.parse::<u32>().ok())
        .filter(|n| (1..=limit).contains(n))
        .ok_or_else(|| {
            Error::param(
                "solvers",
                format!("`{text}`: {suffix}{letter} needs {letter} from 1 to {limit}"),
            )
        })?;
    Ok((rest, count))
}
