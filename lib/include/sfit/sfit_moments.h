/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_moments.h
 * @brief Streaming moments accumulator: the O(1) state a firmware keeps per marker.
 * @defgroup sfit_moments Moments accumulator
 * @{
 *
 * Derivation and notes: docs/api.md#moments
 */
#ifndef SFIT_MOMENTS_H
#define SFIT_MOMENTS_H

#include <stddef.h>
#include <stdint.h>

#include "sfit_config.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Moments in packed form (sums about a point near the mean: the
 *  mean, or an accumulator's origin); members are private. */
typedef struct sfit_cmom {
    uint32_t n;    /**< Sample count. */
    float d[3];    /**< Mean minus the owner's origin. */
    float m2[6];   /**< sum y y^T, packed XX,YY,ZZ,XY,XZ,YZ. */
    float m3[3];   /**< sum |y|^2 y. */
} sfit_cmom_t;

/**
 * @brief Streaming accumulator. Caller-owned; members are private.
 * Initialise with sfit_moments_init() before use.
 */
typedef struct sfit_moments {
    float origin[3];    /**< Frame of `tot` and reference point of the open block:
                             the first sample, then the rounded mean at each
                             block start (tot.d keeps the rounding residue). */
    sfit_cmom_t tot;    /**< Merged full blocks: mean relative to origin (d, the
                             rounding residue), sums about origin (y = x - origin). */
    sfit_cmom_t blk;    /**< Open block, raw sums of z = x - origin: n, d = sum z,
                             m2 = sum z z^T (packed; it starts at the rounding
                             residue of the last fold into `tot`),
                             m3 = sum |z|^2 z. */
} sfit_moments_t;

/**
 * @brief Initialise (or clear) an accumulator to zero samples.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  m is NULL
 */
sfit_status_t sfit_moments_init(sfit_moments_t *m);

/** @brief Same as sfit_moments_init(): forget every sample. */
sfit_status_t sfit_moments_reset(sfit_moments_t *m);

/**
 * @brief Add one sample (O(1); a block merge every SFIT_SUM_BLOCK samples).
 * @par Cost 26 FLOPs per call (tools/flopcount: moments_add_call).
 * @param[in,out] m  Accumulator.
 * @param[in]     x  Sample.
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        NULL pointer
 * @retval SFIT_E_NONFINITE  a coordinate is NaN or Inf; m unchanged (bit for bit)
 * @retval SFIT_E_RANGE      |coordinate| >= 2^SFIT_COORD_MAX_EXP, or the sample
 *                           count is at UINT32_MAX; m unchanged
 */
sfit_status_t sfit_moments_add(sfit_moments_t *m, const sfit_vec3_t *x);

/**
 * @brief Add n samples from a caller-owned array.
 *
 * Every sample is validated first; if any is rejected nothing is added (the
 * accumulator stays bit for bit unchanged) and its status is returned.
 * @param[in,out] m    Accumulator.
 * @param[in]     pts  Array of n samples (may be NULL only when n == 0).
 * @param[in]     n    Number of samples.
 * @param[out]    bad  If not NULL, receives the index of the first rejected
 *                     sample (written only on failure caused by a sample).
 * @retval SFIT_OK           success
 * @retval SFIT_E_ARG        m NULL, or pts NULL with n > 0
 * @retval SFIT_E_NONFINITE  a sample holds NaN or Inf; m unchanged
 * @retval SFIT_E_RANGE      a coordinate out of range, or the count would pass
 *                           UINT32_MAX; m unchanged
 */
sfit_status_t sfit_moments_add_block(sfit_moments_t *m, const sfit_vec3_t *pts, size_t n,
                                     size_t *bad);

/**
 * @brief Merge another accumulator into dst (dst := dst U src).
 * The result equals adding src's samples to dst, up to float rounding.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  NULL pointer
 * @retval SFIT_E_RANGE the merged count would exceed UINT32_MAX, or src is
 *                      corrupted (its totals not finite, e.g. garbage bytes);
 *                      dst unchanged
 * @note dst and src may be the same object (doubles every weight).
 */
sfit_status_t sfit_moments_merge(sfit_moments_t *dst, const sfit_moments_t *src);

/** @brief Number of samples accumulated (0 for NULL). */
uint32_t sfit_moments_count(const sfit_moments_t *m);

/**
 * @brief Read the statistics: mean, C = sum y y^T / (N-1) and
 * S = sum |y|^2 y / (N-1) .
 * @param[in]  m     Accumulator.
 * @param[out] mean  Sample mean (may be NULL).
 * @param[out] c     Sample covariance, symmetric (may be NULL).
 * @param[out] s     Third-moment vector (may be NULL).
 * @retval SFIT_OK         success
 * @retval SFIT_E_ARG      m is NULL
 * @retval SFIT_E_TOO_FEW  fewer than 2 samples
 * @retval SFIT_E_RANGE    a statistic is not finite (only for a corrupted
 *                         accumulator, e.g. garbage bytes): nothing written
 */
sfit_status_t sfit_moments_stats(const sfit_moments_t *m, sfit_vec3_t *mean, sfit_mat3_t *c,
                                 sfit_vec3_t *s);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_MOMENTS_H */
