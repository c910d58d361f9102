/* SPDX-License-Identifier: MIT */
/**
 * @file refine.h
 * @brief The recipe's one flat result (sfit_refine_fit) as the sphere fit
 * and uncertainty a front end prints: shared by `sfit fit --refine`
 * (cmd_fit.c) and the Python binding's fit(refine=True)
 * (tools/python/src/py_fit.c), so that both print the same values.
 */
#ifndef SFIT_TOOLS_REFINE_H
#define SFIT_TOOLS_REFINE_H

#include <string.h>

#include "sfit/sfit.h"

/** The geometric sphere with the start's eigenvalues, trust and verdict (a
 *  UGDK sphere), and the covariance of the geometric centre. */
static inline void refine_parts(const sfit_refine_result_t *rf, sfit_result_t *r,
                                    sfit_uncert_t *u)
{
    memset(r, 0, sizeof *r);
    r->center = rf->center;
    r->radius = rf->radius;
    r->n = rf->n;
    r->eigenvalues = rf->eigenvalues;
    r->axis = rf->axis;
    r->trust_ratio = rf->trust_ratio;
    r->leontief_ratio = rf->leontief_ratio;
    r->flags = rf->flags;
    r->method = SFIT_METHOD_UGDK;
    r->mode = SFIT_MODE_SPHERE;
    u->center_cov = rf->center_cov;
    u->radius_var = rf->radius_var;
    memcpy(u->center_radius_cov, rf->center_radius_cov, sizeof u->center_radius_cov);
    u->noise_var = rf->cov_noise_var;
}

#endif /* SFIT_TOOLS_REFINE_H */
