// Contact between bodies and with itself on the GPU (physics.md, "Contact between bodies and
// with itself"), mirroring src/contact/{mod.rs,find.rs}: the broad phase's uniform hash of
// the surface triangles' predicted bounds grown by the reach (cells twice the reach), the
// narrow phase's closest point (closest_on_triangle) and eligibility, and the contact record.
//
// A pass includes this after common/bindings.glsl and after declaring `positions` and
// `velocities`; it declares the body contact's specialisation constants (ids 1 to 6, set by
// the engine plan) and its static buffers.
#ifndef PHYSICS_BODIES_GLSL
#define PHYSICS_BODIES_GLSL

#include "physics/body_record.glsl"

// Surface nodes of body contact (BodyContact::nodes).
layout(constant_id = 1) const uint BODY_NODE_COUNT = 0u;
// Surface triangles (BodyContact::triangles).
layout(constant_id = 2) const uint TRIANGLE_COUNT = 0u;
// Hash buckets (a power of two).
layout(constant_id = 3) const uint BUCKETS = 1u;
// Hash items the item array holds (more set status flag 4).
layout(constant_id = 4) const uint CAPACITY = 1u;
// Contact thickness r [m] (BodyContact::thickness).
layout(constant_id = 5) const float THICKNESS = 0.0;
// Detection margin [m] (BodyContact::margin).
layout(constant_id = 6) const float MARGIN = 0.0;

// Bit 31 of an object number: the object collides with itself.
#define SELF_CONTACT_BIT 0x80000000u
// Status flag of a broad phase that did not fit its arrays (the frame fails).
#define FLAG_CONTACT_OVERFLOW 4u
// The most hash cells one triangle may cover (more: a blown-up mesh; flag 4).
#define MAX_TRIANGLE_CELLS 4096.0

layout(std430, set = 0, binding = B_BODY_SURFACE) readonly restrict buffer BodySurface { uvec4 body_surface[]; };

// Surface node s: its node, its object (bit 31: self-contact).
uvec4 body_node(uint s) {
    return body_surface[s];
}

// Surface triangle t: its three nodes, its object (bit 31: self-contact).
uvec4 body_triangle(uint t) {
    return body_surface[BODY_NODE_COUNT + t];
}

// Where the parts of the hash (BufferId::ContactHash, one u32 array) start: the buckets'
// counts, their offsets (BUCKETS + 1), the items.
#define HASH_COUNTS 0u
#define HASH_OFFSETS BUCKETS
#define HASH_ITEMS (2u * BUCKETS + 1u)

// Where node i is predicted to end the step without any force: x + dt v.
vec3 predicted(uint i) {
    return positions[i].xyz + pc.dt * velocities[i].xyz;
}

// Detection reach: margin + thickness [m].
float contact_reach() {
    return MARGIN + THICKNESS;
}

// The hash cells' size: twice the reach (at least 2e-9 m).
float cell_size() {
    return max(contact_reach(), 1e-9) * 2.0;
}

bool finite3(vec3 v) {
    return !(any(isnan(v)) || any(isinf(v)));
}

// The cell holding p; false when p is not finite or too far out for integer cells.
bool cell_of(vec3 p, out ivec3 cell) {
    vec3 c = floor(p / cell_size());
    if (!finite3(c) || any(greaterThan(abs(c), vec3(1073741824.0)))) {
        cell = ivec3(0);
        return false;
    }
    cell = ivec3(c);
    return true;
}

// The bucket of a cell.
uint bucket_of(ivec3 c) {
    uvec3 u = uvec3(c);
    return ((u.x * 73856093u) ^ (u.y * 19349663u) ^ (u.z * 83492791u)) & (BUCKETS - 1u);
}

// The cells triangle t's predicted bounds grown by the reach cover, lo to hi; false when
// they cannot be hashed (not finite, or more than MAX_TRIANGLE_CELLS: `too_many`).
bool triangle_cells(uint t, out ivec3 lo, out ivec3 hi, out bool too_many) {
    uvec4 tri = body_triangle(t);
    vec3 a = predicted(tri.x), b = predicted(tri.y), c = predicted(tri.z);
    float reach = contact_reach();
    too_many = false;
    hi = ivec3(0);
    if (!cell_of(min(min(a, b), c) - reach, lo) || !cell_of(max(max(a, b), c) + reach, hi)) {
        return false;
    }
    vec3 span = vec3(hi - lo) + 1.0;
    too_many = span.x * span.y * span.z > MAX_TRIANGLE_CELLS;
    return !too_many;
}

// closest_on_triangle (src/contact/find.rs; Ericson, Real-Time Collision Detection,
// 5.1.5): the barycentric weights of the closest point to p on the triangle (a, b, c).
vec3 closest_on_triangle(vec3 p, vec3 a, vec3 b, vec3 c) {
    vec3 ab = b - a, ac = c - a, ap = p - a;
    float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) {
        return vec3(1.0, 0.0, 0.0);
    }
    vec3 bp = p - b;
    float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) {
        return vec3(0.0, 1.0, 0.0);
    }
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        float v = d1 / (d1 - d3);
        return vec3(1.0 - v, v, 0.0);
    }
    vec3 cp = p - c;
    float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) {
        return vec3(0.0, 0.0, 1.0);
    }
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        float w = d2 / (d2 - d6);
        return vec3(1.0 - w, 0.0, w);
    }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return vec3(0.0, 1.0 - w, w);
    }
    float denom = 1.0 / (va + vb + vc);
    float v = vb * denom, w = vc * denom;
    return vec3(1.0 - v - w, v, w);
}

#endif
