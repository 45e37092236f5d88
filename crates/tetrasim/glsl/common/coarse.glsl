// The finite elements' coarse level (physics.md, fourth edition; src/physics/coarse.rs):
// the aggregates' members and each node's aggregate (CoarseAggregates: A + 1 offsets, the
// members, then N entries), and each aggregate's centre and size (CoarseModes). Include
// after common/bindings.glsl; a pass declares AGGREGATES (specialisation constant 2) first.
#ifndef COMMON_COARSE_GLSL
#define COMMON_COARSE_GLSL

#define NO_AGGREGATE 0xffffffffu

layout(std430, set = 0, binding = B_COARSE_AGGREGATES) readonly restrict buffer CoarseAggregates { uint aggregates[]; };
layout(std430, set = 0, binding = B_COARSE_MODES) restrict buffer CoarseModes { vec4 modes[]; };

uint aggregate_first(uint a) {
    return aggregates[a];
}

uint aggregate_end(uint a) {
    return aggregates[a + 1u];
}

uint aggregate_member(uint k) {
    return aggregates[AGGREGATES + 1u + k];
}

// Node i's aggregate (NO_AGGREGATE: none), `members` being the aggregates' member count.
uint aggregate_of(uint i) {
    return aggregates[AGGREGATES + 1u + aggregates[AGGREGATES] + i];
}

#endif
