// A tet's stiffness for the finite elements' Newton step (physics.md, fourth edition;
// docs/PHYSICS.md, "Finite elements"): taken at a linearisation with the volume term scaled
// back where the Hessian would be indefinite (projected Newton), kept for a later
// linearisation within the step where the tet barely moved, applied to corner moves by the
// conjugate gradients' products, and the tet's energy for the backtracking's potential.
// The twin of src/physics/stiffness.rs and src/physics/definite.rs (same names, same order
// of operations, in float); tests/gpu_elastic_twin.rs runs it against them.
#ifndef PHYSICS_STIFFNESS_GLSL
#define PHYSICS_STIFFNESS_GLSL

// KEPT_STIFFNESS_STRAIN in src/physics/stiffness.rs.
#define KEPT_STIFFNESS_STRAIN 0.01

// One tet's element constants (`ElasticTet`): the shape gradients g1..g3 of corners 1..3
// (corner 0's is their negative sum), the rest volume [m^3], mu_s, lambda_s [Pa] and alpha.
struct ElasticTet {
    vec3 g1;
    vec3 g2;
    vec3 g3;
    float volume;
    float mu;
    float lambda;
    float alpha;
};

// A tet's stiffness at one configuration (`ElasticLinear`): F's columns f0..f2, its
// cofactor's c0..c2, and k = (V0 mu_s (1 - s), V0 2 mu_s s^2, V0 lambda_s, V0 lambda_s
// (J - alpha) as the definite volume term keeps it), s = 1 / (I_C + 1).
struct ElasticLinear {
    vec3 f0;
    vec3 f1;
    vec3 f2;
    vec3 c0;
    vec3 c1;
    vec3 c2;
    vec4 k;
};

// The columns of sum_a p_a g_a^T for corner values p0..p3 (`columns`): F of positions, dF of
// displacements.
void elastic_columns(ElasticTet t, vec3 p0, vec3 p1, vec3 p2, vec3 p3,
                     out vec3 f0, out vec3 f1, out vec3 f2) {
    vec3 e0 = p1 - p0;
    vec3 e1 = p2 - p0;
    vec3 e2 = p3 - p0;
    f0 = e0 * t.g1.x + e1 * t.g2.x + e2 * t.g3.x;
    f1 = e0 * t.g1.y + e1 * t.g2.y + e2 * t.g3.y;
    f2 = e0 * t.g1.z + e1 * t.g2.z + e2 * t.g3.z;
}

// The eigenvalues of the symmetric m (m[i][j], row i), largest first (`eigenvalues`: the
// characteristic cubic's closed form).
vec3 sym3_eigenvalues(float m[3][3]) {
    float off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    float q = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
    float spread = (m[0][0] - q) * (m[0][0] - q) + (m[1][1] - q) * (m[1][1] - q)
        + (m[2][2] - q) * (m[2][2] - q) + 2.0 * off;
    float p = sqrt(spread / 6.0);
    if (isnan(p) || p <= 0.0) {
        return vec3(q);
    }
    float b[3][3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            b[i][j] = (m[i][j] - (i == j ? q : 0.0)) / p;
        }
    }
    float det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1])
        - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0])
        + b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
    float phi = acos(clamp(det / 2.0, -1.0, 1.0)) / 3.0;
    float largest = q + 2.0 * p * cos(phi);
    float least = q + 2.0 * p * cos(phi + 2.0 * 3.14159265358979 / 3.0);
    return vec3(largest, 3.0 * q - largest - least, least);
}

// F's singular values (columns f0..f2) from F^T F's eigenvalues, largest first; the smallest
// negative where det F < 0 (`singular_values`).
vec3 singular_values(vec3 f0, vec3 f1, vec3 f2) {
    vec3 f[3] = vec3[3](f0, f1, f2);
    float c[3][3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            c[i][j] = dot(f[i], f[j]);
        }
    }
    vec3 sigma = sqrt(max(sym3_eigenvalues(c), vec3(0.0)));
    if (dot(f0, cross(f1, f2)) < 0.0) {
        sigma.z = -sigma.z;
    }
    return sigma;
}

// The scaling block a I + b sigma sigma^T + c gamma gamma^T + d H_s(sigma) (`scaling_block`).
void scaling_block(float a, float b, float c, float d, vec3 sigma, out float m[3][3]) {
    vec3 gamma = vec3(sigma.y * sigma.z, sigma.x * sigma.z, sigma.x * sigma.y);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            float diagonal = i == j ? a : d * sigma[3 - i - j];
            m[i][j] = diagonal + b * sigma[i] * sigma[j] + c * gamma[i] * gamma[j];
        }
    }
}

// The lower Cholesky factor l of the symmetric positive definite m; false if it is not.
bool cholesky3(float m[3][3], out float l[3][3]) {
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            l[i][j] = 0.0;
        }
    }
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j <= i; ++j) {
            float sum = 0.0;
            for (int k = 0; k < j; ++k) {
                sum += l[i][k] * l[j][k];
            }
            if (i == j) {
                float pivot = m[i][i] - sum;
                if (isnan(pivot) || pivot <= 0.0) {
                    return false;
                }
                l[i][i] = sqrt(pivot);
            } else {
                l[i][j] = (m[i][j] - sum) / l[j][j];
            }
        }
    }
    return true;
}

// l^-1 v for the lower triangular l.
vec3 lower_solve(float l[3][3], vec3 v) {
    float x0 = v.x / l[0][0];
    float x1 = (v.y - l[1][0] * x0) / l[1][1];
    float x2 = (v.z - l[2][0] * x0 - l[2][1] * x1) / l[2][2];
    return vec3(x0, x1, x2);
}

// The factor to use for d = lambda_s (J - alpha) in the Hessian's products
// (`definite_volume_term`): d where the Hessian is positive semi-definite, else the largest
// share of it (same sign) that makes it so.
float definite_volume_term(float a, float b, float c, float d, vec3 f0, vec3 f1, vec3 f2) {
    vec3 sigma = singular_values(f0, f1, f2);
    float largest = max(max(abs(sigma.x), abs(sigma.y)), abs(sigma.z));
    if (!(largest > 0.0 && !isinf(largest) && a > 0.0)) {
        return d;
    }
    float bound = a / largest;
    float twists = clamp(d, -bound, bound);
    float block[3][3];
    float l[3][3];
    scaling_block(a, b, c, twists, sigma, block);
    if (cholesky3(block, l)) {
        return twists;
    }
    scaling_block(a, b, c, 0.0, sigma, block);
    if (!cholesky3(block, l)) {
        return twists;
    }
    float h[3][3];
    scaling_block(0.0, 0.0, 0.0, twists, sigma, h);
    vec3 columns[3];
    for (int j = 0; j < 3; ++j) {
        columns[j] = lower_solve(l, vec3(h[0][j], h[1][j], h[2][j]));
    }
    float m[3][3];
    for (int i = 0; i < 3; ++i) {
        // Row i of l^-1 h, then (l^-1 h) l^-T by solving against its rows.
        vec3 row = lower_solve(l, vec3(columns[0][i], columns[1][i], columns[2][i]));
        for (int j = 0; j < 3; ++j) {
            m[i][j] = -row[j];
        }
    }
    float symmetric[3][3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            symmetric[i][j] = 0.5 * (m[i][j] + m[j][i]);
        }
    }
    float worst = sym3_eigenvalues(symmetric).x;
    return worst > 1.0 ? twists / worst : twists;
}

// The tet's stiffness at positions p0..p3 (`elastic_linearise`).
ElasticLinear elastic_linearise(ElasticTet t, vec3 p0, vec3 p1, vec3 p2, vec3 p3) {
    ElasticLinear lin;
    elastic_columns(t, p0, p1, p2, p3, lin.f0, lin.f1, lin.f2);
    lin.c0 = cross(lin.f1, lin.f2);
    lin.c1 = cross(lin.f2, lin.f0);
    lin.c2 = cross(lin.f0, lin.f1);
    float j = dot(lin.f0, lin.c0);
    float ic = dot(lin.f0, lin.f0) + dot(lin.f1, lin.f1) + dot(lin.f2, lin.f2);
    float s = 1.0 / (ic + 1.0);
    float a = t.mu * (1.0 - s);
    float b = 2.0 * t.mu * s * s;
    float kept = definite_volume_term(a, b, t.lambda, t.lambda * (j - t.alpha), lin.f0, lin.f1, lin.f2);
    float v = t.volume;
    lin.k = vec4(v * t.mu * (1.0 - s), v * 2.0 * t.mu * s * s, v * t.lambda, v * kept);
    return lin;
}

// The Frobenius norm of a matrix given by its columns.
float frobenius(vec3 m0, vec3 m1, vec3 m2) {
    return sqrt(dot(m0, m0) + dot(m1, m1) + dot(m2, m2));
}

// The tet's stiffness at p0..p3 for a later linearisation within a step
// (`elastic_relinearise`): `kept` where F moved by at most KEPT_STIFFNESS_STRAIN since,
// else taken anew.
ElasticLinear elastic_relinearise(ElasticTet t, vec3 p0, vec3 p1, vec3 p2, vec3 p3, ElasticLinear kept) {
    vec3 f0, f1, f2;
    elastic_columns(t, p0, p1, p2, p3, f0, f1, f2);
    if (frobenius(f0 - kept.f0, f1 - kept.f1, f2 - kept.f2) <= KEPT_STIFFNESS_STRAIN) {
        return kept;
    }
    return elastic_linearise(t, p0, p1, p2, p3);
}

// The stiffness `lin` times the corner moves d0..d3 (`elastic_product_strain`): V0 dP[dF] g_a
// at each corner into q0..q3, and the Frobenius norm of dF returned (the step's strain in
// the tet, the conjugate gradients' trust measure).
float elastic_product_strain(ElasticTet t, ElasticLinear lin, vec3 d0, vec3 d1, vec3 d2, vec3 d3,
                             out vec3 q0, out vec3 q1, out vec3 q2, out vec3 q3) {
    vec3 df0, df1, df2;
    elastic_columns(t, d0, d1, d2, d3, df0, df1, df2);
    vec3 dc0 = cross(df1, lin.f2) + cross(lin.f1, df2);
    vec3 dc1 = cross(df2, lin.f0) + cross(lin.f2, df0);
    vec3 dc2 = cross(df0, lin.f1) + cross(lin.f0, df1);
    float f_df = dot(lin.f0, df0) + dot(lin.f1, df1) + dot(lin.f2, df2);
    float cof_df = dot(lin.c0, df0) + dot(lin.c1, df1) + dot(lin.c2, df2);
    // Columns of V0 dP[dF].
    vec3 dp0 = df0 * lin.k.x + lin.f0 * (lin.k.y * f_df) + lin.c0 * (lin.k.z * cof_df) + dc0 * lin.k.w;
    vec3 dp1 = df1 * lin.k.x + lin.f1 * (lin.k.y * f_df) + lin.c1 * (lin.k.z * cof_df) + dc1 * lin.k.w;
    vec3 dp2 = df2 * lin.k.x + lin.f2 * (lin.k.y * f_df) + lin.c2 * (lin.k.z * cof_df) + dc2 * lin.k.w;
    q1 = dp0 * t.g1.x + dp1 * t.g1.y + dp2 * t.g1.z;
    q2 = dp0 * t.g2.x + dp1 * t.g2.y + dp2 * t.g2.z;
    q3 = dp0 * t.g3.x + dp1 * t.g3.y + dp2 * t.g3.z;
    q0 = -(q1 + q2 + q3);
    return frobenius(df0, df1, df2);
}

// The tet's energy V0 Psi(F) [J] at positions p0..p3 (`elastic_energy`).
float elastic_energy(ElasticTet t, vec3 p0, vec3 p1, vec3 p2, vec3 p3) {
    vec3 f0, f1, f2;
    elastic_columns(t, p0, p1, p2, p3, f0, f1, f2);
    float j = dot(f0, cross(f1, f2));
    float ic = dot(f0, f0) + dot(f1, f1) + dot(f2, f2);
    return t.volume
        * (0.5 * t.mu * (ic - 3.0) + 0.5 * t.lambda * (j - t.alpha) * (j - t.alpha)
           - 0.5 * t.mu * log(ic + 1.0));
}

// log(1 + x) without the cancellation of 1 + x for small x.
float log_1p(float x) {
    float u = 1.0 + x;
    return u == 1.0 ? x : log(u) * x / (u - 1.0);
}

// How much the tet's energy changes, V0 (Psi(F0 + a G) - Psi(F0)), for each step `a` of
// `steps` (up to 9; `count` used) from the corners at p0..p3 along the corner moves
// d0..d3 (G = their dF): the changes of I_C and J expanded in a (det(F + H) = det F +
// cof F : H + F : cof H + det H), so that no change is the difference of two energies
// (in float the step's energy change would drown in the tet's energy). Into `change`.
void elastic_energy_changes(ElasticTet t, vec3 p0, vec3 p1, vec3 p2, vec3 p3, vec3 d0, vec3 d1,
                            vec3 d2, vec3 d3, float steps[9], uint count, out float change[9]) {
    vec3 f0, f1, f2, g0, g1, g2;
    elastic_columns(t, p0, p1, p2, p3, f0, f1, f2);
    elastic_columns(t, d0, d1, d2, d3, g0, g1, g2);
    vec3 c0 = cross(f1, f2);
    vec3 c1 = cross(f2, f0);
    vec3 c2 = cross(f0, f1);
    float j = dot(f0, c0);
    float ic = dot(f0, f0) + dot(f1, f1) + dot(f2, f2);
    float f_g = dot(f0, g0) + dot(f1, g1) + dot(f2, g2);
    float g_g = dot(g0, g0) + dot(g1, g1) + dot(g2, g2);
    float cof_g = dot(c0, g0) + dot(c1, g1) + dot(c2, g2);
    float f_cofg = dot(f0, cross(g1, g2)) + dot(f1, cross(g2, g0)) + dot(f2, cross(g0, g1));
    float det_g = dot(g0, cross(g1, g2));
    for (uint k = 0u; k < 9u; ++k) {
        if (k >= count) {
            change[k] = 0.0;
            continue;
        }
        float a = steps[k];
        float di = a * (2.0 * f_g + a * g_g);
        float dj = a * (cof_g + a * (f_cofg + a * det_g));
        change[k] = t.volume * (0.5 * t.mu * di + 0.5 * t.lambda * dj * (2.0 * (j - t.alpha) + dj)
                                - 0.5 * t.mu * log_1p(di / (ic + 1.0)));
    }
}

#endif
