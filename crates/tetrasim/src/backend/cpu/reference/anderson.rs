//! Anderson acceleration on `cpu-ref` (physics/anderson.rs): the step's forces and
//! compliant multipliers mixed with their history after each iteration, in double
//! precision, node after node.

use glam::DVec3;

use super::step_forces::StepForces;
use super::ReferenceBackend;
use crate::physics::{anderson_weights, gram_index, gram_terms, AndersonIteration};

/// Anderson acceleration's history within one solve of a step.
#[derive(Default)]
pub(super) struct AndersonHistory {
    /// The next input `x`, the last residual `f` and forces `g`, per node.
    x: Vec<DVec3>,
    f: Vec<DVec3>,
    g: Vec<DVec3>,
    /// The ring of `m` columns `df`, `dg`, per node.
    df: Vec<Vec<DVec3>>,
    dg: Vec<Vec<DVec3>>,
    /// The compliant multipliers (springs', then volumes') of the last iteration and their
    /// ring of differences.
    lambda: Vec<f64>,
    dlambda: Vec<Vec<f64>>,
}

impl ReferenceBackend {
    /// Iteration `iteration`'s Anderson mix of `step`'s forces and compliant multipliers
    /// (`anderson_sum` and `anderson_mix` in one), before the floor's and colliders' solve
    /// that follows.
    pub(super) fn anderson(&self, iteration: u32, step: &mut StepForces) {
        let memory = self.problem.params.anderson;
        let at = AndersonIteration::of(iteration, memory);
        let g: Vec<DVec3> = step.total.clone();
        let lambda: Vec<f64> = (step.spring_lambda.iter())
            .chain(&step.volume_lambda)
            .copied()
            .collect();
        let h = &mut step.anderson;
        if at.first {
            h.df = vec![Vec::new(); memory as usize];
            h.dg = vec![Vec::new(); memory as usize];
            h.dlambda = vec![Vec::new(); memory as usize];
            h.x = g;
            h.lambda = lambda;
            return;
        }
        let f: Vec<DVec3> = g.iter().zip(&h.x).map(|(g, x)| *g - *x).collect();
        if let Some(slot) = at.slot {
            h.df[slot] = f.iter().zip(&h.f).map(|(a, b)| *a - *b).collect();
            h.dg[slot] = g.iter().zip(&h.g).map(|(a, b)| *a - *b).collect();
            h.dlambda[slot] = lambda.iter().zip(&h.lambda).map(|(a, b)| a - b).collect();
        }
        let k = at.columns;
        let dot = |a: &[DVec3], b: &[DVec3]| a.iter().zip(b).map(|(p, q)| p.dot(*q)).sum::<f64>();
        let mut sums = vec![0.0; gram_terms(k)];
        for i in 0..k {
            for j in i..k {
                sums[gram_index(i, j, k)] = dot(&h.df[i], &h.df[j]);
            }
            sums[k * (k + 1) / 2 + i] = dot(&h.df[i], &f);
        }
        let gamma = anderson_weights(&sums, k);
        let mut next = g.clone();
        for (j, &w) in gamma[..k].iter().enumerate() {
            for (x, d) in next.iter_mut().zip(&h.dg[j]) {
                *x -= *d * w;
            }
        }
        step.total.clone_from(&next);
        // The multipliers with the same weights: the forces are linear in them (gradients
        // at x(t)), so the mixed multipliers are the mixed forces' own.
        let mut mixed = lambda.clone();
        for (j, &w) in gamma[..k].iter().enumerate() {
            for (x, d) in mixed.iter_mut().zip(&h.dlambda[j]) {
                *x -= *d * w;
            }
        }
        let springs = step.spring_lambda.len();
        step.spring_lambda.copy_from_slice(&mixed[..springs]);
        step.volume_lambda.copy_from_slice(&mixed[springs..]);
        (h.x, h.f, h.g, h.lambda) = (next, f, g, lambda);
    }
}
