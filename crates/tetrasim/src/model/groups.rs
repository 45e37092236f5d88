//! Constraint groups for Gauss-Seidel by colour groups (physics.md, "Faster convergence at
//! equal cost"): the constraints are coloured greedily so that no two of one colour share a
//! node, and the colours are merged into at most `groups` groups of similar size. Groups are
//! solved one after another, each against the forces the previous ones left; within a group
//! constraints are solved together (Jacobi), with the degree of the momentum-conserving
//! scaling counted within the group. One group holding every constraint is the paper's
//! Jacobi sweep.

use super::Csr;

/// Constraints of one kind split into groups solved in sequence.
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintGroups {
    /// Row `g` lists the constraints of group `g`, ascending.
    pub members: Csr,
    /// `degree[g * nodes + k]`: the number of group `g`'s constraints touching node `k`.
    pub degree: Vec<u32>,
    /// Number of colours found before merging (1 for a single Jacobi group).
    pub colours: u32,
}

impl ConstraintGroups {
    /// Number of groups.
    pub fn len(&self) -> usize {
        self.members.offsets.len() - 1
    }

    /// Whether there are no groups (never, for a built model).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The constraints of group `g`.
    pub fn group(&self, g: usize) -> &[u32] {
        self.members.row(g)
    }

    /// Constraints per group.
    pub fn sizes(&self) -> Vec<u32> {
        self.members
            .offsets
            .windows(2)
            .map(|w| w[1] - w[0])
            .collect()
    }

    /// Node degrees within group `g`, one per node.
    pub fn group_degree(&self, g: usize, nodes: usize) -> &[u32] {
        &self.degree[g * nodes..(g + 1) * nodes]
    }

    /// Node -> slot adjacency per group: row `g * nodes + k` lists `K * p + corner` for each
    /// position `p` in [`Self::members`]' items whose constraint touches node `k` at
    /// `corner` (a slot of a per-position result array, as the `cpu` and `vulkan` gathers
    /// use).
    pub fn node_slots<const K: usize>(&self, elements: &[[u32; K]], nodes: usize) -> Csr {
        Csr::from_pairs(self.len() * nodes, || {
            (0..self.len()).flat_map(move |g| {
                let first = self.members.offsets[g] as usize;
                self.group(g).iter().enumerate().flat_map(move |(p, &e)| {
                    elements[e as usize]
                        .iter()
                        .enumerate()
                        .map(move |(corner, &k)| {
                            (g * nodes + k as usize, (K * (first + p) + corner) as u32)
                        })
                })
            })
        })
    }

    /// Every constraint in one group: the Jacobi sweep.
    pub fn single<const K: usize>(elements: &[[u32; K]], nodes: usize) -> Self {
        let members = Csr {
            offsets: vec![0, elements.len() as u32],
            items: (0..elements.len() as u32).collect(),
        };
        Self::with_members(elements, nodes, members, 1)
    }

    /// Colours `elements` greedily (in index order, the smallest colour none of its nodes
    /// has yet) and merges the colours into at most `groups` groups: largest colour first,
    /// each into the group with the fewest constraints so far.
    pub fn coloured<const K: usize>(elements: &[[u32; K]], nodes: usize, groups: u32) -> Self {
        let colour = greedy_colours(elements, nodes);
        let colours = colour.iter().max().map_or(0, |&c| c + 1);
        let mut size = vec![0u32; colours as usize];
        for &c in &colour {
            size[c as usize] += 1;
        }
        let groups = groups.clamp(1, colours.max(1));
        let mut by_size: Vec<u32> = (0..colours).collect();
        by_size.sort_by_key(|&c| (std::cmp::Reverse(size[c as usize]), c));
        let mut group_of_colour = vec![0u32; colours as usize];
        let mut load = vec![0u32; groups as usize];
        for c in by_size {
            let g = (0..groups)
                .min_by_key(|&g| (load[g as usize], g))
                .unwrap_or(0);
            group_of_colour[c as usize] = g;
            load[g as usize] += size[c as usize];
        }
        let members = Csr::from_pairs(groups as usize, || {
            colour
                .iter()
                .enumerate()
                .map(|(e, &c)| (group_of_colour[c as usize] as usize, e as u32))
        });
        Self::with_members(elements, nodes, members, colours)
    }

    fn with_members<const K: usize>(
        elements: &[[u32; K]],
        nodes: usize,
        members: Csr,
        colours: u32,
    ) -> Self {
        let groups = members.offsets.len() - 1;
        let mut degree = vec![0u32; groups * nodes];
        for g in 0..groups {
            for &e in members.row(g) {
                for &k in &elements[e as usize] {
                    degree[g * nodes + k as usize] += 1;
                }
            }
        }
        ConstraintGroups {
            members,
            degree,
            colours,
        }
    }
}

/// A colour per element such that elements sharing a node differ; greedy in index order.
pub fn greedy_colours<const K: usize>(elements: &[[u32; K]], nodes: usize) -> Vec<u32> {
    let mut node_colours: Vec<Vec<u32>> = vec![Vec::new(); nodes];
    let mut taken: Vec<usize> = Vec::new();
    let mut colour = Vec::with_capacity(elements.len());
    for (e, element) in elements.iter().enumerate() {
        let stamp = e + 1;
        for &k in element {
            for &c in &node_colours[k as usize] {
                if taken.len() <= c as usize {
                    taken.resize(c as usize + 1, 0);
                }
                taken[c as usize] = stamp;
            }
        }
        let c = (0..).find(|&c| taken.get(c) != Some(&stamp)).unwrap_or(0) as u32;
        for &k in element {
            node_colours[k as usize].push(c);
        }
        colour.push(c);
    }
    colour
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_cubes() -> Vec<[u32; 4]> {
        // A strip of tets sharing nodes in a chain.
        (0..40u32).map(|i| [i, i + 1, i + 2, i + 3]).collect()
    }

    #[test]
    fn colours_never_share_a_node() {
        let tets = two_cubes();
        let colour = greedy_colours(&tets, 43);
        for (a, ta) in tets.iter().enumerate() {
            for (b, tb) in tets.iter().enumerate().skip(a + 1) {
                if ta.iter().any(|k| tb.contains(k)) {
                    assert_ne!(colour[a], colour[b], "tets {a} and {b} share a node");
                }
            }
        }
        assert_eq!(
            colour.iter().max(),
            Some(&3),
            "a chain of 4-node windows needs 4"
        );
    }

    #[test]
    fn groups_partition_constraints_and_count_degrees() {
        let tets = two_cubes();
        for groups in [1, 2, 3, 4, 10] {
            let g = ConstraintGroups::coloured(&tets, 43, groups);
            assert_eq!(g.len(), groups.min(4) as usize);
            let mut all: Vec<u32> = g.members.items.clone();
            all.sort_unstable();
            assert_eq!(all, (0..40).collect::<Vec<_>>());
            for k in 0..43 {
                let total: u32 = (0..g.len()).map(|i| g.group_degree(i, 43)[k]).sum();
                let touching = tets.iter().filter(|t| t.contains(&(k as u32))).count();
                assert_eq!(total as usize, touching, "node {k}");
            }
        }
        let g = ConstraintGroups::coloured(&tets, 43, 3);
        let slots = g.node_slots(&tets, 43);
        for group in 0..g.len() {
            for k in 0..43 {
                for &slot in slots.row(group * 43 + k) {
                    let (p, corner) = (slot as usize / 4, slot as usize % 4);
                    assert!(g.members.offsets[group] as usize <= p);
                    assert!(p < g.members.offsets[group + 1] as usize);
                    assert_eq!(tets[g.members.items[p] as usize][corner], k as u32);
                }
                assert_eq!(
                    slots.row(group * 43 + k).len() as u32,
                    g.group_degree(group, 43)[k]
                );
            }
        }
        let full = ConstraintGroups::coloured(&tets, 43, 100);
        assert!(
            full.degree.iter().all(|&d| d <= 1),
            "full colouring: degree 0 or 1"
        );
    }
}
