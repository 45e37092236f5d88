#version 460
// Pass `contact_find`: body contact's narrow phase, once per step (BodyContact::find in
// src/contact/find.rs). Every surface node at its predicted position p = x + dt v looks
// through the triangles of its cell's hash bucket (contact_fill; a bucket shared with other
// cells only adds triangles too far to count) for the nearest eligible one (another
// object's, or with self-contact its own when the node is neither a corner nor a spring
// neighbour of one) closer than the reach (margin + thickness) and roughly in front of or
// behind it (|n . (p - q)| >= distance / 2); equal distances go to the lower triangle
// index, so the choice does not depend on the bucket's order. It writes its contact record
// (multiplier 0) and counts the contact on its four nodes' degrees (ContactSums' w, integer atomics).
#include "common/version.glsl"
#include "common/bindings.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
#include "physics/bodies.glsl"
layout(std430, set = 0, binding = B_SPRINGS) readonly restrict buffer Springs { Spring springs[]; };
layout(std430, set = 0, binding = B_NODE_SPRING_OFFSETS) readonly restrict buffer NodeSpringOffsets { uint node_spring_offsets[]; };
layout(std430, set = 0, binding = B_NODE_SPRING_ITEMS) readonly restrict buffer NodeSpringItems { uint node_spring_items[]; };
layout(std430, set = 0, binding = B_CONTACT_HASH) readonly restrict buffer ContactHash { uint hash[]; };
layout(std430, set = 0, binding = B_CONTACTS) writeonly restrict buffer Contacts { BodyContactRecord contacts[]; };
layout(std430, set = 0, binding = B_CONTACT_SUMS) restrict buffer ContactSumsU { uint sums_u[]; };

bool corner(uvec4 tri, uint i) {
    return tri.x == i || tri.y == i || tri.z == i;
}

// BodyContact::eligible: whether `node` of `object` may touch the triangle `tri`.
bool eligible(uint node, uint object, bool self_contact, uvec4 tri) {
    if ((tri.w & ~SELF_CONTACT_BIT) != object) {
        return true;
    }
    if (!self_contact || corner(tri, node)) {
        return false;
    }
    uint end = node_spring_offsets[node + 1u];
    for (uint e = node_spring_offsets[node]; e < end; ++e) {
        Spring s = springs[node_spring_items[e]];
        if (corner(tri, s.a) || corner(tri, s.b)) {
            return false;
        }
    }
    return true;
}

void main() {
    uint s = gl_GlobalInvocationID.x;
    if (s >= BODY_NODE_COUNT) {
        return;
    }
    uvec4 me = body_node(s);
    uint node = me.x;
    uint object = me.y & ~SELF_CONTACT_BIT;
    bool self_contact = (me.y & SELF_CONTACT_BIT) != 0u;
    vec3 p = predicted(node);
    BodyContactRecord best;
    best.nodes = uvec4(NO_CONTACT);
    best.bary_lambda = vec4(0.0);
    best.normal = vec4(0.0);
    float best_distance = 0.0;
    uint best_t = NO_CONTACT;
    float reach = contact_reach();
    ivec3 cell;
    if (cell_of(p, cell)) {
        uint b = bucket_of(cell);
        uint end = min(hash[HASH_OFFSETS + b + 1u], CAPACITY);
        for (uint e = hash[HASH_OFFSETS + b]; e < end; ++e) {
            uint t = hash[HASH_ITEMS + e];
            uvec4 tri = body_triangle(t);
            if (!eligible(node, object, self_contact, tri)) {
                continue;
            }
            vec3 a = predicted(tri.x), bb = predicted(tri.y), c = predicted(tri.z);
            vec3 cr = cross(bb - a, c - a);
            float len = length(cr);
            if (!(len > 0.0) || isinf(1.0 / len)) {
                continue;
            }
            vec3 normal = cr / len;
            vec3 bary = closest_on_triangle(p, a, bb, c);
            vec3 q = a * bary.x + bb * bary.y + c * bary.z;
            float distance = length(p - q);
            bool facing = abs(dot(normal, p - q)) >= 0.5 * distance;
            bool nearer = best_t == NO_CONTACT || distance < best_distance
                || (distance == best_distance && t < best_t);
            if (distance < reach && facing && nearer) {
                best_distance = distance;
                best_t = t;
                best.nodes = uvec4(node, tri.xyz);
                best.bary_lambda = vec4(bary, 0.0);
                best.normal = vec4(normal, 0.0);
            }
        }
    }
    contacts[s] = best;
    if (best_t != NO_CONTACT) {
        atomicAdd(sums_u[4u * best.nodes.x + 3u], 1u);
        atomicAdd(sums_u[4u * best.nodes.y + 3u], 1u);
        atomicAdd(sums_u[4u * best.nodes.z + 3u], 1u);
        atomicAdd(sums_u[4u * best.nodes.w + 3u], 1u);
    }
}
