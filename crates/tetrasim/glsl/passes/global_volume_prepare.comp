#version 460
// Pass `global_volume_prepare`: once per time step, what the iterations of the global
// volume constraints share (physics.md, "One global volume constraint"; positions stay at
// x(t) during the iterations), reduced over the whole GPU: every chunk of an object
// (common/global_chunk.glsl) sums its faces' face_volume (reference point: the object's
// first surface node) and, for its surface nodes, gathers grad_k C_g over their faces
// (stored in SurfaceGradients, w = the node's inverse mass) and sums w_k |grad_k|^2 (its
// share of A); both partials go to its GlobalState entry, which global_volume adds up in a
// fixed order. Mirrors Global::prepare in src/backend/cpu/parallel/mod.rs.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/global_chunk.glsl"
#include "physics/volume.glsl"

WORKGROUP_SUM_PAIR(workgroup_sum2, float)

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_GLOBAL_OBJECTS) readonly restrict buffer GlobalObjects { GlobalObject objects[]; };
layout(std430, set = 0, binding = B_SURFACE_NODES) readonly restrict buffer SurfaceNodes { uint surface_nodes[]; };
layout(std430, set = 0, binding = B_SURFACE_FACES) readonly restrict buffer SurfaceFaces { uvec4 surface_faces[]; };
layout(std430, set = 0, binding = B_NODE_FACE_OFFSETS) readonly restrict buffer NodeFaceOffsets { uint node_face_offsets[]; };
layout(std430, set = 0, binding = B_NODE_FACE_ITEMS) readonly restrict buffer NodeFaceItems { uint node_face_items[]; };
layout(std430, set = 0, binding = B_SURFACE_GRADIENTS) writeonly restrict buffer SurfaceGradients { vec4 surface_gradients[]; };
layout(std430, set = 0, binding = B_GLOBAL_STATE) writeonly restrict buffer GlobalState { vec4 global_state[]; };

// grad_k C_g of the surface node at position k of surface_nodes, measured from o.
vec3 surface_gradient(uint k, vec3 o) {
    vec3 g = vec3(0.0);
    uint end = node_face_offsets[k + 1u];
    for (uint e = node_face_offsets[k]; e < end; ++e) {
        uint item = node_face_items[e];
        uvec4 face = surface_faces[item / 3u];
        uint corner = item % 3u;
        uint b = corner == 0u ? face.y : (corner == 1u ? face.z : face.x);
        uint c = corner == 0u ? face.z : (corner == 1u ? face.x : face.y);
        g += face_volume_gradient(positions[b].xyz, positions[c].xyz, o);
    }
    return g;
}

void main() {
    GlobalObject object = objects[global_object_index()];
    uint k = global_chunk_item();
    vec3 o = positions[surface_nodes[object.node_first]].xyz;
    float c = 0.0;
    if (k < object.face_count) {
        uvec4 face = surface_faces[object.face_first + k];
        c = face_volume(positions[face.x].xyz, positions[face.y].xyz, positions[face.z].xyz, o);
    }
    float a = 0.0;
    if (k < object.node_count) {
        uint at = object.node_first + k;
        vec3 g = surface_gradient(at, o);
        float w = positions[surface_nodes[at]].w;
        a = w * dot(g, g);
        surface_gradients[at] = vec4(g, w);
    }
    workgroup_sum2(c, a);
    vec2 sums = vec2(c, a);
    if (gl_LocalInvocationID.x == 0u) {
        global_state[gl_WorkGroupID.x] = vec4(sums, 0.0, 0.0);
    }
}
