/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_gate.h
 * @brief Outlier gating for streams: reject a sample whose radial residual
 * against the current fit exceeds k sigma (ghost markers, label swaps,
 * magnetic disturbances), count it, and keep the accumulator clean.
 * @defgroup sfit_gate Outlier gate
 * @{
 *
 * Derivation and notes: docs/api.md#gate
 */
#ifndef SFIT_GATE_H
#define SFIT_GATE_H

#include <stdbool.h>
#include <stdint.h>

#include "sfit_fit.h"
#include "sfit_moments.h"
#include "sfit_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Options of a gate. */
typedef struct sfit_gate_cfg {
    sfit_fit_cfg_t fit; /**< Options of the running fit. In planar mode the residual
                             |x - c| - r is the distance from the circle's centre
                             minus its radius (out-of-plane offsets h count as
                             ~ h^2 / 2r): fine for a hinge's stray samples. */
    float k;            /**< Gate width in sigmas (> 1); 0 = SFIT_GATE_K. */
    float noise_var;    /**< sigma^2 of the gate: > 0 fixed, 0 = estimated from residuals. */
    uint32_t refresh;   /**< Re-solve every `refresh` offered samples; 0 = only on
                             sfit_gate_refresh(). */
} sfit_gate_cfg_t;

/** @brief Defaults: GDKE running fit, k = SFIT_GATE_K, estimated sigma, refresh 64. */
extern const sfit_gate_cfg_t sfit_gate_cfg_default;

/** @brief Gate state. Caller-owned; members are private. */
typedef struct sfit_gate {
    sfit_moments_t acc;                 /**< Accepted samples. */
    sfit_gate_cfg_t cfg;                /**< Options (defaults filled in). */
    sfit_vec3_t warm[SFIT_GATE_WARMUP]; /**< Warm-up buffer. */
    uint32_t nwarm;                     /**< Samples in the buffer (warm-up only). */
    uint32_t phase;                     /**< 0 warm-up, 1 ungated (no fit yet), 2 gated. */
    sfit_vec3_t center;                 /**< Current fit (phase 2). */
    float radius;                       /**< Current fit (phase 2). */
    float var;                          /**< Gate sigma^2 (phase 2). */
    sfit_vec3_t mean;                   /**< Mean of the fitted samples (phase 2). */
    float lw[6];                        /**< L^-1/sqrt(N-1) packed (00,11,22,10,20,21),
                                             C = L L^T at the fit: the leverage
                                             h = 1/N + |lw (x - mean)|^2 >= 0. */
    float inv_n;                        /**< 1/N at the fit. */
    float ws1, ws2;                     /**< Window sums of e^2/(1+h) (ws1 unused: 0). */
    uint32_t wn;                        /**< Residuals in the window. */
    uint32_t since;                     /**< Offered since the last refresh. */
    uint32_t wrej;                      /**< Rejected since the last refresh. */
    uint32_t outliers;                  /**< Rejected samples (gate and warm-up). */
    float wres[SFIT_GATE_WARMUP];       /**< Robust-start scratch (kept off the stack). */
    float wtmp[SFIT_GATE_WARMUP];       /**< Robust-start scratch. */
    uint8_t wkeep[SFIT_GATE_WARMUP];    /**< Robust-start scratch. */
    uint8_t wbest[SFIT_GATE_WARMUP];    /**< Robust-start scratch. */
} sfit_gate_t;

/** @brief Counters and the gate's state. */
typedef struct sfit_gate_stats {
    uint32_t accepted; /**< Samples in the accumulator (or buffered). */
    uint32_t outliers; /**< Samples rejected as outliers. */
    bool gated;        /**< true once a fit gates the samples. */
    float noise_var;   /**< Current gate sigma^2 (0 before gating). */
} sfit_gate_stats_t;

/**
 * @brief Initialise (or clear) a gate.
 * @param[out] g    Gate.
 * @param[in]  cfg  Options; NULL = ::sfit_gate_cfg_default.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  g NULL, invalid fit options, k <= 1 or not
 *                     finite (0 allowed: default), negative / non-finite noise_var
 */
sfit_status_t sfit_gate_init(sfit_gate_t *g, const sfit_gate_cfg_t *cfg);

/**
 * @brief Forget every sample and counter, keep the options.
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  g is NULL
 */
sfit_status_t sfit_gate_reset(sfit_gate_t *g);

/**
 * @brief Offer one sample.
 * @param[in,out] g         Gate.
 * @param[in]     x         Sample.
 * @param[out]    accepted  If not NULL: true if the sample was kept (or buffered), false if
 *                          rejected as an outlier. Written only on SFIT_OK.
 * @retval SFIT_OK           the sample was judged (kept or counted as outlier)
 * @retval SFIT_E_ARG        NULL g or x, or a corrupted gate whose phase or buffer
 *                           count is out of range (e.g. uninitialised RAM); g
 *                           unchanged. Other corrupted values (width, sigma^2, the
 *                           fit) are not checked here: the verdict is then arbitrary
 *                           (no non-finite value enters the state); sfit_gate_refresh(),
 *                           sfit_gate_fit() and sfit_gate_stats() return SFIT_E_ARG.
 * @retval SFIT_E_NONFINITE  NaN / Inf coordinate: g unchanged (bit for bit)
 * @retval SFIT_E_RANGE      coordinate out of range or counter full: g unchanged
 */
sfit_status_t sfit_gate_add(sfit_gate_t *g, const sfit_vec3_t *x, bool *accepted);

/**
 * @brief Re-solve the running fit now (also ends a warm-up early when at least
 * SFIT_MIN_SAMPLES + 1 samples are buffered: the robust start on the buffer).
 * When the robust start of a warm-up fails, the buffered samples go into the
 * accumulator ungated and no fit gates until a later refresh succeeds.
 * @retval SFIT_OK  a fit now gates the samples
 * @retval SFIT_E_ARG  g NULL, or a corrupted gate (phase, buffer count, width,
 *                  sigma^2 or the current fit out of range / not finite)
 * @retval SFIT_E_TOO_FEW  warm-up with fewer than SFIT_MIN_SAMPLES + 1 samples
 *                  (buffer kept), or a robust start whose cut keeps no more than
 *                  SFIT_MIN_SAMPLES of them (e.g. 5 samples)
 * @retval SFIT_E_DEGENERATE, SFIT_E_NOT_POSDEF, SFIT_E_NO_CONVERGENCE, SFIT_E_RANGE
 *                  the fit failed (as sfit_fit_moments()); the gate keeps its previous
 *                  fit (in a warm-up: no start could be fitted, e.g. collinear samples)
 * @retval SFIT_E_UNSUPPORTED  as sfit_fit_moments() (SFIT_FULL_SOLVER 0 only); the
 *                  gate keeps its previous fit
 */
sfit_status_t sfit_gate_refresh(sfit_gate_t *g);

/**
 * @brief Fit the accepted samples (as sfit_fit_moments() on the accumulator; the
 * warm-up buffer, if still filling, is fitted as it is).
 * @param[in]  g    Gate.
 * @param[out] out  Written only on SFIT_OK.
 * @retval SFIT_OK            success
 * @retval SFIT_E_ARG         g or out is NULL, or a corrupted gate
 * @retval SFIT_E_TOO_FEW     fewer than SFIT_MIN_SAMPLES accepted samples
 * @retval SFIT_E_DEGENERATE  coincident, collinear or (sphere) planar samples
 * @retval SFIT_E_NOT_POSDEF  C - Sigma_hat not positive definite
 * @retval SFIT_E_NO_CONVERGENCE  the eigen-solver hit its sweep bound
 * @retval SFIT_E_RANGE       the result would not be finite
 * @retval SFIT_E_UNSUPPORTED as sfit_fit_moments() (SFIT_FULL_SOLVER 0 only)
 */
sfit_status_t sfit_gate_fit(const sfit_gate_t *g, sfit_result_t *out);

/**
 * @brief The accumulator of the accepted samples (for sfit_uncert_moments()
 * and friends); NULL while the warm-up buffer is still filling, for NULL g,
 * or for a corrupted gate.
 */
const sfit_moments_t *sfit_gate_moments(const sfit_gate_t *g);

/**
 * @brief Counters. noise_var is always finite: the widening of sigma^2 when the
 * gate rejects too much stops at sigma = r (and at 1e30).
 * @retval SFIT_OK     success
 * @retval SFIT_E_ARG  g or out is NULL, or a corrupted gate
 */
sfit_status_t sfit_gate_stats(const sfit_gate_t *g, sfit_gate_stats_t *out);

#ifdef __cplusplus
}
#endif

/** @} */
#endif /* SFIT_GATE_H */
