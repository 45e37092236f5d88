#version 460
// Pass `global_volume`: one iteration of the global volume constraints (physics.md, "One
// global volume constraint"), after the iteration's local constraint groups. One workgroup
// per object: C_g = sum of its boundary faces' face_volume - V0 and, per surface node, the
// gradient gathered over its faces; A = sum_k w_k |grad_k|^2 and B = C_g / dt^2 +
// sum_k grad_k . (v_k / dt + w_k F_k) are reduced in shared memory in a fixed order
// (bit-identical reruns), then every surface node gets F -= lambda grad_k and its floor
// contact is solved again. Mirrors the global solve of src/cpu (reference and parallel).
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "physics/volume.glsl"
#include "physics/implicit.glsl"
#include "physics/floor.glsl"

// 1 when the scene has a floor (specialisation constant 1, as in constraint_apply).
layout(constant_id = 1) const uint FLOOR = 1u;

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_GLOBAL_OBJECTS) readonly restrict buffer GlobalObjects { GlobalObject objects[]; };
layout(std430, set = 0, binding = B_SURFACE_NODES) readonly restrict buffer SurfaceNodes { uint surface_nodes[]; };
layout(std430, set = 0, binding = B_SURFACE_FACES) readonly restrict buffer SurfaceFaces { uvec4 surface_faces[]; };
layout(std430, set = 0, binding = B_NODE_FACE_OFFSETS) readonly restrict buffer NodeFaceOffsets { uint node_face_offsets[]; };
layout(std430, set = 0, binding = B_NODE_FACE_ITEMS) readonly restrict buffer NodeFaceItems { uint node_face_items[]; };

shared float s_c[gl_WorkGroupSize.x];
shared float s_a[gl_WorkGroupSize.x];
shared float s_b[gl_WorkGroupSize.x];

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
    GlobalObject object = objects[gl_WorkGroupID.x];
    uint l = gl_LocalInvocationID.x;
    uint stride = gl_WorkGroupSize.x;
    vec3 o = positions[surface_nodes[object.node_first]].xyz;
    float c = 0.0;
    for (uint f = l; f < object.face_count; f += stride) {
        uvec4 face = surface_faces[object.face_first + f];
        c += face_volume(positions[face.x].xyz, positions[face.y].xyz, positions[face.z].xyz, o);
    }
    float a = 0.0;
    float b = 0.0;
    for (uint k = l; k < object.node_count; k += stride) {
        uint node = surface_nodes[object.node_first + k];
        vec3 g = surface_gradient(object.node_first + k, o);
        implicit_accumulate(a, b, g, positions[node].w, 1.0, velocities[node].xyz, forces[node].xyz, pc.dt);
    }
    s_c[l] = c;
    s_a[l] = a;
    s_b[l] = b;
    barrier();
    for (uint half_size = stride / 2u; half_size > 0u; half_size >>= 1u) {
        if (l < half_size) {
            s_c[l] += s_c[l + half_size];
            s_a[l] += s_a[l + half_size];
            s_b[l] += s_b[l + half_size];
        }
        barrier();
    }
    float lambda = implicit_lambda(s_c[0] - object.rest_volume, s_a[0], s_b[0], pc.dt, pc.epsilon);
    for (uint k = l; k < object.node_count; k += stride) {
        uint node = surface_nodes[object.node_first + k];
        vec4 f = forces[node];
        f.xyz -= lambda * surface_gradient(object.node_first + k, o);
        if (FLOOR != 0u && pc.floor_on != 0u) {
            vec4 p = positions[node];
            f = floor_solve(f, p.y, velocities[node].y, p.w, pc.dt);
        }
        forces[node] = f;
    }
}
