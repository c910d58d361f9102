/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_common.h
 * @brief Shared pieces of the libFuzzer harnesses: a byte reader that never
 * fails (an exhausted input reads as zeros), float decoders biased towards
 * hostile values, sentinel-filled outputs and the contract checks.
 *
 * A contract violation prints what was violated and calls abort(), which
 * libFuzzer (and the replay driver) report as a crash with the input saved.
 */
#ifndef SFIT_FUZZ_COMMON_H
#define SFIT_FUZZ_COMMON_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit_solve.h" /* sfit_i_check_noise: the PSD rule */


/** Byte pattern of an output the library must not write on failure. */
#define FZ_SENTINEL 0xA5

/** Abort with a message when a contract clause does not hold. */
#define FZ_CHECK(cond, what)                                                           \
    do {                                                                               \
        if (!(cond)) {                                                                 \
            (void)fprintf(stderr, "sfit fuzz: contract violated at %s:%d: %s\n",       \
                          __FILE__, __LINE__, (what));                                 \
            abort();                                                                   \
        }                                                                              \
    } while (0)

/** The input, read front to back. */
typedef struct fz_in {
    const uint8_t *p;
    size_t n;
    size_t i;
} fz_in_t;

/* The byte of a bool without loading it as a bool (a sentinel or a garbage
 * byte: sfit_types.h, "Yes/no"). */
static inline unsigned fz_byte(const void *p)
{
    return *(const unsigned char *)p;
}

static inline int fz_more(const fz_in_t *in)
{
    return in->i < in->n;
}

static inline uint8_t fz_u8(fz_in_t *in)
{
    return (in->i < in->n) ? in->p[in->i++] : (uint8_t)0;
}

static inline uint32_t fz_u32(fz_in_t *in)
{
    uint32_t u = 0u;
    int k;
    for (k = 0; k < 4; k++) {
        u |= (uint32_t)fz_u8(in) << (8 * k);
    }
    return u;
}

/** Four bytes reinterpreted as a float (every NaN, Inf, subnormal). */
static inline float fz_raw(fz_in_t *in)
{
    const uint32_t u = fz_u32(in);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/** Values a glitching sensor or a bad configuration can produce. */
static const float fz_specials[] = {
    0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 100.0f, 2700.0f, -2700.0f,
    FLT_MIN, -FLT_MIN, 1.40129846e-45f /* smallest subnormal */, FLT_EPSILON,
    FLT_MAX, -FLT_MAX, 1e30f, -1e30f, 1.8446743e19f /* ~sqrt(FLT_MAX) */,
    134217728.0f /* 2^27: first rejected coordinate */,
    134217720.0f /* largest accepted coordinate (2^27 - 8) */, -134217720.0f,
    1e-20f, 1e20f, 3.14159274f, 0.999999940f,
    INFINITY, -INFINITY, NAN, -NAN};
#define FZ_NSPECIALS (sizeof fz_specials / sizeof fz_specials[0])

/**
 * A float for a sample or an option: raw bits (1/8), a special value (1/8),
 * or a 16-bit integer times a power of two in 2^-20..2^11 (3/4, so that most
 * inputs reach the solvers rather than the range checks).
 */
static inline float fz_float(fz_in_t *in)
{
    const uint8_t k = fz_u8(in);
    switch (k & 7u) {
    case 0:
        return fz_raw(in);
    case 1:
        return fz_specials[fz_u8(in) % FZ_NSPECIALS];
    default: {
        const int16_t q = (int16_t)(uint16_t)((uint16_t)fz_u8(in) | ((uint16_t)fz_u8(in) << 8));
        return ldexpf((float)q, (int)(k >> 3) - 20);
    }
    }
}

/**
 * A sample near a sphere of radius 100 about one of four centres (one far
 * from the origin, as in motion capture), direction from three signed bytes,
 * an optional small perturbation; so that solves succeed often.
 */
static inline void fz_sphere_point(fz_in_t *in, sfit_vec3_t *x)
{
    static const float centres[4][3] = {
        {0.0f, 0.0f, 0.0f}, {2700.0f, -1200.0f, 900.0f}, {1e6f, 1e6f, -1e6f}, {0.25f, 0.5f, 1.0f}};
    const uint8_t sel = fz_u8(in);
    const float *c = centres[sel & 3u];
    float d[3], nrm;
    int k;
    for (k = 0; k < 3; k++) {
        d[k] = (float)(int8_t)fz_u8(in);
    }
    nrm = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(nrm > 0.0f)) {
        d[0] = 1.0f;
        nrm = 1.0f;
    }
    for (k = 0; k < 3; k++) {
        float e = 0.0f;
        if ((sel & 4u) != 0u) {
            e = ldexpf((float)(int8_t)fz_u8(in), -6); /* +-2 */
        }
        x->v[k] = c[k] + 100.0f * d[k] / nrm + e;
    }
}

static inline int fz_finite(float x)
{
    return isfinite(x) ? 1 : 0;
}

static inline int fz_all_finite(const float *x, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++) {
        if (!fz_finite(x[k])) {
            return 0;
        }
    }
    return 1;
}

/** 1 when every byte of an object still holds the sentinel. */
static inline int fz_untouched(const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    size_t k;
    for (k = 0; k < n; k++) {
        if (b[k] != (unsigned char)FZ_SENTINEL) {
            return 0;
        }
    }
    return 1;
}

/** Every status the library may return; anything else is a violation. */
static inline int fz_status_defined(sfit_status_t st)
{
    switch (st) {
    case SFIT_OK:
    case SFIT_E_ARG:
    case SFIT_E_TOO_FEW:
    case SFIT_E_NOT_POSDEF:
    case SFIT_E_NO_CONVERGENCE:
    case SFIT_E_DEGENERATE:
    case SFIT_E_NONFINITE:
    case SFIT_E_RANGE:
    case SFIT_E_UNSUPPORTED:
        return 1;
    default:
        return 0;
    }
}

/** Defined status, and a failed call left its output untouched. */
#define FZ_CHECK_OUT(st, obj, what)                                                    \
    do {                                                                               \
        FZ_CHECK(fz_status_defined(st), what ": undefined status");                    \
        if ((st) != SFIT_OK) {                                                         \
            FZ_CHECK(fz_untouched(&(obj), sizeof(obj)), what ": output written on failure"); \
        }                                                                              \
    } while (0)

/*
 * A fit configuration decoded from the input, including invalid enums and
 * hostile noise values. With allow_asym, bit 0x20 of the selector byte
 * reads a separate upper XY entry (the library must read only the lower
 * triangle).
 */
static inline void fz_cfg_decode(fz_in_t *in, sfit_fit_cfg_t *cfg, int allow_asym)
{
    const uint8_t b = fz_u8(in);
    int k;
    *cfg = sfit_fit_cfg_default;
    cfg->mode = (sfit_mode_t)(b % 4u);               /* 3 is invalid */
    cfg->noise = (sfit_noise_kind_t)((b >> 2) % 4u); /* 3 is invalid */
    if ((b & 0x10u) != 0u) {
        cfg->planar_ratio = fz_float(in);
    }
    if (cfg->noise == SFIT_NOISE_ISO) {
        cfg->noise_var = fz_float(in);
    } else if (cfg->noise == SFIT_NOISE_COV) {
        float p[6];
        for (k = 0; k < 6; k++) {
            p[k] = fz_float(in);
        }
        cfg->noise_cov.m[0] = p[0];
        cfg->noise_cov.m[4] = p[1];
        cfg->noise_cov.m[8] = p[2];
        cfg->noise_cov.m[1] = p[3];
        cfg->noise_cov.m[3] = (allow_asym && (b & 0x20u) != 0u) ? fz_float(in) : p[3];
        cfg->noise_cov.m[2] = p[4];
        cfg->noise_cov.m[6] = p[4];
        cfg->noise_cov.m[5] = p[5];
        cfg->noise_cov.m[7] = p[5];
    } else {
        /* no noise values */
    }
}

/*
 * Positive semi-definiteness of a noise covariance: the library's own test
 * (sfit_i_check_noise, lib/src/sfit_solve.c) so that the oracle agrees at
 * the rounding boundary; tests/test_hostile.c checks that rule against
 * definite, semi-definite (rank 1 and 2, every scale) and indefinite
 * matrices.
 */
static inline int fz_psd(const sfit_mat3_t *c)
{
    return sfit_i_check_noise(SFIT_NOISE_COV, 0.0f, c) == SFIT_OK;
}

/*
 * What sfit_fit.h rejects with SFIT_E_ARG (NULL aside): a mode or noise
 * kind outside the enum, a planar ratio outside [0, 1) or not finite, a
 * negative or non-finite variance, a non-finite covariance entry, a
 * negative diagonal, or a covariance that is not positive semi-definite
 * (fz_psd: the library's float expressions, lower triangle).
 */
static inline int fz_cfg_valid(const sfit_fit_cfg_t *cfg)
{
    if ((int)cfg->mode < 0 || (int)cfg->mode > 2 || (int)cfg->noise < 0 || (int)cfg->noise > 2) {
        return 0;
    }
    if (!fz_finite(cfg->planar_ratio) || cfg->planar_ratio < 0.0f || cfg->planar_ratio >= 1.0f) {
        return 0;
    }
    if (cfg->noise == SFIT_NOISE_ISO && (!fz_finite(cfg->noise_var) || cfg->noise_var < 0.0f)) {
        return 0;
    }
    if (cfg->noise == SFIT_NOISE_COV) {
        const float *c = cfg->noise_cov.m;
        if (!fz_all_finite(c, 9) || c[0] < 0.0f || c[4] < 0.0f || c[8] < 0.0f) {
            return 0;
        }
        return fz_psd(&cfg->noise_cov);
    }
    return 1;
}

#endif /* SFIT_FUZZ_COMMON_H */
