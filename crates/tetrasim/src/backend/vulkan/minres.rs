//! MINRES's rows' shape on the GPU (docs/GPU.md, "MINRES"), built once on the host: the
//! transpose the node passes gather through, each entry's node, each global row's entries.

use super::plan::MinresCounts;
use crate::model::{GlobalVolume, Model};

/// The `MinresTranspose` buffer of `model`'s rows ([`MinresCounts`]; the global volume
/// constraints' rows from `global`): `N + 1` offsets of each node's items; an item per
/// entry of the node, `(entry, row)`, in entry order (the CPU's `StepRows::each` order, so
/// a node sums its rows in the same order); each entry's node; each global row's first
/// entry and the end (`objects + 1`).
pub(super) fn transpose(
    model: &Model,
    global: Option<&GlobalVolume>,
    m: &MinresCounts,
) -> Vec<u32> {
    // Each entry's node and row, in entry order.
    let mut entries: Vec<(u32, u32)> = Vec::with_capacity(m.entries() as usize);
    let mut row = 0u32;
    for segment in [m.springs, m.distances] {
        for spring in &model.springs[..segment as usize] {
            entries.extend([(spring[0], row), (spring[1], row)]);
            row += 1;
        }
    }
    for tet in &model.tets[..m.tets as usize] {
        entries.extend(tet.iter().map(|&node| (node, row)));
        row += 1;
    }
    let mut object_first = vec![entries.len() as u32];
    if let Some(global) = global.filter(|_| m.objects > 0) {
        for object in &global.objects {
            let first = object.node_first as usize;
            let nodes = &global.nodes[first..first + object.node_count as usize];
            entries.extend(nodes.iter().map(|&node| (node, row)));
            object_first.push(entries.len() as u32);
            row += 1;
        }
    }
    let n = model.node_count();
    let mut offsets = vec![0u32; n + 1];
    for &(node, _) in &entries {
        offsets[node as usize + 1] += 1;
    }
    for i in 0..n {
        offsets[i + 1] += offsets[i];
    }
    let mut items = vec![0u32; 2 * entries.len()];
    let mut next = offsets[..n].to_vec();
    for (e, &(node, row)) in entries.iter().enumerate() {
        let at = next[node as usize] as usize;
        next[node as usize] += 1;
        items[2 * at] = e as u32;
        items[2 * at + 1] = row;
    }
    let mut out = offsets;
    out.extend(items);
    out.extend(entries.iter().map(|&(node, _)| node));
    out.extend(object_first);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backend::vulkan::plan::{GlobalCounts, PlanCounts, GLOBAL_WORKGROUP};
    use crate::mesh::grid::box_tets;
    use crate::model::ModelBuilder;
    use crate::params::{Method, SimParams};
    use crate::schedule::{MinresRowKinds, Schedule, SweepPlan};

    /// A box of two cells' tets with its global volume constraint.
    fn model() -> Model {
        let mesh = box_tets(glam::DVec3::ZERO, 0.5, [2, 1, 1]);
        ModelBuilder::new(&mesh).build().expect("box model")
    }

    #[test]
    fn transpose_lists_every_entry_once_under_its_node_in_entry_order() {
        let model = model();
        let global = GlobalVolume::new(&model);
        let params = SimParams {
            method: Method::Volume,
            minres: 5,
            ..SimParams::default()
        };
        let sweeps: Vec<SweepPlan> = (model.constraint_sweeps(&params).iter())
            .map(SweepPlan::of)
            .collect();
        let schedule = Schedule::new(&params, sweeps, true, false);
        let counts = PlanCounts::of(&model).unwrap();
        let m = MinresCounts::of(
            &schedule,
            counts,
            Some(GlobalCounts::of(&global)),
            GLOBAL_WORKGROUP,
        )
        .expect("minres rows");
        assert_eq!(
            m.kinds,
            MinresRowKinds {
                volumes: true,
                global: true,
                ..Default::default()
            }
        );
        let out = transpose(&model, Some(&global), &m);
        let (n, e) = (model.node_count(), m.entries() as usize);
        assert_eq!(e, 4 * model.tets.len() + global.nodes.len());
        assert_eq!(out.len(), n + 1 + 3 * e + m.objects as usize + 1);
        let (offsets, rest) = out.split_at(n + 1);
        let (items, rest) = rest.split_at(2 * e);
        let (nodes, firsts) = rest.split_at(e);
        assert_eq!(offsets[n] as usize, e);
        let mut seen = vec![0; e];
        for i in 0..n {
            let mine = &items[2 * offsets[i] as usize..2 * offsets[i + 1] as usize];
            let mut last = None;
            for pair in mine.chunks(2) {
                let (entry, row) = (pair[0] as usize, pair[1]);
                assert_eq!(nodes[entry] as usize, i, "entry {entry} is node {i}'s");
                assert!(last < Some(entry), "node {i}'s entries ascend");
                last = Some(entry);
                seen[entry] += 1;
                let expected = match entry < 4 * model.tets.len() {
                    true => (entry / 4) as u32,
                    false => model.tets.len() as u32,
                };
                assert_eq!(row, expected, "entry {entry}'s row");
            }
        }
        assert!(seen.iter().all(|&k| k == 1), "every entry once");
        assert_eq!(firsts, [4 * model.tets.len() as u32, e as u32]);
    }
}
