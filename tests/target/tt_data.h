/* SPDX-License-Identifier: MIT */
/**
 * @file tt_data.h
 * @brief Test data for the on-target tests: samples drawn in double with
 * tests/test_util.h (splitmix64, fixed seeds), rounded to float once; the
 * double copy is the float data itself, so the library and the double
 * oracle (tests/ref) see the same input.
 *
 * Tolerances (tt_tol_*) follow one float error model, stated here once:
 * every stored float carries a relative rounding of FLT_EPSILON/2; the
 * moments accumulator sums blocks of B = SFIT_SUM_BLOCK samples and
 * then N/B blocks, so a centred sum of N terms bounded by T is off by at
 * most (B + N/B + 8) FLT_EPSILON T (8: the merge and solve steps); the
 * centre is then origin + (d + w): one more rounding of |c|, plus the
 * relative error of C^-1 S amplified by the condition number kappa of C.
 * Each tolerance is that bound times 4 (a margin for the few steps the
 * model lumps together), never fitted to observed errors.
 */
#ifndef SFIT_TT_DATA_H
#define SFIT_TT_DATA_H

#include <float.h>
#include <math.h>
#include <stddef.h>

#include "sfit/sfit.h"
#include "sfit_ref.h"
#include "test_util.h"
#include "tt.h"

#define TT_N 400

/** FLT_EPSILON as a double (no implicit promotion). */
#define TT_EPS ((double)FLT_EPSILON)

static const double tt_c[3] = {1500.0, -2000.0, 1000.0}; /* |c| = 2693 mm */
static const double tt_z[3] = {0.3, -0.2, 1.0};           /* cap axis */

/** Round to float and copy back. */
static inline void tt_store(const double p[3], sfit_vec3_t *f, double d[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        f->v[k] = (float)p[k];
        d[k] = (double)f->v[k];
    }
}

/** n samples on a cap of half-angle theta (radians), radius r, noise sigma. */
static inline void tt_cap(uint64_t seed, double r, double theta, double sigma, size_t n,
                          sfit_vec3_t *f, double (*d)[3])
{
    tu_rng_t g;
    size_t i;
    tu_rng_seed(&g, seed);
    for (i = 0; i < n; i++) {
        double p[3];
        tu_sample_cap(&g, tt_c, r, tt_z, theta, sigma, p);
        tt_store(p, &f[i], d[i]);
    }
}

/** Unit of the last place of x in float. */
static inline double tt_ulp(double x)
{
    int e;
    (void)frexp(fabs(x), &e);
    return ldexp(1.0, e - 24);
}

/** Relative error bound of an accumulated centred sum of n samples. */
static inline double tt_sum_rel(size_t n)
{
    return ((double)SFIT_SUM_BLOCK + (double)n / (double)SFIT_SUM_BLOCK + 8.0)
           * TT_EPS;
}

/** Centre tolerance: 4 x (4 ulp of the far centre + kappa * sum error * r). */
static inline double tt_tol_centre(size_t n, double r, double kappa)
{
    return 4.0 * (4.0 * tt_ulp(tu_norm3(tt_c) + r) + kappa * tt_sum_rel(n) * r);
}

/** kappa = lambda_max / lambda_min of the covariance of d (double). */
static inline double tt_kappa(const double (*d)[3], size_t n)
{
    double m[3], c[3][3], s[3], w[3], v[3][3];
    if (ref_moments(d, n, m, c, s) != 0) {
        return 1e30;
    }
    ref_sym3_eig(REF_C3(c), w, v);
    return w[2] / w[0];
}

#endif /* SFIT_TT_DATA_H */
