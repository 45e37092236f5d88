#version 460
// Pass `elastic_begin` (finite elements, one workgroup): the conjugate gradients' r . z and beta, or a Newton step's start
// (passes/elastic_scalars.glsl).
#define BEGIN
#include "passes/elastic_scalars.glsl"
