/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_status.h
 * @brief Status codes returned by every fallible sfit function, and their names.
 */
#ifndef SFIT_STATUS_H
#define SFIT_STATUS_H

#include "sfit_config.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * @brief Status returned by every fallible function.
 *
 * 0 is success, negative values are errors. Outputs are written only when
 * the status is ::SFIT_OK.
 */
typedef enum sfit_status {
    SFIT_OK = 0,               /**< Success. */
    SFIT_E_ARG = -1,           /**< NULL pointer or invalid argument/option. */
    SFIT_E_TOO_FEW = -2,       /**< Fewer samples than the solution needs. */
    SFIT_E_NOT_POSDEF = -3,    /**< Matrix not positive definite (e.g. C - Sigma for UGDK). */
    SFIT_E_NO_CONVERGENCE = -4,/**< An iteration hit its compile-time bound. */
    SFIT_E_DEGENERATE = -5,    /**< Degenerate geometry: coincident, collinear or (sphere) planar. */
    SFIT_E_NONFINITE = -6,     /**< A NaN or Inf input (sample rejected, state unchanged). */
    SFIT_E_RANGE = -7,         /**< A finite value out of the supported range, or a counter full. */
    SFIT_E_UNSUPPORTED = -8    /**< The call needs what this build leaves out (SFIT_FULL_SOLVER 0:
                                    a fit the screened solve cannot prove). */
} sfit_status_t;

/**
 * @brief Short constant name of a status ("ok", "too_few_samples", ...).
 * @param[in] s  Status code.
 * @return A static string; "unknown" for a value that is not a status.
 */
const char *sfit_status_str(sfit_status_t s);

#ifdef __cplusplus
}
#endif

#endif /* SFIT_STATUS_H */
