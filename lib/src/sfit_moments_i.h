/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_moments_i.h
 * @brief Internal accumulator layer: the centred totals of an accumulator
 * (sfit_moments.c).
 */
#ifndef SFIT_MOMENTS_I_H
#define SFIT_MOMENTS_I_H

#include "sfit/sfit_moments.h"
#include "sfit_mat3_i.h"

/** @brief The accumulator's total centred moments including the open block. */
void sfit_i_moments_total(const sfit_moments_t *m, sfit_cmom_t *out);

/** @brief m := the n samples of a caller's array (statuses of sfit_moments_add_block()). */
sfit_status_t sfit_i_moments_of(const sfit_vec3_t *pts, size_t n, sfit_moments_t *m);

/** @brief st, or SFIT_E_TOO_FEW when st is SFIT_OK and m holds < SFIT_MIN_SAMPLES samples. */
SFIT_INLINE sfit_status_t sfit_i_enough(sfit_status_t st, const sfit_moments_t *m)
{
    return (st == SFIT_OK && sfit_moments_count(m) < SFIT_MIN_SAMPLES) ? SFIT_E_TOO_FEW : st;
}

/**
 * @brief C = M2/(N-1) (full) and b = M3/(2(N-1)) of a total with n >= 2.
 */
void sfit_i_cmom_system(const sfit_cmom_t *t, sfit_mat3_t *c, float b[3]);

/** @brief The linear system of a total: C, b and its mean. */
typedef struct sfit_i_msys {
    sfit_mat3_t c;   /**< C = M2/(N-1), symmetric: its lower triangle (the upper one is
                          not written by sfit_i_moments_system(); the solvers read the
                          lower one, the full solver mirrors it) */
    sfit_vec3_t rhs; /**< b = S/2 = M3/(2(N-1)) */
    float d[3];      /**< mean - origin */
} sfit_i_msys_t;

/**
 * @brief The fit system s of the totals tot and open block blk (raw sums of
 * an accumulator; NULL when there is none) of >= 2 samples (C, lower
 * triangle only, and b as
 * sfit_i_cmom_system()); returns the sample count (the totals stay in this
 * function's frame, off the solver's stack path: stack trick 5,
 * sfit_solve.h).
 */
uint32_t sfit_i_moments_system(const sfit_cmom_t *tot, const sfit_cmom_t *blk, sfit_i_msys_t *s);

/** @brief The samples of an accumulator reduced to its total: origin + t. */
typedef struct sfit_i_total {
    float origin[3]; /**< the accumulator's origin */
    sfit_cmom_t t;   /**< its total centred moments (sfit_i_moments_total()) */
} sfit_i_total_t;

/**
 * @brief The total of the n samples of a caller's array (the accumulator
 * of sfit_i_moments_of() stays in this function's frame); statuses of
 * sfit_moments_add_block().
 */
sfit_status_t sfit_i_points_total(const sfit_vec3_t *pts, size_t n, sfit_i_total_t *out);

#endif /* SFIT_MOMENTS_I_H */
