//! `cpu`'s conjugate-gradient vectors for the finite elements, kept from step to step and
//! shared with the team while a step runs ([`NewtonVectors`], [`NewtonShared`]).

use glam::Vec3A;

use crate::backend::cpu::shared::SharedSlice;
use crate::physics::{CoarseSpace, ElasticLinear, Sym3};

/// Nodes per chunk of a dot product's partial sums.
pub(super) const CHUNK: usize = 256;

/// The conjugate gradients' vectors, kept from step to step (empty without finite
/// elements): per node the linearisation point, the residual, the preconditioned residual,
/// the search direction, the matrix times it, the inverse diagonal block and the stiffening
/// of the contact holding the node (zero: none; `cpu-ref`'s `held`); per tet its
/// stiffness at the linearisation point and its product's corners; per chunk a partial sum.
#[derive(Debug, Clone, Default)]
pub(super) struct NewtonVectors {
    at: Vec<Vec3A>,
    /// Where inertia alone would take each node, the displacement added to `at` so far and
    /// a trial position (the line search's).
    y: Vec<Vec3A>,
    dx: Vec<Vec3A>,
    trial: Vec<Vec3A>,
    r: Vec<Vec3A>,
    z: Vec<Vec3A>,
    p: Vec<Vec3A>,
    q: Vec<Vec3A>,
    inverse: Vec<Sym3<f32>>,
    held: Vec<Vec3A>,
    linear: Vec<ElasticLinear<Vec3A>>,
    corners: Vec<[Vec3A; 4]>,
    sums: Vec<f64>,
    /// Per chunk: two partial sums (the rigid-part correction's length).
    pair_sums: Vec<f64>,
    /// Per chunk of tets: a partial sum of their energies.
    tet_sums: Vec<f64>,
    /// The preconditioner's coarse level at the linearisation (one, the leader's) and
    /// `P^T r`, six entries per aggregate.
    coarse: Vec<CoarseSpace>,
    restricted: Vec<f64>,
    /// The coarse matrix's columns as the members fill them.
    columns: Vec<f64>,
    /// Per node: in contact at the latest linearisation (left out of the coarse correction).
    touching: Vec<bool>,
}

impl NewtonVectors {
    /// The vectors of `nodes` nodes, `tets` tets and `aggregates` aggregates.
    pub(super) fn new(nodes: usize, tets: usize, aggregates: usize) -> Self {
        NewtonVectors {
            at: vec![Vec3A::ZERO; nodes],
            y: vec![Vec3A::ZERO; nodes],
            dx: vec![Vec3A::ZERO; nodes],
            trial: vec![Vec3A::ZERO; nodes],
            r: vec![Vec3A::ZERO; nodes],
            z: vec![Vec3A::ZERO; nodes],
            p: vec![Vec3A::ZERO; nodes],
            q: vec![Vec3A::ZERO; nodes],
            inverse: vec![[0.0; 6]; nodes],
            held: vec![Vec3A::ZERO; nodes],
            linear: vec![ElasticLinear::default(); tets],
            corners: vec![[Vec3A::ZERO; 4]; tets],
            sums: vec![0.0; nodes.div_ceil(CHUNK)],
            pair_sums: vec![0.0; 2 * nodes.div_ceil(CHUNK)],
            tet_sums: vec![0.0; tets.div_ceil(CHUNK)],
            coarse: vec![CoarseSpace::default()],
            restricted: vec![0.0; 6 * aggregates],
            columns: vec![0.0; 36 * aggregates * aggregates],
            touching: vec![false; nodes],
        }
    }

    /// The coarse level kept from step to step, once built (none without finite
    /// elements).
    pub(super) fn coarse(&self) -> Option<&CoarseSpace> {
        self.coarse.first().filter(|c| c.is_built())
    }

    /// Puts back the coarse level a checkpoint carried.
    pub(super) fn set_coarse(&mut self, coarse: CoarseSpace) {
        if let Some(slot) = self.coarse.first_mut() {
            *slot = coarse;
        }
    }

    /// The number of the coarse level's aggregates.
    pub(super) fn aggregates(&self) -> usize {
        self.restricted.len() / 6
    }

    /// The vectors shared with the team.
    pub(super) fn share(&mut self) -> NewtonShared<'_> {
        NewtonShared {
            at: SharedSlice::new(&mut self.at),
            y: SharedSlice::new(&mut self.y),
            dx: SharedSlice::new(&mut self.dx),
            trial: SharedSlice::new(&mut self.trial),
            r: SharedSlice::new(&mut self.r),
            z: SharedSlice::new(&mut self.z),
            p: SharedSlice::new(&mut self.p),
            q: SharedSlice::new(&mut self.q),
            inverse: SharedSlice::new(&mut self.inverse),
            held: SharedSlice::new(&mut self.held),
            linear: SharedSlice::new(&mut self.linear),
            corners: SharedSlice::new(&mut self.corners),
            sums: SharedSlice::new(&mut self.sums),
            pair_sums: SharedSlice::new(&mut self.pair_sums),
            tet_sums: SharedSlice::new(&mut self.tet_sums),
            coarse: SharedSlice::new(&mut self.coarse),
            restricted: SharedSlice::new(&mut self.restricted),
            columns: SharedSlice::new(&mut self.columns),
            touching: SharedSlice::new(&mut self.touching),
        }
    }
}

/// [`NewtonVectors`] shared by the team.
pub(super) struct NewtonShared<'a> {
    pub(super) at: SharedSlice<'a, Vec3A>,
    pub(super) y: SharedSlice<'a, Vec3A>,
    pub(super) dx: SharedSlice<'a, Vec3A>,
    pub(super) trial: SharedSlice<'a, Vec3A>,
    pub(super) r: SharedSlice<'a, Vec3A>,
    pub(super) z: SharedSlice<'a, Vec3A>,
    pub(super) p: SharedSlice<'a, Vec3A>,
    pub(super) q: SharedSlice<'a, Vec3A>,
    pub(super) inverse: SharedSlice<'a, Sym3<f32>>,
    pub(super) held: SharedSlice<'a, Vec3A>,
    pub(super) linear: SharedSlice<'a, ElasticLinear<Vec3A>>,
    pub(super) corners: SharedSlice<'a, [Vec3A; 4]>,
    pub(super) sums: SharedSlice<'a, f64>,
    pub(super) pair_sums: SharedSlice<'a, f64>,
    pub(super) tet_sums: SharedSlice<'a, f64>,
    pub(super) coarse: SharedSlice<'a, CoarseSpace>,
    pub(super) restricted: SharedSlice<'a, f64>,
    pub(super) columns: SharedSlice<'a, f64>,
    pub(super) touching: SharedSlice<'a, bool>,
}
