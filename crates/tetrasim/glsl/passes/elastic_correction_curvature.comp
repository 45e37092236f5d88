#version 460
// Pass `elastic_correction_curvature` (after the last conjugate-gradient iteration): the curvature of
// passes/elastic_curvature.glsl on the rigid-part correction's moves.
#define CORRECTION
#include "passes/elastic_curvature.glsl"
