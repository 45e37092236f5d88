// Anderson acceleration of a step's constraint iterations, mirroring src/physics/anderson.rs:
// which history column iteration k writes and how many the mix uses, the Gram terms'
// indices and the mixing weights (Cholesky of the regularised normal equations, in single
// precision here). Include after common/bindings.glsl; MEMORY (specialisation constant 5) is
// the history's column count.
#ifndef PHYSICS_ANDERSON_GLSL
#define PHYSICS_ANDERSON_GLSL

// ANDERSON_MAX_MEMORY and gram_terms(ANDERSON_MAX_MEMORY).
#define ANDERSON_MAX_MEMORY 8u
#define ANDERSON_MAX_TERMS 44u
// ANDERSON_REGULARIZATION.
#define ANDERSON_REGULARIZATION 1e-6

layout(constant_id = 5) const uint MEMORY = 1u;
// The multipliers mixed with the forces (specialisation constants 6 and 7): every spring's
// when a sweep solves springs, every tet's when one solves volumes (else 0).
layout(constant_id = 6) const uint MIX_SPRINGS = 0u;
layout(constant_id = 7) const uint MIX_TETS = 0u;

// AndersonIteration::of(iteration, MEMORY): the column written (-1: none) and used.
int anderson_slot(uint iteration) {
    return iteration >= 2u ? int((iteration - 2u) % max(MEMORY, 1u)) : -1;
}
uint anderson_columns(uint iteration) {
    return iteration >= 1u ? min(iteration - 1u, max(MEMORY, 1u)) : 0u;
}

uint gram_terms(uint k) {
    return k * (k + 1u) / 2u + k;
}

// The index of df_i . df_j (i <= j) among the gram_terms(k).
uint gram_index(uint i, uint j, uint k) {
    uint lo = min(i, j);
    uint hi = max(i, j);
    return lo * k - (lo * (lo > 0u ? lo - 1u : 0u)) / 2u + (hi - lo);
}

// anderson_weights: gamma from the summed terms of k columns (all zeros: no mix).
void anderson_weights(float sums[ANDERSON_MAX_TERMS], uint k, out float gamma[ANDERSON_MAX_MEMORY]) {
    for (uint i = 0u; i < ANDERSON_MAX_MEMORY; ++i) {
        gamma[i] = 0.0;
    }
    float scale = 0.0;
    for (uint i = 0u; i < k; ++i) {
        scale = max(scale, sums[gram_index(i, i, k)]);
    }
    if (k == 0u || !(scale > 0.0) || isinf(scale)) {
        return;
    }
    float l[ANDERSON_MAX_MEMORY * ANDERSON_MAX_MEMORY];
    for (uint i = 0u; i < k; ++i) {
        for (uint j = 0u; j <= i; ++j) {
            float s = sums[gram_index(i, j, k)];
            if (i == j) {
                s += ANDERSON_REGULARIZATION * scale;
            }
            for (uint p = 0u; p < j; ++p) {
                s -= l[i * k + p] * l[j * k + p];
            }
            if (i == j) {
                if (!(s > 0.0)) {
                    return;
                }
                l[i * k + i] = sqrt(s);
            } else {
                l[i * k + j] = s / l[j * k + j];
            }
        }
    }
    uint rhs = k * (k + 1u) / 2u;
    float y[ANDERSON_MAX_MEMORY];
    for (uint i = 0u; i < k; ++i) {
        float s = sums[rhs + i];
        for (uint p = 0u; p < i; ++p) {
            s -= l[i * k + p] * y[p];
        }
        y[i] = s / l[i * k + i];
    }
    float x[ANDERSON_MAX_MEMORY];
    for (uint r = 0u; r < k; ++r) {
        uint i = k - 1u - r;
        float s = y[i];
        for (uint p = i + 1u; p < k; ++p) {
            s -= l[p * k + i] * x[p];
        }
        x[i] = s / l[i * k + i];
    }
    for (uint i = 0u; i < k; ++i) {
        if (isnan(x[i]) || isinf(x[i])) {
            return;
        }
    }
    for (uint i = 0u; i < k; ++i) {
        gamma[i] = x[i];
    }
}

#endif
