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

// Mode l (0..6) of an aggregate at a node rho from its centre per unit of its size
// (CoarseSpace::modes): the translations, then the rotations e_l x rho.
vec3 coarse_mode(uint l, vec3 rho) {
    vec3 e = vec3(l % 3u == 0u ? 1.0 : 0.0, l % 3u == 1u ? 1.0 : 0.0, l % 3u == 2u ? 1.0 : 0.0);
    return l < 3u ? e : cross(e, rho);
}

// Where x lies from aggregate a's centre, per unit of its size.
vec3 coarse_rho(uint a, vec3 x) {
    vec4 centre = modes[a];
    return (x - centre.xyz) / centre.w;
}

#endif
