//! The finite elements' coarse level's assembly on the GPU, indexed once on the host
//! (docs/GPU.md, "Finite elements on the GPU"): `P^T A P` is assembled every
//! `COARSE_REBUILD_STEPS` steps from one 6 x 6 block per item, an item being a tet's corner
//! seen from one of the aggregates of its corners (the corner's modes against that
//! aggregate's) or a free node of an aggregate (its own block); each (column aggregate, row
//! aggregate) block of the matrix then adds its items in a fixed order, so the assembly
//! needs no atomics and gives the same bits every run.

use crate::model::{Csr, Model};
use crate::physics::{Aggregates, NO_AGGREGATE};

/// Which items make each block of the coarse matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct CoarseIndex {
    /// Per tet: its items, `aggregate << 2 | corner` (the column aggregate and the corner),
    /// the column aggregates in the order their first corner comes; an item's scratch row
    /// is its index in `items`.
    pub tets: Csr,
    /// Per block `a * A + b` (column aggregate `a`, row aggregate `b`): the scratch rows of
    /// its items, tets' first, then (on the diagonal) its nodes', at `tets.items.len()` plus
    /// the node's index in the aggregates' member lists.
    pub blocks: Csr,
}

impl CoarseIndex {
    /// The index of `aggregates` over `model`'s tets.
    pub fn of(aggregates: &Aggregates, model: &Model) -> Self {
        let of = |k: u32| aggregates.of[k as usize];
        let tet_items = |t: usize| {
            let tet = model.tets[t];
            let mut items = Vec::new();
            for (c, &k) in tet.iter().enumerate() {
                let a = of(k);
                if a == NO_AGGREGATE || tet[..c].iter().any(|&j| of(j) == a) {
                    continue;
                }
                for (j, &corner) in tet.iter().enumerate() {
                    if of(corner) != NO_AGGREGATE {
                        items.push(a << 2 | j as u32);
                    }
                }
            }
            items
        };
        let tets = Csr::from_pairs(model.tets.len(), || {
            (0..model.tets.len()).flat_map(move |t| tet_items(t).into_iter().map(move |i| (t, i)))
        });
        let count = aggregates.len();
        let node_first = tets.items.len() as u32;
        let block_pairs = || {
            let tet_rows = (0..model.tets.len()).flat_map(|t| {
                let tets = &tets;
                let first = tets.offsets[t];
                (tets.row(t).iter().enumerate()).map(move |(e, &item)| {
                    let (a, j) = (item >> 2, item & 3);
                    let b = of(model.tets[t][j as usize]);
                    ((a * count as u32 + b) as usize, first + e as u32)
                })
            });
            let mut member = node_first;
            let node_rows = (aggregates.members.iter().enumerate()).flat_map(move |(a, nodes)| {
                let first = member;
                member += nodes.len() as u32;
                (0..nodes.len() as u32).map(move |k| (a * count + a, first + k))
            });
            tet_rows.chain(node_rows)
        };
        let blocks = Csr::from_pairs(count * count, block_pairs);
        CoarseIndex { tets, blocks }
    }

    /// Its words as `COARSE_INDEX` holds them: the tets' offsets (T + 1) and items, then
    /// the blocks' offsets (A^2 + 1) and items.
    pub fn words(&self) -> Vec<u32> {
        let mut out = self.tets.offsets.clone();
        out.extend(&self.tets.items);
        out.extend(&self.blocks.offsets);
        out.extend(&self.blocks.items);
        out
    }

    /// Scratch rows (of 36 floats): the tets' items, then the aggregates' nodes.
    pub fn scratch_rows(&self, aggregates: &Aggregates) -> usize {
        self.tets.items.len() + aggregates.members.iter().map(Vec::len).sum::<usize>()
    }
}
