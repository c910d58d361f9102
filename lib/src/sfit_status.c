/* SPDX-License-Identifier: MIT */
/** @file sfit_status.c  Status names. */
#include "sfit/sfit_status.h"

const char *sfit_status_str(sfit_status_t s)
{
    switch (s) {
    case SFIT_OK: return "ok";
    case SFIT_E_ARG: return "bad_argument";
    case SFIT_E_TOO_FEW: return "too_few_samples";
    case SFIT_E_NOT_POSDEF: return "not_positive_definite";
    case SFIT_E_NO_CONVERGENCE: return "no_convergence";
    case SFIT_E_DEGENERATE: return "degenerate";
    case SFIT_E_NONFINITE: return "non_finite";
    case SFIT_E_RANGE: return "out_of_range";
    case SFIT_E_UNSUPPORTED: return "unsupported";
    default: return "unknown";
    }
}
