#version 460
// Pass `elastic_rigid_part` (after the last conjugate-gradient iteration, a workgroup per
// object): the rigid part of each free object's elastic forces (passes/elastic_rigid.glsl).
// @variant plain:
// @variant colliders: COLLIDERS_ON
#define PART
#include "passes/elastic_rigid.glsl"
