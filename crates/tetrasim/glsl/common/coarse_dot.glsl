// The coarse factor's and inverse's inner products, eight terms per loop iteration: lavapipe
// (llvmpipe) ends an invocation silently after 65535 loop iterations, all its loops together
// (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS), and a term per iteration put a 384-unknown
// factor's or inverse's column past it (the horse's 64 aggregates: the factor stopped at
// column 332 of 384 and left the rest out, the preconditioner wrong where they were). With
// eight terms a column of the inverse takes about U^2 / 8 + 20 U iterations, 26,000 at the
// most aggregates. Include after declaring the float array `coarse`.
#ifndef COMMON_COARSE_DOT_GLSL
#define COMMON_COARSE_DOT_GLSL

// sum over t < count of coarse[a + t a_step] * coarse[b + t b_step].
float coarse_dot(uint a, uint a_step, uint b, uint b_step, uint count) {
    vec4 sum = vec4(0.0);
    uint t = 0u;
    for (; t + 8u <= count; t += 8u) {
        uint p = a + t * a_step;
        uint q = b + t * b_step;
        sum += vec4(coarse[p], coarse[p + a_step], coarse[p + 2u * a_step], coarse[p + 3u * a_step])
             * vec4(coarse[q], coarse[q + b_step], coarse[q + 2u * b_step], coarse[q + 3u * b_step]);
        p += 4u * a_step;
        q += 4u * b_step;
        sum += vec4(coarse[p], coarse[p + a_step], coarse[p + 2u * a_step], coarse[p + 3u * a_step])
             * vec4(coarse[q], coarse[q + b_step], coarse[q + 2u * b_step], coarse[q + 3u * b_step]);
    }
    float total = (sum.x + sum.y) + (sum.z + sum.w);
    for (; t < count; ++t) {
        total += coarse[a + t * a_step] * coarse[b + t * b_step];
    }
    return total;
}

#endif
