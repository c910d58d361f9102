/* SPDX-License-Identifier: MIT */
/** @file sfit_check.c  Validators shared by every function on a caller's array. */
#include "sfit_float.h"

sfit_status_t sfit_i_check_points(const sfit_vec3_t *pts, size_t n, size_t nmin)
{
    size_t i;
    if (n < nmin) {
        return SFIT_E_TOO_FEW;
    }
#if SIZE_MAX > UINT32_MAX
    if (n > (size_t)UINT32_MAX) {
        return SFIT_E_RANGE;
    }
#endif
    for (i = 0; i < n; i++) {
        const sfit_status_t st = sfit_i_check_sample(pts[i].v);
        if (st != SFIT_OK) {
            return st;
        }
    }
    return SFIT_OK;
}

sfit_status_t sfit_i_check_fit(const sfit_vec3_t *center, const float *radius)
{
    if (!sfit_i_finite3(center->v) || (radius != NULL && !sfit_i_isfinite(*radius))) {
        return SFIT_E_NONFINITE;
    }
    return (radius == NULL || *radius > 0.0f) ? SFIT_OK : SFIT_E_ARG;
}
