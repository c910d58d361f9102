/* SPDX-License-Identifier: MIT */
/**
 * @file tt_moments.c
 * @brief On-target: moments accumulator against the double oracle on a
 * far-away cap, merge = sequential add, rejected samples leave the state
 * bit for bit unchanged. Tolerances: tt_data.h error model (mean: 4 ulp of
 * the centre x 4; C: sum bound x trace C x 4; S: sum bound x r^3 x 4 plus the
 * mean error times 3 tr C, the first-order effect of a shifted mean on S).
 */
#include <string.h>

#include "tt_data.h"

void tt_moments(void);

static sfit_vec3_t tt_f[TT_N];
static double tt_d[TT_N][3];

static void tt_cmp_stats(const sfit_moments_t *m, size_t n, double r)
{
    sfit_vec3_t mean, s;
    sfit_mat3_t c;
    double mr[3], cr[3][3], sr[3], tr, tol_m, tol_c, tol_s;
    int i, j;
    if (!TT_EQ_INT(sfit_moments_stats(m, &mean, &c, &s), SFIT_OK)) {
        return;
    }
    (void)ref_moments(REF_C3(tt_d), n, mr, cr, sr);
    tr = cr[0][0] + cr[1][1] + cr[2][2];
    tol_m = 4.0 * 4.0 * tt_ulp(tu_norm3(tt_c) + r);
    tol_c = 4.0 * tt_sum_rel(n) * tr;
    tol_s = 4.0 * (tt_sum_rel(n) * r * r * r + tol_m * 3.0 * tr);
    for (i = 0; i < 3; i++) {
        TT_NEAR(mean.v[i], mr[i], tol_m);
        TT_NEAR(s.v[i], sr[i], tol_s);
        for (j = 0; j < 3; j++) {
            TT_NEAR(c.m[3 * i + j], cr[i][j], tol_c);
        }
    }
}

void tt_moments(void)
{
    static sfit_moments_t a, b, ref;
    sfit_moments_t save;
    sfit_vec3_t bad;
    const double r = 100.0;
    size_t i, idx = 99;

    tt_cap(7u, r, 0.25 * TU_PI, 0.5, TT_N, tt_f, tt_d);

    tt_case("moments.stats_vs_ref");
    (void)sfit_moments_init(&a);
    for (i = 0; i < TT_N; i++) {
        if (sfit_moments_add(&a, &tt_f[i]) != SFIT_OK) {
            TT_TRUE(0);
        }
    }
    TT_EQ_INT(sfit_moments_count(&a), TT_N);
    tt_cmp_stats(&a, TT_N, r);

    tt_case("moments.block_equals_adds");
    (void)sfit_moments_init(&ref);
    TT_EQ_INT(sfit_moments_add_block(&ref, tt_f, TT_N, NULL), SFIT_OK);
    TT_TRUE(memcmp(&ref, &a, sizeof a) == 0);

    tt_case("moments.merge");
    (void)sfit_moments_init(&a);
    (void)sfit_moments_init(&b);
    TT_EQ_INT(sfit_moments_add_block(&a, tt_f, 150, NULL), SFIT_OK);
    TT_EQ_INT(sfit_moments_add_block(&b, tt_f + 150, TT_N - 150, NULL), SFIT_OK);
    TT_EQ_INT(sfit_moments_merge(&a, &b), SFIT_OK);
    TT_EQ_INT(sfit_moments_count(&a), TT_N);
    tt_cmp_stats(&a, TT_N, r);

    tt_case("moments.reject_unchanged");
    save = ref;
    bad = tt_f[0];
    bad.v[1] = NAN;
    TT_EQ_INT(sfit_moments_add(&ref, &bad), SFIT_E_NONFINITE);
    bad.v[1] = INFINITY;
    TT_EQ_INT(sfit_moments_add(&ref, &bad), SFIT_E_NONFINITE);
    bad.v[1] = 1e30f;
    TT_EQ_INT(sfit_moments_add(&ref, &bad), SFIT_E_RANGE);
    TT_TRUE(memcmp(&save, &ref, sizeof ref) == 0);
    tt_f[100].v[2] = NAN;
    TT_EQ_INT(sfit_moments_add_block(&ref, tt_f, TT_N, &idx), SFIT_E_NONFINITE);
    TT_EQ_INT(idx, 100);
    TT_TRUE(memcmp(&save, &ref, sizeof ref) == 0);
    tt_f[100].v[2] = (float)tt_d[100][2];

    tt_case("moments.contract");
    TT_EQ_INT(sfit_moments_add(NULL, &tt_f[0]), SFIT_E_ARG);
    TT_EQ_INT(sfit_moments_init(NULL), SFIT_E_ARG);
    (void)sfit_moments_init(&a);
    (void)sfit_moments_add(&a, &tt_f[0]);
    TT_EQ_INT(sfit_moments_stats(&a, NULL, NULL, NULL), SFIT_E_TOO_FEW);
}
