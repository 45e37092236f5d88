#version 460
// Pass `volume_sum`: the volume metrics (physics.md, "Metrics" and "Local volume error") on
// the GPU. One invocation per tet computes its signed volume; each workgroup reduces its
// volumes, inverted count (signed volume <= 0) and local error |V - V0| in shared memory
// and writes one VolumePartial. The host reads the
// few partials and sums them in f64. The workgroup size must be a power of two.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/volume.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = B_REST_VOLUMES) readonly restrict buffer RestVolumes { float rest_volumes[]; };
layout(std430, set = 0, binding = B_VOLUME_PARTIALS) writeonly restrict buffer Partials { VolumePartial partials[]; };

shared float s_volume[gl_WorkGroupSize.x];
shared uint s_inverted[gl_WorkGroupSize.x];
shared float s_error[gl_WorkGroupSize.x];

void main() {
    uint t = gl_GlobalInvocationID.x;
    uint l = gl_LocalInvocationID.x;
    float v = 0.0;
    uint inverted = 0u;
    float error = 0.0;
    if (t < pc.tet_count) {
        uvec4 tet = tets[t];
        v = tet_volume(positions[tet.x].xyz, positions[tet.y].xyz, positions[tet.z].xyz, positions[tet.w].xyz);
        inverted = v <= 0.0 ? 1u : 0u;
        error = abs(v - rest_volumes[t]);
    }
    s_volume[l] = v;
    s_inverted[l] = inverted;
    s_error[l] = error;
    barrier();
    for (uint stride = gl_WorkGroupSize.x / 2u; stride > 0u; stride >>= 1u) {
        if (l < stride) {
            s_volume[l] += s_volume[l + stride];
            s_inverted[l] += s_inverted[l + stride];
            s_error[l] += s_error[l + stride];
        }
        barrier();
    }
    if (l == 0u) {
        partials[gl_WorkGroupID.x] = VolumePartial(s_volume[0], s_inverted[0], s_error[0], 0u);
    }
}
