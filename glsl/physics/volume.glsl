// Volume constraint (physics.md, paper Eqs. 9, 10), mirroring src/physics: with
// e1 = p2 - p1, e2 = p3 - p1, e3 = p4 - p1,
//   C = (e1 x e2) . e3 / 6 - V0,
//   grad_2 = (e2 x e3) / 6, grad_3 = (e3 x e1) / 6, grad_4 = (e1 x e2) / 6,
//   grad_1 = -(grad_2 + grad_3 + grad_4).
#ifndef PHYSICS_VOLUME_GLSL
#define PHYSICS_VOLUME_GLSL

// Signed volume [m^3], positive for a positively oriented tet.
float tet_volume(vec3 p1, vec3 p2, vec3 p3, vec3 p4) {
    vec3 e1 = p2 - p1;
    vec3 e2 = p3 - p1;
    vec3 e3 = p4 - p1;
    return dot(cross(e1, e2), e3) / 6.0;
}

float volume_value(vec3 p1, vec3 p2, vec3 p3, vec3 p4, float rest) {
    return tet_volume(p1, p2, p3, p4) - rest;
}

// Gradients of C with respect to p1..p4.
void volume_gradients(vec3 p1, vec3 p2, vec3 p3, vec3 p4, out vec3 g1, out vec3 g2, out vec3 g3, out vec3 g4) {
    vec3 e1 = p2 - p1;
    vec3 e2 = p3 - p1;
    vec3 e3 = p4 - p1;
    g2 = cross(e2, e3) / 6.0;
    g3 = cross(e3, e1) / 6.0;
    g4 = cross(e1, e2) / 6.0;
    g1 = -(g2 + g3 + g4);
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
