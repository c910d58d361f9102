/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_pass.h
 * @brief Internal: one pass over a caller's samples that sums rows built
 * from each sample's distance d and unit direction u to a centre
 * (sfit_pass.c). Used by the geometric refinement, the uncertainties and
 * the self-calibration; not part of the API. The row kinds are a closed
 * set (no callback): every call is direct, so the stack stays statically
 * bounded.
 */
#ifndef SFIT_PASS_H
#define SFIT_PASS_H

#include "sfit_float.h"

/** @brief Which row each sample contributes (k floats, see sfit_i_pass()). */
typedef enum sfit_i_rows_kind {
    SFIT_I_ROWS_RESID,   /**< k = 2: d - ref, (d - ref)^2 */
    SFIT_I_ROWS_DIRS,    /**< k = 4: u, d - ref; k = 5: also (d - ref)^2 */
    SFIT_I_ROWS_LM,      /**< k = 9: packed v v^T, v (d - dbar); v = u - ub */
    SFIT_I_ROWS_CENTRED, /**< k = 6 or 13: packed v v^T, [6..11] packed
                              (d - dbar)/d (I - u u^T), [12] (d - dbar)^2 */
    SFIT_I_ROWS_SANDWICH /**< k = 9: packed eta eta^T, [6..8] (d - dbar) u
                              (self-calibrated sandwich, docs/api.md#uncert) */
} sfit_i_rows_kind_t;

/** @brief The row kind and what its rows read. */
typedef struct sfit_i_rows {
    sfit_i_rows_kind_t kind;
    int first;    /**< DIRS: ref := the first sample's distance (then 0) */
    float ref;    /**< RESID, DIRS: reference distance */
    float ub[3];  /**< LM, CENTRED: mean direction */
    float dbar;   /**< LM, CENTRED, SANDWICH: mean distance */
    /* SANDWICH: eta = (gt y - 2 kv z)/2 + p (f^2 - sv + alpha_n gt), with
     * z = x - c, y = x - m, f = d - dbar, gt = |z|^2 - mean |z|^2. */
    float m[3];    /**< sample mean */
    float a[3];    /**< m - c */
    float p[3];    /**< weight of the noise equation in eta */
    float mf2;     /**< mean f^2 */
    float kv;      /**< (N-1)/N sigma^2 */
    float alpha_n; /**< alpha / N */
    float sv;      /**< (N-4)/N (sigma^2 - sigma^4/r^2) */
} sfit_i_rows_t;

/** @brief q := rows of this kind about ref, ub (NULL: zero) and dbar; the
 * other fields zero (SANDWICH: the caller sets them). */
void sfit_i_rows_init(sfit_i_rows_t *q, sfit_i_rows_kind_t kind, float ref, const float *ub,
                      float dbar);

/**
 * @brief s := the two-level sum over the n samples of their rows (k floats
 * each), with d and u taken from c (p NULL) or from c + p, formed as
 * (x - c) - p so that a small offset keeps its digits.
 * @return 1, or 0 (s incomplete) at the first sample at the centre.
 */
int sfit_i_pass(const sfit_vec3_t *pts, size_t n, const float c[3], const float *p,
                sfit_i_rows_t *q, int k, sfit_i_sum_t *s);

#endif /* SFIT_PASS_H */
