// One body contact of a step as the GPU keeps it (src/contact/mod.rs, Contact), and its
// constraint's value; physics/bodies.glsl and the passes that only read the records
// (contact_measure) include it.
#ifndef PHYSICS_BODY_RECORD_GLSL
#define PHYSICS_BODY_RECORD_GLSL

// A record's node when the surface node has no contact this step.
#define NO_CONTACT 0xFFFFFFFFu

// One surface node's contact of the step (48 bytes per surface node, BufferId::Contacts).
struct BodyContactRecord {
    uvec4 nodes;      // the node, then the triangle's three (outward order); NO_CONTACT: none
    vec4 bary_lambda; // the closest point's barycentric weights; w the multiplier so far (<= 0)
    vec4 normal;      // the triangle's outward unit normal (w unused)
};

// Contact::value with thickness 0: n . (x_p - sum_k b_k x_k), the node at p and the
// triangle's corners at a, b, c (negative: the node is behind the triangle).
float contact_separation(BodyContactRecord rec, vec3 p, vec3 a, vec3 b, vec3 c) {
    vec3 bary = rec.bary_lambda.xyz;
    return dot(rec.normal.xyz, p - (a * bary.x + b * bary.y + c * bary.z));
}

#endif
