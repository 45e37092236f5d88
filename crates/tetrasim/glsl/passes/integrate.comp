#version 460
// Pass `integrate`: the floor's final solve, symplectic Euler (physics.md Eqs. 2, 3) with
// floor friction, force reset.
//   F.y gets the floor force (physics/integrate.glsl; the only floor solve of springs-only
//   methods, a repeat of constraint_apply's last one otherwise),
//   v += dt * w * F   (F already holds m g); a node in contact (floor force > 0) loses
//   `friction` of its tangential velocity;  x += dt * v;
// finally F = m g for the next step. Variant `colliders`: after the floor's solve the
// kinematic colliders' (physics/contact.glsl), and after the floor's friction the friction
// of the collider the node touches; the colliders' force is reset to 0 for the next step (w:
// whether one pushed the node).
// Variants `split`: split contact keeps the velocity solve's velocities (split_velocity).
// The body is passes/integrate_body.glsl.
// @variant plain:
// @variant colliders: COLLIDERS_ON
// @variant split: SPLIT_ON
// @variant colliders_split: COLLIDERS_ON SPLIT_ON
#include "passes/integrate_body.glsl"
