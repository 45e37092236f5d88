//! Blocks of block Gauss-Seidel (physics.md, "Block Gauss-Seidel"): the constraints are cut,
//! in index order (Morton order for meshes `tetprep` writes), into blocks of at most
//! `block_size` constraints touching at most [`MAX_BLOCK_NODES`] nodes. An iteration solves
//! every block at once: within a block the constraints one colour after another (a true
//! Gauss-Seidel sweep, on the GPU one workgroup in shared memory), each against the forces
//! its block's earlier colours left; between blocks Jacobi, with the momentum-conserving
//! scaling counted in blocks (a node's degree is the number of blocks touching it). The
//! sweep is one constraint group whose members are in block order, each block's by colour,
//! so the per-node gather of the colour-group path sums it unchanged.
//!
//! A block needs at least as many colours as its busiest node has constraints, and each
//! colour is a barrier on the GPU: a poorly shaped mesh has nodes with hundreds of tets
//! (the horse's busiest has 305). Nodes with more than [`HUB_DEGREE`] constraints are
//! hubs: the colouring ignores them, so their constraints share colours, and they take
//! the Jacobi scaling (their degree is their constraint count) and keep the iteration's
//! forces within every block (no block's copy of them moves).
//!
//! Both limits are a GPU workgroup's. Blocks larger than
//! [`crate::params::MAX_WORKGROUP_BLOCK`] are thread blocks, which only the `cpu` backends
//! run (a thread solves a block in colour order, from its own copy of the block's nodes):
//! they touch any number of nodes and have no hubs.

use std::collections::HashMap;

use super::{greedy_colours, ConstraintGroups, Csr};

/// The most nodes one block may touch: a block's nodes live in a workgroup's shared memory
/// (48 bytes each, so 320 nodes take 15 KiB of the 16 KiB every Vulkan device has).
pub const MAX_BLOCK_NODES: usize = 320;

/// The most constraints a node may have and still be coloured within its blocks: busier
/// nodes are hubs (see the module).
pub const HUB_DEGREE: u32 = 64;

/// What a block may hold: the limits of a workgroup block, none for a thread block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockLimits {
    /// The most constraints in one block.
    pub constraints: usize,
    /// The most nodes one block may touch.
    pub nodes: usize,
    /// The most constraints a node may have and still be coloured (busier nodes are hubs).
    pub hub_degree: u32,
}

impl BlockLimits {
    /// The limits of blocks of `block_size` constraints (see the module).
    pub fn of(block_size: u32) -> Self {
        let constraints = block_size.max(1) as usize;
        match block_size <= crate::params::MAX_WORKGROUP_BLOCK {
            true => BlockLimits {
                constraints,
                nodes: MAX_BLOCK_NODES,
                hub_degree: HUB_DEGREE,
            },
            false => BlockLimits {
                constraints,
                nodes: usize::MAX,
                hub_degree: u32::MAX,
            },
        }
    }
}

/// A sweep's constraints cut into blocks (the members of its one group, in block order).
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintBlocks {
    /// Row `b`: positions in the group's members of block `b`'s constraints (contiguous,
    /// in colour order), `blocks + 1` offsets.
    pub first: Vec<u32>,
    /// Row `b`: the global indices of block `b`'s nodes, in the order its constraints
    /// first touch them (their local indices).
    pub nodes: Csr,
    /// Per member position: its corners' local indices within its block.
    pub corners: Vec<[u32; 4]>,
    /// Per member position: its colour within its block (a block's constraints of one
    /// colour share no node).
    pub colour: Vec<u32>,
    /// Per block: its number of colours.
    pub colours: Vec<u32>,
    /// Per node: whether it is a hub (more than [`HUB_DEGREE`] constraints; its block
    /// copies never move).
    pub hub: Vec<bool>,
}

impl ConstraintBlocks {
    /// Number of blocks.
    pub fn len(&self) -> usize {
        self.colours.len()
    }

    /// Whether there are none (never for a sweep with constraints).
    pub fn is_empty(&self) -> bool {
        self.colours.is_empty()
    }

    /// The member positions of block `b`.
    pub fn members(&self, b: usize) -> std::ops::Range<usize> {
        self.first[b] as usize..self.first[b + 1] as usize
    }

    /// The most constraints in one block.
    pub fn largest(&self) -> u32 {
        self.first
            .windows(2)
            .map(|w| w[1] - w[0])
            .max()
            .unwrap_or(0)
    }

    /// How far a force moves node `k`'s copy in its block: `a_scale * weight * omega` of
    /// its `factors` (`(a_scale, weight)` per node), 0 for a hub, whose copies stay.
    pub fn copy_scale(&self, k: usize, factors: &[(f64, f64)], omega: f64) -> f64 {
        match self.hub[k] {
            true => 0.0,
            false => factors[k].0 * factors[k].1 * omega,
        }
    }

    /// The most colours in one block.
    pub fn most_colours(&self) -> u32 {
        self.colours.iter().copied().max().unwrap_or(0)
    }
}

/// The cuts of `elements` into workgroup blocks in index order: a block ends at
/// `limits.constraints` or before its nodes would pass `limits.nodes` (without the last
/// cut, `elements.len()`).
fn workgroup_cuts<const K: usize>(elements: &[[u32; K]], limits: &BlockLimits) -> Vec<usize> {
    let mut cuts = vec![0usize];
    let mut local: HashMap<u32, u32> = HashMap::new();
    for (e, element) in elements.iter().enumerate() {
        let fresh = element.iter().filter(|k| !local.contains_key(k)).count();
        let count = e - cuts[cuts.len() - 1];
        let full = count == limits.constraints || local.len() + fresh > limits.nodes;
        if count > 0 && full {
            cuts.push(e);
            local.clear();
        }
        for &k in element {
            let next = local.len() as u32;
            local.entry(k).or_insert(next);
        }
    }
    cuts
}

/// The cuts of `n` constraints into `ceil(n / size)` blocks whose sizes differ by at most
/// one (thread blocks: the threads that own them get equal work; without the last cut,
/// `n`).
fn even_cuts(n: usize, size: usize) -> Vec<usize> {
    let blocks = n.div_ceil(size.max(1)).max(1);
    (0..blocks).map(|b| b * n / blocks).collect()
}

impl ConstraintGroups {
    /// `elements` in blocks of at most `block_size` within [`BlockLimits::of`] it (see the module): one group holding
    /// every constraint in block order, each block's by colour, with each node's degree the
    /// number of blocks touching it; and the blocks. `elements` have at most 4 nodes.
    pub fn blocked<const K: usize>(
        elements: &[[u32; K]],
        nodes: usize,
        block_size: u32,
    ) -> (Self, ConstraintBlocks) {
        let limits = BlockLimits::of(block_size);
        let mut touching = vec![0u32; nodes];
        for element in elements {
            for &k in element {
                touching[k as usize] += 1;
            }
        }
        let hub: Vec<bool> = touching.iter().map(|&d| d > limits.hub_degree).collect();
        // Cut in index order: a workgroup block ends at its most constraints or before its
        // nodes would pass their limit; thread blocks are equal shares.
        let mut cuts = match limits.nodes {
            usize::MAX => even_cuts(elements.len(), limits.constraints),
            _ => workgroup_cuts(elements, &limits),
        };
        cuts.push(elements.len());
        cuts.dedup();
        // A sweep without constraints keeps one empty block: a block pass always has a row.
        if cuts.len() < 2 {
            cuts.push(0);
        }
        let mut members = Vec::with_capacity(elements.len());
        let mut corners = Vec::with_capacity(elements.len());
        let mut colour = Vec::with_capacity(elements.len());
        let mut colours = Vec::new();
        let mut first = vec![0u32];
        let mut block_nodes: Vec<Vec<u32>> = Vec::new();
        for range in cuts.windows(2) {
            let mut index: HashMap<u32, u32> = HashMap::new();
            let mut order: Vec<u32> = Vec::new();
            let local_elements: Vec<[u32; K]> = elements[range[0]..range[1]]
                .iter()
                .map(|element| {
                    element.map(|k| {
                        *index.entry(k).or_insert_with(|| {
                            order.push(k);
                            order.len() as u32 - 1
                        })
                    })
                })
                .collect();
            // Hubs do not constrain the colouring: each constraint sees its own copy.
            let unhubbed: Vec<[u32; K]> = (local_elements.iter().enumerate())
                .map(|(j, element)| {
                    let mut out = *element;
                    for (corner, (slot, &l)) in out.iter_mut().zip(element).enumerate() {
                        if hub[order[l as usize] as usize] {
                            *slot = (order.len() + K * j + corner) as u32;
                        }
                    }
                    out
                })
                .collect();
            let local_colour = greedy_colours(&unhubbed, order.len() + K * unhubbed.len());
            let mut sorted: Vec<usize> = (0..local_elements.len()).collect();
            sorted.sort_by_key(|&j| (local_colour[j], j));
            for j in sorted {
                members.push((range[0] + j) as u32);
                let mut c = [0u32; 4];
                c[..K].copy_from_slice(&local_elements[j]);
                corners.push(c);
                colour.push(local_colour[j]);
            }
            colours.push(local_colour.iter().max().map_or(0, |&c| c + 1));
            first.push(members.len() as u32);
            block_nodes.push(order);
        }
        let mut degree = vec![0u32; nodes];
        for row in &block_nodes {
            for &k in row {
                degree[k as usize] += 1;
            }
        }
        for (d, (&h, &t)) in degree.iter_mut().zip(hub.iter().zip(&touching)) {
            if h {
                *d = t;
            }
        }
        let nodes_csr = Csr::from_pairs(block_nodes.len(), || {
            block_nodes
                .iter()
                .enumerate()
                .flat_map(|(b, row)| row.iter().map(move |&k| (b, k)))
        });
        let groups = ConstraintGroups {
            members: Csr {
                offsets: vec![0, members.len() as u32],
                items: members,
            },
            degree,
            colours: colours.iter().copied().max().unwrap_or(0),
        };
        let blocks = ConstraintBlocks {
            first,
            nodes: nodes_csr,
            corners,
            colour,
            colours,
            hub,
        };
        (groups, blocks)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(n: u32) -> Vec<[u32; 4]> {
        (0..n).map(|i| [i, i + 1, i + 2, i + 3]).collect()
    }

    #[test]
    fn blocks_partition_the_constraints_by_colour() {
        let tets = chain(40);
        let (groups, blocks) = ConstraintGroups::blocked(&tets, 43, 16);
        assert_eq!(groups.len(), 1);
        assert_eq!(blocks.len(), 3, "40 tets in blocks of 16");
        let mut all = groups.members.items.clone();
        all.sort_unstable();
        assert_eq!(all, (0..40).collect::<Vec<_>>());
        for b in 0..blocks.len() {
            let range = blocks.members(b);
            let nodes = blocks.nodes.row(b);
            let colours = &blocks.colour[range.clone()];
            assert!(
                colours.windows(2).all(|w| w[0] <= w[1]),
                "block {b} by colour"
            );
            for p in range.clone() {
                let tet = tets[groups.members.items[p] as usize];
                for (k, &l) in tet.iter().zip(&blocks.corners[p]) {
                    assert_eq!(nodes[l as usize], *k, "local index of member {p}");
                }
                for q in range.clone().filter(|&q| q != p) {
                    let other = tets[groups.members.items[q] as usize];
                    if tet.iter().any(|k| other.contains(k)) {
                        assert_ne!(blocks.colour[p], blocks.colour[q], "{p} and {q}");
                    }
                }
            }
        }
        // Nodes 16..19 are touched by blocks 0 and 1 (tets 13..15 and 16).
        assert_eq!(groups.degree[17], 2);
        assert_eq!(groups.degree[0], 1);
    }

    #[test]
    fn a_block_never_passes_its_node_limit() {
        // Tets with no shared node: 4 nodes each, so 80 tets per block at most.
        let tets: Vec<[u32; 4]> = (0..200u32)
            .map(|i| [4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3])
            .collect();
        let (_, blocks) = ConstraintGroups::blocked(&tets, 800, 1024);
        assert!(blocks.largest() as usize <= MAX_BLOCK_NODES / 4);
        for b in 0..blocks.len() {
            assert!(blocks.nodes.row(b).len() <= MAX_BLOCK_NODES);
        }
        assert_eq!(blocks.most_colours(), 1);
        let (none, empty) = ConstraintGroups::blocked::<4>(&[], 4, 64);
        assert_eq!(
            (none.members.items.len(), empty.len()),
            (0, 1),
            "one empty block"
        );
    }

    #[test]
    fn hubs_are_left_out_of_the_colouring() {
        // A fan of tets around node 0 (and node 1): both are hubs.
        let fan = HUB_DEGREE + 20;
        let tets: Vec<[u32; 4]> = (0..fan).map(|i| [0, 1, 2 + i, 3 + i]).collect();
        let nodes = fan as usize + 3;
        let (groups, blocks) = ConstraintGroups::blocked(&tets, nodes, 1024);
        assert!(blocks.hub[0] && blocks.hub[1] && !blocks.hub[2]);
        assert_eq!(groups.degree[0], fan, "a hub takes the Jacobi scaling");
        assert_eq!(groups.degree[5], 1, "one block touches the rest");
        // Consecutive fan tets share two ring nodes: 2 colours, not one per tet.
        assert_eq!(blocks.most_colours(), 2);
        // The shader's shared memory holds as many nodes as blocks may touch.
        let glsl = include_str!("../../glsl/common/block.glsl");
        assert!(glsl.contains(&format!("#define MAX_BLOCK_NODES {MAX_BLOCK_NODES}\n")));
    }

    #[test]
    fn thread_blocks_have_no_node_limit_and_no_hubs() {
        // The fan of `hubs_are_left_out_of_the_colouring`, and tets with no shared node.
        let fan = HUB_DEGREE + 20;
        let tets: Vec<[u32; 4]> = (0..fan).map(|i| [0, 1, 2 + i, 3 + i]).collect();
        let size = crate::params::MAX_WORKGROUP_BLOCK + 1;
        let (groups, blocks) = ConstraintGroups::blocked(&tets, fan as usize + 3, size);
        assert!(!blocks.hub.iter().any(|&h| h), "no hubs in a thread block");
        assert_eq!((blocks.len(), groups.degree[0]), (1, 1));
        assert_eq!(blocks.most_colours(), fan, "every fan tet its own colour");
        let apart: Vec<[u32; 4]> = (0..2000u32)
            .map(|i| [4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3])
            .collect();
        // 2000 in blocks of at most 1025: two equal shares (a team's threads get equal
        // work), not 1025 and 975.
        let (_, blocks) = ConstraintGroups::blocked(&apart, 8000, size);
        assert_eq!(blocks.len(), 2);
        assert_eq!(
            (blocks.nodes.row(0).len(), blocks.nodes.row(1).len()),
            (4000, 4000)
        );
    }

    #[test]
    fn thread_blocks_are_equal_shares() {
        // 10 in blocks of at most 3: 4 blocks of 2 or 3, never one of 1.
        assert_eq!(even_cuts(10, 3), [0, 2, 5, 7]);
        assert_eq!(even_cuts(134_091, 43_000).len(), 4);
        for (n, size) in [
            (134_091, 43_000),
            (85_638, 43_000),
            (7, 7),
            (7, 100),
            (0, 5),
        ] {
            let mut cuts = even_cuts(n, size);
            cuts.push(n);
            let sizes: Vec<usize> = cuts.windows(2).map(|w| w[1] - w[0]).collect();
            let (least, most) = (sizes.iter().min(), sizes.iter().max());
            assert!(most.unwrap() - least.unwrap() <= 1 && *most.unwrap() <= size);
        }
    }
}
