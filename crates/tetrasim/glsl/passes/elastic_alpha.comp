#version 460
// Pass `elastic_alpha` (finite elements, one workgroup): the step alpha along the direction
// (passes/elastic_scalars.glsl).
#define ALPHA
#include "passes/elastic_scalars.glsl"
