/* SPDX-License-Identifier: MIT */
/**
 * @file test_mat3.c
 * @brief Cholesky and Jacobi kernels: invariants (L L^T = A, V D V^T = A,
 * V^T V = I), agreement with the double reference, every error path.
 */
#include "test_cmocka.h"

#include <float.h>
#include <string.h>

#include "sfit_ref.h"

/* Random symmetric matrix V diag(e) V^T with a random rotation V (double),
 * rounded to float. */
static void rand_sym(tu_rng_t *g, const double e[3], sfit_mat3_t *a, double ad[3][3])
{
    double q[3], n, v[3][3];
    int i, j, k;
    /* Random rotation from a random unit quaternion. */
    double w = tu_rng_gauss(g), x = tu_rng_gauss(g), y = tu_rng_gauss(g), z = tu_rng_gauss(g);
    n = sqrt(w * w + x * x + y * y + z * z);
    w /= n; x /= n; y /= n; z /= n;
    v[0][0] = 1 - 2 * (y * y + z * z); v[0][1] = 2 * (x * y - z * w); v[0][2] = 2 * (x * z + y * w);
    v[1][0] = 2 * (x * y + z * w); v[1][1] = 1 - 2 * (x * x + z * z); v[1][2] = 2 * (y * z - x * w);
    v[2][0] = 2 * (x * z - y * w); v[2][1] = 2 * (y * z + x * w); v[2][2] = 1 - 2 * (x * x + y * y);
    (void)q;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double s = 0.0;
            for (k = 0; k < 3; k++) {
                s += v[i][k] * e[k] * v[j][k];
            }
            ad[i][j] = s;
        }
    }
    /* Symmetrise exactly, then round to float; the double copy is the
     * float matrix itself so both sides see the same input. */
    for (i = 0; i < 3; i++) {
        for (j = 0; j <= i; j++) {
            const float f = (float)(0.5 * (ad[i][j] + ad[j][i]));
            a->m[3 * i + j] = f;
            a->m[3 * j + i] = f;
        }
    }
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            ad[i][j] = (double)a->m[3 * i + j];
        }
    }
}

static double frob(double a[3][3])
{
    double s = 0.0;
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            s += a[i][j] * a[i][j];
        }
    }
    return sqrt(s);
}

static void test_chol_invariant_and_solve(void **state)
{
    tu_rng_t g;
    int t;
    (void)state;
    tu_rng_seed(&g, 1);
    for (t = 0; t < 2000; t++) {
        /* Condition numbers up to 1e4: float Cholesky keeps ~1e-7 * cond. */
        const double e[3] = {pow(10.0, -4.0 * tu_rng_uniform(&g)), 0.3 + tu_rng_uniform(&g), 1.0};
        sfit_mat3_t a, l;
        double ad[3][3], nrm, x_ref[3], bd[3];
        sfit_vec3_t b, x;
        int i, j, k;
        rand_sym(&g, e, &a, ad);
        assert_int_equal(sfit_mat3_chol(&a, &l), SFIT_OK);
        nrm = frob(ad);
        /* Upper triangle zero, positive diagonal, L L^T = A. */
        assert_true(l.m[1] == 0.0f && l.m[2] == 0.0f && l.m[5] == 0.0f);
        for (i = 0; i < 3; i++) {
            assert_true(l.m[4 * i] > 0.0f);
            for (j = 0; j < 3; j++) {
                double s = 0.0;
                for (k = 0; k < 3; k++) {
                    s += (double)l.m[3 * i + k] * (double)l.m[3 * j + k];
                }
                assert_near(s, ad[i][j], 8.0 * TC_FEPS * nrm, "L L^T");
            }
        }
        /* Solve vs the exact double solution: error <= k * eps * cond. */
        for (i = 0; i < 3; i++) {
            b.v[i] = (float)(2.0 * tu_rng_uniform(&g) - 1.0);
            bd[i] = (double)b.v[i];
        }
        assert_int_equal(sfit_mat3_chol_solve(&l, &b, &x), SFIT_OK);
        {
            /* x_ref = A^-1 b via the reference eigen-decomposition. */
            double w[3], v[3][3], y[3];
            ref_sym3_eig(REF_C3(ad), w, v);
            for (k = 0; k < 3; k++) {
                y[k] = (v[0][k] * bd[0] + v[1][k] * bd[1] + v[2][k] * bd[2]) / w[k];
            }
            for (i = 0; i < 3; i++) {
                x_ref[i] = v[i][0] * y[0] + v[i][1] * y[1] + v[i][2] * y[2];
            }
            {
                const double xn = tu_norm3(x_ref);
                const double cond = w[2] / w[0];
                for (i = 0; i < 3; i++) {
                    assert_near(x.v[i], x_ref[i], 16.0 * TC_FEPS * cond * xn, "chol_solve");
                }
            }
        }
    }
}

static void test_chol_known(void **state)
{
    /* A = L L^T with L = [[2,0,0],[1,3,0],[-1,2,4]]: exact in float. */
    const sfit_mat3_t a = {{4, 2, -2, 2, 10, 5, -2, 5, 21}};
    const float lx[9] = {2, 0, 0, 1, 3, 0, -1, 2, 4};
    sfit_mat3_t l;
    sfit_vec3_t b = {{2.0f, 12.0f, 24.0f}}, x; /* A * (1,1,1)^T = (4,17,24)... */
    (void)state;
    assert_int_equal(sfit_mat3_chol(&a, &l), SFIT_OK);
    assert_memory_equal(l.m, lx, sizeof lx);
    b.v[0] = 4.0f; b.v[1] = 17.0f; b.v[2] = 24.0f;
    assert_int_equal(sfit_mat3_chol_solve(&l, &b, &x), SFIT_OK);
    assert_vec3_near(x.v, ((const double[3]){1.0, 1.0, 1.0}), 1e-6, "known solve");
    /* In-place: x may alias b. */
    assert_int_equal(sfit_mat3_chol_solve(&l, &b, &b), SFIT_OK);
    assert_vec3_near(b.v, ((const double[3]){1.0, 1.0, 1.0}), 1e-6, "aliased solve");
    /* a and l may alias. */
    l = a;
    assert_int_equal(sfit_mat3_chol(&l, &l), SFIT_OK);
    assert_memory_equal(l.m, lx, sizeof lx);
}

static void test_chol_errors_leave_output(void **state)
{
    const sfit_mat3_t bad[] = {
        {{0, 0, 0, 0, 0, 0, 0, 0, 0}},           /* zero */
        {{1, 0, 0, 0, -1, 0, 0, 0, 1}},          /* indefinite */
        {{1, 2, 0, 2, 1, 0, 0, 0, 1}},           /* indefinite via off-diagonal */
        {{1, 0, 0, 0, 1, 0, 0, 0, 1e-9f}},       /* pivot below the relative threshold */
        {{NAN, 0, 0, 0, 1, 0, 0, 0, 1}},
        {{1, 0, 0, NAN, 1, 0, 0, 0, 1}},         /* NaN off-diagonal (lower) */
        {{1, 0, 0, 0, 1, 0, INFINITY, 0, 1}},
        {{1, 0, 0, 0, 1, 0, 0, NAN, 1}},
        {{INFINITY, 0, 0, 0, 1, 0, 0, 0, 1}},
    };
    size_t i;
    (void)state;
    for (i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sfit_mat3_t l, sentinel;
        memset(&sentinel, 0xA5, sizeof sentinel);
        l = sentinel;
        assert_int_equal(sfit_mat3_chol(&bad[i], &l), SFIT_E_NOT_POSDEF);
        assert_memory_equal(&l, &sentinel, sizeof l);
    }
    {
        sfit_mat3_t l;
        sfit_vec3_t v = {{1, 2, 3}};
        assert_int_equal(sfit_mat3_chol(NULL, &l), SFIT_E_ARG);
        assert_int_equal(sfit_mat3_chol(&bad[0], NULL), SFIT_E_ARG);
        assert_int_equal(sfit_mat3_chol_solve(NULL, &v, &v), SFIT_E_ARG);
        assert_int_equal(sfit_mat3_chol_solve(&l, NULL, &v), SFIT_E_ARG);
        assert_int_equal(sfit_mat3_chol_solve(&l, &v, NULL), SFIT_E_ARG);
    }
    /* A factor not from sfit_mat3_chol() (a zero or NaN pivot) or a
     * non-finite right-hand side: SFIT_E_RANGE, x untouched (it was
     * SFIT_OK with Inf / NaN in x). */
    {
        const sfit_mat3_t good = {{2, 0, 0, 1, 3, 0, -1, 2, 4}};
        sfit_mat3_t l;
        sfit_vec3_t v = {{1, 2, 3}}, x, xs;
        int k;
        memset(&xs, 0x5A, sizeof xs);
        for (k = 0; k < 4; k++) {
            l = good;
            v.v[0] = 1.0f;
            if (k == 0) {
                l.m[4] = 0.0f;
            } else if (k == 1) {
                l.m[8] = NAN;
            } else if (k == 2) {
                v.v[0] = INFINITY;
            } else {
                l.m[0] = 1e-30f; /* overflow */
                v.v[0] = 1e30f;
            }
            x = xs;
            assert_int_equal(sfit_mat3_chol_solve(&l, &v, &x), SFIT_E_RANGE);
            assert_memory_equal(&x, &xs, sizeof x);
        }
    }
}

static void check_eig(const sfit_mat3_t *a, double ad[3][3], double rel)
{
    sfit_vec3_t w;
    sfit_mat3_t v;
    double wr[3], vr[3][3], nrm = frob(ad);
    int i, j, k;

    assert_int_equal(sfit_mat3_eig_sym(a, &w, &v), SFIT_OK);
    assert_true(w.v[0] <= w.v[1] && w.v[1] <= w.v[2]);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double vtv = 0.0, vdv = 0.0;
            for (k = 0; k < 3; k++) {
                vtv += (double)v.m[3 * k + i] * (double)v.m[3 * k + j];
                vdv += (double)v.m[3 * i + k] * (double)w.v[k] * (double)v.m[3 * j + k];
            }
            assert_near(vtv, i == j ? 1.0 : 0.0, 8.0 * TC_FEPS, "V^T V = I");
            assert_near(vdv, ad[i][j], rel * nrm, "V D V^T = A");
        }
    }
    ref_sym3_eig(REF_C3(ad), wr, vr);
    for (i = 0; i < 3; i++) {
        /* Eigenvalues are perturbed by at most ~eps * ||A|| (Weyl). */
        assert_near(w.v[i], wr[i], rel * nrm, "eigenvalue vs reference");
    }
}

static void test_eig_random(void **state)
{
    tu_rng_t g;
    int t;
    (void)state;
    tu_rng_seed(&g, 2);
    for (t = 0; t < 5000; t++) {
        double e[3], ad[3][3];
        sfit_mat3_t a;
        int kind = t % 5;
        e[0] = 2.0 * tu_rng_uniform(&g) - 1.0;
        e[1] = 2.0 * tu_rng_uniform(&g) - 1.0;
        e[2] = 2.0 * tu_rng_uniform(&g) - 1.0;
        if (kind == 1) { e[1] = e[0]; }                       /* repeated pair */
        if (kind == 2) { e[1] = e[0]; e[2] = e[0]; }          /* all equal */
        if (kind == 3) { e[0] = 1e-6 * e[0]; }                /* wide spread */
        if (kind == 4) { e[0] *= 1e3; e[1] *= 1e-3; }         /* scaled */
        rand_sym(&g, e, &a, ad);
        check_eig(&a, ad, 8.0 * TC_FEPS);
    }
}

static void test_eig_special(void **state)
{
    const sfit_mat3_t z = {{0, 0, 0, 0, 0, 0, 0, 0, 0}};
    const sfit_mat3_t d = {{3, 0, 0, 0, -1, 0, 0, 0, 2}};
    const sfit_mat3_t tiny = {{1e-30f, 1e-31f, 0, 1e-31f, 2e-30f, 0, 0, 0, 3e-30f}};
    const sfit_mat3_t big = {{1e30f, 1e29f, 0, 1e29f, 2e30f, 1e28f, 0, 1e28f, 3e30f}};
    /* Off-diagonal much larger than the diagonal difference (theta -> 0)
     * and the reverse (theta huge). */
    const sfit_mat3_t offd = {{1, 1e6f, 0, 1e6f, 1, 0, 0, 0, 1}};
    const sfit_mat3_t hugetheta = {{1e30f, 1e-10f, 0, 1e-10f, -1e30f, 0, 0, 0, 0}};
    const sfit_mat3_t *cases[] = {&z, &d, &tiny, &big, &offd, &hugetheta};
    sfit_vec3_t w;
    size_t i;
    (void)state;
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double ad[3][3];
        int r, c;
        for (r = 0; r < 3; r++) {
            for (c = 0; c < 3; c++) {
                ad[r][c] = (double)cases[i]->m[3 * (r > c ? r : c) + (r > c ? c : r)];
            }
        }
        check_eig(cases[i], ad, 8.0 * TC_FEPS);
    }
    /* v may be NULL. */
    assert_int_equal(sfit_mat3_eig_sym(&d, &w, NULL), SFIT_OK);
    assert_vec3_near(w.v, ((const double[3]){-1.0, 2.0, 3.0}), 0.0, "diagonal");
}

static void test_eig_errors(void **state)
{
    sfit_mat3_t a = {{1, 0, 0, 0, 1, 0, 0, 0, 1}}, v, vs;
    sfit_vec3_t w, ws;
    (void)state;
    assert_int_equal(sfit_mat3_eig_sym(NULL, &w, &v), SFIT_E_ARG);
    assert_int_equal(sfit_mat3_eig_sym(&a, NULL, &v), SFIT_E_ARG);
    memset(&ws, 0x5A, sizeof ws);
    memset(&vs, 0x5A, sizeof vs);
    w = ws;
    v = vs;
    a.m[3] = NAN;
    assert_int_equal(sfit_mat3_eig_sym(&a, &w, &v), SFIT_E_NONFINITE);
    a.m[3] = 0.0f;
    a.m[8] = -INFINITY;
    assert_int_equal(sfit_mat3_eig_sym(&a, &w, &v), SFIT_E_NONFINITE);
    assert_memory_equal(&w, &ws, sizeof w);
    assert_memory_equal(&v, &vs, sizeof v);
    {
        /* Finite but near FLT_MAX: a rotation overflows (fuzz finding: an
         * infinite eigenvalue came back with SFIT_OK). */
        const sfit_mat3_t huge = {{3e38f, 1e38f, 2e38f, 1e38f, -3e38f, 1e37f, 2e38f, 1e37f, 3e38f}};
        assert_int_equal(sfit_mat3_eig_sym(&huge, &w, &v), SFIT_E_RANGE);
        assert_memory_equal(&w, &ws, sizeof w);
    }
}

static void test_status_names(void **state)
{
    (void)state;
    assert_string_equal(sfit_status_str(SFIT_OK), "ok");
    assert_string_equal(sfit_status_str(SFIT_E_ARG), "bad_argument");
    assert_string_equal(sfit_status_str(SFIT_E_TOO_FEW), "too_few_samples");
    assert_string_equal(sfit_status_str(SFIT_E_NOT_POSDEF), "not_positive_definite");
    assert_string_equal(sfit_status_str(SFIT_E_NO_CONVERGENCE), "no_convergence");
    assert_string_equal(sfit_status_str(SFIT_E_DEGENERATE), "degenerate");
    assert_string_equal(sfit_status_str(SFIT_E_NONFINITE), "non_finite");
    assert_string_equal(sfit_status_str(SFIT_E_RANGE), "out_of_range");
    assert_string_equal(sfit_status_str((sfit_status_t)-99), "unknown");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_chol_known),
        cmocka_unit_test(test_chol_invariant_and_solve),
        cmocka_unit_test(test_chol_errors_leave_output),
        cmocka_unit_test(test_eig_random),
        cmocka_unit_test(test_eig_special),
        cmocka_unit_test(test_eig_errors),
        cmocka_unit_test(test_status_names),
    };
    return cmocka_run_group_tests_name("mat3", tests, NULL, NULL);
}
