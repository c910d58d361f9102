/* SPDX-License-Identifier: MIT */
/**
 * @file tt_mat3.c
 * @brief On-target: Cholesky and Jacobi known answers and invariants.
 * Tolerances: a backward-stable 3x3 factorisation / rotation sequence has
 * a residual of a few TT_EPS x |A| (Higham, Accuracy and Stability,
 * ch. 10 and 8); we allow 16 TT_EPS |A|max (Cholesky, Jacobi
 * reconstruction, orthogonality) and compare eigenvalues to the double
 * oracle within the same bound (Weyl: a perturbation E moves each
 * eigenvalue of a symmetric matrix by at most |E|).
 */
#include <string.h>

#include "tt_data.h"

void tt_mat3(void);

static void tt_rand_spd(tu_rng_t *g, const double e[3], sfit_mat3_t *a)
{
    double q[4], n = 0.0, v[3][3];
    int i, j, k;
    for (i = 0; i < 4; i++) {
        q[i] = tu_rng_gauss(g);
        n += q[i] * q[i];
    }
    n = sqrt(n);
    for (i = 0; i < 4; i++) {
        q[i] /= n;
    }
    /* rotation matrix of the unit quaternion (w, x, y, z) = q */
    v[0][0] = 1 - 2 * (q[2] * q[2] + q[3] * q[3]);
    v[0][1] = 2 * (q[1] * q[2] - q[3] * q[0]);
    v[0][2] = 2 * (q[1] * q[3] + q[2] * q[0]);
    v[1][0] = 2 * (q[1] * q[2] + q[3] * q[0]);
    v[1][1] = 1 - 2 * (q[1] * q[1] + q[3] * q[3]);
    v[1][2] = 2 * (q[2] * q[3] - q[1] * q[0]);
    v[2][0] = 2 * (q[1] * q[3] - q[2] * q[0]);
    v[2][1] = 2 * (q[2] * q[3] + q[1] * q[0]);
    v[2][2] = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
    for (i = 0; i < 3; i++) {
        for (j = 0; j <= i; j++) {
            double s = 0.0;
            for (k = 0; k < 3; k++) {
                s += v[i][k] * e[k] * v[j][k];
            }
            a->m[3 * i + j] = (float)s;
            a->m[3 * j + i] = (float)s;
        }
    }
}

static double tt_amax(const sfit_mat3_t *a)
{
    double m = 0.0;
    int i;
    for (i = 0; i < 9; i++) {
        if (fabs((double)a->m[i]) > m) {
            m = fabs((double)a->m[i]);
        }
    }
    return m;
}

void tt_mat3(void)
{
    static const double spectra[4][3] = {
        {1.0, 2.0, 3.0}, {1e-3, 1.0, 1e3}, {5.0, 5.0, 5.0}, {0.25, 40.0, 41.0}};
    tu_rng_t g;
    sfit_mat3_t a, l, v;
    sfit_vec3_t w, b, x;
    int t, i, j, k;

    tt_case("mat3.eig_known");
    memset(&a, 0, sizeof a);
    a.m[0] = 2.0f; a.m[1] = 1.0f; a.m[3] = 1.0f; a.m[4] = 2.0f; a.m[8] = 5.0f;
    if (TT_EQ_INT(sfit_mat3_eig_sym(&a, &w, &v), SFIT_OK)) {
        TT_NEAR(w.v[0], 1.0, 16.0 * TT_EPS * 5.0);
        TT_NEAR(w.v[1], 3.0, 16.0 * TT_EPS * 5.0);
        TT_NEAR(w.v[2], 5.0, 16.0 * TT_EPS * 5.0);
        /* eigenvector of 5 is +-e_z */
        TT_NEAR(fabs((double)v.m[8]), 1.0, 16.0 * TT_EPS);
    }

    tu_rng_seed(&g, 20240601u);
    for (t = 0; t < 4; t++) {
        double am, ad[3][3], wr[3], vr[3][3];
        tt_rand_spd(&g, spectra[t], &a);
        am = tt_amax(&a);
        tt_case("mat3.chol");
        if (TT_EQ_INT(sfit_mat3_chol(&a, &l), SFIT_OK)) {
            for (i = 0; i < 3; i++) {
                for (j = 0; j <= i; j++) {
                    double s = 0.0;
                    for (k = 0; k < 3; k++) {
                        s += (double)l.m[3 * i + k] * (double)l.m[3 * j + k];
                    }
                    TT_NEAR(s, a.m[3 * i + j], 16.0 * TT_EPS * am);
                }
            }
            TT_TRUE(l.m[1] == 0.0f && l.m[2] == 0.0f && l.m[5] == 0.0f);
            tt_case("mat3.chol_solve");
            b.v[0] = 1.0f; b.v[1] = -2.0f; b.v[2] = 0.5f;
            if (TT_EQ_INT(sfit_mat3_chol_solve(&l, &b, &x), SFIT_OK)) {
                /* residual |A x - b| <= 16 eps |A| |x| (backward stable) */
                double xn = fabs((double)x.v[0]) + fabs((double)x.v[1]) + fabs((double)x.v[2]);
                for (i = 0; i < 3; i++) {
                    double s = 0.0;
                    for (k = 0; k < 3; k++) {
                        s += (double)a.m[3 * i + k] * (double)x.v[k];
                    }
                    TT_NEAR(s, b.v[i], 16.0 * TT_EPS * am * xn);
                }
            }
        }
        tt_case("mat3.eig");
        if (TT_EQ_INT(sfit_mat3_eig_sym(&a, &w, &v), SFIT_OK)) {
            for (i = 0; i < 3; i++) {
                for (j = 0; j < 3; j++) {
                    double s = 0.0, o = 0.0;
                    for (k = 0; k < 3; k++) {
                        s += (double)v.m[3 * i + k] * (double)w.v[k] * (double)v.m[3 * j + k];
                        o += (double)v.m[3 * k + i] * (double)v.m[3 * k + j];
                    }
                    TT_NEAR(s, a.m[3 * i + j], 16.0 * TT_EPS * am); /* V D V^T = A */
                    TT_NEAR(o, i == j ? 1.0 : 0.0, 16.0 * TT_EPS);  /* V^T V = I */
                    ad[i][j] = (double)a.m[3 * i + j];
                }
            }
            ref_sym3_eig(REF_C3(ad), wr, vr);
            for (i = 0; i < 3; i++) {
                TT_NEAR(w.v[i], wr[i], 16.0 * TT_EPS * am);
            }
            TT_TRUE(w.v[0] <= w.v[1] && w.v[1] <= w.v[2]);
        }
    }

    tt_case("mat3.errors");
    memset(&a, 0, sizeof a);
    a.m[0] = 1.0f; a.m[4] = -1.0f; a.m[8] = 1.0f; /* indefinite */
    memset(&l, 0x5A, sizeof l);
    v = l;
    TT_EQ_INT(sfit_mat3_chol(&a, &l), SFIT_E_NOT_POSDEF);
    TT_TRUE(memcmp(&l, &v, sizeof l) == 0); /* output untouched */
    TT_EQ_INT(sfit_mat3_chol(NULL, &l), SFIT_E_ARG);
    TT_EQ_INT(sfit_mat3_chol_solve(&l, NULL, &x), SFIT_E_ARG);
    a.m[4] = NAN;
    TT_EQ_INT(sfit_mat3_eig_sym(&a, &w, &v), SFIT_E_NONFINITE);
    TT_EQ_INT(sfit_mat3_eig_sym(&a, NULL, &v), SFIT_E_ARG);
}
