#version 460
// The kinematic colliders: triangles tessellated once in each collider's local frame
// (src/render/colliders.rs), placed by that collider's pose at the picture's time. One draw
// for all of them, no vertex buffer.
#include "render/common.glsl"

struct ColliderVertex {
    vec4 position;  // local [m]; w: the collider's index
    vec4 normal;    // local unit normal
};
layout(std430, set = 0, binding = R_COLLIDER_VERTICES) readonly restrict buffer ColliderVertices { ColliderVertex collider_vertices[]; };
layout(std430, set = 0, binding = R_COLLIDER_POSES) readonly restrict buffer ColliderPoses { mat4 collider_poses[]; };

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;

void main() {
    ColliderVertex v = collider_vertices[gl_VertexIndex];
    mat4 pose = collider_poses[uint(v.position.w)];
    vec4 world = pose * vec4(v.position.xyz, 1.0);
    v_world = world.xyz;
    v_normal = mat3(pose) * v.normal.xyz;  // a rotation: normals turn with the points
    gl_Position = pc.view_proj * world;
}
