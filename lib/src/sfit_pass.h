/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_pass.h
 * @brief Internal: one pass over a caller's samples that sums rows built
 * from each sample's distance and direction to a centre (sfit_pass.c).
 * Used by the geometric refinement, the uncertainties and the
 * self-calibration; not part of the API.
 */
#ifndef SFIT_PASS_H
#define SFIT_PASS_H

#include "sfit_float.h"

/**
 * @brief Builds the row t (k floats) of sample x at distance d > 0 and
 * unit direction u from the centre; ctx is the caller's.
 */
typedef void (*sfit_i_row_fn)(void *ctx, const float x[3], float d, const float u[3], float *t);

/** @brief What sfit_i_row_dirs() reads and keeps. */
typedef struct sfit_i_dirs {
    float ref;   /**< reference distance (set from the first sample if first) */
    int first;   /**< 1: ref := the first sample's distance */
    int k;       /**< 4: (u, d - ref); 5: also (d - ref)^2 */
} sfit_i_dirs_t;

/** @brief Rows (u, d - ref[, (d - ref)^2]) (ctx: sfit_i_dirs_t). */
void sfit_i_row_dirs(void *ctx, const float x[3], float d, const float u[3], float *t);

/**
 * @brief s := the two-level sum over the n samples of row(ctx, x, d, u),
 * k floats each, with d and u taken from c (p NULL) or from c + p, formed
 * as (x - c) - p so that a small offset keeps its digits.
 * @return 1, or 0 (s incomplete) at the first sample at the centre.
 */
int sfit_i_pass(const sfit_vec3_t *pts, size_t n, const float c[3], const float *p,
                sfit_i_row_fn row, void *ctx, int k, sfit_i_sum_t *s);

#endif /* SFIT_PASS_H */
