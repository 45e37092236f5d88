#version 460
// Pass `contact_solve`: not yet on the GPU (the vulkan backend refuses body contact).
#include "common/version.glsl"
#include "common/bindings.glsl"
void main() {}
