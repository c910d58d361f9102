/* SPDX-License-Identifier: MIT */
/**
 * @file names.h
 * @brief The one table of status texts and the one table of flag names of
 * the host tools (CLI text and JSON, the session file, the Python binding).
 * A name that differs by context has one family per context, side by side
 * here, so that they cannot drift apart unseen. Host only.
 */
#ifndef SFIT_NAMES_H
#define SFIT_NAMES_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "json_out.h"
#include "sfit/sfit.h"
#include "sfit/sfit_pair.h"

/** Who reads a status text: the CLI (its option names) or Python (its keyword names). */
typedef enum names_ctx { NAMES_CLI = 0, NAMES_PY = 1 } names_ctx_t;

/** A readable explanation of a status, worded for `ctx` ("message" in JSON, stderr, exceptions). */
const char *names_status_message(sfit_status_t st, names_ctx_t ctx);

/** Flag families: one bit set, names by context. */
typedef enum names_family {
    NAMES_FIT,       /**< a fit's sfit_flag bits (+ SFIT_SELFCAL_FLAG_CAPPED, SFIT_MULTI_FLAG_SKIPPED) */
    NAMES_PAIR,      /**< a pair of segments (SFIT_PAIR_FLAG_*; FEW_SAMPLES is "few_frames") */
    NAMES_SESSION,   /**< a calibrated session's joint (the session file) */
    NAMES_SKEL,      /**< a skeleton's pair or joint (SKEL_F_*) */
    NAMES_SKEL_WHY,  /**< why a skeleton's joint is untrusted (SKEL_U_*) */
    NAMES_PAIR_INFO, /**< a pair's information bits (SFIT_PAIR_INFO_*: facts about the data) */
    NAMES_NOISE,     /**< a noise estimate (SFIT_NOISE_FLAG_*; Python's names, the CLI prints booleans) */
    NAMES_IMU,       /**< the joint between two IMUs (SFIT_IMU_FLAG_*; each with a reason, names_imu_reason) */
    NAMES_NFAMILY
} names_family_t;

/** The (bit, name) table of a family, *n its length; NULL for a bad family. */
const json_out_flag_t *names_flags(names_family_t fam, size_t *n);

/** The JSON array of the names of `flags` in family `fam`. */
void names_flags_json(FILE *f, names_family_t fam, uint32_t flags);

/** Why an IMU joint carrying flag `bit` (one SFIT_IMU_FLAG_*) is untrusted, in words; NULL for
 *  another bit. */
const char *names_imu_reason(uint32_t bit);

/** The reasons of every IMU flag set in `flags`, joined by "; " into out[size] (truncated, always
 *  terminated); returns out. */
char *names_imu_reasons(uint32_t flags, char *out, size_t size);

/** The name of a pair's reason (sfit_pair_reason_t), as in JSON and Python. */
const char *names_pair_reason(sfit_pair_reason_t r);

#endif /* SFIT_NAMES_H */
