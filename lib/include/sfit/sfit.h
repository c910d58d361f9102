/* SPDX-License-Identifier: MIT */
/**
 * @file sfit.h
 * @brief sfit umbrella header: sphere and circle fitting for microcontrollers.
 */
#ifndef SFIT_H
#define SFIT_H

#define SFIT_VERSION_MAJOR 0
#define SFIT_VERSION_MINOR 3
#define SFIT_VERSION_PATCH 0

#include "sfit_config.h"
#include "sfit_status.h"
#include "sfit_types.h"
#include "sfit_mat3.h"
#include "sfit_moments.h"
#include "sfit_fit.h"
#include "sfit_multi.h"
#include "sfit_noise.h"
#include "sfit_coverage.h"
#include "sfit_incr.h"
#include "sfit_selfcal.h"
#include "sfit_refine.h"
#include "sfit_uncert.h"
#include "sfit_gate.h"
#include "sfit_cluster.h"
#include "sfit_joint.h"
#include "sfit_pair.h"
#include "sfit_imu.h"

#endif /* SFIT_H */
