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

#endif /* SFIT_INTERNAL_H */
