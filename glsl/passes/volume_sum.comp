#version 460
// Pass `volume_sum`: the volume metric (physics.md, "Metrics") on the GPU. One invocation
// per tet computes its signed volume; each workgroup reduces its volumes and inverted count
// (signed volume <= 0) in shared memory and writes one VolumePartial. The host reads the
// few partials and sums them in f64. The workgroup size must be a power of two.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/volume.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_VOLUME_PARTIALS) writeonly restrict buffer Partials { VolumePartial partials[]; };

shared float s_volume[gl_WorkGroupSize.x];
shared uint s_inverted[gl_WorkGroupSize.x];

void main() {
    uint t = gl_GlobalInvocationID.x;
    uint l = gl_LocalInvocationID.x;
    float v = 0.0;
    uint inverted = 0u;
    if (t < pc.tet_count) {
        uvec4 tet = tets[t];
        v = tet_volume(positions[tet.x].xyz, positions[tet.y].xyz, positions[tet.z].xyz, positions[tet.w].xyz);
        inverted = v <= 0.0 ? 1u : 0u;
    }
    s_volume[l] = v;
    s_inverted[l] = inverted;
    barrier();
    for (uint stride = gl_WorkGroupSize.x / 2u; stride > 0u; stride >>= 1u) {
        if (l < stride) {
            s_volume[l] += s_volume[l + stride];
            s_inverted[l] += s_inverted[l + stride];
        }
        barrier();
    }
    if (l == 0u) {
        partials[gl_WorkGroupID.x] = VolumePartial(s_volume[0], s_inverted[0]);
    }
}
