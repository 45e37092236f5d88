// Volume constraint (physics.md, paper Eqs. 9, 10), mirroring src/physics: with
// e1 = p2 - p1, e2 = p3 - p1, e3 = p4 - p1,
//   C = (e1 x e2) . e3 / 6 - V0,
//   grad_2 = (e2 x e3) / 6, grad_3 = (e3 x e1) / 6, grad_4 = (e1 x e2) / 6,
//   grad_1 = -(grad_2 + grad_3 + grad_4).
#ifndef PHYSICS_VOLUME_GLSL
#define PHYSICS_VOLUME_GLSL

// Signed volume [m^3], positive for a positively oriented tet (tet_volume in
// tools/tetmesh/src/geometry/mod.rs, computed in the same order).
float tet_volume(vec3 p1, vec3 p2, vec3 p3, vec3 p4) {
    vec3 e1 = p2 - p1;
    vec3 e2 = p3 - p1;
    vec3 e3 = p4 - p1;
    return dot(cross(e1, e2), e3) * (1.0 / 6.0);
}

// C and its gradients with respect to p1..p4 (volume_constraint in
// tools/tetmesh/src/geometry/mod.rs, computed in the same order).
float volume_constraint(vec3 p1, vec3 p2, vec3 p3, vec3 p4, float rest, out vec3 g1, out vec3 g2, out vec3 g3, out vec3 g4) {
    vec3 e1 = p2 - p1;
    vec3 e2 = p3 - p1;
    vec3 e3 = p4 - p1;
    const float sixth = 1.0 / 6.0;
    g2 = cross(e2, e3) * sixth;
    g3 = cross(e3, e1) * sixth;
    g4 = cross(e1, e2) * sixth;
    g1 = -(g2 + g3 + g4);
    return dot(g4, e3) - rest;
}

// One boundary face's share of the enclosed volume measured from the reference point o
// (face_volume in src/physics/constraint.rs): (a - o) . ((b - o) x (c - o)) / 6 [m^3].
float face_volume(vec3 a, vec3 b, vec3 c, vec3 o) {
    return dot(a - o, cross(b - o, c - o)) / 6.0;
}

// Its gradient with respect to the corner a of the face (a, b, c), in the face's winding:
// (b - o) x (c - o) / 6 [m^2] (the other corners' by rotating the arguments).
vec3 face_volume_gradient(vec3 b, vec3 c, vec3 o) {
    return cross(b - o, c - o) / 6.0;
}

#endif
