/* SPDX-License-Identifier: MIT */
/**
 * @file test_capset.h
 * @brief The far-offset cap / arc sample set of test_noise.c and
 * test_coverage.c (one translation unit each): the float samples g_fpts,
 * the same values in double g_pts, and make_pts() that draws them.
 */
#ifndef SFIT_TEST_CAPSET_H
#define SFIT_TEST_CAPSET_H

#include "test_cmocka.h"

#define NMAX 100000
static double g_pts[NMAX][3];
static sfit_vec3_t g_fpts[NMAX];

static const double k_center[3] = {2700.0, -1200.0, 800.0}; /* |c| = 3061 mm */
static const double k_axis[3] = {0.267261241912424, 0.534522483824849, 0.801783725737273};
static const double k_ref_dir[3] = {1.0, 0.0, 0.0};

#define DEG (TU_PI / 180.0)

/* n samples (cap or arc), rounded to float; g_pts holds exactly the float
 * values so library and oracle see the same data. */
static void make_pts(tu_rng_t *g, int arc, size_t n, double r, double theta, double sigma)
{
    tc_sample_set(g, arc, n, k_center, r, k_axis, k_ref_dir, theta, sigma, g_fpts, g_pts);
}

#endif /* SFIT_TEST_CAPSET_H */
