#version 460
// Pass `split_velocity` (split contact, physics.md "Contact that does not bounce back"):
// ends the step's velocity solve like `integrate` ends the full one (the floor's and the
// colliders' final solve with pc.phase = velocity, symplectic Euler with friction, the
// forces reset), but keeps only the new velocity, in SplitVelocities, for `integrate`.
// The body is passes/integrate_body.glsl.
// @variant plain: SPLIT_VELOCITY_PASS
// @variant colliders: SPLIT_VELOCITY_PASS COLLIDERS_ON
#include "passes/integrate_body.glsl"
