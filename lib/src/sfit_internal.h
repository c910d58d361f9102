/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_internal.h
 * @brief Cross-file helpers of the implementation (not part of the API).
 *
 * Packed symmetric storage: p[0..5] = XX, YY, ZZ, XY, XZ, YZ.
 */
#ifndef SFIT_INTERNAL_H
#define SFIT_INTERNAL_H

#include <stdint.h>

#include "sfit/sfit_moments.h"
#include "sfit/sfit_types.h"
#include "sfit_port.h"

/** @brief Unpack a packed symmetric matrix into a full row-major one. */
void sfit_i_sym_unpack(const float p[6], sfit_mat3_t *a);

/** @brief The accumulator's total centred moments including the open block. */
void sfit_i_moments_total(const sfit_moments_t *m, sfit_cmom_t *out);

/** @brief 1 when x is neither NaN nor Inf (bit test; no FP operation). */
int sfit_i_isfinite(float x);

/** @brief Check a sample: SFIT_OK, SFIT_E_NONFINITE or SFIT_E_RANGE. */
sfit_status_t sfit_i_check_sample(const float x[3]);

/* ---- shared by the sphere/circle solvers (sfit_fit.c, sfit_multi.c) ---- */
#include "sfit/sfit_fit.h"

/** @brief The linear problem (C - Sigma) w = b of every GDKE-type estimator. */
typedef struct sfit_i_system {
    sfit_mat3_t c;     /**< C (or sum of C_p): symmetric, its eigenvalues are reported */
    sfit_mat3_t sigma; /**< noise matrix subtracted from c (zero for GDKE) */
    int noisy;         /**< 1 for UGDK (sigma given) */
    sfit_vec3_t rhs;   /**< b */
    float scale;       /**< spread at or below which samples count as coincident */
} sfit_i_system_t;

/** @brief Solution of a system: w, the eigen-summary, trust. */
typedef struct sfit_i_solution {
    sfit_vec3_t w;           /**< (C - Sigma)^-1 b, or its pseudo-inverse form (planar) */
    sfit_vec3_t eigenvalues; /**< eigenvalues of c, ascending */
    sfit_vec3_t axis;        /**< dropped / smallest eigen-direction (unit, sign-normalised) */
    float trace;             /**< trace of C - Sigma over the directions used */
    float rho;               /**< rho(C'^-1 Sigma): Leontief ratio (0 when not noisy) */
    uint32_t flags;          /**< SFIT_FLAG_NEAR_PLANAR, SFIT_FLAG_UNTRUSTED */
    sfit_mode_t mode;        /**< SFIT_MODE_SPHERE or SFIT_MODE_PLANAR */
} sfit_i_solution_t;

/** @brief Validate a fit configuration (SFIT_OK or SFIT_E_ARG). */
sfit_status_t sfit_i_check_cfg(const sfit_fit_cfg_t *cfg);

/** @brief Sigma_hat of a configuration as a full symmetric matrix (zero for none). */
void sfit_i_sigma(const sfit_fit_cfg_t *cfg, sfit_mat3_t *sg);

/** @brief Coincidence threshold (a spread) for samples whose mean is origin + d. */
float sfit_i_coincident_scale(const float origin[3], const float d[3]);

/**
 * @brief Solve (C - Sigma) w = b as a sphere or, near-planar/forced, with the
 * pseudo-inverse over the two largest eigen-directions; geometry checks and
 * trust ratio included. Statuses as sfit_fit_solve().
 */
sfit_status_t sfit_i_solve(const sfit_i_system_t *sys, sfit_mode_t mode, float planar_ratio,
                           sfit_i_solution_t *out);

#endif /* SFIT_INTERNAL_H */
