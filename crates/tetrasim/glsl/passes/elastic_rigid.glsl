// The body of the passes `elastic_rigid_part` and `elastic_rigid_apply` (finite elements,
// after the last conjugate-gradient iteration; one workgroup per object; docs/GPU.md,
// "Finite elements on the GPU"): the rigid part of each free object's elastic forces (what
// the unconverged residual leaves) taken off them, so that they conserve momentum: whole on
// a body nothing holds, as far as it lowers the step's quadratic model on one a contact
// holds. With PART (`elastic_rigid_part`): the rigid part (RigidPart::of over the nodes at
// the step's start, a held node weighing nothing, the elastic force so far plus the
// iteration's increment SUM; about the object's first node, so that the second moments do
// not cancel in float) into ElasticObjects, and the moves the correction would make,
// -force w dt^2, into P (zero on pinned objects) for `elastic_correction_product` and
// `elastic_correction_curvature`. With APPLY (`elastic_rigid_apply`): the correction's
// length (correction_length of r . d and d . A d; 1 where nothing holds the object) and SUM
// less that share of the rigid part's force, into SUM and the node's contribution slot.
// The twin of cpu-ref's `elastic_group` and `correction_length`
// (src/backend/cpu/reference/elastic.rs). With COLLIDERS_ON: the colliders' force so far
// is not elastic either.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "physics/newton.glsl"

layout(std430, set = 0, binding = B_POSITIONS) readonly restrict buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = B_VELOCITIES) readonly restrict buffer Velocities { vec4 velocities[]; };
layout(std430, set = 0, binding = B_FORCES) readonly restrict buffer Forces { vec4 forces[]; };
layout(std430, set = 0, binding = B_ELASTIC_NODES) restrict buffer ElasticNodesBuffer { vec4 nodes[]; };
layout(std430, set = 0, binding = B_ELASTIC_OBJECTS) restrict buffer ElasticObjectsU { uint objects_u[]; };
layout(std430, set = 0, binding = B_ELASTIC_OBJECTS) restrict buffer ElasticObjectsF { vec4 objects[]; };

#ifdef APPLY
layout(std430, set = 0, binding = B_CONTRIBUTIONS) writeonly restrict buffer Contributions { vec4 contributions[]; };
#endif
#ifdef COLLIDERS_ON
layout(std430, set = 0, binding = B_COLLIDER_CONTACTS) readonly restrict buffer ColliderContacts { vec4 collider_contacts[]; };
#endif

WORKGROUP_SUM_PAIR(rigid_sum, vec4)

shared vec4 part[3];

vec3 plane(uint k, uint i) {
    return nodes[k * pc.node_count + i].xyz;
}

// The mass a node brings to the rigid part: none where a contact holds it (held_mass).
float rigid_mass(uint i) {
    return plane(ELASTIC_PLANE_HELD, i) == vec3(0.0) ? velocities[i].w : 0.0;
}

// The rigid part's force on node i (RigidPart::force).
vec3 rigid_force(uint i) {
    return (part[1].xyz + cross(part[2].xyz, positions[i].xyz - part[0].xyz)) * rigid_mass(i);
}

void main() {
    uint o = gl_WorkGroupID.x;
    uint first = objects_u[16u * o];
    uint end = objects_u[16u * o + 1u];
    bool free_object = objects_u[16u * o + 2u] != 0u;
    uint me = gl_LocalInvocationID.x;
    uint lanes = gl_WorkGroupSize.x;
#ifdef PART
    if (!free_object) {
        for (uint i = first + me; i < end; i += lanes) {
            nodes[ELASTIC_PLANE_P * pc.node_count + i] = vec4(0.0);
        }
        return;
    }
    vec3 origin = positions[first].xyz;
    vec4 moments = vec4(0.0);  // m, m r
    vec4 force = vec4(0.0);    // f, held nodes
    vec4 torque = vec4(0.0);   // r x f
    vec4 diagonal = vec4(0.0); // m rx rx, m ry ry, m rz rz, m rx ry
    vec4 off = vec4(0.0);      // m rx rz, m ry rz
    vec4 unused = vec4(0.0);
    for (uint i = first + me; i < end; i += lanes) {
        float m = rigid_mass(i);
        vec3 r = positions[i].xyz - origin;
        vec4 f4 = forces[i];
        vec3 f = f4.xyz - pc.gravity * velocities[i].w - vec3(0.0, f4.w, 0.0) + plane(ELASTIC_PLANE_SUM, i);
#ifdef COLLIDERS_ON
        f -= collider_contacts[i].xyz;
#endif
        moments += vec4(m, r * m);
        force += vec4(f, plane(ELASTIC_PLANE_HELD, i) == vec3(0.0) ? 0.0 : 1.0);
        torque += vec4(cross(r, f), 0.0);
        diagonal += vec4(r * r * m, r.x * r.y * m);
        off += vec4(r.x * r.z * m, r.y * r.z * m, 0.0, 0.0);
    }
    rigid_sum(moments, force);
    barrier();
    rigid_sum(torque, diagonal);
    barrier();
    rigid_sum(off, unused);
    if (me == 0u) {
        float mass = moments.x;
        vec3 centre = vec3(0.0);
        vec3 acceleration = vec3(0.0);
        vec3 angular = vec3(0.0);
        if (mass > 0.0) {
            centre = moments.yzw / mass;
            // Second moment and torque about the centre of mass.
            mat3 second = mat3(diagonal.x, diagonal.w, off.x,
                               diagonal.w, diagonal.y, off.y,
                               off.x, off.y, diagonal.z);
            mat3 about = second - outerProduct(centre, centre * mass);
            vec3 turn = torque.xyz - cross(centre, force.xyz);
            float trace = about[0][0] + about[1][1] + about[2][2];
            mat3 inertia = mat3(trace) - about;
            if (abs(determinant(inertia)) > 1e-12 * abs(trace * trace * trace)) {
                angular = inverse(inertia) * turn;
            }
            acceleration = force.xyz / mass;
        }
        objects[4u * o + 1u] = vec4(centre + origin, 0.0);
        objects[4u * o + 2u] = vec4(acceleration, 0.0);
        objects[4u * o + 3u] = vec4(angular, 0.0);
        objects_u[16u * o + 3u] = force.w > 0.0 ? 1u : 0u;
        part[0] = vec4(centre + origin, 0.0);
        part[1] = vec4(acceleration, 0.0);
        part[2] = vec4(angular, 0.0);
    }
    barrier();
    float reach = pc.dt * pc.dt;
    for (uint i = first + me; i < end; i += lanes) {
        nodes[ELASTIC_PLANE_P * pc.node_count + i] = vec4(-rigid_force(i) * (positions[i].w * reach), 0.0);
    }
#endif
#ifdef APPLY
    if (!free_object) {
        return;
    }
    if (me == 0u) {
        part[0] = objects[4u * o + 1u];
        part[1] = objects[4u * o + 2u];
        part[2] = objects[4u * o + 3u];
    }
    barrier();
    float length = 1.0;
    if (objects_u[16u * o + 3u] != 0u) {
        vec4 sums = vec4(0.0);
        vec4 unused = vec4(0.0);
        for (uint i = first + me; i < end; i += lanes) {
            vec3 d = plane(ELASTIC_PLANE_P, i);
            sums += vec4(dot(plane(ELASTIC_PLANE_R, i), d), dot(d, plane(ELASTIC_PLANE_Q, i)), 0.0, 0.0);
        }
        rigid_sum(sums, unused);
        // correction_length: as far as it lowers the model, within [0, 1].
        length = sums.x > 0.0 && sums.y > 0.0 ? min(sums.x / sums.y, 1.0) : 0.0;
    }
    for (uint i = first + me; i < end; i += lanes) {
        vec3 sum = plane(ELASTIC_PLANE_SUM, i) - rigid_force(i) * length;
        nodes[ELASTIC_PLANE_SUM * pc.node_count + i] = vec4(sum, 0.0);
        contributions[pc.slot_first + i] = vec4(sum, 0.0);
    }
#endif
}
