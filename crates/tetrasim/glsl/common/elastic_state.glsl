// The finite elements' conjugate-gradient state (glsl/physics/newton.glsl, ELASTIC_STATE_*)
// as floats and as uints, and a node pass's workgroup partial of a dot product. Include
// after common/bindings.glsl and physics/newton.glsl.
#ifndef COMMON_ELASTIC_STATE_GLSL
#define COMMON_ELASTIC_STATE_GLSL

#include "common/workgroup_sum.glsl"

layout(std430, set = 0, binding = B_ELASTIC_STATE) coherent restrict buffer ElasticStateF { float state[]; };
layout(std430, set = 0, binding = B_ELASTIC_STATE) coherent restrict buffer ElasticStateU { uint state_u[]; };

WORKGROUP_SUM_PAIR(elastic_workgroup_sum, float)

// COARSE_REBUILD_STEPS in src/physics/coarse.rs.
#define COARSE_REBUILD_STEPS 10u

// Whether this iteration (pc.iteration) begins a Newton step: the step's first, or one
// after a step beyond the linearisation's trust (`elastic_backtrack`, `elastic`), which
// `elastic_begin` then clears. The linearisation's passes run only then.
bool elastic_linearises() {
    return pc.iteration == 0u || state_u[ELASTIC_STATE_RELINEARISE] != 0u;
}

// Whether the preconditioner runs this iteration: at a linearisation, or while the
// conjugate gradients go on.
bool elastic_preconditions() {
    return elastic_linearises() || state_u[ELASTIC_STATE_DONE] == 0u;
}

// Whether the step builds the coarse level anew (`rebuilds` in src/physics/coarse.rs): at
// its first iteration, every COARSE_REBUILD_STEPS steps from the backend's first.
bool coarse_rebuilds() {
    return pc.iteration == 0u && state_u[ELASTIC_STATE_STEP] % COARSE_REBUILD_STEPS == 0u;
}

// Every invocation of a node pass calls it (in uniform control flow) with its node's share
// of a dot product; the workgroup's sum is stored as its partial.
void store_partial(float value) {
    float unused = 0.0;
    elastic_workgroup_sum(value, unused);
    if (gl_LocalInvocationID.x == 0u) {
        state[ELASTIC_STATE_PARTIALS + gl_WorkGroupID.x] = value;
    }
}

#endif
