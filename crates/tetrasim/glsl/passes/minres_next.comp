#version 460
// Pass `minres_next`: after MINRES's iterations (common/minres.glsl), in the row passes'
// shape: the last iteration's next Lanczos vector's norm and, from it, the recurrence's
// last rotation (lanczos_norm into state ITERATIONS), which minres_finish applies. Within
// the iterations minres_nodes' row workgroups do this.
#include "common/version.glsl"
#include "common/bindings.glsl"
#include "common/workgroup_sum.glsl"
#include "common/minres.glsl"

void main() {
    lanczos_norm(ITERATIONS, gl_WorkGroupID.x);
}
