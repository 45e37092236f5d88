#version 460
// Pass `elastic_backtrack` (finite elements, one workgroup): the backtracking's decision
// (passes/elastic_scalars.glsl).
#define BACKTRACK
#include "passes/elastic_scalars.glsl"
