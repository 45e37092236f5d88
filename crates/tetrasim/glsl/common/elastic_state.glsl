// The finite elements' conjugate-gradient state (glsl/physics/newton.glsl, ELASTIC_STATE_*)
// as floats and as uints, and a node pass's workgroup partial of a dot product. Include
// after common/bindings.glsl and physics/newton.glsl.
#ifndef COMMON_ELASTIC_STATE_GLSL
#define COMMON_ELASTIC_STATE_GLSL

#include "common/workgroup_sum.glsl"

layout(std430, set = 0, binding = B_ELASTIC_STATE) coherent restrict buffer ElasticStateF { float state[]; };
layout(std430, set = 0, binding = B_ELASTIC_STATE) coherent restrict buffer ElasticStateU { uint state_u[]; };

WORKGROUP_SUM_PAIR(elastic_workgroup_sum, float)

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
