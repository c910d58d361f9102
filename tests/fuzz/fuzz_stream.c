/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_stream.c
 * @brief libFuzzer harness: the input is a little program driving the
 * stateful API (moments accumulators, fit / batch / multi solves, the
 * incremental estimator, noise calibration) with hostile floats, and the
 * contract is asserted after every operation:
 *  - every call returns one of the sfit_status_t values;
 *  - a rejected sample (or block, merge, init) leaves the state byte for
 *    byte unchanged (memcmp with a copy taken before the call);
 *  - a solve / stats / calibrate that fails leaves its sentinel-filled
 *    output untouched, and never modifies its const input state;
 *  - every float of an SFIT_OK result is finite (radius > 0, counts right);
 *  - the sample count follows a shadow count kept by the harness.
 *
 * Program format: a sequence of [opcode byte][operands]; operands are read
 * from the bytes that follow and an exhausted input reads as zeros. See
 * tests/fuzz/README.md for the opcode table.
 */
#include "fuzz_common.h"

#define FZ_NACC 3   /* moments accumulators (markers) */
#define FZ_RING 64  /* recent samples, for block / batch / start operations */
#define FZ_MAX_OPS 256

typedef struct fz_state {
    sfit_moments_t acc[FZ_NACC];
    uint64_t count[FZ_NACC]; /* shadow sample counts */
    sfit_vec3_t ring[FZ_RING];
    size_t ring_n;   /* valid entries (<= FZ_RING) */
    size_t ring_pos; /* next write position */
    sfit_vec3_t last;
    sfit_incr_t inc;
    uint64_t inc_count;
} fz_state_t;

enum fz_op {
    OP_ADD_RAW = 0,    /* acc, 3 raw floats */
    OP_ADD_FLOAT,      /* acc, 3 mixed floats (fz_float) */
    OP_ADD_SPHERE,     /* acc, a point near a sphere */
    OP_REPEAT,         /* acc, count: the last sample again (coincident points) */
    OP_ADD_BLOCK,      /* acc, length, source: a block from the ring buffer */
    OP_MERGE,          /* dst, src (may be the same) */
    OP_RESET,          /* acc */
    OP_SOLVE,          /* acc, config */
    OP_BATCH,          /* length, config: sfit_fit_points over the ring buffer */
    OP_MULTI,          /* count, config, weight */
    OP_STATS,          /* acc */
    OP_INCR_INIT,      /* config */
    OP_INCR_ADD,       /* which, sample */
    OP_INCR_START,     /* length */
    OP_INCR_SOLVE,     /* - */
    OP_CALIBRATE,      /* acc, c0, r0 */
    OP_NULLS,          /* every entry point with NULL pointers */
    OP_COUNT
};

static void fz_remember(fz_state_t *s, const sfit_vec3_t *x)
{
    s->ring[s->ring_pos] = *x;
    s->ring_pos = (s->ring_pos + 1u) % FZ_RING;
    if (s->ring_n < FZ_RING) {
        s->ring_n++;
    }
    s->last = *x;
}

/* A sample in one of three encodings (raw bits, mixed, near a sphere). */
static void fz_sample(fz_in_t *in, uint8_t how, sfit_vec3_t *x)
{
    int k;
    switch (how % 3u) {
    case 0:
        for (k = 0; k < 3; k++) {
            x->v[k] = fz_raw(in);
        }
        break;
    case 1:
        for (k = 0; k < 3; k++) {
            x->v[k] = fz_float(in);
        }
        break;
    default:
        fz_sphere_point(in, x);
        break;
    }
}

static void fz_cfg(fz_in_t *in, sfit_fit_cfg_t *cfg)
{
    fz_cfg_decode(in, cfg, 1);
}


static void fz_check_result(const sfit_result_t *r, uint64_t count, const sfit_fit_cfg_t *cfg)
{
    FZ_CHECK(fz_all_finite(r->center.v, 3) && fz_finite(r->radius), "fit: non-finite centre/radius");
    FZ_CHECK(fz_all_finite(r->eigenvalues.v, 3) && fz_all_finite(r->axis.v, 3),
             "fit: non-finite eigen-summary");
    FZ_CHECK(fz_finite(r->trust_ratio) && fz_finite(r->leontief_ratio), "fit: non-finite trust");
    FZ_CHECK(r->radius > 0.0f, "fit: radius not positive");
    FZ_CHECK((uint64_t)r->n == count, "fit: n differs from the samples added");
    FZ_CHECK(r->eigenvalues.v[0] <= r->eigenvalues.v[1] && r->eigenvalues.v[1] <= r->eigenvalues.v[2],
             "fit: eigenvalues not ascending");
    FZ_CHECK(r->mode == SFIT_MODE_SPHERE || r->mode == SFIT_MODE_PLANAR, "fit: mode");
    FZ_CHECK(cfg->mode == SFIT_MODE_AUTO || r->mode == cfg->mode, "fit: not the mode asked for");
    FZ_CHECK(r->method == ((cfg->noise == SFIT_NOISE_NONE) ? SFIT_METHOD_GDKE : SFIT_METHOD_UGDK),
             "fit: method");
    FZ_CHECK(r->trust_ratio >= 0.0f && r->trust_ratio <= 1.0f, "fit: trust ratio outside [0, 1]");
    FZ_CHECK(r->leontief_ratio >= 0.0f, "fit: negative Leontief ratio");
}

/* Status expectations common to every solve-like call. */
static void fz_check_cfg_status(sfit_status_t st, const sfit_fit_cfg_t *cfg, const char *what)
{
    if (!fz_cfg_valid(cfg)) {
        if (st != SFIT_E_ARG) {
            (void)fprintf(stderr, "%s: invalid option accepted (status %d)\n", what, (int)st);
        }
        FZ_CHECK(st == SFIT_E_ARG, "invalid option not rejected with SFIT_E_ARG");
    } else {
        if (st == SFIT_E_ARG) {
            (void)fprintf(stderr, "%s: valid option rejected\n", what);
        }
        FZ_CHECK(st != SFIT_E_ARG, "valid option rejected with SFIT_E_ARG");
    }
}

static void fz_solve(const sfit_moments_t *m, uint64_t count, const sfit_fit_cfg_t *cfg_or_null)
{
    const sfit_fit_cfg_t *cfg = (cfg_or_null != NULL) ? cfg_or_null : &sfit_fit_cfg_default;
    sfit_moments_t before;
    sfit_result_t r;
    sfit_status_t st;
    memcpy(&before, m, sizeof before);
    memset(&r, FZ_SENTINEL, sizeof r);
    st = sfit_fit_moments(m, cfg_or_null, &r);
    FZ_CHECK_OUT(st, r, "sfit_fit_moments");
    FZ_CHECK(memcmp(&before, m, sizeof before) == 0, "sfit_fit_moments modified its input");
    fz_check_cfg_status(st, cfg, "sfit_fit_moments");
    if (st == SFIT_OK) {
        fz_check_result(&r, count, cfg);
    } else if (fz_cfg_valid(cfg) && count < SFIT_MIN_SAMPLES) {
        FZ_CHECK(st == SFIT_E_TOO_FEW, "sfit_fit_moments: too few samples not reported");
    } else {
        /* any other defined status */
    }
    if (cfg->eigen == 0) {
        /* The screened solve against the full solver on the same moments:
         * the same status, flags, centre and radius; a trust bound that is
         * not below the exact ratio. */
        sfit_fit_cfg_t ce = *cfg;
        sfit_result_t re;
        sfit_status_t se;
        ce.eigen = true;
        se = sfit_fit_moments(m, &ce, &re);
        FZ_CHECK(se == st, "screened and full solve: different status");
        if (st == SFIT_OK && se == SFIT_OK) {
            FZ_CHECK(re.exact == 1, "full solve: exact not set");
            if (r.flags != re.flags || r.mode != re.mode) {
                (void)fprintf(stderr, "screened: flags 0x%x mode %d exact %d rho %g; full: flags 0x%x mode %d "
                              "rho %g eig %g %g %g; cfg mode %d noise %d var %g ratio %g\n",
                              (unsigned)r.flags, (int)r.mode, r.exact, (double)r.leontief_ratio,
                              (unsigned)re.flags, (int)re.mode, (double)re.leontief_ratio,
                              (double)re.eigenvalues.v[0], (double)re.eigenvalues.v[1],
                              (double)re.eigenvalues.v[2], (int)cfg->mode, (int)cfg->noise,
                              (double)cfg->noise_var, (double)cfg->planar_ratio);
            }
            FZ_CHECK(r.flags == re.flags && r.mode == re.mode && r.method == re.method,
                     "screened and full solve: different flags");
            FZ_CHECK(memcmp(r.center.v, re.center.v, sizeof r.center.v) == 0
                         && r.radius == re.radius,
                     "screened and full solve: different sphere");
            FZ_CHECK(r.exact == 1 || r.leontief_ratio >= re.leontief_ratio,
                     "screened solve: trust bound below the exact ratio");
        }
        if (cfg_or_null == NULL) {
            /* sfit_fit_moments_default: the full solve with the defaults
             * (ce: eigen true) bit for bit, the accumulator unchanged. */
            sfit_result_t rd;
            sfit_status_t sd;
            memset(&rd, FZ_SENTINEL, sizeof rd);
            sd = sfit_fit_moments_default(m, &rd);
            FZ_CHECK_OUT(sd, rd, "sfit_fit_moments_default");
            FZ_CHECK(sd == se, "default fit and full solve: different status");
            FZ_CHECK(sd != SFIT_OK || memcmp(&rd, &re, sizeof rd) == 0,
                     "default fit and full solve: different result");
            FZ_CHECK(memcmp(&before, m, sizeof before) == 0,
                     "sfit_fit_moments_default modified its input");
        }
    }
}

/* Add one sample to accumulator a; check all-or-nothing. */
static void fz_add(fz_state_t *s, int a, const sfit_vec3_t *x)
{
    sfit_moments_t before;
    sfit_status_t st;
    memcpy(&before, &s->acc[a], sizeof before);
    st = sfit_moments_add(&s->acc[a], x);
    FZ_CHECK(fz_status_defined(st), "sfit_moments_add: undefined status");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_all_finite(x->v, 3), "sfit_moments_add accepted NaN/Inf");
        s->count[a]++;
    } else {
        FZ_CHECK(memcmp(&before, &s->acc[a], sizeof before) == 0,
                 "sfit_moments_add: rejected sample changed the state");
        FZ_CHECK(st == SFIT_E_NONFINITE || st == SFIT_E_RANGE, "sfit_moments_add: status");
        FZ_CHECK(st != SFIT_E_NONFINITE || !fz_all_finite(x->v, 3),
                 "sfit_moments_add: finite sample called non-finite");
    }
    FZ_CHECK((uint64_t)sfit_moments_count(&s->acc[a]) == s->count[a], "count drifted");
    fz_remember(s, x);
}

static void fz_check_est(const sfit_sphere_t *e, uint64_t count)
{
    FZ_CHECK(fz_all_finite(e->center.v, 3) && fz_finite(e->radius), "incr: non-finite estimate");
    FZ_CHECK(e->radius > 0.0f, "incr: radius not positive");
    FZ_CHECK((uint64_t)e->n == count, "incr: n differs from the samples added");
}

static void fz_nulls(fz_state_t *s)
{
    sfit_result_t r;
    sfit_multi_result_t mr;
    sfit_vec3_t v;
    sfit_mat3_t c;
    size_t bad = 0u;
    memset(&r, FZ_SENTINEL, sizeof r);
    memset(&mr, FZ_SENTINEL, sizeof mr);
    FZ_CHECK(sfit_moments_init(NULL) == SFIT_E_ARG, "init(NULL)");
    FZ_CHECK(sfit_moments_reset(NULL) == SFIT_E_ARG, "reset(NULL)");
    FZ_CHECK(sfit_moments_add(NULL, &s->last) == SFIT_E_ARG, "add(NULL, x)");
    FZ_CHECK(sfit_moments_add(&s->acc[0], NULL) == SFIT_E_ARG, "add(m, NULL)");
    FZ_CHECK(sfit_moments_add_block(&s->acc[0], NULL, 1u, &bad) == SFIT_E_ARG, "add_block(NULL pts)");
    FZ_CHECK(sfit_moments_add_block(NULL, s->ring, 1u, &bad) == SFIT_E_ARG, "add_block(NULL m)");
    FZ_CHECK(sfit_moments_merge(NULL, &s->acc[0]) == SFIT_E_ARG, "merge(NULL, src)");
    FZ_CHECK(sfit_moments_merge(&s->acc[0], NULL) == SFIT_E_ARG, "merge(dst, NULL)");
    FZ_CHECK(sfit_moments_count(NULL) == 0u, "count(NULL)");
    FZ_CHECK(sfit_moments_stats(NULL, &v, &c, &v) == SFIT_E_ARG, "stats(NULL)");
    FZ_CHECK(sfit_fit_moments(NULL, NULL, &r) == SFIT_E_ARG, "solve(NULL m)");
    FZ_CHECK(sfit_fit_moments(&s->acc[0], NULL, NULL) == SFIT_E_ARG, "solve(NULL out)");
    FZ_CHECK(sfit_fit_moments_default(NULL, &r) == SFIT_E_ARG, "default fit(NULL m)");
    FZ_CHECK(sfit_fit_moments_default(&s->acc[0], NULL) == SFIT_E_ARG, "default fit(NULL out)");
    FZ_CHECK(sfit_fit_points(NULL, 5u, NULL, &r) == SFIT_E_ARG, "batch(NULL pts)");
    FZ_CHECK(sfit_fit_points(s->ring, 1u, NULL, NULL) == SFIT_E_ARG, "batch(NULL out)");
    FZ_CHECK(sfit_multi_fit(NULL, 1u, NULL, &mr, NULL) == SFIT_E_ARG, "multi(NULL markers)");
    FZ_CHECK(sfit_multi_fit(s->acc, 1u, NULL, NULL, NULL) == SFIT_E_ARG, "multi(NULL out)");
    FZ_CHECK(fz_untouched(&r, sizeof r) && fz_untouched(&mr, sizeof mr), "NULL call wrote output");
    FZ_CHECK(bad == 0u, "add_block(NULL) wrote bad");
    FZ_CHECK(sfit_incr_init(NULL, NULL) == SFIT_E_ARG, "incr_init(NULL)");
    FZ_CHECK(sfit_incr_reset(NULL) == SFIT_E_ARG, "incr_reset(NULL)");
    FZ_CHECK(sfit_incr_add(NULL, &s->last) == SFIT_E_ARG, "incr_add(NULL)");
    FZ_CHECK(sfit_incr_add(&s->inc, NULL) == SFIT_E_ARG, "incr_add(s, NULL)");
    FZ_CHECK(sfit_incr_fit(NULL, NULL) == SFIT_E_ARG, "incr_solve(NULL)");
    FZ_CHECK(sfit_incr_update(&s->inc, &s->last, NULL) == SFIT_E_ARG, "incr_update(out NULL)");
    FZ_CHECK(sfit_incr_start(&s->inc, NULL, 4u, NULL) == SFIT_E_ARG, "incr_start(NULL pts)");
    FZ_CHECK(sfit_incr_count(NULL) == 0u, "incr_count(NULL)");
    {
        sfit_noise_est_t ne;
        FZ_CHECK(sfit_noise_calibrate(NULL, &v, 1.0f, &ne) == SFIT_E_ARG, "calibrate(NULL)");
        FZ_CHECK(sfit_noise_calibrate(&s->acc[0], NULL, 1.0f, &ne) == SFIT_E_ARG, "calibrate(NULL c0)");
        FZ_CHECK(sfit_noise_calibrate(&s->acc[0], &v, 1.0f, NULL) == SFIT_E_ARG, "calibrate(NULL out)");
    }
}

/* Copy `len` samples ending at the newest from the ring buffer. */
static size_t fz_ring_block(const fz_state_t *s, size_t len, sfit_vec3_t *dst)
{
    size_t k;
    if (len > s->ring_n) {
        len = s->ring_n;
    }
    for (k = 0; k < len; k++) {
        dst[k] = s->ring[(s->ring_pos + FZ_RING - len + k) % FZ_RING];
    }
    return len;
}

static int fz_block_ok(const sfit_vec3_t *pts, size_t n, size_t *first_bad, sfit_status_t *why)
{
    size_t k;
    int j;
    for (k = 0; k < n; k++) {
        for (j = 0; j < 3; j++) {
            const float x = pts[k].v[j];
            if (!fz_finite(x) || fabsf(x) >= 134217728.0f) { /* 2^SFIT_COORD_MAX_EXP */
                int i2;
                *first_bad = k;
                *why = SFIT_E_RANGE;
                for (i2 = 0; i2 < 3; i2++) {
                    if (!fz_finite(pts[k].v[i2])) {
                        *why = SFIT_E_NONFINITE;
                    }
                }
                return 0;
            }
        }
    }
    return 1;
}

static void fz_step(fz_state_t *s, fz_in_t *in)
{
    const uint8_t op = fz_u8(in);
    const int a = (int)(fz_u8(in) % FZ_NACC);
    sfit_fit_cfg_t cfg;
    sfit_vec3_t x, blk[FZ_RING];
    sfit_status_t st;
    size_t n, k;

    switch ((enum fz_op)(op % OP_COUNT)) {
    case OP_ADD_RAW:
    case OP_ADD_FLOAT:
    case OP_ADD_SPHERE:
        fz_sample(in, (uint8_t)(op % OP_COUNT), &x);
        fz_add(s, a, &x);
        break;
    case OP_REPEAT:
        n = (size_t)fz_u8(in);
        x = s->last;
        for (k = 0; k < n; k++) {
            fz_add(s, a, &x);
        }
        break;
    case OP_ADD_BLOCK: {
        sfit_moments_t before;
        size_t bad = (size_t)-1, fb = 0u;
        sfit_status_t why = SFIT_OK;
        n = fz_ring_block(s, (size_t)(fz_u8(in) % (FZ_RING + 1u)), blk);
        if ((fz_u8(in) & 1u) != 0u && n > 0u) { /* poison one entry */
            fz_sample(in, 0u, &blk[fz_u8(in) % n]);
        }
        memcpy(&before, &s->acc[a], sizeof before);
        st = sfit_moments_add_block(&s->acc[a], blk, n, &bad);
        FZ_CHECK(fz_status_defined(st), "add_block: undefined status");
        if (fz_block_ok(blk, n, &fb, &why)) {
            FZ_CHECK(st == SFIT_OK || st == SFIT_E_RANGE, "add_block: valid block rejected");
        } else {
            FZ_CHECK(st == why, "add_block: wrong status for the first bad sample");
            FZ_CHECK(bad == fb, "add_block: wrong index of the first bad sample");
        }
        if (st == SFIT_OK) {
            s->count[a] += n;
        } else {
            FZ_CHECK(memcmp(&before, &s->acc[a], sizeof before) == 0, "add_block: rejected block changed the state");
        }
        FZ_CHECK((uint64_t)sfit_moments_count(&s->acc[a]) == s->count[a], "count drifted (block)");
        break;
    }
    case OP_MERGE: {
        const int b = (int)(fz_u8(in) % FZ_NACC);
        sfit_moments_t before, src_before;
        memcpy(&before, &s->acc[a], sizeof before);
        memcpy(&src_before, &s->acc[b], sizeof src_before);
        st = sfit_moments_merge(&s->acc[a], &s->acc[b]);
        FZ_CHECK(st == SFIT_OK || st == SFIT_E_RANGE, "merge: status");
        if (st == SFIT_OK) {
            FZ_CHECK(s->count[a] + s->count[b] <= UINT32_MAX, "merge: counter overflow accepted");
            s->count[a] += (a == b) ? s->count[a] : s->count[b];
            if (a != b) {
                FZ_CHECK(memcmp(&src_before, &s->acc[b], sizeof src_before) == 0, "merge modified src");
            }
        } else {
            FZ_CHECK(s->count[a] + s->count[b] > UINT32_MAX, "merge: spurious SFIT_E_RANGE");
            FZ_CHECK(memcmp(&before, &s->acc[a], sizeof before) == 0, "merge: rejected merge changed dst");
        }
        FZ_CHECK((uint64_t)sfit_moments_count(&s->acc[a]) == s->count[a], "count drifted (merge)");
        break;
    }
    case OP_RESET:
        FZ_CHECK(sfit_moments_reset(&s->acc[a]) == SFIT_OK, "reset");
        s->count[a] = 0u;
        FZ_CHECK(sfit_moments_count(&s->acc[a]) == 0u, "reset: count");
        break;
    case OP_SOLVE:
        fz_cfg(in, &cfg);
        fz_solve(&s->acc[a], s->count[a], ((fz_u8(in) & 7u) == 0u) ? NULL : &cfg);
        break;
    case OP_BATCH: {
        sfit_result_t r;
        size_t fb = 0u;
        sfit_status_t why = SFIT_OK;
        n = fz_ring_block(s, (size_t)(fz_u8(in) % (FZ_RING + 1u)), blk);
        fz_cfg(in, &cfg);
        memset(&r, FZ_SENTINEL, sizeof r);
        st = sfit_fit_points(blk, n, &cfg, &r);
        FZ_CHECK_OUT(st, r, "sfit_fit_points");
        if (st == SFIT_OK) {
            fz_check_result(&r, n, &cfg);
        }
        if (fz_block_ok(blk, n, &fb, &why)) {
            fz_check_cfg_status(st, &cfg, "sfit_fit_points");
        } else {
            FZ_CHECK(st != SFIT_OK, "sfit_fit_points accepted a bad sample");
        }
        break;
    }
    case OP_MULTI: {
        sfit_multi_cfg_t mc;
        sfit_multi_result_t r;
        float radii[FZ_NACC];
        sfit_moments_t before[FZ_NACC];
        const uint8_t b = fz_u8(in);
        const size_t cnt = (size_t)(b % (FZ_NACC + 1u));
        uint64_t total = 0u;
        mc = sfit_multi_cfg_default;
        fz_cfg(in, &mc.fit);
        mc.weight = (sfit_multi_weight_t)((b >> 2) % 3u); /* 2 is invalid */
        memcpy(before, s->acc, sizeof before);
        memset(&r, FZ_SENTINEL, sizeof r);
        memset(radii, FZ_SENTINEL, sizeof radii);
        st = sfit_multi_fit(s->acc, cnt, &mc, &r, ((b & 0x80u) != 0u) ? NULL : radii);
        FZ_CHECK_OUT(st, r, "sfit_multi_fit");
        FZ_CHECK(memcmp(before, s->acc, sizeof before) == 0, "sfit_multi_fit modified a marker");
        if (st != SFIT_OK) {
            FZ_CHECK(fz_untouched(radii, sizeof radii), "sfit_multi_fit wrote radii on failure");
        } else {
            FZ_CHECK(fz_all_finite(r.center.v, 3) && fz_all_finite(r.eigenvalues.v, 3)
                         && fz_all_finite(r.axis.v, 3) && fz_finite(r.trust_ratio)
                         && fz_finite(r.leontief_ratio),
                     "multi: non-finite result");
            FZ_CHECK(r.markers + r.skipped == cnt, "multi: markers + skipped != count");
            for (k = 0; k < cnt; k++) {
                if (s->count[k] >= SFIT_MIN_SAMPLES) {
                    total += s->count[k];
                }
                if ((b & 0x80u) == 0u) {
                    FZ_CHECK(fz_finite(radii[k]) && radii[k] >= 0.0f, "multi: bad radius");
                }
            }
            FZ_CHECK(total == r.n_total, "multi: n_total");
            if ((b & 0x80u) == 0u) {
                for (k = cnt; k < FZ_NACC; k++) {
                    FZ_CHECK(fz_untouched(&radii[k], sizeof radii[k]), "multi: wrote past radii[count]");
                }
            }
        }
        if (fz_cfg_valid(&mc.fit) && (int)mc.weight <= 1) {
            FZ_CHECK(st != SFIT_E_ARG, "multi: valid options rejected");
        } else {
            FZ_CHECK(st == SFIT_E_ARG, "multi: invalid options accepted");
        }
        break;
    }
    case OP_STATS: {
        sfit_vec3_t mean, sv;
        sfit_mat3_t c;
        memset(&mean, FZ_SENTINEL, sizeof mean);
        memset(&sv, FZ_SENTINEL, sizeof sv);
        memset(&c, FZ_SENTINEL, sizeof c);
        st = sfit_moments_stats(&s->acc[a], &mean, &c, &sv);
        FZ_CHECK_OUT(st, mean, "sfit_moments_stats");
        FZ_CHECK_OUT(st, c, "sfit_moments_stats");
        FZ_CHECK_OUT(st, sv, "sfit_moments_stats");
        FZ_CHECK((st == SFIT_E_TOO_FEW) == (s->count[a] < 2u), "stats: too-few status");
        if (st == SFIT_OK) {
            FZ_CHECK(fz_all_finite(mean.v, 3) && fz_all_finite(c.m, 9) && fz_all_finite(sv.v, 3),
                     "stats: non-finite statistics");
            FZ_CHECK(c.m[0] >= 0.0f && c.m[4] >= 0.0f && c.m[8] >= 0.0f, "stats: negative variance");
        }
        break;
    }
    case OP_INCR_INIT: {
        sfit_incr_t before;
        sfit_incr_cfg_t ic;
        int valid;
        fz_cfg(in, &cfg); /* the same input bytes as before: only the noise model is used */
        ic.noise = cfg.noise;
        ic.noise_var = cfg.noise_var;
        ic.noise_cov = cfg.noise_cov;
        cfg.mode = SFIT_MODE_AUTO;
        cfg.planar_ratio = 0.0f;
        valid = fz_cfg_valid(&cfg);
        memcpy(&before, &s->inc, sizeof before);
        st = sfit_incr_init(&s->inc, &ic);
        FZ_CHECK(fz_status_defined(st), "incr_init: undefined status");
        if (st == SFIT_OK) {
            s->inc_count = 0u;
            FZ_CHECK(valid, "incr_init: invalid option accepted");
        } else {
            FZ_CHECK(st == SFIT_E_ARG, "incr_init: status");
            FZ_CHECK(memcmp(&before, &s->inc, sizeof before) == 0, "incr_init: failure changed the state");
            FZ_CHECK(!valid, "incr_init: valid option rejected");
        }
        break;
    }
    case OP_INCR_ADD: {
        sfit_incr_t before;
        sfit_sphere_t e;
        const uint8_t how = fz_u8(in);
        fz_sample(in, how, &x);
        memcpy(&before, &s->inc, sizeof before);
        memset(&e, FZ_SENTINEL, sizeof e);
        st = ((how & 8u) != 0u) ? sfit_incr_update(&s->inc, &x, &e) : sfit_incr_add(&s->inc, &x);
        FZ_CHECK_OUT(st, e, "sfit_incr_update");
        if (sfit_incr_count(&s->inc) != sfit_incr_count(&before)) {
            /* Kept: add succeeded; update keeps the sample even if its solve fails. */
            FZ_CHECK(st == SFIT_OK || ((how & 8u) != 0u && st != SFIT_E_ARG && st != SFIT_E_NONFINITE),
                     "incr: sample kept but a rejection reported");
            FZ_CHECK(fz_all_finite(x.v, 3), "incr accepted NaN/Inf");
            s->inc_count++;
        } else {
            FZ_CHECK(st == SFIT_E_NONFINITE || st == SFIT_E_RANGE, "incr: sample dropped without a rejection");
            FZ_CHECK(memcmp(&before, &s->inc, sizeof before) == 0, "incr_add: rejected sample changed the state");
        }
        if (st == SFIT_OK && (how & 8u) != 0u) {
            fz_check_est(&e, s->inc_count);
        }
        FZ_CHECK((uint64_t)sfit_incr_count(&s->inc) == s->inc_count, "incr: count drifted");
        fz_remember(s, &x);
        break;
    }
    case OP_INCR_START: {
        sfit_incr_t before;
        sfit_sphere_t e;
        n = fz_ring_block(s, (size_t)(fz_u8(in) % (FZ_RING + 1u)), blk);
        memcpy(&before, &s->inc, sizeof before);
        memset(&e, FZ_SENTINEL, sizeof e);
        st = sfit_incr_start(&s->inc, blk, n, &e);
        FZ_CHECK_OUT(st, e, "sfit_incr_start");
        if (st == SFIT_OK) {
            s->inc_count = n;
            fz_check_est(&e, n);
        } else {
            FZ_CHECK(memcmp(&before, &s->inc, sizeof before) == 0, "incr_start: failure changed the state");
        }
        FZ_CHECK((uint64_t)sfit_incr_count(&s->inc) == s->inc_count, "incr: count drifted (start)");
        break;
    }
    case OP_INCR_SOLVE: {
        sfit_incr_t before;
        sfit_sphere_t e;
        memcpy(&before, &s->inc, sizeof before);
        memset(&e, FZ_SENTINEL, sizeof e);
        st = sfit_incr_fit(&s->inc, &e);
        FZ_CHECK_OUT(st, e, "sfit_incr_fit");
        FZ_CHECK(memcmp(&before, &s->inc, sizeof before) == 0, "incr_solve modified the state");
        FZ_CHECK((st == SFIT_E_TOO_FEW) == (s->inc_count < SFIT_MIN_SAMPLES), "incr_solve: too-few status");
        if (st == SFIT_OK) {
            fz_check_est(&e, s->inc_count);
        }
        break;
    }
    case OP_CALIBRATE: {
        sfit_moments_t before;
        sfit_noise_est_t e;
        sfit_vec3_t c0;
        float r0;
        fz_sample(in, fz_u8(in), &c0);
        r0 = ((fz_u8(in) & 1u) != 0u) ? fz_float(in) : 100.0f;
        memcpy(&before, &s->acc[a], sizeof before);
        memset(&e, FZ_SENTINEL, sizeof e);
        st = sfit_noise_calibrate(&s->acc[a], &c0, r0, &e);
        FZ_CHECK_OUT(st, e, "sfit_noise_calibrate");
        FZ_CHECK(memcmp(&before, &s->acc[a], sizeof before) == 0, "calibrate modified the accumulator");
        if (st == SFIT_OK) {
            FZ_CHECK(fz_finite(e.noise_trace) && fz_finite(e.noise_var) && fz_finite(e.noise_var_std),
                     "calibrate: non-finite estimate");
            FZ_CHECK(e.noise_var_std >= 0.0f, "calibrate: negative standard deviation");
            FZ_CHECK((uint64_t)e.n == s->count[a], "calibrate: n");
        } else if (!fz_all_finite(c0.v, 3) || !fz_finite(r0)) {
            FZ_CHECK(st == SFIT_E_NONFINITE, "calibrate: non-finite c0/r0 not reported");
        } else if (r0 < 0.0f) {
            FZ_CHECK(st == SFIT_E_ARG, "calibrate: negative r0 not reported");
        } else if (s->count[a] == 0u) {
            FZ_CHECK(st == SFIT_E_TOO_FEW, "calibrate: empty accumulator not reported");
        } else {
            FZ_CHECK(st == SFIT_E_RANGE, "calibrate: unexpected status");
        }
        break;
    }
    case OP_NULLS:
        fz_nulls(s);
        break;
    case OP_COUNT:
    default:
        break;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fz_state_t s; /* large: keep it off the stack; reset every input */
    fz_in_t in;
    int k, ops = 0;

    in.p = data;
    in.n = size;
    in.i = 0u;
    memset(&s, 0, sizeof s);
    for (k = 0; k < FZ_NACC; k++) {
        FZ_CHECK(sfit_moments_init(&s.acc[k]) == SFIT_OK, "init");
    }
    FZ_CHECK(sfit_incr_init(&s.inc, NULL) == SFIT_OK, "incr_init(NULL cfg)");
    while (fz_more(&in) && ops < FZ_MAX_OPS) {
        fz_step(&s, &in);
        ops++;
    }
    return 0;
}
