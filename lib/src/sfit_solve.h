/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_solve.h
 * @brief Internal solver layer: the sphere / circle system (C - Sigma) w = b
 * shared by the single- and multi-marker fits (sfit_solve.c).
 */
#ifndef SFIT_SOLVE_H
#define SFIT_SOLVE_H

#include "sfit/sfit_fit.h"
#include "sfit_moments_i.h"

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
    float lmin_lo;           /**< screened solve only: <= lambda_min(C') */
    float lmax_hi;           /**< screened solve only: >= lambda_max(C) */
} sfit_i_solution_t;

/** @brief Validate a noise model (SFIT_OK or SFIT_E_ARG). */
sfit_status_t sfit_i_check_noise(sfit_noise_kind_t kind, float var, const sfit_mat3_t *cov);

/** @brief Validate a fit configuration (SFIT_OK or SFIT_E_ARG). */
sfit_status_t sfit_i_check_cfg(const sfit_fit_cfg_t *cfg);

/** @brief Sigma_hat of a noise model as a full symmetric matrix (zero for none). */
void sfit_i_sigma(sfit_noise_kind_t kind, float var, const sfit_mat3_t *cov, sfit_mat3_t *sg);

/** @brief Coincidence threshold (a spread) for samples whose mean is origin + d. */
float sfit_i_coincident_scale(const float origin[3], const float d[3]);

/**
 * @brief Solve (C - Sigma) w = b as a sphere or, near-planar/forced, with the
 * pseudo-inverse over the two largest eigen-directions; geometry checks and
 * trust ratio included. Statuses as sfit_moments_fit(); out is scratch
 * (partly written) on failure.
 */
sfit_status_t sfit_i_solve(const sfit_i_system_t *sys, sfit_mode_t mode, float planar_ratio,
                           sfit_i_solution_t *out);

/** @brief sfit_i_solve_lean(): the screen cannot prove the answer; run sfit_i_solve(). */
#define SFIT_I_SCREEN_TRIPPED 1

/**
 * @brief The screened sphere solve of C' = C - var I (sfit_lean.c): SFIT_OK
 * with w, trace and an upper bound of the trust ratio (rho) when a cheap
 * bound on lambda_min(C') proves that sfit_i_solve() would return the same
 * sphere, status and flags; else SFIT_I_SCREEN_TRIPPED (out is scratch).
 * Eigenvalues and axis are left zero. ratio: the planar threshold in use.
 */
int sfit_i_solve_lean(const sfit_mat3_t *c, const sfit_vec3_t *rhs, float var, float scale,
                      float ratio, sfit_i_solution_t *out);

#endif /* SFIT_SOLVE_H */
