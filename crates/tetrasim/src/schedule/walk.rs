//! One time step unrolled into its dispatches, in the order every backend runs them.

use super::{PassKind, Repeat, Schedule};
use crate::physics::Solve;

/// Where a constraint group lies, for the dispatches that run per group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GroupAt {
    /// Its sweep ([`Schedule::sweeps`]).
    pub sweep: usize,
    /// Its index within the sweep.
    pub group: usize,
    /// Its index over every sweep's groups, sweep after sweep (degrees, slot rows).
    pub index: u32,
    /// Its first constraint among the sweep's members, in group order.
    pub first: u32,
    /// Its constraints.
    pub count: u32,
}

/// One run of one stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dispatch {
    /// The stage ([`Schedule::stages`]).
    pub stage: usize,
    /// The constraint iteration, for the stages that repeat per iteration.
    pub iteration: Option<u32>,
    /// The constraint group, for the stages that run per group.
    pub group: Option<GroupAt>,
    /// Which of the step's solves it belongs to (split contact's velocity solve, or the
    /// full one: every dispatch without split contact).
    pub solve: Solve,
}

impl Schedule {
    /// One time step's dispatches, in execution order: the step's stages in order, with the
    /// per-iteration block (the first [`Repeat::Iteration`] stage to the last
    /// [`Repeat::IterationEnd`] one after it) unrolled `iterations` times, each time sweep
    /// after sweep and group after group (the sweep's own stage, then the stages of no
    /// sweep), then the stages that end an iteration. With split contact
    /// ([`Schedule::split`]) the step's dispatches up to `integrate` run twice: first as the
    /// velocity solve ([`Solve::Velocity`]), ended by `split_velocity`, then as the full
    /// solve. MINRES's stages follow the iterations: those of [`Repeat::AfterIterations`]
    /// once (their iteration is the iteration count), its iterations' `minres` times, and
    /// when no inversion sweep follows, the global volume stages once more after its last
    /// ([`Schedule::closes_minres`]).
    pub fn step(&self) -> Vec<Dispatch> {
        let full = self.solve();
        if !self.split {
            return full;
        }
        let stage_of = |kind| {
            (self.stages.iter())
                .position(|s| s.kind == kind)
                .expect("a split schedule has both ends")
        };
        let split_velocity = stage_of(PassKind::SplitVelocity);
        let integrate = stage_of(PassKind::Integrate);
        let solve_end = (full.iter())
            .position(|d| d.stage == integrate)
            .unwrap_or(full.len());
        let end = Dispatch {
            stage: split_velocity,
            iteration: None,
            group: None,
            solve: Solve::Full,
        };
        let velocity = (full[..solve_end].iter())
            .chain(std::iter::once(&end))
            .map(|d| Dispatch {
                solve: Solve::Velocity,
                ..*d
            });
        velocity.chain(full.iter().copied()).collect()
    }

    /// One solve's dispatches (every stage of the step but `split_velocity`).
    fn solve(&self) -> Vec<Dispatch> {
        let step: Vec<usize> = (0..self.stages.len())
            .filter(|&i| {
                let stage = &self.stages[i];
                stage.repeat != Repeat::Frame && stage.kind != PassKind::SplitVelocity
            })
            .collect();
        let once = |stage| Dispatch {
            stage,
            iteration: None,
            group: None,
            solve: Solve::Full,
        };
        let repeat = |k: usize| self.stages[step[k]].repeat;
        // The stages of no sweep that follow every group (constraint_apply).
        let shared: Vec<usize> = (step.iter().copied())
            .filter(|&i| self.stages[i].repeat == Repeat::Iteration)
            .filter(|&i| self.stages[i].sweep.is_none())
            .collect();
        let mut out = Vec::new();
        let mut k = 0;
        while k < step.len() {
            match repeat(k) {
                r if r.in_iterations() => {}
                Repeat::Restore => {
                    // After the iterations: the stage's sweep, group by group, then the
                    // global volume constraint when it is solved (the floor moves surface
                    // nodes), as further iterations that solve only those.
                    let stage = step[k];
                    let sweep = self.stages[stage]
                        .sweep
                        .expect("a restore stage has a sweep");
                    let global = self.global_stages(&step);
                    for round in 0..self.inversion_sweeps {
                        let iteration = Some(self.iterations + round);
                        self.push_groups(&mut out, sweep, &[stage], &shared, iteration);
                        for &g in &global {
                            out.push(Dispatch {
                                iteration,
                                ..once(g)
                            });
                        }
                    }
                    k += 1;
                    continue;
                }
                Repeat::AfterIterations => {
                    let iteration = Some(self.iterations);
                    out.push(Dispatch {
                        iteration,
                        ..once(step[k])
                    });
                    if self.stages[step[k]].kind == PassKind::MinresForces && self.closes_minres() {
                        // MINRES's close: the global volume constraints once more.
                        for &g in &self.global_stages(&step) {
                            out.push(Dispatch {
                                iteration,
                                ..once(g)
                            });
                        }
                    }
                    k += 1;
                    continue;
                }
                Repeat::Minres => {
                    let end = (k..step.len())
                        .find(|&e| repeat(e) != Repeat::Minres)
                        .unwrap_or(step.len());
                    for iteration in 0..self.minres {
                        for &stage in &step[k..end] {
                            out.push(Dispatch {
                                iteration: Some(iteration),
                                ..once(stage)
                            });
                        }
                    }
                    k = end;
                    continue;
                }
                _ => {
                    out.push(once(step[k]));
                    k += 1;
                    continue;
                }
            }
            let end = (k..step.len())
                .find(|&e| !repeat(e).in_iterations())
                .unwrap_or(step.len());
            let after_end = (end..step.len())
                .find(|&e| repeat(e) != Repeat::IterationEnd)
                .unwrap_or(step.len());
            let block = &step[k..end];
            for iteration in 0..self.iterations {
                for s in 0..self.sweeps.len() {
                    let own: Vec<usize> = (block.iter().copied())
                        .filter(|&i| self.stages[i].sweep == Some(s))
                        .filter(|&i| (self.stages[i].repeat).runs_in(iteration, self.iterations))
                        .collect();
                    self.push_groups(&mut out, s, &own, &shared, Some(iteration));
                }
                for &stage in &step[end..after_end] {
                    out.push(Dispatch {
                        iteration: Some(iteration),
                        ..once(stage)
                    });
                }
            }
            k = after_end;
        }
        out
    }

    /// The global volume constraints' stages among `step`'s (`global_volume_sum`, then
    /// `global_volume`; none when the step does not solve them).
    fn global_stages(&self, step: &[usize]) -> Vec<usize> {
        (step.iter().copied())
            .filter(|&i| self.stages[i].kind.is_global_volume())
            .collect()
    }

    /// The dispatches of sweep `s`'s groups in one iteration: per group, the sweep's `own`
    /// stages, then the `shared` ones.
    fn push_groups(
        &self,
        out: &mut Vec<Dispatch>,
        s: usize,
        own: &[usize],
        shared: &[usize],
        iteration: Option<u32>,
    ) {
        let before: usize = self.sweeps[..s].iter().map(|w| w.groups.len()).sum();
        let mut first = 0;
        for (g, &count) in self.sweeps[s].groups.iter().enumerate() {
            let group = GroupAt {
                sweep: s,
                group: g,
                index: (before + g) as u32,
                first,
                count,
            };
            for &stage in own.iter().chain(shared) {
                out.push(Dispatch {
                    stage,
                    iteration,
                    group: Some(group),
                    solve: Solve::Full,
                });
            }
            first += count;
        }
    }

    /// The stages that run once per frame after the last step, in order.
    pub fn frame_end(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.stages.len()).filter(|&i| self.stages[i].repeat == Repeat::Frame)
    }
}
