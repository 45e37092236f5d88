// Which of a time step's solves runs (physics.md, "Contact that does not bounce back"),
// mirroring src/physics/contact.rs `Solve`: the full solve (positions, and velocities with
// combined contact) or split contact's velocity solve, which asks every hard constraint for
// no change of its value and every one-sided constraint to close its gap without undoing
// the penetration it starts the step with. The pass reads it from `pc.phase`.
#ifndef PHYSICS_SOLVE_GLSL
#define PHYSICS_SOLVE_GLSL

// Values of pc.phase (src/gpu/layout.rs, `phase`).
#define PHASE_FULL 0u
#define PHASE_VELOCITY 1u

// Solve::hard: the value a hard constraint of value c is solved for (0 in the velocity
// solve). Compliant constraints keep theirs.
float solve_hard(uint phase, float c) {
    return phase == PHASE_VELOCITY ? 0.0 : c;
}

// Solve::slack: what a one-sided constraint starting the step at c_start adds to its value
// (its penetration max(-c_start, 0) in the velocity solve, else 0).
float solve_slack(uint phase, float c_start) {
    return phase == PHASE_VELOCITY ? max(-c_start, 0.0) : 0.0;
}

#endif
