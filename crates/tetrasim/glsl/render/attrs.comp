#version 460
// Render pass `attrs`: per surface node, the smooth normal (area-weighted sum of the adjacent
// surface triangles' normals) and the colour-mode scalar: V/V0 averaged over the adjacent tets
// (MODE_VOLUME) or the spring strain (l - l0) / l0 averaged over the adjacent springs
// (MODE_STRAIN). Gathers through CSR adjacency, so no atomics; one invocation per surface node.
#include "render/common.glsl"
#include "physics/volume.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = R_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = R_ATTRS) writeonly restrict buffer Attrs { vec4 attrs[]; };
layout(std430, set = 0, binding = R_SURFACE_NODES) readonly restrict buffer SurfaceNodes { uint surface_nodes[]; };
layout(std430, set = 0, binding = R_FACE_OFFSETS) readonly restrict buffer FaceOffsets { uint face_offsets[]; };
layout(std430, set = 0, binding = R_FACE_ITEMS) readonly restrict buffer FaceItems { uint face_items[]; };
layout(std430, set = 0, binding = R_TRIANGLES) readonly restrict buffer Triangles { uint triangles[]; };
layout(std430, set = 0, binding = R_TET_OFFSETS) readonly restrict buffer TetOffsets { uint tet_offsets[]; };
layout(std430, set = 0, binding = R_TET_ITEMS) readonly restrict buffer TetItems { uint tet_items[]; };
layout(std430, set = 0, binding = R_TETS) readonly restrict buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = R_REST_VOLUMES) readonly restrict buffer RestVolumes { float rest_volumes[]; };
layout(std430, set = 0, binding = R_SPRING_OFFSETS) readonly restrict buffer SpringOffsets { uint spring_offsets[]; };
layout(std430, set = 0, binding = R_SPRING_ITEMS) readonly restrict buffer SpringItems { uint spring_items[]; };
// The simulation's springs (GpuSpring: a, b, rest length bits, stiffness bits).
layout(std430, set = 0, binding = R_SPRINGS) readonly restrict buffer Springs { uvec4 springs[]; };

vec3 p(uint node) {
    return positions[node].xyz;
}

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= surface_nodes.length()) {
        return;
    }
    uint i = surface_nodes[k];
    vec3 n = vec3(0.0);
    for (uint e = face_offsets[i]; e < face_offsets[i + 1u]; ++e) {
        uint f = 3u * face_items[e];
        vec3 a = p(triangles[f]);
        n += cross(p(triangles[f + 1u]) - a, p(triangles[f + 2u]) - a);
    }
    float len = length(n);
    n = len > 0.0 ? n / len : vec3(0.0, 1.0, 0.0);

    float s = 0.0;
    if (pc.mode == MODE_VOLUME) {
        uint begin = tet_offsets[i];
        uint end = tet_offsets[i + 1u];
        for (uint e = begin; e < end; ++e) {
            uint t = tet_items[e];
            uvec4 tet = tets[t];
            s += tet_volume(p(tet.x), p(tet.y), p(tet.z), p(tet.w)) / rest_volumes[t];
        }
        s = end > begin ? s / float(end - begin) : 1.0;
    } else if (pc.mode == MODE_STRAIN) {
        uint begin = spring_offsets[i];
        uint end = spring_offsets[i + 1u];
        for (uint e = begin; e < end; ++e) {
            uvec4 spring = springs[spring_items[e]];
            float rest = uintBitsToFloat(spring.z);
            s += (distance(p(spring.x), p(spring.y)) - rest) / rest;
        }
        s = end > begin ? s / float(end - begin) : 0.0;
    }
    attrs[i] = vec4(n, s);
}
