/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_solve.h
 * @brief Internal solver layer: the sphere / circle system (C - Sigma) w = b
 * shared by the single- and multi-marker fits: the full solver
 * (sfit_solve.c), the screened solve and the rounding test (sfit_lean.c),
 * the fit's body (sfit_fit.c), the solver's entry point and what a build
 * serves (inline, below).
 *
 * Stack-saving tricks (the one list; sites say "stack trick N"). The fit's
 * deepest path, sfit_fit_moments -> sfit_i_fit_totals -> sfit_i_solve ->
 * Jacobi / trust ratio, is budgeted at 320 B on Cortex-M4F at -Os
 * (tools/flopcount/footprint_budget.txt); each trick below was measured
 * against it (giving up trick 2 and 3, a local lamp and threshold, costs
 * 24 B on that path: 336 B).
 *  1. The system's C (sys->ms.c) is the full solver's working matrix: the
 *     Jacobi, then C' and its Cholesky factor; C itself is kept as a
 *     copy in sfit_i_solve_plain() and the noisy solve, mirrored back by
 *     sfit_i_sym_full() (the 6 floats of packed storage took 8 B less
 *     frame, 312 -> 304 B on sfit_fit_moments, but linked
 *     sfit_i_sym_unpack() too: 42 B more code in the two-fit application).
 *  2. sfit_i_solve(): out->w holds the eigenvalues of C' (lamp) or the
 *     trust ratio's scratch until the solution's w is written last
 *     (prv_sphere, prv_planar).
 *  3. sfit_i_solve() and sfit_i_solve_plain(): out->trace holds the planar
 *     threshold, stored before any call (no float register kept across
 *     calls) until the sphere or planar solve sets the trace.
 *  4. sfit_i_solution_t.flags is one byte beside mode (8 B less frame).
 *  5. The totals of an accumulator stay in the frame of
 *     sfit_i_moments_system() (sfit_moments.c), and the accumulator of a
 *     caller's array in that of sfit_i_points_total(): neither shares a
 *     frame with the solve (sfit_fit_points, sfit_fit_moments).
 *  6. sfit_i_solve_fit() is inline: no frame of its own on the path, and
 *     sfit_i_fit_totals calls it once in its loop (a second inlined copy
 *     costs 16 B of frame).
 *  7. prv_fold_block and prv_cmom_merge (sfit_moments.c) are written out, not
 *     looped: fewer live registers on sfit_moments_add's deepest path (a
 *     looped merge and centring measured 116 B against its budget of
 *     64 B); prv_fold_block takes three arguments (a fifth on the stack put a
 *     frame on that path: 80 B).
 */
#ifndef SFIT_SOLVE_H
#define SFIT_SOLVE_H

#include "sfit/sfit_fit.h"
#include "sfit/sfit_multi.h"
#include "sfit_moments_i.h"

#include <float.h>

/** @brief The linear problem (C - Sigma) w = b of every GDKE-type estimator. */
typedef struct sfit_i_system {
    sfit_i_msys_t ms;         /**< ms.c: C (or sum of C_p), symmetric (its lower triangle is
                                   read), its eigenvalues are reported; ms.rhs: b; ms.d: the
                                   fit's mean - origin (not read by the solver) */
    int noisy;                /**< the noise model (a sfit_noise_kind_t): SFIT_NOISE_NONE (0,
                                   GDKE), SFIT_NOISE_ISO (Sigma = sigma.var I) or
                                   SFIT_NOISE_COV (Sigma = *sigma.m, symmetric: its lower
                                   triangle is read) */
    union {
        const sfit_mat3_t *m; /**< SFIT_NOISE_COV */
        float var;            /**< SFIT_NOISE_ISO (0 for SFIT_NOISE_NONE) */
    } sigma;                  /**< Sigma_hat, subtracted from c */
    float scale;              /**< spread at or below which samples count as coincident */
} sfit_i_system_t;

/** @brief Solution of a system: w, the eigen-summary, trust. */
typedef struct sfit_i_solution {
    sfit_vec3_t w;           /**< (C - Sigma)^-1 b, or its pseudo-inverse form (planar) */
    sfit_vec3_t eigenvalues; /**< eigenvalues of c, ascending */
    sfit_vec3_t axis;        /**< dropped / smallest eigen-direction (unit, sign-normalised) */
    float trace;             /**< trace of C - Sigma over the directions used */
    float rho;               /**< rho(C'^-1 Sigma): Leontief ratio (0 when not noisy) */
    sfit_mode_t mode;        /**< SFIT_MODE_SPHERE or SFIT_MODE_PLANAR */
    uint8_t flags;           /**< SFIT_FLAG_NEAR_PLANAR, SFIT_FLAG_UNTRUSTED (and the fit's
                                  FEW_SAMPLES, ROUNDING: every flag a solution carries is
                                  below 0x100): one byte beside mode (stack trick 4) */
} sfit_i_solution_t;

/** Square of the merge constant of the rounding model below (0.5^2;
 * measured: tools/montecarlo/smallcap.c). */
#define SFIT_ROUNDING_K2 0.25f
/** Constant of the first block's term of the rounding model below
 * (measured: tools/montecarlo/smallcap.c small, docs/api.md#fit). */
#define SFIT_ROUNDING_KB2 4.0f
/** Relative accuracy an unflagged result promises (the README's 1e-4 r). */
#define SFIT_ROUNDING_TOL 1e-4f

/**
 * @brief 1 when the float arithmetic may not carry the centre to
 * SFIT_ROUNDING_TOL r (SFIT_FLAG_ROUNDING). Model of the centre's error
 * (docs/api.md#fit, issue 32):
 *   |c - c_double| / r <= eps (cond(C') K(N) + |c|_inf / r),
 *   K(N)^2 = SFIT_ROUNDING_K2 (N/SFIT_SUM_BLOCK + 1) + SFIT_ROUNDING_KB2 g(N).
 * The first term: each block merge rounds the totals relative to eps and
 * these errors add as a random walk. The second: the open first block's
 * sums (about its first sample) round each partial sum, a random walk of
 * sqrt(k) over its k terms, g = N while N <= SFIT_SUM_BLOCK (B), then
 * diluted by the block's weight B/N in the totals, g = B^3 / N^2 (rounded
 * up). Both are amplified by cond(C') = lmax / lmin; the two add in
 * quadrature. The last term is the float rounding of the centre's own
 * coordinates (half an ulp each, plus the mean's). lmax >= lambda_max(C)
 * and lmin <= lambda_min(C') (the full solver: C's largest and C''s
 * smallest used eigenvalue minus an upper bound of the noise; the screened
 * solve: its bounds); r the radius, c the centre (cinf = max |c_i|). lmin
 * not positive flags (sfit_lean.c: one copy for both paths).
 */
int sfit_i_rounding_test(uint32_t n, float lmax, float lmin, float r, const float c[3]);

/** @brief The solution's summary in a result: eigenvalues, axis, Leontief
 * ratio rho and trust ratio rho / (1 + rho). */
SFIT_INLINE void sfit_i_solution_out(const sfit_i_solution_t *sol, sfit_vec3_t *eig,
                                     sfit_vec3_t *axis, float *leontief, float *trust)
{
    *eig = sol->eigenvalues;
    *axis = sol->axis;
    *leontief = sol->rho;
    *trust = sol->rho / (1.0f + sol->rho);
}

/** @brief The coverage rule (docs/coverage.md): a fit whose trust ratio is
 * above SFIT_COV_MAX_TRUST, or that rests on fewer than
 * SFIT_COV_MIN_SAMPLES samples, is outside the range where its reported
 * covariance was shown to cover its error: UNTRUSTED + COV_LIMIT. */
SFIT_INLINE uint32_t sfit_i_cov_limit(float trust, uint32_t n)
{
    return (trust > SFIT_COV_MAX_TRUST || n < SFIT_COV_MIN_SAMPLES)
               ? ((uint32_t)SFIT_FLAG_UNTRUSTED | (uint32_t)SFIT_FLAG_COV_LIMIT)
               : 0u;
}

/**
 * @brief A centre's covariance var a^+ m a^+ from its system matrix a and
 * the covariance m of its estimating equation per unit variance: a^+ = a^-1
 * (sphere) or, planar, the pseudo-inverse normal to the unit axis,
 * (P a P + s ax ax^T)^-1 - ax ax^T / s, P = I - ax ax^T, s = tr a (the size
 * of the kept eigenvalues, so the factor stays well conditioned).
 * SFIT_OK (cov written), SFIT_E_NOT_POSDEF or SFIT_E_RANGE (not finite).
 */
sfit_status_t sfit_i_center_cov(const sfit_mat3_t *a, sfit_mode_t mode, const sfit_vec3_t *axis,
                                const sfit_mat3_t *m, float var, sfit_mat3_t *cov);

/** @brief Markers with at least SFIT_MIN_SAMPLES samples; *sum_n1 = sum of their N_p - 1. */
uint32_t sfit_i_multi_used(const sfit_moments_t *markers, size_t count, uint64_t *sum_n1);

/** @brief Weight of a used marker: 1, or (N_p - 1) M / sum_q (N_q - 1) (exactly 1
 * when every count is the same). */
float sfit_i_multi_weight(const sfit_multi_cfg_t *cfg, uint32_t n, uint32_t used,
                          uint64_t sum_n1);

/** @brief Validate a noise model (SFIT_OK or SFIT_E_ARG). */
sfit_status_t sfit_i_check_noise(sfit_noise_kind_t kind, float var, const sfit_mat3_t *cov);

/** @brief Validate a fit configuration (SFIT_OK or SFIT_E_ARG). */
sfit_status_t sfit_i_check_cfg(const sfit_fit_cfg_t *cfg);

/** @brief Validate a multi-marker configuration (SFIT_OK or SFIT_E_ARG). */
sfit_status_t sfit_i_check_multi_cfg(const sfit_multi_cfg_t *cfg);

/** @brief Sigma_hat of a noise model as a full symmetric matrix (zero for none). */
void sfit_i_sigma(sfit_noise_kind_t kind, float var, const sfit_mat3_t *cov, sfit_mat3_t *sg);

/** @brief SFIT_OK when w and the trace of a solution are finite, else
 * SFIT_E_RANGE (the full solver's last check; the screen's too). */
sfit_status_t sfit_i_solution_finite(const sfit_i_solution_t *out);

/** @brief Coincidence threshold (a spread) for samples whose mean is origin + d. */
float sfit_i_coincident_scale(const float origin[3], const float d[3]);

/**
 * @brief Solve (C - Sigma) w = b as a sphere or, near-planar/forced, with the
 * pseudo-inverse over the two largest eigen-directions; geometry checks and
 * trust ratio included; a system without a noise model takes the same
 * steps with Sigma = 0 (the answer of sfit_i_solve_plain(), bit for bit:
 * one full solver in a build). sys->ms.c is used as working storage (destroyed;
 * stack trick 1), out->w and out->trace too until written last (stack
 * tricks 2, 3). Statuses as sfit_fit_moments(); out is scratch (partly
 * written) on failure.
 */
sfit_status_t sfit_i_solve(sfit_i_system_t *sys, sfit_mode_t mode, float planar_ratio,
                           sfit_i_solution_t *out);

/**
 * @brief sfit_i_solve() of a system without a noise model (sys->noisy
 * SFIT_NOISE_NONE), written for it alone: C's Jacobi
 * eigen-decomposition, the geometry checks, then the sphere (Cholesky of C)
 * or the planar pseudo-inverse. Links neither the noise models nor the
 * screen: the whole solver of sfit_fit_moments_default(). Arguments and
 * statuses as sfit_i_solve().
 */
sfit_status_t sfit_i_solve_plain(sfit_i_system_t *sys, sfit_mode_t mode, float planar_ratio,
                                 sfit_i_solution_t *out);

/**
 * @brief The fit of the samples of an accumulator m (pt NULL) or of a total
 * pt (m not read): the body of sfit_fit_moments() and sfit_fit_points(),
 * with their statuses after the argument checks (cfg NULL: the defaults).
 */
sfit_status_t sfit_i_fit_totals(const sfit_moments_t *m, const sfit_i_total_t *pt,
                                const sfit_fit_cfg_t *cfg, sfit_result_t *out);

/** @brief 1 when SFIT_MIN_SPREAD^2 is above FLT_MIN (its documented range,
 * SFIT_MIN_SPREAD >= 1e-12): a spread test against it then also proves
 * the variance normal, so the geometry checks need no test against
 * FLT_MIN of their own (a constant: one of the two tests is compiled). */
#define SFIT_I_SPREAD2_NORMAL (SFIT_MIN_SPREAD * SFIT_MIN_SPREAD > FLT_MIN)

/** @brief sfit_i_solve_lean(): the screen cannot prove the answer; run sfit_i_solve(). */
#define SFIT_I_SCREEN_TRIPPED 1




/**
 * @brief The screened sphere solve of C' = C - var I (sfit_lean.c) of n
 * samples: SFIT_OK with w, trace and an upper bound of the Leontief ratio
 * (rho) when a cheap bound on lambda_min(C') proves that sfit_i_solve()
 * would return the same sphere, status and flags, and that the coverage
 * limit (sfit_i_cov_limit) would not be raised; else SFIT_I_SCREEN_TRIPPED
 * (out is scratch). The rounding flag needs the centre: the caller tests
 * it (sfit_i_rounding_test) on the bounds the screen leaves in
 * out->eigenvalues (v[0] <= lambda_min(C'), v[2] >= lambda_max(C); v[1]
 * not written) and runs the full solver when they cannot prove it clear;
 * a screened result clears the three. Axis left zero. ratio: the planar
 * threshold in use.
 */
int sfit_i_solve_lean(const sfit_i_system_t *sys, uint32_t n, float ratio,
                      sfit_i_solution_t *out);

/**
 * @brief A lower bound of lambda_min(C) for a symmetric C (its lower
 * triangle), the screen's bound: det C / e2(C) less the screen's margins
 * (sfit_lean.c). 0 when it proves nothing (C not positive definite, not
 * finite, or the margins exceed the bound). Used where a build without the
 * full solver (SFIT_FULL_SOLVER 0) needs lambda_min (self-calibration's cap).
 */
float sfit_i_lmin_lower(const sfit_mat3_t *c); /* defined when SFIT_FULL_SOLVER is 0 */

/** @brief sfit_i_solve_fit(): solved by the screen (out->eigenvalues hold
 * its bounds, see sfit_i_solve_lean()); SFIT_OK: by the full solver. */
#define SFIT_I_SCREENED ((sfit_status_t)1)

/**
 * @brief The solver's entry point for the fit of n samples: it hides the
 * screened / full choice and the build without the full solver. The
 * screened solve (sfit_i_solve_lean) when cfg allows it (sphere, no or
 * isotropic noise, cfg->eigen 0) and full is 0, and its bounds prove the
 * answer: SFIT_I_SCREENED. Otherwise the full solver (sfit_i_solve) and
 * its status (SFIT_OK: solved); without it (SFIT_FULL_SOLVER 0)
 * SFIT_E_UNSUPPORTED. full 1 skips the screen (the caller could not prove
 * the rounding flag clear on the screen's bounds). sys as sfit_i_solve()
 * (sys->ms.c is destroyed by the full solver only). Inline (stack
 * trick 6).
 */
SFIT_INLINE sfit_status_t sfit_i_solve_fit(sfit_i_system_t *sys, uint32_t n,
                                           const sfit_fit_cfg_t *cfg, int full,
                                           sfit_i_solution_t *out)
{
    if (!full && cfg->eigen == 0 && cfg->mode != SFIT_MODE_PLANAR
        && cfg->noise != SFIT_NOISE_COV
        && sfit_i_solve_lean(sys, n,
                             (cfg->planar_ratio > 0.0f) ? cfg->planar_ratio : SFIT_PLANAR_RATIO,
                             out) != SFIT_I_SCREEN_TRIPPED) {
        return SFIT_I_SCREENED;
    }
#if SFIT_FULL_SOLVER
    return sfit_i_solve(sys, cfg->mode, cfg->planar_ratio, out);
#else
    (void)sys;
    (void)out;
    return SFIT_E_UNSUPPORTED; /* the screen cannot prove the fit: no fallback built */
#endif
}

/** @brief 1 when this build's fit serves the noise model kind exactly (the
 * full solver is built, or kind is not a full covariance); 0: the fit of
 * a full covariance returns SFIT_E_UNSUPPORTED (SFIT_FULL_SOLVER 0). */
SFIT_INLINE int sfit_i_solve_serves(sfit_noise_kind_t kind)
{
    return SFIT_FULL_SOLVER || kind != SFIT_NOISE_COV;
}

/** @brief 1 when this build's fit reports C's eigenvalues (cfg.eigen 1:
 * the full solver is built); 0 when only the screen's bounds exist. */
SFIT_INLINE int sfit_i_solve_has_eigen(void)
{
    return SFIT_FULL_SOLVER != 0;
}

/**
 * @brief lambda_min(C) of an accumulator acc fitted with cfg.eigen =
 * sfit_i_solve_has_eigen() (result fit): the full solver's eigenvalue
 * (*exact 1), or without it the screen's lower bound from C
 * (sfit_i_lmin_lower, *exact 0; 0 when it proves nothing).
 */
SFIT_INLINE float sfit_i_solve_lmin(const sfit_moments_t *acc, const sfit_result_t *fit,
                                    int *exact)
{
#if SFIT_FULL_SOLVER
    (void)acc;
    *exact = 1;
    return fit->eigenvalues.v[0];
#else
    sfit_mat3_t c;
    (void)fit;
    (void)sfit_moments_stats(acc, NULL, &c, NULL); /* fitted: N >= 2, finite */
    *exact = 0;
    return sfit_i_lmin_lower(&c);
#endif
}

#endif /* SFIT_SOLVE_H */
