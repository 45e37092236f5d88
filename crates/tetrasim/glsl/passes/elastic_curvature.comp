#version 460
// Pass `elastic_curvature`: passes/elastic_curvature.glsl.
#include "passes/elastic_curvature.glsl"
