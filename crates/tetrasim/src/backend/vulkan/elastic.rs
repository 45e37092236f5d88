//! The finite elements' data on the GPU (docs/GPU.md, "Finite elements on the GPU"),
//! prepared once on the host from the problem: each tet's constants, each node's tets, the
//! coarse level's aggregates and assembly index, the objects the rigid-part correction
//! works on, and the node planes' fixed entries.

use super::plan::{ElasticCounts, ELASTIC_PLANES};
use super::CoarseIndex;
use crate::gpu::layout::vec4;
use crate::problem::Problem;
use crate::schedule::family::ElasticNodes;
use crate::schedule::BufferId;
use glam::DVec3;

/// What the finite elements' buffers start with.
pub struct ElasticData {
    /// The sizes the plan follows.
    pub counts: ElasticCounts,
    /// Per tet, 4 vec4s (`elastic_tet_at`, common/elastic_tets.glsl): its shape gradients'
    /// rows with its rest volume, mu and lambda in w; then alpha and its first node's
    /// damping time.
    pub tets: Vec<[f32; 4]>,
    /// The node -> tet corners CSR's offsets (N + 1)...
    pub node_tet_offsets: Vec<u32>,
    /// ... and items (`4 t + corner`).
    pub node_tet_items: Vec<u32>,
    /// The node planes (`ElasticNodes`), zero but for each node's reach in its last plane.
    pub nodes: Vec<[f32; 4]>,
    /// `COARSE_AGGREGATES`: the aggregates' member offsets (A + 1), their members, each
    /// node's aggregate.
    pub aggregates: Vec<u32>,
    /// `COARSE_INDEX` ([`CoarseIndex::words`]).
    pub index: Vec<u32>,
    /// `ElasticObjects`: per object its first node, end, whether it is free, then words the
    /// passes fill.
    pub objects: Vec<u32>,
}

impl ElasticData {
    /// The finite elements' data of `problem`.
    pub fn prepare(problem: &Problem) -> Self {
        let model = &problem.model;
        let nodes = ElasticNodes::<f64>::prepare(problem);
        let n = model.node_count();
        let tets = (nodes.tets.iter().zip(&model.tets))
            .flat_map(|(e, tet)| {
                let g = |k: usize| DVec3::from_array(e.shape[k]);
                let beta = nodes.damping[tet[0] as usize].max(0.0);
                [
                    vec4(g(0), e.volume),
                    vec4(g(1), e.mu),
                    vec4(g(2), e.lambda),
                    [e.alpha as f32, beta as f32, 0.0, 0.0],
                ]
            })
            .collect();
        let mut planes = vec![[0.0f32; 4]; ELASTIC_PLANES as usize * n];
        let last = (ELASTIC_PLANES as usize - 1) * n;
        for (i, &reach) in nodes.reach.iter().enumerate() {
            planes[last + i][0] = reach as f32;
        }
        let a = &nodes.aggregates;
        let mut aggregates = vec![0u32];
        for members in &a.members {
            aggregates.push(aggregates.last().copied().unwrap_or(0) + members.len() as u32);
        }
        aggregates.extend(a.members.iter().flatten());
        aggregates.extend(&a.of);
        let index = CoarseIndex::of(a, model);
        let objects: Vec<u32> = (model.objects.windows(2))
            .flat_map(|w| {
                let free = model.inv_mass[w[0] as usize..w[1] as usize]
                    .iter()
                    .all(|&m| m > 0.0);
                let mut words = [0u32; 16];
                words[..3].copy_from_slice(&[w[0], w[1], u32::from(free)]);
                words
            })
            .collect();
        ElasticData {
            counts: ElasticCounts::of(a, &index, model.objects.len().saturating_sub(1)),
            tets,
            node_tet_offsets: nodes.node_tets.offsets.clone(),
            node_tet_items: nodes.node_tets.items.clone(),
            nodes: planes,
            aggregates,
            index: index.words(),
            objects,
        }
    }
}

/// The finite elements' buffers (the plan builds them all, or none).
pub(crate) const BUFFERS: [BufferId; 14] = [
    BufferId::ElasticTets,
    BufferId::NodeTetOffsets,
    BufferId::NodeTetItems,
    BufferId::ElasticLinear,
    BufferId::ElasticCorners,
    BufferId::ElasticNodes,
    BufferId::ElasticState,
    BufferId::CoarseMatrix,
    BufferId::CoarseVector,
    BufferId::CoarseAggregates,
    BufferId::CoarseModes,
    BufferId::CoarseIndex,
    BufferId::CoarseScratch,
    BufferId::ElasticObjects,
];

impl ElasticData {
    /// The buffers that start with data, and that data; the others start zeroed (the
    /// state's step counter at 0: the first step builds the coarse level).
    pub fn uploads(&self) -> [(BufferId, &[u8]); 7] {
        [
            (BufferId::ElasticTets, bytemuck::cast_slice(&self.tets)),
            (BufferId::NodeTetOffsets, u32s(&self.node_tet_offsets)),
            (BufferId::NodeTetItems, u32s(&self.node_tet_items)),
            (BufferId::ElasticNodes, bytemuck::cast_slice(&self.nodes)),
            (BufferId::CoarseAggregates, u32s(&self.aggregates)),
            (BufferId::CoarseIndex, u32s(&self.index)),
            (BufferId::ElasticObjects, u32s(&self.objects)),
        ]
    }
}

fn u32s(v: &[u32]) -> &[u8] {
    bytemuck::cast_slice(v)
}
