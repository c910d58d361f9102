/* SPDX-License-Identifier: MIT */
/**
 * @file test_cmocka.h
 * @brief cmocka glue shared by the host tests: includes in the order cmocka
 * needs, float/double conversions, and near-equality assertions that print
 * the failing index and both values.
 */
#ifndef SFIT_TEST_CMOCKA_H
#define SFIT_TEST_CMOCKA_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "sfit/sfit.h"
#include "test_util.h"

/** FLT_EPSILON as a double (avoids -Wdouble-promotion in tolerances). */
#define TC_FEPS 1.1920928955078125e-07

/** Fail unless |a - b| <= tol (doubles), printing what and the values. */
#define assert_near(a, b, tol, what)                                                       \
    do {                                                                                   \
        const double a_ = (double)(a), b_ = (double)(b), t_ = (double)(tol);              \
        if (!(fabs(a_ - b_) <= t_)) {                                                      \
            print_error("%s: %.10g vs %.10g (|diff| %.3g > tol %.3g)\n", (what), a_, b_,  \
                        fabs(a_ - b_), t_);                                                \
            fail();                                                                        \
        }                                                                                  \
    } while (0)

/** Fail unless every component of two 3-vectors is within tol. */
#define assert_vec3_near(a, b, tol, what)                                                  \
    do {                                                                                   \
        int i_;                                                                            \
        for (i_ = 0; i_ < 3; i_++) {                                                       \
            if (!(fabs((double)(a)[i_] - (double)(b)[i_]) <= (double)(tol))) {             \
                print_error("%s[%d]: %.10g vs %.10g (tol %.3g)\n", (what), i_,             \
                            (double)(a)[i_], (double)(b)[i_], (double)(tol));              \
                fail();                                                                    \
            }                                                                              \
        }                                                                                  \
    } while (0)

/* Round to float through a volatile: GCC 12.2 -O2 (SLP vectorizer) was
 * seen to store the unrounded doubles when a float round trip
 * `f = (float)x; d = (double)f;` of a 3-vector was inlined (tests then
 * compared the library with a reference fed different data). */
static inline void tc_to_vec3(const double x[3], sfit_vec3_t *v)
{
    int i;
    for (i = 0; i < 3; i++) {
        volatile float t = (float)x[i];
        v->v[i] = t;
    }
}

static inline void tc_to_double3(const sfit_vec3_t *v, double x[3])
{
    x[0] = (double)v->v[0];
    x[1] = (double)v->v[1];
    x[2] = (double)v->v[2];
}

/** n samples of a cap (arc = 0) or an arc (arc = 1) of tu_sample_cap() /
 * tu_sample_arc(), rounded to float into f and read back into d, so that
 * the library (f) and a double oracle (d) see the same data. */
static inline void tc_sample_set(tu_rng_t *g, int arc, size_t n, const double c[3], double r,
                                 const double axis[3], const double ref_dir[3], double theta,
                                 double sigma, sfit_vec3_t *f, double (*d)[3])
{
    size_t i;
    for (i = 0; i < n; i++) {
        double p[3];
        if (arc) {
            tu_sample_arc(g, c, r, axis, ref_dir, theta, sigma, p);
        } else {
            tu_sample_cap(g, c, r, axis, theta, sigma, p);
        }
        tc_to_vec3(p, &f[i]);
        tc_to_double3(&f[i], d[i]);
    }
}

/** Euclidean distance between a float vec3 and a double 3-vector. */
static inline double tc_dist(const sfit_vec3_t *a, const double b[3])
{
    const double d0 = (double)a->v[0] - b[0];
    const double d1 = (double)a->v[1] - b[1];
    const double d2 = (double)a->v[2] - b[2];
    return sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

#endif /* SFIT_TEST_CMOCKA_H */
