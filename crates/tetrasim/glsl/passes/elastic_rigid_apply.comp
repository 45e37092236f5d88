#version 460
// Pass `elastic_rigid_apply` (after `elastic_correction_curvature`, a workgroup per object):
// the rigid part taken off the increments (passes/elastic_rigid.glsl).
#define APPLY
#include "passes/elastic_rigid.glsl"
