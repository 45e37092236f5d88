//! MINRES after the iterations on the GPU (`minres > 0`; docs/PHYSICS.md, "MINRES after the
//! sweeps", docs/GPU.md, "MINRES"): its stages and its rows.
//!
//! The rows are every constraint of the step, each kind once, in segments: the implicit
//! springs, the distance constraints, the volume constraints (one row per spring or tet,
//! in element order), then one row per global volume constraint. Their entries follow in
//! the same order: two per spring row, four per tet, one per surface node of an object.

use super::stages::stage;
use super::{Access, BufferId, Domain, PassKind, Repeat, Stage, SweepPlan};
use crate::model::ConstraintKind;

/// The segments of MINRES's rows: which constraint kinds have rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MinresRowKinds {
    /// The implicit springs (one row per spring).
    pub springs: bool,
    /// The distance constraints (one row per spring).
    pub distances: bool,
    /// The volume constraints (one row per tet).
    pub volumes: bool,
    /// The global volume constraints (one row per object).
    pub global: bool,
}

impl MinresRowKinds {
    /// The kinds of `sweeps` (each once), with the global volume constraints when `global`.
    pub fn of(sweeps: &[SweepPlan], global: bool) -> Self {
        let has = |kind| sweeps.iter().any(|w| w.kind == kind);
        MinresRowKinds {
            springs: has(ConstraintKind::Spring),
            distances: has(ConstraintKind::Distance),
            volumes: has(ConstraintKind::Volume),
            global,
        }
    }

    /// The name of the `minres_rows` shader variant that builds these rows: a letter per
    /// segment (`s`, `d`, `v`, `g`; `none` for none).
    pub fn variant(&self) -> &'static str {
        const NAMES: [&str; 16] = [
            "none", "s", "d", "sd", "v", "sv", "dv", "sdv", "g", "sg", "dg", "sdg", "vg", "svg",
            "dvg", "sdvg",
        ];
        let bits = [self.springs, self.distances, self.volumes, self.global];
        let index = (bits.iter().enumerate()).fold(0, |a, (k, &on)| a | (usize::from(on) << k));
        NAMES[index]
    }
}

/// MINRES's stages for `minres` iterations after the constraint `sweeps` (none when 0), with
/// rows for the global volume constraints when `global`.
pub(super) fn stages(minres: u32, sweeps: &[SweepPlan], global: bool) -> Vec<Stage> {
    use Access::{Read, ReadWrite, Write};
    use BufferId::*;
    if minres == 0 || sweeps.is_empty() {
        return Vec::new();
    }
    let kinds = MinresRowKinds::of(sweeps, global);
    let after = |kind, domain, bindings| stage(kind, Repeat::AfterIterations, domain, bindings);
    let iteration = |kind, domain, bindings| stage(kind, Repeat::Minres, domain, bindings);
    let mut rows = vec![(Positions, Read), (Velocities, Read), (Forces, Read)];
    if kinds.springs || kinds.distances {
        rows.push((Springs, Read));
    }
    if kinds.springs {
        rows.extend([(SpringDamping, Read), (SpringMultipliers, Read)]);
    }
    if kinds.volumes {
        rows.extend([
            (Tets, Read),
            (RestVolumes, Read),
            (VolumeCompliance, Read),
            (VolumeMultipliers, Read),
        ]);
    }
    if kinds.global {
        rows.extend([
            (GlobalObjects, Read),
            (SurfaceNodes, Read),
            (SurfaceGradients, Read),
            (GlobalState, Read),
        ]);
    }
    rows.extend([
        (MinresTranspose, Read),
        (MinresNodeVectors, Read),
        (MinresGrads, Write),
        (MinresVectors, Write),
        (MinresSums, ReadWrite),
        (MinresState, Write),
    ]);
    let mut finish = vec![(MinresVectors, ReadWrite), (MinresState, Read)];
    if kinds.springs {
        finish.push((SpringMultipliers, ReadWrite));
    }
    if kinds.volumes {
        finish.push((VolumeMultipliers, ReadWrite));
    }
    let (transpose, grads) = ((MinresTranspose, Read), (MinresGrads, Read));
    vec![
        after(
            PassKind::MinresSetup,
            Domain::Nodes,
            vec![
                (Positions, Read),
                (Forces, Read),
                (MinresNodeVectors, Write),
            ],
        ),
        after(PassKind::MinresRows, Domain::Rows, rows),
        // Each of its workgroups a node workgroup, then a row workgroup that ends the last
        // iteration (glsl/passes/minres_nodes.comp).
        iteration(
            PassKind::MinresNodes,
            Domain::Nodes,
            vec![
                transpose,
                grads,
                (MinresSums, ReadWrite),
                (MinresState, ReadWrite),
                (MinresVectors, Read),
                (MinresNodeVectors, ReadWrite),
            ],
        ),
        iteration(
            PassKind::MinresProduct,
            Domain::Rows,
            vec![
                transpose,
                grads,
                (MinresSums, ReadWrite),
                (MinresState, ReadWrite),
                (MinresVectors, ReadWrite),
                (MinresNodeVectors, Read),
            ],
        ),
        after(
            PassKind::MinresNext,
            Domain::Rows,
            vec![
                (MinresSums, ReadWrite),
                (MinresState, ReadWrite),
                (MinresVectors, Read),
            ],
        ),
        after(PassKind::MinresFinish, Domain::Rows, finish),
        after(
            PassKind::MinresForces,
            Domain::Nodes,
            vec![
                (Positions, Read),
                (Velocities, Read),
                (Forces, ReadWrite),
                (MinresTranspose, Read),
                (MinresGrads, Read),
                (MinresVectors, Read),
                (MinresNodeVectors, Read),
            ],
        ),
    ]
}
