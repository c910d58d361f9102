/* SPDX-License-Identifier: MIT */
/** @file names.c  Status texts and flag names (names.h). */
#include "names.h"

#include "sfit/sfit_imu.h"
#include "sfit/sfit_multi.h"
#include "sfit/sfit_selfcal.h"
#include "skel.h"

#include <string.h>

/* The status texts: the CLI's and Python's words side by side. */
static const struct {
    sfit_status_t st;
    const char *text[2]; /* NAMES_CLI, NAMES_PY */
} g_status[] = {
    {SFIT_OK, {"ok", "ok"}},
    {SFIT_E_ARG, {"invalid option value", "invalid argument or option"}},
    {SFIT_E_TOO_FEW,
     {"fewer than 4 valid samples", "fewer valid samples than the solution needs"}},
    {SFIT_E_NOT_POSDEF,
     {"C - Sigma_hat is not positive definite: the noise model is larger "
      "than the spread of the samples",
      "not positive definite: the noise model is larger than the spread "
      "of the samples (or the geometry is ill-posed)"}},
    {SFIT_E_NO_CONVERGENCE,
     {"the iteration did not converge within its bound",
      "the iteration did not converge within its bound"}},
    {SFIT_E_DEGENERATE,
     {"degenerate geometry: samples coincident, collinear, or planar "
      "(try --mode planar)",
      "degenerate geometry: samples coincident, collinear, or planar "
      "(try mode='planar')"}},
    {SFIT_E_NONFINITE, {"non-finite value", "non-finite value (NaN or Inf)"}},
    {SFIT_E_RANGE,
     {"value out of the supported float range", "value out of the supported float range"}},
    {SFIT_E_UNSUPPORTED,
     {"not in this build of the library (SFIT_FULL_SOLVER 0)",
      "not in this build of the library (SFIT_FULL_SOLVER 0)"}},
};

const char *names_status_message(sfit_status_t st, names_ctx_t ctx)
{
    const int c = ctx == NAMES_PY ? 1 : 0;
    size_t k;
    for (k = 0; k < sizeof g_status / sizeof g_status[0]; k++) {
        if (g_status[k].st == st) {
            return g_status[k].text[c];
        }
    }
    return c == 1 ? "unknown status" : "unknown error";
}

/* The flag names, one table per family, in the order they are written. */
static const json_out_flag_t g_fit[] = {
    {SFIT_FLAG_UNTRUSTED, "untrusted"},         {SFIT_FLAG_FEW_SAMPLES, "few_samples"},
    {SFIT_FLAG_NEAR_PLANAR, "near_planar"},     {SFIT_FLAG_ROUNDING, "rounding"},
    {SFIT_SELFCAL_FLAG_CAPPED, "noise_capped"}, {SFIT_FLAG_COV_LIMIT, "cov_limit"},
    {SFIT_MULTI_FLAG_SKIPPED, "skipped_markers"},
};
static const json_out_flag_t g_pair[] = {
    {SFIT_FLAG_UNTRUSTED, "untrusted"},            {SFIT_FLAG_FEW_SAMPLES, "few_frames"},
    {SFIT_PAIR_FLAG_SMALL_MOTION, "small_motion"}, {SFIT_PAIR_FLAG_AXIS_FREE, "axis_free"},
    {SFIT_PAIR_FLAG_AMBIGUOUS, "ambiguous"},       {SFIT_PAIR_FLAG_MISFIT, "misfit"},
    {SFIT_PAIR_FLAG_NO_NOISE, "no_noise"},
};
static const json_out_flag_t g_session[] = {
    {SFIT_FLAG_NEAR_PLANAR, "near_planar"},
    {SFIT_FLAG_FEW_SAMPLES, "few_samples"},
    {SFIT_FLAG_UNTRUSTED, "untrusted"},
};
static const json_out_flag_t g_skel[] = {
    {SKEL_F_NO_MOTION, "no_motion"},   {SKEL_F_SMALL_RANGE, "small_range"},
    {SKEL_F_FEW_FRAMES, "few_frames"}, {SKEL_F_BORDERLINE, "borderline"},
    {SKEL_F_FORCED, "forced"},         {SKEL_F_TYPE_TRIAL, "type_from_trial"},
    {SKEL_F_ONE_TRIAL, "one_trial"},   {SKEL_F_UNTRUSTED, "untrusted"},
};
static const json_out_flag_t g_skel_why[] = {
    {SKEL_U_MISFIT, "misfit"},
    {SKEL_U_COST, "cost"},
    {SKEL_U_REACH, "reach"},
    {SKEL_U_MODULE, "module"},
};

static const json_out_flag_t g_pair_info[] = {
    {SFIT_PAIR_INFO_AXIS_FREE, "axis_free"},
    {SFIT_PAIR_INFO_SKIN, "skin_motion"},
};
static const json_out_flag_t g_noise[] = {
    {SFIT_NOISE_FLAG_NEGATIVE, "negative"},
    {SFIT_NOISE_FLAG_IMPRECISE, "imprecise"},
};
/* The IMU joint's flags: a name (JSON, Python) and the reason in words (same order). */
static const json_out_flag_t g_imu[] = {
    {SFIT_IMU_FLAG_LOW_ROTATION, "low_rotation"},
    {SFIT_IMU_FLAG_LOW_VARIETY, "low_variety"},
    {SFIT_IMU_FLAG_SLIP, "slip"},
    {SFIT_IMU_FLAG_AMBIGUOUS, "ambiguous"},
    {SFIT_IMU_FLAG_AXIS_OFF, "axis_off"},
    {SFIT_IMU_FLAG_WOBBLE, "wobble"},
};
static const char *const g_imu_why[sizeof g_imu / sizeof g_imu[0]] = {
    "a sensor hardly rotates: its joint position is not determined",
    "too little variety of motion: a joint position is uncertain beyond the accepted SD",
    "the residual is far above the sensors' noise: a sensor slips, or the joint is not one",
    "ball and hinge cannot be told apart",
    ("the hinge axes from the rates disagree with the line along which the accelerometers "
     "leave the joint free: a wobble in step with the flexion biases them"),
    ("the hinge axes from the rates do not fit the accelerometers: the axis turns in the "
     "segments in step with the flexion, and the axes may be off by several degrees"),
};

const char *names_imu_reason(uint32_t bit)
{
    size_t k;
    for (k = 0; k < sizeof g_imu / sizeof g_imu[0]; k++) {
        if (g_imu[k].bit == bit) {
            return g_imu_why[k];
        }
    }
    return NULL;
}

char *names_imu_reasons(uint32_t flags, char *out, size_t size)
{
    size_t k;
    if (out == NULL || size == 0u) {
        return out;
    }
    out[0] = '\0';
    for (k = 0; k < sizeof g_imu / sizeof g_imu[0]; k++) {
        if (flags & g_imu[k].bit) {
            if (out[0] != '\0') {
                strncat(out, "; ", size - strlen(out) - 1u);
            }
            strncat(out, g_imu_why[k], size - strlen(out) - 1u);
        }
    }
    return out;
}

const json_out_flag_t *names_flags(names_family_t fam, size_t *n)
{
#define NAMES_TAB(t) (*n = sizeof(t) / sizeof((t)[0]), (t))
    switch (fam) {
    case NAMES_FIT: return NAMES_TAB(g_fit);
    case NAMES_PAIR: return NAMES_TAB(g_pair);
    case NAMES_SESSION: return NAMES_TAB(g_session);
    case NAMES_SKEL: return NAMES_TAB(g_skel);
    case NAMES_SKEL_WHY: return NAMES_TAB(g_skel_why);
    case NAMES_PAIR_INFO: return NAMES_TAB(g_pair_info);
    case NAMES_NOISE: return NAMES_TAB(g_noise);
    case NAMES_IMU: return NAMES_TAB(g_imu);
    case NAMES_NFAMILY:
    default: *n = 0; return NULL;
    }
#undef NAMES_TAB
}

void names_flags_json(FILE *f, names_family_t fam, uint32_t flags)
{
    size_t n;
    const json_out_flag_t *t = names_flags(fam, &n);
    json_out_flags(f, flags, t, n);
}

const char *names_pair_reason(sfit_pair_reason_t r)
{
    switch (r) {
    case SFIT_PAIR_REASON_FEW_FRAMES: return "few_frames";
    case SFIT_PAIR_REASON_SMALL_MOTION: return "small_motion";
    case SFIT_PAIR_REASON_AXIS_FREE: return "axis_free";
    case SFIT_PAIR_REASON_AMBIGUOUS: return "ambiguous";
    case SFIT_PAIR_REASON_MISFIT: return "misfit";
    case SFIT_PAIR_REASON_NO_NOISE: return "no_noise";
    case SFIT_PAIR_REASON_NONE:
    default: return "none";
    }
}
