/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_types.h
 * @brief Value types and result flags shared by every sfit module (the
 * status codes: sfit_status.h).
 */
#ifndef SFIT_TYPES_H
#define SFIT_TYPES_H

#include <stdbool.h>
#include <stdint.h>

#include "sfit_config.h"
#include "sfit_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Yes/no: every yes/no of the API is a C99 bool. A bool the library reads
 * from a caller's options or state is read as its byte (never loaded as a
 * bool): a byte other than 0 or 1 (uninitialised RAM, a corrupted state) is
 * refused with SFIT_E_ARG, like any other field out of range; bools the
 * library writes are always 0 or 1.
 */

/** @brief A 3-vector of floats (assignable value type). */
typedef struct sfit_vec3 {
    float v[3];
} sfit_vec3_t;

/** @brief A 3x3 matrix of floats, row-major: m[3*row + col]. */
typedef struct sfit_mat3 {
    float m[9];
} sfit_mat3_t;

/**
 * @brief Every result flag of the library (bit mask; each result's `flags`
 * says which of them it can carry). One enum, distinct bits.
 */
enum sfit_flag {
    SFIT_FLAG_UNTRUSTED = 0x1u,        /**< Fits: do not believe the centre or its covariance;
                                            the reason is one of: leontief_ratio >= 1
                                            (trust_ratio >= 1/2), ::SFIT_FLAG_COV_LIMIT,
                                            ::SFIT_SELFCAL_FLAG_CAPPED. Without it, the
                                            reported centre covariance describes the
                                            centre's real error (docs/coverage.md). */
    SFIT_FLAG_FEW_SAMPLES = 0x2u,      /**< Fits: N < SFIT_FEW_SAMPLES. */
    SFIT_FLAG_NEAR_PLANAR = 0x4u,      /**< Fits: lambda_min/lambda_max < planar_ratio. */
    SFIT_SELFCAL_FLAG_CAPPED = 0x8u,   /**< Self-calibration (and its fit, with
                                            SFIT_FLAG_UNTRUSTED): sigma^2 hit the
                                            SFIT_SELFCAL_MAX_TRUST cap, the data cannot
                                            separate noise from geometry. */
    SFIT_NOISE_FLAG_NEGATIVE = 0x10u,  /**< Noise calibration: the estimate is negative
                                            (reported unclamped). */
    SFIT_NOISE_FLAG_IMPRECISE = 0x20u, /**< Noise calibration: below twice its own
                                            predicted standard deviation. */
    SFIT_FLAG_ROUNDING = 0x40u,        /**< Fits: the conditioning of C' (with N) or the
                                            centre's distance |c|/r is beyond what float
                                            carries; the centre may be more than 1e-4 r from
                                            a double-precision fit of the same samples
                                            (small caps at any N, N ~ 1e5 and more on
                                            larger ones, |c|/r ~ 1e3; sfit_fit.h "Range"). */
    SFIT_FLAG_COV_LIMIT = 0x80u,       /**< Fits (with SFIT_FLAG_UNTRUSTED): outside the
                                            range where the reported covariance was
                                            validated: trust_ratio > SFIT_COV_MAX_TRUST, or
                                            fewer than SFIT_COV_MIN_SAMPLES samples. */
    SFIT_MULTI_FLAG_SKIPPED = 0x100u   /**< Multi-marker: a marker with too few samples
                                            was skipped. */
};

/** @brief A sphere: centre, radius and the samples behind it. */
typedef struct sfit_sphere {
    sfit_vec3_t center; /**< Sphere centre. */
    float radius;       /**< Sphere radius. */
    uint32_t n;         /**< Samples behind the estimate. */
} sfit_sphere_t;

#ifdef __cplusplus
}
#endif

#endif /* SFIT_TYPES_H */
