#version 460
#include "common/version.glsl"
layout(local_size_x_id = 0) in;
layout(std430, set = 0, binding = 0) buffer Data { float values[]; };
void main() { uint i = gl_GlobalInvocationID.x; if (i < values.length()) values[i] *= 2.0; }
