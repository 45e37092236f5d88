//! The forces of one time step of `cpu-ref` while its dispatches run, and what the step's
//! forces come to ([`Forces`]).

use glam::DVec3;

use super::ReferenceBackend;
use crate::collider::{self, NodeContact};
use crate::contact::Contact;
use crate::physics::Solve;

/// The forces of a time step while its dispatches run.
pub(super) struct StepForces {
    /// Which solve of the step these forces are (split contact solves twice).
    pub(super) solve: Solve,
    pub(super) gravity: Vec<DVec3>,
    /// Explicit spring forces, or the warm start's (zeros without a spring force stage).
    pub(super) springs: Vec<DVec3>,
    /// The total force so far.
    pub(super) total: Vec<DVec3>,
    /// The floor's normal force so far.
    pub(super) floor: Vec<f64>,
    /// The colliders' force and contact so far.
    pub(super) contacts: Vec<NodeContact>,
    /// Each node's [`collider::clearance`] in this step (empty until the first solve).
    pub(super) clearance: Vec<f64>,
    /// Each node's attachment to a grab in this step.
    pub(super) attached: Vec<Option<collider::Attachment>>,
    /// The compliant constraints' multipliers found so far in this step (the warm start's
    /// for the springs).
    pub(super) spring_lambda: Vec<f64>,
    pub(super) volume_lambda: Vec<f64>,
    /// Chebyshev: the total and floor forces two iterations back.
    pub(super) before_total: Vec<DVec3>,
    pub(super) before_floor: Vec<f64>,
    /// The current group's per-node constraint sums.
    pub(super) sum: Vec<DVec3>,
    /// The finite elements' conjugate gradients within the step.
    pub(super) newton: super::elastic::NewtonCg,
    /// Per global volume object: `C_g`, the surface gradients and the multiplier.
    pub(super) global: Vec<(f64, Vec<DVec3>, f64)>,
    /// The step's body contacts with their multipliers so far (`<= 0`: they push).
    pub(super) bodies: Vec<(Contact, f64)>,
    /// Anderson acceleration's history (`anderson > 0`).
    pub(super) anderson: super::anderson::AndersonHistory,
}

impl StepForces {
    /// Gravity alone, at the start of solve `solve` of a step of `backend`.
    pub(super) fn new(backend: &ReferenceBackend, solve: Solve) -> Self {
        let problem = &backend.problem;
        let n = problem.model.node_count();
        let down = problem.params.gravity;
        let gravity: Vec<DVec3> = problem.model.mass.iter().map(|&m| down * m).collect();
        let mut step = StepForces {
            solve,
            springs: vec![DVec3::ZERO; n],
            total: Vec::new(),
            floor: vec![0.0; n],
            contacts: vec![NodeContact::NONE; n],
            clearance: Vec::new(),
            attached: Vec::new(),
            spring_lambda: backend.spring_warm.clone(),
            volume_lambda: vec![0.0; problem.model.tets.len()],
            before_total: Vec::new(),
            before_floor: Vec::new(),
            sum: Vec::new(),
            newton: Default::default(),
            global: Vec::new(),
            bodies: Vec::new(),
            anderson: Default::default(),
            gravity,
        };
        step.set_springs(vec![DVec3::ZERO; n]);
        // Finite elements start from the last step's elastic forces (zeros otherwise).
        for ((t, b), w) in
            (step.total.iter_mut().zip(&mut step.before_total)).zip(&backend.elastic_warm)
        {
            *t += *w;
            *b += *w;
        }
        step
    }

    /// The elastic force so far on node `i`: the total less gravity, springs, the floor's
    /// and the colliders' forces (finite elements: the forces their node steps added).
    pub(super) fn elastic(&self, i: usize) -> DVec3 {
        self.total[i]
            - self.gravity[i]
            - self.springs[i]
            - DVec3::Y * self.floor[i]
            - self.contacts[i].force
    }

    /// The spring forces: the total becomes gravity plus them (and so do the Chebyshev
    /// forces before the first iteration).
    pub(super) fn set_springs(&mut self, springs: Vec<DVec3>) {
        self.total = (self.gravity.iter().zip(&springs))
            .map(|(g, s)| *g + *s)
            .collect();
        self.springs = springs;
        self.before_total.clone_from(&self.total);
        self.before_floor.clone_from(&self.floor);
    }
}

/// The forces of steps 1 and 2 of one time step, per node [N]; their sum is the `F` that is
/// integrated.
#[derive(Debug, Clone, PartialEq)]
pub struct Forces {
    /// `m g` along -Y.
    pub gravity: Vec<DVec3>,
    /// Spring forces (zero for methods without springs).
    pub springs: Vec<DVec3>,
    /// Constraint forces of all iterations, combined and relaxed.
    pub constraints: Vec<DVec3>,
    /// The floor's normal force (along +Y, `>= 0`; zero without a floor).
    pub floor: Vec<f64>,
    /// The kinematic colliders' force and contact ([`collider::solve_node`]; none without
    /// colliders).
    pub contacts: Vec<NodeContact>,
    /// The step's contacts between bodies with their multipliers.
    pub bodies: Vec<(Contact, f64)>,
    /// Per spring, the multiplier of its implicit spring after the step's iterations (the
    /// force is `-lambda grad C`); zeros with explicit springs.
    pub spring_multipliers: Vec<f64>,
    /// Per tet, the multiplier of its compliant volume constraint after the iterations
    /// (zero for hard ones).
    pub volume_multipliers: Vec<f64>,
}

impl Forces {
    /// The total force on each node.
    pub fn total(&self) -> Vec<DVec3> {
        (0..self.gravity.len())
            .map(|i| {
                self.gravity[i]
                    + self.springs[i]
                    + self.constraints[i]
                    + DVec3::Y * self.floor[i]
                    + self.contacts[i].force
            })
            .collect()
    }
}
