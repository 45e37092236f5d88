//! The speed/accuracy trade as one dial (`--accuracy`, a scene's `[solver] accuracy`,
//! Python's `accuracy=`): each level is a point of the front measured on `cpu`
//! (docs/BENCHMARKS.md, "The front on 2 cores"; the figures of each level in
//! docs/guide/accuracy.md), written onto the parameters before any setting given
//! explicitly, which overrides it.

use serde::{Deserialize, Serialize};

use super::{SimParams, Solver};

/// A level of the speed/accuracy dial.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum Accuracy {
    /// 0.35 to 0.86 of the default's time, about twice its local volume error (on `cpu`):
    /// Gauss-Seidel over 4 colour groups with the global volume constraint, 5 iterations.
    Fast,
    /// The defaults: Gauss-Seidel over 8 colour groups with the global volume constraint,
    /// 10 iterations, one step per frame.
    Balanced,
    /// About twice the default's time, about half its local volume error: the
    /// defaults' solver and iterations at two steps per frame of half the time step.
    Accurate,
}

impl Accuracy {
    /// Every level, fastest first.
    pub const ALL: [Accuracy; 3] = [Accuracy::Fast, Accuracy::Balanced, Accuracy::Accurate];

    /// `fast`, `balanced` or `accurate`: its name in flags, scenes, Python and records.
    pub fn name(self) -> &'static str {
        match self {
            Accuracy::Fast => "fast",
            Accuracy::Balanced => "balanced",
            Accuracy::Accurate => "accurate",
        }
    }

    /// Writes the level's settings onto `params` (whose `dt` and `substeps` are the base
    /// the `accurate` level halves and doubles); the caller writes the settings given
    /// explicitly afterwards. The finite elements use its iterations and steps (their
    /// conjugate gradients ignore the sweeps' solver and groups).
    pub fn apply(self, params: &mut SimParams) {
        params.solver = Solver::GaussSeidel;
        // Gauss-Seidel's default: on.
        params.global_volume = None;
        params.iterations = 10;
        params.groups = 8;
        match self {
            Accuracy::Fast => {
                params.groups = 4;
                params.iterations = 5;
            }
            Accuracy::Balanced => {}
            Accuracy::Accurate => {
                params.substeps = params.substeps.saturating_mul(2);
                params.dt /= 2.0;
            }
        }
    }

    /// What the level chose, for a run's header: `fast (gauss-seidel, 4 groups + global
    /// volume, 5 iterations)`.
    pub fn describe(self, params: &SimParams) -> String {
        format!(
            "{} (gauss-seidel, {} groups + global volume, {} iterations, {} step{} of {} s per frame)",
            self.name(),
            params.groups,
            params.iterations,
            params.substeps,
            if params.substeps == 1 { "" } else { "s" },
            params.dt
        )
    }
}

impl std::fmt::Display for Accuracy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_levels_cost_more_work_in_order_and_balanced_is_the_default() {
        let work = |a: Accuracy| {
            let mut p = SimParams::default();
            a.apply(&mut p);
            // Sweeps per frame, and the frame's length kept.
            (p.iterations * p.substeps, p.dt * f64::from(p.substeps))
        };
        let [fast, balanced, accurate] = Accuracy::ALL.map(work);
        assert!(fast.0 < balanced.0 && balanced.0 < accurate.0);
        assert_eq!((fast.1, accurate.1), (balanced.1, balanced.1));
        let mut p = SimParams::default();
        Accuracy::Balanced.apply(&mut p);
        let d = SimParams::default();
        assert_eq!(
            (
                p.solver,
                p.groups,
                p.global_volume,
                p.iterations,
                p.substeps,
                p.dt
            ),
            (
                d.solver,
                d.groups,
                d.global_volume,
                d.iterations,
                d.substeps,
                d.dt
            )
        );
    }
}
