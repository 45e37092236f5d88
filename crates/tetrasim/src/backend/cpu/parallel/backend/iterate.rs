//! The step's constraint iterations of the `cpu` backend: the sweeps' multipliers and the
//! Chebyshev state set, the dispatches run by the thread team ([`iterations::run`]).

use super::*;

impl ParallelBackend {
    /// The step's constraint iterations, the dispatches `range`: the sweeps' multipliers
    /// (the warm start's for the springs) and the Chebyshev state set, the dispatches run by
    /// `team` with MINRES between the iterations and the inversion sweeps (`minres > 0`), the
    /// springs' multipliers kept for the next step's warm start.
    pub(super) fn iterations(
        &mut self,
        team: &Team,
        range: std::ops::Range<usize>,
        at: &[ColliderAt<'_>],
    ) {
        let global = self.global.take();
        if let Some(c) = &mut self.chebyshev {
            c.before_f.clone_from(&self.f);
            c.before_n.clone_from(&self.floor_force);
        }
        let mut sweeps = std::mem::take(&mut self.sweeps);
        for sweep in &mut sweeps {
            match (sweep.kind, self.spring_warm.is_empty()) {
                (ConstraintKind::Spring, false) => {
                    let warm = &self.spring_warm;
                    for (m, &s) in sweep.multipliers.iter_mut().zip(&sweep.members.items) {
                        *m = warm[s as usize];
                    }
                }
                _ => sweep.multipliers.fill(0.0),
            }
        }
        // MINRES where the schedule has its rows: after the iterations, before the inversion
        // sweeps (its other passes are the GPU's; the team skips them).
        let minres = (range.clone())
            .find(|&d| self.stages[self.dispatches[d].stage] == PassKind::MinresRows);
        let split = minres.unwrap_or(range.end);
        self.iterate(team, &mut sweeps, global.as_ref(), range.start..split, at);
        if minres.is_some() {
            self.minres_solve(team, &mut sweeps, global.as_ref());
        }
        if split < range.end {
            self.iterate(team, &mut sweeps, global.as_ref(), split..range.end, at);
        }
        if !self.spring_warm.is_empty() {
            for sweep in sweeps.iter().filter(|s| s.kind == ConstraintKind::Spring) {
                for (&m, &s) in sweep.multipliers.iter().zip(&sweep.members.items) {
                    self.spring_warm[s as usize] = m;
                }
            }
        }
        self.sweeps = sweeps;
        self.global = global;
    }

    /// The dispatches `range` of the step's constraint iterations (every group of every
    /// sweep, then the global volume constraints), run by the team ([`iterations::run`]).
    pub(super) fn iterate(
        &mut self,
        team: &Team,
        sweeps: &mut [Sweep],
        global: Option<&Global>,
        range: std::ops::Range<usize>,
        at: &[ColliderAt<'_>],
    ) {
        let mut multipliers: Vec<Vec<f32>> = (sweeps.iter_mut())
            .map(|s| std::mem::take(&mut s.multipliers))
            .collect();
        let chunks = global.map_or(0, |g| {
            let chunks = iterations::global_chunks(g);
            chunks.last().map_or(0, |(first, count)| first + count)
        });
        let mut partial = vec![[0.0f32; 2]; chunks];
        let ParallelBackend {
            x,
            v,
            inv_mass,
            rest_volume,
            tets,
            k,
            floor,
            chebyshev,
            anderson,
            stages,
            dispatches,
            f,
            floor_force,
            contact,
            clearance,
            attached,
            bodies,
            body_contacts,
            pair_out,
            tet_out,
            node_out,
            newton,
            steps,
            ..
        } = self;
        let (chebyshev_weights, chebyshev) = match chebyshev {
            Some(Chebyshev {
                weights,
                before_f,
                before_n,
            }) => (
                Some(&weights[..]),
                Some((SharedSlice::new(before_f), SharedSlice::new(before_n))),
            ),
            None => (None, None),
        };
        let inputs = Inputs {
            x,
            v,
            inv_mass,
            rest_volume,
            tets,
            k: *k,
            floor: *floor,
            // The clock was advanced at the step's start.
            step: *steps - 1,
            colliders: (!at.is_empty() || !attached.is_empty()).then_some(Colliders {
                at,
                x,
                v,
                w: inv_mass,
                dt: k.dt,
                clear: clearance,
                attached,
                solve: k.solve,
            }),
            bodies: bodies
                .as_ref()
                .and_then(|p| p.bodies.as_ref().map(|b| (b, p))),
            sweeps,
            global,
            chebyshev_weights,
            anderson: anderson.as_ref().map_or(0, |a| a.memory),
            anderson_volumes: anderson.as_ref().is_some_and(|a| a.volumes),
            stages,
            dispatches: &dispatches[range],
        };
        let outputs = Outputs {
            f: SharedSlice::new(f),
            floor_force: SharedSlice::new(floor_force),
            contact: SharedSlice::new(contact),
            body_contacts: SharedSlice::new(body_contacts),
            multipliers: multipliers
                .iter_mut()
                .map(|m| SharedSlice::new(m))
                .collect(),
            pair_out: SharedSlice::new(pair_out),
            tet_out: SharedSlice::new(tet_out),
            node_out: SharedSlice::new(node_out),
            newton: newton.share(),
            chebyshev,
            partial: SharedSlice::new(&mut partial),
            anderson: anderson.as_mut().map(|a| {
                (
                    SharedSlice::new(&mut a.history),
                    SharedSlice::new(&mut a.sums),
                    SharedSlice::new(&mut a.multipliers),
                )
            }),
        };
        team.run(|member| iterations::run(member, &inputs, &outputs));
        drop(outputs);
        for (sweep, m) in sweeps.iter_mut().zip(multipliers) {
            sweep.multipliers = m;
        }
    }
}
