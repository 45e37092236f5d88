//! Every pass of a plan binds every buffer its shader declares: a binding the descriptor
//! set lacks is an error the validation layer reports only when it records the dispatch
//! (lavapipe's layer crashed on it).

use super::tests::COUNTS;
use super::*;
use crate::gpu::spirv::Module;
use crate::params::{MassMode, Solver};

/// The plans checked: the default, the volume constraints on both solvers, and the finite
/// elements with and without colliders and grabs.
fn plans() -> Vec<(String, EnginePlan)> {
    let elastic = SimParams {
        method: Method::NeoHookean,
        youngs_modulus: Some(1e6),
        poisson_ratio: Some(0.3),
        mass: MassMode::Density { density: 1000.0 },
        ..SimParams::default()
    };
    let volume = SimParams {
        method: Method::Volume,
        ..SimParams::default()
    };
    let jacobi = SimParams {
        solver: Solver::Jacobi,
        ..volume.clone()
    };
    let nodes = [SweepPlan {
        kind: ConstraintKind::Elastic,
        groups: vec![COUNTS.nodes],
        blocks: None,
    }];
    let sizes = ElasticCounts {
        aggregates: 2,
        members: 8,
        objects: 1,
        index_words: 40,
        scratch_rows: 30,
    };
    let mut out = Vec::new();
    for (colliders, grabbed) in [(0, 0), (1, 0), (0, 2)] {
        let counts = PlanCounts {
            colliders,
            grabbed,
            ..COUNTS
        };
        let plan = |params: &SimParams, sweeps: &[SweepPlan]| {
            EnginePlan::new(counts, params, 64, true, sweeps, None)
        };
        let name = format!("{colliders} colliders, {grabbed} grabbed");
        out.push((
            format!("neo-hookean, {name}"),
            plan(&elastic, &nodes).with_elastic(sizes),
        ));
        out.push((
            format!("volume, {name}"),
            plan(&volume, &tests::volume_sweep()),
        ));
        out.push((
            format!("jacobi, {name}"),
            plan(&jacobi, &tests::volume_sweep()),
        ));
        for method in [Method::Mss, Method::MssNode, Method::Distance] {
            for floor in [false, true] {
                let params = SimParams {
                    method,
                    floor,
                    ..SimParams::default()
                };
                out.push((
                    format!("{method}, floor {floor}, {name}"),
                    plan(&params, &[]),
                ));
            }
        }
        let split = SimParams {
            contact: crate::params::ContactMode::Split,
            ..volume.clone()
        };
        out.push((
            format!("split, {name}"),
            plan(&split, &tests::volume_sweep()),
        ));
        for metrics in [false, true] {
            let clamped = PlanCounts {
                clamps: 1,
                clamped: 2,
                ..counts
            };
            let p = EnginePlan::new(clamped, &volume, 64, metrics, &tests::volume_sweep(), None);
            out.push((format!("clamps, metrics {metrics}, {name}"), p));
        }
    }
    out
}

#[test]
fn every_pass_binds_what_its_shader_declares() {
    let (mut checked, mut missing) = (0, Vec::new());
    for (name, plan) in plans() {
        for pass in &plan.passes {
            let key = pass.shader_key("ext");
            let bytes = crate::shaders::SHADERS
                .iter()
                .find(|(k, _)| *k == key)
                .unwrap_or_else(|| panic!("{name}: no shader `{key}`"))
                .1;
            let bound: Vec<u32> = (pass.stage.bindings.iter())
                .map(|(id, _)| id.binding())
                .collect();
            for (block, number) in Module::parse(bytes).unwrap().block_bindings() {
                if !bound.contains(&number) {
                    missing.push(format!(
                        "{name}: `{}` declares `{block}` (binding {number}), which its stage \
                         does not bind",
                        pass.label()
                    ));
                }
                checked += 1;
            }
        }
    }
    assert!(missing.is_empty(), "{}", missing.join("\n"));
    assert!(checked > 300, "{checked} bindings checked");
}
