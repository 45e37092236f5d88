// The end of every pass that changes a node's force inside the iterations
// (`constraint_apply`, `global_volume`, `contact_apply`): the node's floor
// contact solved again against its new force F (the floor is a one-sided constraint solved
// in the same iterations; its force is kept in F.w), then, in the `COLLIDERS_ON` variants,
// the kinematic colliders' contacts (physics/contact.glsl; their force kept in
// ColliderContacts). Include after the pass's `positions`, `velocities` (and, with
// COLLIDERS_ON, `contacts`) buffers and physics/contact.glsl.
#ifndef PASSES_NODE_CONTACTS_GLSL
#define PASSES_NODE_CONTACTS_GLSL

vec4 node_contacts(uint i, vec4 f) {
    if (FLOOR != 0u && pc.floor_on != 0u) {
        vec4 p = positions[i];
        f = floor_solve(f, p.y + solve_slack(pc.phase, p.y), velocities[i].y, p.w, pc.dt);
    }
#ifdef COLLIDERS_ON
    {
        vec4 p = positions[i];
        vec3 contact = contacts[i].xyz;
        int touching;
        vec3 normal;
        float pressed;
        f.xyz = colliders_solve(i, f.xyz, contact, p.xyz, velocities[i].xyz, p.w, pc.dt, touching, normal, pressed);
        contacts[i] = vec4(contact, 0.0);
    }
#endif
    return f;
}

#endif
