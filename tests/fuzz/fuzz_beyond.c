/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_beyond.c
 * @brief libFuzzer harness for the modules beyond the core fit: the
 * self-calibrated UGDK (sfit_selfcal.h), the geometric refinement
 * (sfit_refine.h), the fit uncertainty (sfit_uncert.h) and the outlier gate
 * (sfit_gate.h). The input is a little program that builds a bounded point
 * buffer (at most FZ_MAXPTS samples: spheres, caps, circles, coincident,
 * collinear and planar sets, raw bit patterns, rescaled by hostile factors)
 * and calls the APIs on windows of it with hostile options; after every call
 * the contract is asserted:
 *  - every call returns one of the sfit_status_t values, and the status
 *    documented for the cause (E_ARG iff an invalid argument, TOO_FEW below
 *    the sample minimum, NONFINITE / RANGE for a bad sample);
 *  - a failed call leaves its sentinel-filled output untouched;
 *  - every float of an SFIT_OK result is finite (radius > 0, counts right);
 *  - the array functions read only pts[0..n-1] (the window is copied to the
 *    END of a static array, so a read past n hits ASan's global redzone)
 *    and never write it;
 *  - a sample rejected by sfit_gate_add (status != SFIT_OK) leaves the gate
 *    byte for byte unchanged, and accepted + outliers follows a shadow count.
 *
 * Program format: a sequence of [opcode byte][operands]; an exhausted input
 * reads as zeros. See tests/fuzz/README.md for the opcode table.
 */
#include "fuzz_common.h"

#include "sfit/sfit_gate.h"
#include "sfit/sfit_refine.h"
#include "sfit/sfit_selfcal.h"
#include "sfit/sfit_uncert.h"

#define FZ_MAXPTS 128u /* point buffer: bounds the cost of every call */
#define FZ_MAX_OPS 48
/*
 * Work budget per input, so that libFuzzer keeps > 2000 executions/s under
 * ASan + UBSan: at most FZ_MAX_HEAVY self-calibrations / refinements that
 * reach their iterations (valid arguments, n >= 5, no bad sample; cheaper
 * calls are not counted) and FZ_MAX_GATES gate lives (each may run the
 * robust start); further such operations are skipped.
 */
#define FZ_MAX_HEAVY 8u
#define FZ_MAX_GATES 3u

/*
 * Findings of this harness, all fixed in lib/ and checked strictly
 * (FZ_STRICT defaults to 1; 0 restores the old tolerance for bisecting):
 *  1. sfit_selfcal_points() returns SFIT_E_ARG on valid input when its GDKE
 *     start reports a negative smallest eigenvalue of C (rounding on
 *     near-degenerate samples): the cap SFIT_SELFCAL_MAX_TRUST * lambda_min
 *     is then a negative noise variance, which sfit_fit_moments() rejects.
 *     Tolerated exactly in that case (the harness repeats the GDKE start).
 *  2. sfit_selfcal_noise_var() returns SFIT_E_DEGENERATE for a sample at
 *     the centre: now documented in its header.
 *  3. sfit_refine_points() returns SFIT_OK ("converged" at c0) on coincident
 *     samples (n >= 10): it factors A + lambda diag(A), which the diagonal
 *     damping makes regular when A is singular, and never tests A itself.
 */
#ifndef FZ_STRICT
#define FZ_STRICT 1
#endif

/* Fewest samples of selfcal / refine: 4 parameters plus one residual. */
#define FZ_MIN5 ((SFIT_MIN_SAMPLES > 5u) ? (size_t)SFIT_MIN_SAMPLES : (size_t)5u)

typedef struct fz_state {
    sfit_vec3_t pts[FZ_MAXPTS];
    size_t npts;   /* valid points (<= FZ_MAXPTS) */
    size_t cursor; /* next write position once full (ring) */
    sfit_gate_t gate;
    uint64_t gate_offered; /* samples the gate judged (status OK) since init / reset */
    unsigned heavy;        /* budget used: iterative selfcal / refine calls */
    unsigned gates;        /* budget used: gate lives */
    /* The last fit produced by any call: operands of the next calls. */
    sfit_vec3_t ctx_center;
    float ctx_radius;
    float ctx_var;
} fz_state_t;

/* Windows are copied to the end of this array (see the file comment). */
static sfit_vec3_t fz_win[FZ_MAXPTS];

enum {
    OP_POINTS = 0,     /* kind, operands: grow / transform the point buffer */
    OP_SELFCAL,        /* window, cfg */
    OP_SELFCAL_VAR,    /* window, centre/radius selector */
    OP_REFINE,         /* window, c0 selector, refine cfg */
    OP_UNCERT_MOM,     /* source, selector, kind */
    OP_UNCERT_PTS,     /* window, selector */
    OP_GATE_INIT,      /* gate cfg */
    OP_GATE_ADD,       /* how, sample */
    OP_GATE_FEED,      /* window: every sample to the gate */
    OP_GATE_REFRESH,   /* - */
    OP_GATE_SOLVE,     /* - */
    OP_GATE_RESET,     /* - */
    OP_BATCH,          /* window: sfit_fit_points, sets the context */
    OP_NULLS,          /* every entry point with NULL pointers */
    OP_COUNT
};

/* ---------------------------------------------------------------- inputs */

static void fz_mixed3(fz_in_t *in, sfit_vec3_t *x)
{
    int k;
    for (k = 0; k < 3; k++) {
        x->v[k] = fz_float(in);
    }
}

static void fz_raw3(fz_in_t *in, sfit_vec3_t *x)
{
    int k;
    for (k = 0; k < 3; k++) {
        x->v[k] = fz_raw(in);
    }
}

static void fz_push(fz_state_t *s, const sfit_vec3_t *x)
{
    if (s->npts < FZ_MAXPTS) {
        s->pts[s->npts++] = *x;
    } else {
        s->pts[s->cursor] = *x;
        s->cursor = (s->cursor + 1u) % FZ_MAXPTS;
    }
}

/*
 * Points on a cap of half-angle (cap + 1) pi / 256 about one axis (golden
 * angle spiral), optionally flattened to the circle z = 0 (planar), with a
 * small deterministic perturbation; centre and radius are hostile floats.
 */
static void fz_gen_cap(fz_state_t *s, fz_in_t *in)
{
    const uint8_t flags = fz_u8(in);
    const uint8_t capb = fz_u8(in);
    const size_t cnt = (size_t)fz_u8(in);
    const uint8_t noise = fz_u8(in);
    sfit_vec3_t c;
    float r, cap, amp;
    uint32_t lcg = 0x9E3779B9u ^ noise;
    size_t i;
    fz_mixed3(in, &c);
    r = fz_float(in);
    cap = 3.14159265f * ((float)capb + 1.0f) / 256.0f;
    amp = ((flags & 4u) != 0u) ? r * ldexpf(1.0f, -(int)(noise & 31u)) : 0.0f;
    for (i = 0; i < cnt; i++) {
        const float u = ((float)i + 0.5f) / (float)cnt;
        const float z = ((flags & 1u) != 0u) ? 0.0f : 1.0f - u * (1.0f - cosf(cap));
        const float phi = ((flags & 1u) != 0u) ? cap * (2.0f * u - 1.0f) : 2.39996323f * (float)i;
        const float q = ((flags & 1u) != 0u) ? 1.0f : sqrtf(fmaxf(0.0f, 1.0f - z * z));
        float d[3], e[3];
        sfit_vec3_t x;
        int k;
        d[0] = q * cosf(phi);
        d[1] = q * sinf(phi);
        d[2] = z;
        for (k = 0; k < 3; k++) {
            lcg = lcg * 1664525u + 1013904223u;
            e[k] = amp * ((float)(lcg >> 8) * (1.0f / 16777216.0f) - 0.5f);
        }
        for (k = 0; k < 3; k++) {
            /* flags & 2: rotate the axes (cap about x instead of z) */
            const int j = ((flags & 2u) != 0u) ? (k + 1) % 3 : k;
            x.v[k] = c.v[k] + r * d[j] + e[k];
        }
        fz_push(s, &x);
    }
}

static void fz_points(fz_state_t *s, fz_in_t *in)
{
    const uint8_t kind = fz_u8(in);
    sfit_vec3_t x, d;
    size_t cnt, i;
    int k;
    switch ((kind & 0x7Fu) % 9u) {
    case 0: /* points near a sphere of radius 100 (fuzz_common.h) */
        cnt = (size_t)(fz_u8(in) % 65u);
        for (i = 0; i < cnt; i++) {
            fz_sphere_point(in, &x);
            fz_push(s, &x);
        }
        break;
    case 1: /* one sample: raw bits */
        fz_raw3(in, &x);
        fz_push(s, &x);
        break;
    case 2: /* one sample: mixed floats */
        fz_mixed3(in, &x);
        fz_push(s, &x);
        break;
    case 3: /* coincident: the last point (or a new one) many times */
        cnt = (size_t)fz_u8(in);
        if ((kind & 0x80u) != 0u || s->npts == 0u) {
            fz_mixed3(in, &x);
        } else {
            x = s->pts[(s->npts < FZ_MAXPTS) ? s->npts - 1u : (s->cursor + FZ_MAXPTS - 1u) % FZ_MAXPTS];
        }
        for (i = 0; i < cnt; i++) {
            fz_push(s, &x);
        }
        break;
    case 4: /* collinear: base + i dir */
        cnt = (size_t)fz_u8(in);
        fz_mixed3(in, &x);
        fz_mixed3(in, &d);
        for (i = 0; i < cnt; i++) {
            sfit_vec3_t y;
            for (k = 0; k < 3; k++) {
                y.v[k] = x.v[k] + (float)i * d.v[k];
            }
            fz_push(s, &y);
        }
        break;
    case 5: /* cap / circle with hostile centre and radius */
        fz_gen_cap(s, in);
        break;
    case 6: { /* transform every point: x * scale + offset */
        const float sc = fz_float(in);
        fz_mixed3(in, &d);
        for (i = 0; i < s->npts; i++) {
            for (k = 0; k < 3; k++) {
                s->pts[i].v[k] = s->pts[i].v[k] * sc + d.v[k];
            }
        }
        break;
    }
    case 7: /* poison one point with raw bits */
        if (s->npts > 0u) {
            i = (size_t)fz_u8(in) % s->npts;
            fz_raw3(in, &s->pts[i]);
        }
        break;
    default: /* keep the first k points */
        s->npts = (size_t)fz_u8(in) % (s->npts + 1u);
        s->cursor = 0u;
        break;
    }
}

/* A window [start, start + n) of the buffer, copied to the end of fz_win. */
typedef struct fz_win {
    const sfit_vec3_t *p;
    size_t n;
    size_t start;
} fz_win_t;

static void fz_window(const fz_state_t *s, fz_in_t *in, fz_win_t *w)
{
    const size_t start = (size_t)fz_u8(in) % (s->npts + 1u);
    const uint8_t b = fz_u8(in);
    const size_t rest = s->npts - start;
    const size_t len = (b == 0u) ? rest : (size_t)b % (rest + 1u);
    sfit_vec3_t *dst = &fz_win[FZ_MAXPTS - len];
    if (len > 0u) {
        memcpy(dst, &s->pts[start], len * sizeof *dst);
    }
    w->p = dst;
    w->n = len;
    w->start = start;
}

/* The array functions take const samples: the window must be unchanged. */
static void fz_check_window(const fz_state_t *s, const fz_win_t *w, const char *what)
{
    if (w->n > 0u) {
        FZ_CHECK(memcmp(w->p, &s->pts[w->start], w->n * sizeof *w->p) == 0, what);
    }
}

/* Bit mask of the bad samples of an array: 1 some NaN/Inf, 2 some out of range. */
static unsigned fz_bad_kinds(const sfit_vec3_t *p, size_t n)
{
    unsigned m = 0u;
    size_t i;
    for (i = 0; i < n; i++) {
        if (!fz_all_finite(p[i].v, 3)) {
            m |= 1u;
        } else if (fabsf(p[i].v[0]) >= 134217728.0f || fabsf(p[i].v[1]) >= 134217728.0f
                   || fabsf(p[i].v[2]) >= 134217728.0f) {
            m |= 2u; /* |x| >= 2^SFIT_COORD_MAX_EXP */
        } else {
            /* valid */
        }
    }
    return m;
}

/* 1 when the n >= 1 samples are bit-for-bit the same point (directions span 1-D). */
static int fz_coincident(const sfit_vec3_t *p, size_t n)
{
    size_t i;
    for (i = 1; i < n; i++) {
        if (memcmp(&p[i], &p[0], sizeof p[0]) != 0) {
            return 0;
        }
    }
    return n > 0u;
}

/* The status of an array with bad samples: NONFINITE / RANGE per cause. */
static void fz_check_bad_status(sfit_status_t st, unsigned bad, const char *what)
{
    if (bad == 1u) {
        FZ_CHECK(st == SFIT_E_NONFINITE, what);
    } else if (bad == 2u) {
        FZ_CHECK(st == SFIT_E_RANGE, what);
    } else {
        FZ_CHECK(st == SFIT_E_NONFINITE || st == SFIT_E_RANGE, what);
    }
}

static void fz_cfg(fz_in_t *in, sfit_fit_cfg_t *cfg)
{
    fz_cfg_decode(in, cfg, 0);
}


/*
 * Centre, radius and noise variance operands: the last fit, hostile floats,
 * a buffer point as the centre (a sample at the centre), or the last fit
 * scaled / shifted by hostile floats.
 */
static void fz_fit_operands(const fz_state_t *s, fz_in_t *in, sfit_vec3_t *c, float *r, float *v)
{
    const uint8_t sel = fz_u8(in);
    int k;
    switch (sel & 3u) {
    case 0:
        *c = s->ctx_center;
        break;
    case 1:
        fz_mixed3(in, c);
        break;
    case 2:
        *c = (s->npts > 0u) ? s->pts[(size_t)fz_u8(in) % s->npts] : s->ctx_center;
        break;
    default:
        fz_mixed3(in, c);
        for (k = 0; k < 3; k++) {
            c->v[k] += s->ctx_center.v[k];
        }
        break;
    }
    switch ((sel >> 2) & 3u) {
    case 0:
        *r = s->ctx_radius;
        break;
    case 1:
        *r = fz_float(in);
        break;
    case 2:
        *r = s->ctx_radius * fz_float(in);
        break;
    default:
        *r = ((sel & 0x40u) != 0u) ? -s->ctx_radius : 0.0f;
        break;
    }
    switch ((sel >> 4) & 3u) {
    case 0:
        *v = s->ctx_var;
        break;
    case 1:
        *v = fz_float(in);
        break;
    case 2:
        *v = 0.0f;
        break;
    default:
        *v = s->ctx_var * fz_float(in);
        break;
    }
}

/* The status rule for a fit handed in: any NaN/Inf -> E_NONFINITE, else a
 * radius <= 0 or a negative variance -> E_ARG. */
static sfit_status_t fz_fit_args_status(const sfit_vec3_t *c, float r, float v)
{
    if (!fz_all_finite(c->v, 3) || !fz_finite(r) || !fz_finite(v)) {
        return SFIT_E_NONFINITE;
    }
    return (r > 0.0f && v >= 0.0f) ? SFIT_OK : SFIT_E_ARG;
}

static void fz_set_ctx(fz_state_t *s, const sfit_vec3_t *c, float r, float v)
{
    s->ctx_center = *c;
    s->ctx_radius = r;
    s->ctx_var = v;
}

/* Checks of an SFIT_OK sfit_result_t (as fuzz_stream.c). */
static void fz_check_result(const sfit_result_t *r, uint64_t n, const sfit_fit_cfg_t *cfg,
                            const char *what)
{
    FZ_CHECK(fz_all_finite(r->center.v, 3) && fz_finite(r->radius), what);
    FZ_CHECK(fz_all_finite(r->eigenvalues.v, 3) && fz_all_finite(r->axis.v, 3), what);
    FZ_CHECK(fz_finite(r->trust_ratio) && fz_finite(r->leontief_ratio), what);
    FZ_CHECK(r->radius > 0.0f, what);
    FZ_CHECK((uint64_t)r->n == n, what);
    FZ_CHECK(r->eigenvalues.v[0] <= r->eigenvalues.v[1] && r->eigenvalues.v[1] <= r->eigenvalues.v[2],
             what);
    FZ_CHECK(r->mode == SFIT_MODE_SPHERE || r->mode == SFIT_MODE_PLANAR, what);
    FZ_CHECK(cfg->mode == SFIT_MODE_AUTO || r->mode == cfg->mode, what);
    FZ_CHECK(r->method == ((cfg->noise == SFIT_NOISE_NONE) ? SFIT_METHOD_GDKE : SFIT_METHOD_UGDK), what);
    FZ_CHECK(r->trust_ratio >= 0.0f && r->trust_ratio <= 1.0f, what);
    FZ_CHECK(r->leontief_ratio >= 0.0f, what);
}

/* ------------------------------------------------------ selfcal / refine */

/* Known finding 1: the GDKE start of sfit_selfcal_points() (sphere, no noise,
 * the caller's planar ratio) succeeds with lambda_min(C) < 0. */
static int fz_selfcal_negative_cap(const sfit_vec3_t *w, size_t n, const sfit_fit_cfg_t *pc)
{
    sfit_moments_t m;
    sfit_fit_cfg_t fc = (pc != NULL) ? *pc : sfit_fit_cfg_default;
    sfit_result_t r;
    fc.mode = SFIT_MODE_SPHERE;
    fc.noise = SFIT_NOISE_NONE;
    fc.noise_var = 0.0f;
    (void)sfit_moments_init(&m);
    return sfit_moments_add_block(&m, w, n, NULL) == SFIT_OK && sfit_fit_moments(&m, &fc, &r) == SFIT_OK
           && r.eigenvalues.v[0] < 0.0f;
}

static void fz_selfcal(fz_state_t *s, fz_in_t *in)
{
    fz_win_t win;
    const sfit_vec3_t *w;
    size_t n;
    sfit_fit_cfg_t cfg;
    const sfit_fit_cfg_t *pc;
    sfit_selfcal_cfg_t sc;
    int valid;
    sfit_selfcal_result_t r;
    sfit_status_t st;
    unsigned bad;
    fz_window(s, in, &win);
    w = win.p;
    n = win.n;
    fz_cfg(in, &cfg);
    pc = ((fz_u8(in) & 7u) == 0u) ? NULL : &cfg;
    /* The same input bytes as before; only the planar ratio is an option
     * of the self-calibration now. */
    sc.planar_ratio = cfg.planar_ratio;
    cfg.mode = SFIT_MODE_SPHERE;
    cfg.noise = SFIT_NOISE_NONE;
    valid = (pc == NULL) || fz_cfg_valid(pc);
    memset(&r, FZ_SENTINEL, sizeof r);
    bad = fz_bad_kinds(w, n);
    if (n >= FZ_MIN5 && bad == 0u && valid) {
        if (s->heavy >= FZ_MAX_HEAVY) {
            return; /* budget spent */
        }
        s->heavy++;
    }
    st = sfit_selfcal_points(w, n, (pc != NULL) ? &sc : NULL, &r);
    FZ_CHECK_OUT(st, r, "sfit_selfcal_points");
    fz_check_window(s, &win, "sfit_selfcal_points wrote its samples");
    if (!valid) {
        FZ_CHECK(st == SFIT_E_ARG, "sfit_selfcal_points: invalid option accepted");
    } else if (n < FZ_MIN5) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_selfcal_points: too few samples not reported");
    } else if (bad != 0u) {
        fz_check_bad_status(st, bad, "sfit_selfcal_points: wrong status for a bad sample");
    } else {
        if (st == SFIT_E_ARG && !FZ_STRICT && fz_selfcal_negative_cap(w, n, pc)) {
            st = SFIT_E_DEGENERATE; /* known finding 1 */
        }
        if (st == SFIT_E_ARG) {
            (void)fprintf(stderr, "sfit_selfcal_points: E_ARG on valid arguments (n %u)\n", (unsigned)n);
        }
        FZ_CHECK(st != SFIT_E_ARG && st != SFIT_E_TOO_FEW && st != SFIT_E_NONFINITE,
                 "sfit_selfcal_points: argument / sample status on valid input");
    }
    if (fz_coincident(w, n)) {
        FZ_CHECK(st != SFIT_OK, "sfit_selfcal_points: a fit through coincident samples");
    }
    if (st == SFIT_OK) {
        sfit_fit_cfg_t used = sfit_fit_cfg_default;
        used.mode = SFIT_MODE_SPHERE;
        used.noise = SFIT_NOISE_ISO;
        fz_check_result(&r.fit, n, &used, "sfit_selfcal_points: bad fit");
        FZ_CHECK(fz_finite(r.noise_var) && r.noise_var >= 0.0f, "sfit_selfcal_points: noise_var");
        FZ_CHECK(r.iterations >= 1u && r.iterations <= (uint32_t)SFIT_SELFCAL_MAX_ITERS,
                 "sfit_selfcal_points: iterations");
        FZ_CHECK((r.flags & ~(uint32_t)SFIT_SELFCAL_FLAG_CAPPED) == 0u, "sfit_selfcal_points: flags");
        fz_set_ctx(s, &r.fit.center, r.fit.radius, r.noise_var);
    }
}

static void fz_selfcal_var(fz_state_t *s, fz_in_t *in)
{
    fz_win_t win;
    const sfit_vec3_t *w;
    size_t n;
    sfit_vec3_t c;
    float rad, v, out;
    sfit_status_t st;
    unsigned bad;
    fz_window(s, in, &win);
    w = win.p;
    n = win.n;
    fz_fit_operands(s, in, &c, &rad, &v);
    memset(&out, FZ_SENTINEL, sizeof out);
    st = sfit_selfcal_noise_var(w, n, &c, rad, &out);
    FZ_CHECK_OUT(st, out, "sfit_selfcal_noise_var");
    fz_check_window(s, &win, "sfit_selfcal_noise_var wrote its samples");
    bad = fz_bad_kinds(w, n);
    if (fz_fit_args_status(&c, rad, 0.0f) != SFIT_OK) {
        FZ_CHECK(st == fz_fit_args_status(&c, rad, 0.0f),
                 "sfit_selfcal_noise_var: bad centre / radius: wrong status");
    } else if (n < 5u) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_selfcal_noise_var: too few samples not reported");
    } else if (st == SFIT_E_DEGENERATE) {
        /* a sample at the centre (before any bad sample): documented */
    } else if (bad != 0u) {
        fz_check_bad_status(st, bad, "sfit_selfcal_noise_var: wrong status for a bad sample");
    } else {
        FZ_CHECK(st == SFIT_OK || st == SFIT_E_RANGE, "sfit_selfcal_noise_var: status");
    }
    if (st == SFIT_OK) {
        FZ_CHECK(fz_finite(out) && out >= 0.0f, "sfit_selfcal_noise_var: estimate");
    }
}

static void fz_refine(fz_state_t *s, fz_in_t *in)
{
    fz_win_t win;
    const sfit_vec3_t *w;
    size_t n;
    sfit_vec3_t c0;
    float rad, v;
    sfit_refine_cfg_t cfg = sfit_refine_cfg_default;
    const sfit_refine_cfg_t *pc = NULL;
    sfit_refine_result_t r;
    sfit_status_t st;
    uint32_t maxit;
    int args_ok, tol_ok;
    uint8_t b;
    unsigned bad;
    fz_window(s, in, &win);
    w = win.p;
    n = win.n;
    b = fz_u8(in);
    fz_fit_operands(s, in, &c0, &rad, &v);
    if ((b & 1u) == 0u) {
        pc = &cfg;
        switch ((b >> 1) & 3u) {
        case 0:
            cfg.max_iters = 0u;
            break;
        case 1:
            cfg.max_iters = 1u;
            break;
        case 2:
            cfg.max_iters = fz_u32(in);
            break;
        default:
            cfg.max_iters = fz_u8(in);
            break;
        }
        if ((b & 8u) != 0u) {
            cfg.tol = fz_float(in);
        }
    }
    maxit = (cfg.max_iters == 0u || cfg.max_iters > (uint32_t)SFIT_REFINE_MAX_ITERS)
                ? (uint32_t)SFIT_REFINE_MAX_ITERS
                : cfg.max_iters;
    tol_ok = fz_finite(cfg.tol) && (cfg.tol == 0.0f || (cfg.tol >= 1e-7f && cfg.tol <= 1e-2f));
    args_ok = tol_ok && fz_all_finite(c0.v, 3);
    memset(&r, FZ_SENTINEL, sizeof r);
    bad = fz_bad_kinds(w, n);
    if (args_ok && n >= FZ_MIN5 && bad == 0u) {
        if (s->heavy >= FZ_MAX_HEAVY) {
            return; /* budget spent */
        }
        s->heavy++;
    }
    st = sfit_refine_points(w, n, &c0, pc, &r);
    FZ_CHECK_OUT(st, r, "sfit_refine_points");
    fz_check_window(s, &win, "sfit_refine_points wrote its samples");
    if (!args_ok) {
        FZ_CHECK(st == (tol_ok ? SFIT_E_NONFINITE : SFIT_E_ARG),
                 "sfit_refine_points: invalid c0 / tol: wrong status");
    } else if (n < FZ_MIN5) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_refine_points: too few samples not reported");
    } else if (bad != 0u) {
        fz_check_bad_status(st, bad, "sfit_refine_points: wrong status for a bad sample");
    } else {
        FZ_CHECK(st == SFIT_OK || st == SFIT_E_RANGE || st == SFIT_E_DEGENERATE
                     || st == SFIT_E_NO_CONVERGENCE,
                 "sfit_refine_points: status");
    }
    if (fz_coincident(w, n) && st == SFIT_OK) {
        FZ_CHECK(!FZ_STRICT, "sfit_refine_points: converged on coincident samples (known finding 3)");
        st = SFIT_E_DEGENERATE; /* tolerated: no context from it */
    }
    if (st == SFIT_OK) {
        FZ_CHECK(fz_all_finite(r.center.v, 3) && fz_finite(r.radius) && fz_finite(r.rms)
                     && fz_finite(r.noise_var),
                 "sfit_refine_points: non-finite result");
        FZ_CHECK(r.radius > 0.0f && r.rms >= 0.0f && r.noise_var >= 0.0f, "sfit_refine_points: signs");
        FZ_CHECK((size_t)r.n == n && r.converged, "sfit_refine_points: n / converged");
        FZ_CHECK(r.iterations >= 1u && r.iterations <= maxit, "sfit_refine_points: iterations");
        fz_set_ctx(s, &r.center, r.radius, r.noise_var);
    }
}

/* ------------------------------------------------------------ uncertainty */

static int fz_uncert_finite(const sfit_uncert_t *u)
{
    return fz_all_finite(u->center_cov.m, 9) && fz_finite(u->radius_var)
           && fz_all_finite(u->center_radius_cov, 3) && fz_finite(u->noise_var);
}

static void fz_check_uncert(sfit_status_t st, const sfit_uncert_t *u, float v, const char *what)
{
    if (st == SFIT_OK) {
        FZ_CHECK(fz_uncert_finite(u), what);
        FZ_CHECK(u->noise_var == v, what);
    }
}

static void fz_uncert_mom(fz_state_t *s, fz_in_t *in)
{
    const uint8_t src = fz_u8(in);
    sfit_moments_t acc, before;
    const sfit_moments_t *m;
    sfit_vec3_t c;
    float rad, v;
    sfit_uncert_noise_t kind;
    sfit_uncert_t u;
    sfit_status_t st;
    uint32_t cnt;
    if ((src & 1u) != 0u) {
        m = sfit_gate_moments(&s->gate); /* NULL during the warm-up */
    } else {
        fz_win_t win;
        fz_window(s, in, &win);
        (void)sfit_moments_init(&acc);
        (void)sfit_moments_add_block(&acc, win.p, win.n, NULL); /* all or nothing */
        m = &acc;
    }
    fz_fit_operands(s, in, &c, &rad, &v);
    kind = (sfit_uncert_noise_t)((src >> 1) % 3u); /* 2 is invalid */
    if (m != NULL) {
        memcpy(&before, m, sizeof before);
    }
    memset(&u, FZ_SENTINEL, sizeof u);
    st = sfit_uncert_moments(m, &c, rad, v, kind, &u);
    FZ_CHECK_OUT(st, u, "sfit_uncert_moments");
    if (m != NULL) {
        FZ_CHECK(memcmp(&before, m, sizeof before) == 0, "sfit_uncert_moments modified its input");
    }
    cnt = (m != NULL) ? sfit_moments_count(m) : 0u;
    if (m == NULL || (int)kind > 1) {
        FZ_CHECK(st == SFIT_E_ARG, "sfit_uncert_moments: invalid argument accepted");
    } else if (fz_fit_args_status(&c, rad, v) != SFIT_OK) {
        FZ_CHECK(st == fz_fit_args_status(&c, rad, v), "sfit_uncert_moments: bad fit: wrong status");
    } else if (cnt < SFIT_MIN_SAMPLES) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_uncert_moments: too few samples not reported");
    } else {
        FZ_CHECK(st == SFIT_OK || st == SFIT_E_NOT_POSDEF || st == SFIT_E_RANGE,
                 "sfit_uncert_moments: status");
    }
    fz_check_uncert(st, &u, v, "sfit_uncert_moments: non-finite or wrong result");
}

static void fz_uncert_pts(fz_state_t *s, fz_in_t *in)
{
    fz_win_t win;
    const sfit_vec3_t *w;
    size_t n;
    sfit_vec3_t c;
    float rad, v;
    sfit_uncert_t u;
    sfit_status_t st;
    unsigned bad;
    fz_window(s, in, &win);
    w = win.p;
    n = win.n;
    fz_fit_operands(s, in, &c, &rad, &v);
    memset(&u, FZ_SENTINEL, sizeof u);
    st = sfit_uncert_points(w, n, &c, rad, v, &u);
    FZ_CHECK_OUT(st, u, "sfit_uncert_points");
    fz_check_window(s, &win, "sfit_uncert_points wrote its samples");
    bad = fz_bad_kinds(w, n);
    if (fz_fit_args_status(&c, rad, v) != SFIT_OK) {
        FZ_CHECK(st == fz_fit_args_status(&c, rad, v), "sfit_uncert_points: bad fit: wrong status");
    } else if (n < (size_t)SFIT_MIN_SAMPLES) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_uncert_points: too few samples not reported");
    } else if (bad != 0u) {
        fz_check_bad_status(st, bad, "sfit_uncert_points: wrong status for a bad sample");
    } else {
        FZ_CHECK(st == SFIT_OK || st == SFIT_E_DEGENERATE || st == SFIT_E_RANGE,
                 "sfit_uncert_points: status");
    }
    if (fz_coincident(w, n)) {
        FZ_CHECK(st != SFIT_OK, "sfit_uncert_points: J^T J of coincident samples accepted");
    }
    fz_check_uncert(st, &u, v, "sfit_uncert_points: non-finite or wrong result");

    /* The sandwich of the geometric fit on the same window and centre (no
     * extra input bytes: the corpus keeps its meaning). */
    memset(&u, FZ_SENTINEL, sizeof u);
    st = sfit_uncert_geometric(w, n, &c, &u);
    FZ_CHECK_OUT(st, u, "sfit_uncert_geometric");
    fz_check_window(s, &win, "sfit_uncert_geometric wrote its samples");
    if (!fz_all_finite(c.v, 3)) {
        FZ_CHECK(st == SFIT_E_NONFINITE, "sfit_uncert_geometric: invalid centre accepted");
    } else if (n < 5u || n < (size_t)SFIT_MIN_SAMPLES) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_uncert_geometric: too few samples not reported");
    } else if (bad != 0u) {
        fz_check_bad_status(st, bad, "sfit_uncert_geometric: wrong status for a bad sample");
    } else {
        FZ_CHECK(st == SFIT_OK || st == SFIT_E_DEGENERATE || st == SFIT_E_NOT_POSDEF
                     || st == SFIT_E_RANGE,
                 "sfit_uncert_geometric: status");
    }
    if (fz_coincident(w, n)) {
        FZ_CHECK(st != SFIT_OK, "sfit_uncert_geometric: coincident samples accepted");
    }
    if (st == SFIT_OK) {
        FZ_CHECK(fz_uncert_finite(&u) && u.noise_var >= 0.0f,
                 "sfit_uncert_geometric: non-finite result");
    }

    /* The self-calibration's sandwich on the same window, centre, radius
     * and noise level (no extra input bytes). */
    memset(&u, FZ_SENTINEL, sizeof u);
    st = sfit_uncert_selfcal(w, n, &c, rad, v, &u);
    FZ_CHECK_OUT(st, u, "sfit_uncert_selfcal");
    fz_check_window(s, &win, "sfit_uncert_selfcal wrote its samples");
    if (fz_fit_args_status(&c, rad, v) != SFIT_OK) {
        FZ_CHECK(st == fz_fit_args_status(&c, rad, v),
                 "sfit_uncert_selfcal: bad fit: wrong status");
    } else if (n < 14u || n < (size_t)SFIT_MIN_SAMPLES) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_uncert_selfcal: too few samples not reported");
    } else if (bad != 0u) {
        fz_check_bad_status(st, bad, "sfit_uncert_selfcal: wrong status for a bad sample");
    } else {
        FZ_CHECK(st == SFIT_OK || st == SFIT_E_DEGENERATE || st == SFIT_E_NOT_POSDEF
                     || st == SFIT_E_RANGE,
                 "sfit_uncert_selfcal: status");
    }
    if (st == SFIT_OK) {
        FZ_CHECK(fz_uncert_finite(&u) && u.noise_var == v,
                 "sfit_uncert_selfcal: non-finite result");
    }
}

/* ------------------------------------------------------------------ gate */

/* Counters consistent with the harness' shadow count; finite noise. */
static void fz_gate_check(const fz_state_t *s)
{
    sfit_gate_stats_t gs;
    const sfit_moments_t *m;
    memset(&gs, FZ_SENTINEL, sizeof gs);
    FZ_CHECK(sfit_gate_stats(&s->gate, &gs) == SFIT_OK, "sfit_gate_stats");
    FZ_CHECK((uint64_t)gs.accepted + gs.outliers == s->gate_offered,
             "gate: accepted + outliers != samples judged");
    FZ_CHECK(fz_byte(&gs.gated) <= 1u, "gate: gated flag"); /* a bool the library wrote: 0 or 1 */
    FZ_CHECK(fz_finite(gs.noise_var) && gs.noise_var >= 0.0f, "gate: noise_var not finite / negative");
    m = sfit_gate_moments(&s->gate);
    if (m != NULL) {
        FZ_CHECK(sfit_moments_count(m) == gs.accepted, "gate: moments count != accepted");
    } else {
        FZ_CHECK(gs.accepted <= (uint32_t)SFIT_GATE_WARMUP && !gs.gated,
                 "gate: no moments outside the warm-up");
    }
}

static void fz_gate_init(fz_state_t *s, fz_in_t *in)
{
    sfit_gate_cfg_t cfg = sfit_gate_cfg_default;
    const uint8_t b = fz_u8(in);
    sfit_status_t st;
    int valid;
    fz_cfg(in, &cfg.fit);
    cfg.k = ((b & 1u) != 0u) ? fz_float(in) : 0.0f;
    cfg.noise_var = ((b & 2u) != 0u) ? fz_float(in) : 0.0f;
    cfg.refresh = ((b & 4u) != 0u) ? fz_u32(in) : (uint32_t)fz_u8(in);
    valid = fz_cfg_valid(&cfg.fit) && fz_finite(cfg.k) && (cfg.k == 0.0f || cfg.k > 1.0f)
            && fz_finite(cfg.noise_var) && cfg.noise_var >= 0.0f;
    if (s->gates >= FZ_MAX_GATES && (valid || (b & 8u) != 0u)) {
        return; /* budget spent */
    }
    if ((b & 8u) != 0u) { /* NULL cfg: the defaults */
        st = sfit_gate_init(&s->gate, NULL);
        FZ_CHECK(st == SFIT_OK, "sfit_gate_init(NULL cfg)");
        s->gate_offered = 0u;
        s->gates++;
    } else {
        static sfit_gate_t before;
        memcpy(&before, &s->gate, sizeof before);
        st = sfit_gate_init(&s->gate, &cfg);
        FZ_CHECK(st == SFIT_OK || st == SFIT_E_ARG, "sfit_gate_init: status");
        FZ_CHECK((st == SFIT_OK) == (valid != 0), "sfit_gate_init: option validity");
        if (st == SFIT_OK) {
            s->gate_offered = 0u;
            s->gates++;
        } else {
            FZ_CHECK(memcmp(&before, &s->gate, sizeof before) == 0, "sfit_gate_init: failure changed the gate");
        }
    }
    fz_gate_check(s);
}

static void fz_gate_add1(fz_state_t *s, const sfit_vec3_t *x, int want_acc)
{
    static sfit_gate_t before;
    sfit_status_t st;
    bool acc;
    const unsigned bad = fz_bad_kinds(x, 1u);
    if (bad != 0u) { /* a valid sample must be judged (status OK), checked below */
        memcpy(&before, &s->gate, sizeof before);
    }
    memset(&acc, FZ_SENTINEL, sizeof acc);
    st = sfit_gate_add(&s->gate, x, want_acc ? &acc : NULL);
    FZ_CHECK_OUT(st, acc, "sfit_gate_add");
    if (bad != 0u) {
        fz_check_bad_status(st, bad, "sfit_gate_add: wrong status for a bad sample");
    } else {
        FZ_CHECK(st == SFIT_OK, "sfit_gate_add: valid sample not judged");
    }
    if (st != SFIT_OK) {
        FZ_CHECK(memcmp(&before, &s->gate, sizeof before) == 0, "sfit_gate_add: rejected sample changed the gate");
    } else {
        s->gate_offered++;
        if (want_acc) {
            FZ_CHECK(fz_byte(&acc) <= 1u, "sfit_gate_add: accepted flag");
        }
    }
}

static void fz_gate_solve(fz_state_t *s)
{
    static sfit_gate_t before;
    sfit_result_t r;
    sfit_gate_stats_t gs;
    sfit_status_t st;
    memcpy(&before, &s->gate, sizeof before);
    memset(&r, FZ_SENTINEL, sizeof r);
    st = sfit_gate_fit(&s->gate, &r);
    FZ_CHECK_OUT(st, r, "sfit_gate_fit");
    FZ_CHECK(memcmp(&before, &s->gate, sizeof before) == 0, "sfit_gate_fit modified the gate");
    FZ_CHECK(st != SFIT_E_ARG && st != SFIT_E_NONFINITE, "sfit_gate_fit: status");
    FZ_CHECK(sfit_gate_stats(&s->gate, &gs) == SFIT_OK, "sfit_gate_stats");
    if (st == SFIT_OK) {
        fz_check_result(&r, gs.accepted, &s->gate.cfg.fit, "sfit_gate_fit: bad fit");
        fz_set_ctx(s, &r.center, r.radius, s->ctx_var);
    } else if (gs.accepted < SFIT_MIN_SAMPLES) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_gate_fit: too few samples not reported");
    } else {
        /* any other fit status */
    }
}

static void fz_gate_refresh(fz_state_t *s)
{
    sfit_vec3_t c;
    float rad, var;
    uint32_t phase;
    sfit_status_t st;
    c = s->gate.center;
    rad = s->gate.radius;
    var = s->gate.var;
    phase = s->gate.phase;
    st = sfit_gate_refresh(&s->gate);
    FZ_CHECK(fz_status_defined(st), "sfit_gate_refresh: undefined status");
    FZ_CHECK(st != SFIT_E_ARG && st != SFIT_E_NONFINITE, "sfit_gate_refresh: status");
    if (st != SFIT_OK && phase != 0u) {
        /* "the gate keeps its previous fit" */
        FZ_CHECK(memcmp(&c, &s->gate.center, sizeof c) == 0 && memcmp(&rad, &s->gate.radius, sizeof rad) == 0
                     && memcmp(&var, &s->gate.var, sizeof var) == 0,
                 "sfit_gate_refresh: failure changed the fit");
    }
}

/* ------------------------------------------------------------------ NULLs */

static void fz_nulls(fz_state_t *s)
{
    sfit_selfcal_result_t sr;
    sfit_refine_result_t rr;
    sfit_uncert_t u;
    sfit_result_t r;
    sfit_gate_stats_t gs;
    sfit_moments_t m;
    static sfit_gate_t before;
    const sfit_vec3_t *p = s->pts;
    const size_t n = s->npts;
    const sfit_vec3_t *c = &s->ctx_center;
    float v;
    bool acc;
    (void)sfit_moments_init(&m);
    memset(&sr, FZ_SENTINEL, sizeof sr);
    memset(&rr, FZ_SENTINEL, sizeof rr);
    memset(&u, FZ_SENTINEL, sizeof u);
    memset(&r, FZ_SENTINEL, sizeof r);
    memset(&gs, FZ_SENTINEL, sizeof gs);
    memset(&v, FZ_SENTINEL, sizeof v);
    memset(&acc, FZ_SENTINEL, sizeof acc);
    memcpy(&before, &s->gate, sizeof before);
    FZ_CHECK(sfit_selfcal_points(NULL, n, NULL, &sr) == SFIT_E_ARG, "selfcal_fit(NULL pts)");
    FZ_CHECK(sfit_selfcal_points(NULL, 0u, NULL, &sr) == SFIT_E_ARG, "selfcal_fit(NULL pts, 0)");
    FZ_CHECK(sfit_selfcal_points(p, n, NULL, NULL) == SFIT_E_ARG, "selfcal_fit(NULL out)");
    FZ_CHECK(sfit_selfcal_noise_var(NULL, n, c, 1.0f, &v) == SFIT_E_ARG, "noise_var(NULL pts)");
    FZ_CHECK(sfit_selfcal_noise_var(p, n, NULL, 1.0f, &v) == SFIT_E_ARG, "noise_var(NULL centre)");
    FZ_CHECK(sfit_selfcal_noise_var(p, n, c, 1.0f, NULL) == SFIT_E_ARG, "noise_var(NULL out)");
    FZ_CHECK(sfit_refine_points(NULL, n, c, NULL, &rr) == SFIT_E_ARG, "refine(NULL pts)");
    FZ_CHECK(sfit_refine_points(p, n, NULL, NULL, &rr) == SFIT_E_ARG, "refine(NULL c0)");
    FZ_CHECK(sfit_refine_points(p, n, c, NULL, NULL) == SFIT_E_ARG, "refine(NULL out)");
    FZ_CHECK(sfit_uncert_moments(NULL, c, 1.0f, 0.0f, SFIT_UNCERT_NOISE_KNOWN, &u) == SFIT_E_ARG,
             "uncert_moments(NULL m)");
    FZ_CHECK(sfit_uncert_moments(&m, NULL, 1.0f, 0.0f, SFIT_UNCERT_NOISE_KNOWN, &u) == SFIT_E_ARG,
             "uncert_moments(NULL centre)");
    FZ_CHECK(sfit_uncert_moments(&m, c, 1.0f, 0.0f, SFIT_UNCERT_NOISE_KNOWN, NULL) == SFIT_E_ARG,
             "uncert_moments(NULL out)");
    FZ_CHECK(sfit_uncert_points(NULL, n, c, 1.0f, 0.0f, &u) == SFIT_E_ARG, "uncert_points(NULL pts)");
    FZ_CHECK(sfit_uncert_points(p, n, NULL, 1.0f, 0.0f, &u) == SFIT_E_ARG, "uncert_points(NULL centre)");
    FZ_CHECK(sfit_uncert_points(p, n, c, 1.0f, 0.0f, NULL) == SFIT_E_ARG, "uncert_points(NULL out)");
    FZ_CHECK(sfit_uncert_geometric(NULL, n, c, &u) == SFIT_E_ARG, "uncert_geometric(NULL pts)");
    FZ_CHECK(sfit_uncert_geometric(p, n, NULL, &u) == SFIT_E_ARG, "uncert_geometric(NULL centre)");
    FZ_CHECK(sfit_uncert_geometric(p, n, c, NULL) == SFIT_E_ARG, "uncert_geometric(NULL out)");
    FZ_CHECK(sfit_gate_init(NULL, NULL) == SFIT_E_ARG, "gate_init(NULL)");
    FZ_CHECK(sfit_gate_init(NULL, &sfit_gate_cfg_default) == SFIT_E_ARG, "gate_init(NULL, cfg)");
    FZ_CHECK(sfit_gate_reset(NULL) == SFIT_E_ARG, "gate_reset(NULL)");
    FZ_CHECK(sfit_gate_add(NULL, c, &acc) == SFIT_E_ARG, "gate_add(NULL gate)");
    FZ_CHECK(sfit_gate_add(&s->gate, NULL, &acc) == SFIT_E_ARG, "gate_add(NULL sample)");
    FZ_CHECK(sfit_gate_refresh(NULL) == SFIT_E_ARG, "gate_refresh(NULL)");
    FZ_CHECK(sfit_gate_fit(NULL, &r) == SFIT_E_ARG, "gate_solve(NULL gate)");
    FZ_CHECK(sfit_gate_fit(&s->gate, NULL) == SFIT_E_ARG, "gate_solve(NULL out)");
    FZ_CHECK(sfit_gate_moments(NULL) == NULL, "gate_moments(NULL)");
    FZ_CHECK(sfit_gate_stats(NULL, &gs) == SFIT_E_ARG, "gate_stats(NULL gate)");
    FZ_CHECK(sfit_gate_stats(&s->gate, NULL) == SFIT_E_ARG, "gate_stats(NULL out)");
    FZ_CHECK(fz_untouched(&sr, sizeof sr) && fz_untouched(&rr, sizeof rr) && fz_untouched(&u, sizeof u)
                 && fz_untouched(&r, sizeof r) && fz_untouched(&gs, sizeof gs)
                 && fz_untouched(&v, sizeof v) && fz_untouched(&acc, sizeof acc),
             "NULL argument: an output was written");
    FZ_CHECK(memcmp(&before, &s->gate, sizeof before) == 0, "NULL argument: the gate changed");
}

/* ------------------------------------------------------------------ steps */

static void fz_step(fz_state_t *s, fz_in_t *in)
{
    const uint8_t op = fz_u8(in);
    sfit_vec3_t x;
    size_t n, i;

    switch (op % (unsigned)OP_COUNT) {
    case OP_POINTS:
        fz_points(s, in);
        break;
    case OP_SELFCAL:
        fz_selfcal(s, in);
        break;
    case OP_SELFCAL_VAR:
        fz_selfcal_var(s, in);
        break;
    case OP_REFINE:
        fz_refine(s, in);
        break;
    case OP_UNCERT_MOM:
        fz_uncert_mom(s, in);
        break;
    case OP_UNCERT_PTS:
        fz_uncert_pts(s, in);
        break;
    case OP_GATE_INIT:
        fz_gate_init(s, in);
        break;
    case OP_GATE_ADD: {
        const uint8_t how = fz_u8(in);
        switch (how % 4u) {
        case 0:
            fz_raw3(in, &x);
            break;
        case 1:
            fz_mixed3(in, &x);
            break;
        case 2:
            fz_sphere_point(in, &x);
            break;
        default:
            if (s->npts > 0u) {
                x = s->pts[(size_t)fz_u8(in) % s->npts];
            } else {
                fz_mixed3(in, &x);
            }
            break;
        }
        fz_gate_add1(s, &x, (how & 4u) == 0u);
        fz_gate_check(s);
        break;
    }
    case OP_GATE_FEED: {
        fz_win_t win;
        const sfit_vec3_t *w;
        fz_window(s, in, &win);
        w = win.p;
        n = win.n;
        for (i = 0; i < n; i++) {
            fz_gate_add1(s, &w[i], (i & 1u) == 0u);
        }
        fz_gate_check(s);
        break;
    }
    case OP_GATE_REFRESH:
        fz_gate_refresh(s);
        fz_gate_check(s);
        break;
    case OP_GATE_SOLVE:
        fz_gate_solve(s);
        break;
    case OP_GATE_RESET: {
        const sfit_gate_cfg_t keep = s->gate.cfg;
        if (s->gates >= FZ_MAX_GATES) {
            break; /* budget spent */
        }
        s->gates++;
        FZ_CHECK(sfit_gate_reset(&s->gate) == SFIT_OK, "sfit_gate_reset");
        FZ_CHECK(memcmp(&keep, &s->gate.cfg, sizeof keep) == 0, "sfit_gate_reset: options changed");
        s->gate_offered = 0u;
        fz_gate_check(s);
        break;
    }
    case OP_BATCH: {
        fz_win_t win;
        const sfit_vec3_t *w;
        fz_window(s, in, &win);
        w = win.p;
        n = win.n;
        sfit_result_t r;
        sfit_status_t st;
        memset(&r, FZ_SENTINEL, sizeof r);
        st = sfit_fit_points(w, n, NULL, &r);
        FZ_CHECK_OUT(st, r, "sfit_fit_points");
        if (st == SFIT_OK) {
            fz_check_result(&r, n, &sfit_fit_cfg_default, "sfit_fit_points: bad fit");
            fz_set_ctx(s, &r.center, r.radius, s->ctx_var);
        }
        break;
    }
    case OP_NULLS:
        fz_nulls(s);
        break;
    default:
        break;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fz_state_t s; /* large: keep it off the stack; reset every input */
    fz_in_t in;
    int ops = 0;

    in.p = data;
    in.n = size;
    in.i = 0u;
    memset(&s, 0, sizeof s);
    FZ_CHECK(sfit_gate_init(&s.gate, NULL) == SFIT_OK, "sfit_gate_init(NULL cfg)");
    s.gates = 1u;
    s.ctx_radius = 100.0f;
    s.ctx_var = 1.0f;
    while (fz_more(&in) && ops < FZ_MAX_OPS) {
        fz_step(&s, &in);
        ops++;
    }
    return 0;
}
