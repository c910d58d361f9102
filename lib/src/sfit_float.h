/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_float.h
 * @brief Lowest internal layer: float helpers, validators and the two-level
 * sum shared by every module (not part of the API).
 *
 * Layers (each header includes only the ones above it in this list):
 *   sfit_float.h   config, types, port; helpers on floats and samples
 *   sfit_mat3_i.h  packed symmetric storage, SPD inverse (sfit_mat3.c)
 *   sfit_pass.h    one distance pass over a caller's samples (sfit_pass.c)
 *   sfit_moments_i.h  centred totals of an accumulator (sfit_moments.c)
 *   sfit_solve.h   the shared sphere / circle solver (sfit_solve.c)
 */
#ifndef SFIT_FLOAT_H
#define SFIT_FLOAT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "sfit/sfit_config.h"
#include "sfit/sfit_types.h"
#include "sfit_port.h"

/**
 * @brief Keeps a static function out of line where the compiler would inline
 * it into its only caller: its locals then stay off the caller's frame, so
 * that they are not on the stack during the caller's deeper calls (the
 * worst-case stack of tools/flopcount/footprint.sh). No effect elsewhere.
 */
#if defined(__GNUC__)
#define SFIT_I_NOINLINE __attribute__((noinline))
#else
#define SFIT_I_NOINLINE
#endif

/**
 * @brief The byte that holds a caller's bool (sfit_types.h, "Yes/no"): read
 * as an unsigned char, never as a bool, so that a garbage byte in a caller's
 * options or state (uninitialised RAM, a fuzzer's bytes) is a value to
 * refuse (> 1) and not undefined behaviour. The ABIs the library targets
 * store bool in one byte (tests/test_lean.c asserts it).
 */
SFIT_INLINE unsigned sfit_i_bool_byte(const bool *b)
{
    unsigned char c;
    memcpy(&c, b, sizeof c);
    return c;
}

/** @brief 1 when x is neither NaN nor Inf (bit test; no FP operation). */
SFIT_INLINE int sfit_i_isfinite(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return ((u >> 23) & 0xFFu) != 0xFFu;
}

/** @brief 1 when the three floats are finite. */
SFIT_INLINE int sfit_i_finite3(const float v[3])
{
    return sfit_i_isfinite(v[0]) && sfit_i_isfinite(v[1]) && sfit_i_isfinite(v[2]);
}

/** @brief 1 when some coordinate is NaN (bit test; no FP operation). */
SFIT_INLINE int sfit_i_has_nan3(const float v[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        uint32_t u;
        memcpy(&u, &v[i], sizeof u);
        if ((u & 0x7F800000u) == 0x7F800000u && (u & 0x007FFFFFu) != 0u) {
            return 1;
        }
    }
    return 0;
}

/** @brief A sample: SFIT_OK, SFIT_E_NONFINITE or SFIT_E_RANGE (too large). */
SFIT_INLINE sfit_status_t sfit_i_check_sample(const float x[3])
{
    sfit_status_t st = SFIT_OK;
    int i;
    for (i = 0; i < 3; i++) {
        uint32_t u, e;
        memcpy(&u, &x[i], sizeof u);
        e = (u >> 23) & 0xFFu;
        if (e == 0xFFu) {
            return SFIT_E_NONFINITE;
        }
        if (e >= (uint32_t)(127 + SFIT_COORD_MAX_EXP)) {
            st = SFIT_E_RANGE;
        }
    }
    return st;
}

/**
 * @brief A marker that may be occluded (NaN): *seen = 0 for a NaN
 * coordinate, else 1; SFIT_E_NONFINITE for +-Inf (reject at once), else
 * SFIT_OK with *range set to SFIT_E_RANGE when a coordinate is too large
 * (reported later, in the order of the status rule).
 */
SFIT_INLINE sfit_status_t sfit_i_check_marker(const float x[3], uint8_t *seen,
                                              sfit_status_t *range)
{
    sfit_status_t si;
    *seen = 0u;
    if (sfit_i_has_nan3(x)) {
        return SFIT_OK;
    }
    si = sfit_i_check_sample(x);
    if (si == SFIT_E_NONFINITE) {
        return si;
    }
    if (si != SFIT_OK) {
        *range = si;
    }
    *seen = 1u;
    return SFIT_OK;
}

/**
 * @brief A caller's array: SFIT_E_TOO_FEW below nmin, SFIT_E_RANGE above
 * UINT32_MAX, else the status of the first bad sample.
 */
sfit_status_t sfit_i_check_points(const sfit_vec3_t *pts, size_t n, size_t nmin);

/**
 * @brief A fit handed in by the caller: a non-finite centre or radius is
 * SFIT_E_NONFINITE, a radius <= 0 SFIT_E_ARG (radius NULL: centre only).
 */
sfit_status_t sfit_i_check_fit(const sfit_vec3_t *center, const float *radius);

/** @brief One sample offered to a state: SFIT_E_ARG for NULL, else as sfit_i_check_sample(). */
SFIT_INLINE sfit_status_t sfit_i_check_add(const void *state, const sfit_vec3_t *x)
{
    return (state == NULL || x == NULL) ? SFIT_E_ARG : sfit_i_check_sample(x->v);
}

/** @brief 1 when a centre and radius are finite (a result may be written). */
SFIT_INLINE int sfit_i_sphere_finite(const sfit_vec3_t *c, float r)
{
    return sfit_i_finite3(c->v) && sfit_i_isfinite(r);
}

/** @brief a . b for 3-vectors. */
SFIT_INLINE float sfit_i_dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/** @brief u := u / |u| with *len = |u|; 0 (u unchanged) when |u| is 0 or NaN. */
SFIT_INLINE int sfit_i_unit3(float u[3], float *len)
{
    int i;
    *len = SFIT_SQRTF(sfit_i_dot3(u, u));
    if (!(*len > 0.0f)) {
        return 0;
    }
    for (i = 0; i < 3; i++) {
        u[i] /= *len;
    }
    return 1;
}

/**
 * @brief Distance d = |x - c| and unit direction u = (x - c)/d; 0 (u, d
 * undefined) when x is at c.
 */
SFIT_INLINE int sfit_i_dist_dir(const float x[3], const float c[3], float *d, float u[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        u[i] = x[i] - c[i];
    }
    return sfit_i_unit3(u, d);
}

/**
 * @brief Noise variance from the residual variance s2 of a sphere of radius
 * r: the root of E s^2 = sigma^2 - sigma^4 / r^2 (docs/api.md), clamped so
 * that sigma^2 <= 2 s^2.
 */
SFIT_INLINE float sfit_i_curvature_var(float s2, float r)
{
    const float q = 4.0f * s2 / (r * r);
    return 2.0f * s2 / (1.0f + SFIT_SQRTF((q < 1.0f) ? (1.0f - q) : 0.0f));
}

/** Constant K of the widening below (docs/coverage.md, rule 7; a build may
 * set another for a study, e.g. -DSFIT_I_COV_WIDEN_K=2.5f, as
 * SFIT_COV_MAX_TRUST). */
#ifndef SFIT_I_COV_WIDEN_K
#define SFIT_I_COV_WIDEN_K 3.5f
#endif

/**
 * @brief Factor by which a centre covariance resting on an estimated noise
 * level (self-calibrated sandwich, refined recipe) is widened (issue 28,
 * docs/coverage.md rule 7): 1 + K (sigma_hat / r)^2 s / s(100), s =
 * sqrt(2 / (N - 4)), i.e. 1 + K (v / r^2) sqrt(96 / (N - 4)) (N - 4 taken
 * at least 10). v = sigma_hat^2 >= 0, r > 0 the radius, n = N.
 */
float sfit_i_cov_widen(float v, float r, size_t n); /* sfit_uncert.c */

/** @brief Most quantities one two-level sum carries. */
#define SFIT_I_SUM_MAX 13

/**
 * @brief Two-level sum of up to SFIT_I_SUM_MAX floats: an inner sum of at
 * most SFIT_SUM_BLOCK terms is folded into the outer one, so each rounding
 * is relative to a partial sum of about sqrt(N) terms instead of N.
 */
typedef struct sfit_i_sum {
    float tot[SFIT_I_SUM_MAX]; /**< outer level (the result after sfit_i_sum_end) */
    float blk[SFIT_I_SUM_MAX]; /**< inner level */
    uint32_t inblk;            /**< terms in the inner level */
} sfit_i_sum_t;

/** @brief Fold the inner level into tot (the sums are then in tot). */
SFIT_INLINE void sfit_i_sum_end(sfit_i_sum_t *s, int k)
{
    int j;
    for (j = 0; j < k; j++) {
        s->tot[j] += s->blk[j];
        s->blk[j] = 0.0f;
    }
    s->inblk = 0u;
}

/** @brief Count one term added to blk[0..k-1] by the caller (folds a full
 * inner level). */
SFIT_INLINE void sfit_i_sum_next(sfit_i_sum_t *s, int k)
{
    if (++s->inblk == (uint32_t)SFIT_SUM_BLOCK) {
        sfit_i_sum_end(s, k);
    }
}

/** @brief Add one term of k quantities. */
SFIT_INLINE void sfit_i_sum_add(sfit_i_sum_t *s, const float *v, int k)
{
    int j;
    SFIT_ASSERT(k <= SFIT_I_SUM_MAX);
    for (j = 0; j < k; j++) {
        s->blk[j] += v[j];
    }
    sfit_i_sum_next(s, k);
}

#endif /* SFIT_FLOAT_H */
