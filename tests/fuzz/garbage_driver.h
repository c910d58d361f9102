/* SPDX-License-Identifier: MIT */
/**
 * @file garbage_driver.h
 * @brief The garbage-state program (issue 19): a public state struct full
 * of random bytes, or a valid one with out-of-range counters, indices and
 * phases written into it (uninitialised or .noinit RAM, a state read back
 * from flash), driven through every public function that takes it.
 *
 * Shared by the libFuzzer harness fuzz_garbage.c and the cmocka test
 * tests/test_garbage.c (fixed-seed random programs; under ASan and UBSan
 * in tests/scripts/test_sanitizers.sh). The contract checked: no crash and
 * no sanitizer report, every status defined, an output written only on
 * SFIT_OK and then finite, the gate's noise_var finite and >= 0.
 *
 * Program: [target] [fill] state bytes ... [ops]...
 *   target % 8: 0 accumulator, 1 incremental, 2 gate, 3 cluster + pose,
 *               4 joint, 5 accumulator array for sfit_multi_fit, 6 pair,
 *               7 IMU joint
 *   fill % 3:   0 every byte of the state from the input;
 *               1 a valid state (a few samples), then `k` patches: an
 *                 aligned word offset (2 bytes) and a value from a table of
 *                 hostile counters / floats or 4 raw bytes;
 *               2 the whole state one repeated byte (0x00, 0xFF, 0xA5 ...)
 *   then at most 32 operations, `op` byte each, on the target.
 */
#ifndef SFIT_GARBAGE_DRIVER_H
#define SFIT_GARBAGE_DRIVER_H

#include "fuzz_common.h"

#include "sfit/sfit_cluster.h"
#include "sfit/sfit_gate.h"
#include "sfit/sfit_imu.h"
#include "sfit/sfit_incr.h"
#include "sfit/sfit_joint.h"
#include "sfit/sfit_multi.h"
#include "sfit/sfit_noise.h"
#include "sfit/sfit_pair.h"
#include "sfit/sfit_uncert.h"

/** Counter values a corrupted state is likely to hold. */
static const uint32_t fz_g_words[] = {0u,          1u,          2u,          3u,
                                      4u,          5u,          7u,          8u,
                                      63u,         64u,         65u,         255u,
                                      256u,        1000000u,    0x7FFFFFFFu, 0x80000000u,
                                      0xFFFFFFFEu, 0xFFFFFFFFu, 0x7F800000u /* +Inf */,
                                      0x7FC00000u /* NaN */,    0xFF800000u /* -Inf */,
                                      0x7F7FFFFFu /* FLT_MAX */, 0x00000001u /* subnormal */,
                                      0xBF800000u /* -1.0f */,  0xA5A5A5A5u};
#define FZ_G_NWORDS (sizeof fz_g_words / sizeof fz_g_words[0])

/* Overwrite the state: fill mode 0 (bytes), 2 (one byte), or patches (1). */
static inline void fz_g_fill(fz_in_t *in, void *state, size_t size, uint8_t fill)
{
    unsigned char *b = (unsigned char *)state;
    size_t i;
    if (fill == 0u) {
        for (i = 0; i < size; i++) {
            b[i] = fz_u8(in);
        }
    } else if (fill == 2u) {
        const uint8_t v = fz_u8(in);
        memset(b, v, size);
    } else {
        const uint8_t k = (uint8_t)(fz_u8(in) % 8u);
        uint8_t j;
        for (j = 0; j < k; j++) {
            const size_t words = size / 4u;
            const size_t off = 4u * (((size_t)fz_u8(in) | ((size_t)fz_u8(in) << 8)) % words);
            const uint8_t how = fz_u8(in);
            uint32_t w = ((how & 1u) != 0u) ? fz_u32(in) : fz_g_words[(how >> 1) % FZ_G_NWORDS];
            memcpy(&b[off], &w, sizeof w);
        }
    }
}

/* A sample: near a sphere (mostly) or three hostile floats. */
static inline void fz_g_sample(fz_in_t *in, sfit_vec3_t *x)
{
    if ((fz_u8(in) & 3u) != 0u) {
        fz_sphere_point(in, x);
    } else {
        x->v[0] = fz_float(in);
        x->v[1] = fz_float(in);
        x->v[2] = fz_float(in);
    }
}

static inline void fz_g_check_result(sfit_status_t st, const sfit_result_t *r)
{
    FZ_CHECK_OUT(st, *r, "garbage: fit");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_all_finite(r->center.v, 3) && fz_finite(r->radius)
                     && fz_all_finite(r->eigenvalues.v, 3) && fz_finite(r->trust_ratio),
                 "garbage: fit OK with a non-finite output");
    }
}

static inline void fz_g_check_multi(sfit_status_t st, const sfit_multi_result_t *r)
{
    FZ_CHECK_OUT(st, *r, "garbage: multi fit");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_all_finite(r->center.v, 3) && fz_all_finite(r->eigenvalues.v, 3)
                     && fz_finite(r->trust_ratio),
                 "garbage: multi fit OK with a non-finite output");
    }
}

/* Calls that read an accumulator (stats, fits, multi, calibrate, uncert). */
static inline void fz_g_read_moments(fz_in_t *in, const sfit_moments_t *m, uint8_t op)
{
    switch (op % 6u) {
    case 0: {
        sfit_vec3_t mean, s;
        sfit_mat3_t c;
        sfit_status_t st;
        memset(&mean, FZ_SENTINEL, sizeof mean);
        memset(&s, FZ_SENTINEL, sizeof s);
        memset(&c, FZ_SENTINEL, sizeof c);
        st = sfit_moments_stats(m, &mean, &c, &s);
        FZ_CHECK_OUT(st, mean, "garbage: stats mean");
        FZ_CHECK_OUT(st, c, "garbage: stats C");
        if (st == SFIT_OK) {
            FZ_CHECK(fz_all_finite(mean.v, 3) && fz_all_finite(c.m, 9) && fz_all_finite(s.v, 3),
                     "garbage: stats OK with a non-finite output");
        }
        break;
    }
    case 1:
    case 2: {
        sfit_fit_cfg_t cfg;
        sfit_result_t r;
        fz_cfg_decode(in, &cfg, 0);
        memset(&r, FZ_SENTINEL, sizeof r);
        fz_g_check_result(sfit_fit_moments(m, (op % 6u == 1u) ? NULL : &cfg, &r), &r);
        memset(&r, FZ_SENTINEL, sizeof r);
        fz_g_check_result(sfit_fit_moments_default(m, &r), &r);
        break;
    }
    case 3: {
        sfit_vec3_t c0;
        sfit_noise_est_t e;
        sfit_status_t st;
        fz_g_sample(in, &c0);
        memset(&e, FZ_SENTINEL, sizeof e);
        st = sfit_noise_calibrate(m, &c0, 100.0f, &e);
        FZ_CHECK_OUT(st, e, "garbage: calibrate");
        if (st == SFIT_OK) {
            FZ_CHECK(fz_finite(e.noise_var) && fz_finite(e.noise_trace)
                         && fz_finite(e.noise_var_std),
                     "garbage: calibrate OK with a non-finite output");
        }
        break;
    }
    case 4: {
        sfit_vec3_t c0;
        sfit_uncert_t u;
        sfit_status_t st;
        fz_g_sample(in, &c0);
        memset(&u, FZ_SENTINEL, sizeof u);
        st = sfit_uncert_moments(m, &c0, 100.0f, 1.0f, SFIT_UNCERT_NOISE_KNOWN, &u);
        FZ_CHECK_OUT(st, u, "garbage: uncert");
        if (st == SFIT_OK) {
            FZ_CHECK(fz_all_finite(u.center_cov.m, 9) && fz_finite(u.radius_var),
                     "garbage: uncert OK with a non-finite output");
        }
        break;
    }
    default: {
        sfit_multi_result_t r;
        memset(&r, FZ_SENTINEL, sizeof r);
        fz_g_check_multi(sfit_multi_fit(m, 1u, NULL, &r, NULL), &r);
        break;
    }
    }
}

static inline void fz_g_moments(fz_in_t *in, uint8_t fill)
{
    sfit_moments_t m, v;
    int ops;
    (void)sfit_moments_init(&m);
    (void)sfit_moments_init(&v);
    if (fill == 1u) {
        int i;
        const int k = fz_u8(in) % 200;
        for (i = 0; i < k; i++) {
            sfit_vec3_t x;
            fz_sphere_point(in, &x);
            (void)sfit_moments_add(&m, &x);
            (void)sfit_moments_add(&v, &x);
        }
    }
    fz_g_fill(in, &m, sizeof m, fill);
    for (ops = 0; ops < 32 && fz_more(in); ops++) {
        const uint8_t op = fz_u8(in);
        sfit_vec3_t x[4];
        size_t bad = 0;
        int k;
        switch (op % 7u) {
        case 0:
            fz_g_sample(in, &x[0]);
            FZ_CHECK(fz_status_defined(sfit_moments_add(&m, &x[0])), "garbage: add");
            break;
        case 1:
            for (k = 0; k < 4; k++) {
                fz_g_sample(in, &x[k]);
            }
            FZ_CHECK(fz_status_defined(sfit_moments_add_block(&m, x, 4u, &bad)), "garbage: block");
            break;
        case 2: {
            /* Issue 32: a garbage source is refused with the valid dst
             * unchanged, or the merged dst stays usable (stats never
             * SFIT_E_RANGE for an accumulator the API built). */
            const sfit_moments_t v0 = v;
            const sfit_status_t st = sfit_moments_merge(&v, &m);
            FZ_CHECK(fz_status_defined(st), "garbage: merge into valid");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&v, &v0, sizeof v) == 0, "garbage: refused merge changed dst");
            } else if (sfit_moments_count(&v) >= 2u) {
                FZ_CHECK(sfit_moments_stats(&v, NULL, NULL, NULL) != SFIT_E_RANGE,
                         "garbage: merge made a valid dst unusable");
            }
            break;
        }
        case 3:
            FZ_CHECK(fz_status_defined(sfit_moments_merge(&m, &v)), "garbage: merge valid in");
            break;
        case 4:
            FZ_CHECK(fz_status_defined(sfit_moments_merge(&m, &m)), "garbage: self merge");
            break;
        case 5:
            (void)sfit_moments_count(&m);
            fz_g_read_moments(in, &v, fz_u8(in));
            break;
        default:
            fz_g_read_moments(in, &m, fz_u8(in));
            break;
        }
    }
}

static inline void fz_g_incr(fz_in_t *in, uint8_t fill)
{
    sfit_incr_t s;
    int ops;
    (void)sfit_incr_init(&s, NULL);
    if (fill == 1u) {
        int i;
        const int k = fz_u8(in) % 64;
        for (i = 0; i < k; i++) {
            sfit_vec3_t x;
            fz_sphere_point(in, &x);
            (void)sfit_incr_add(&s, &x);
        }
    }
    fz_g_fill(in, &s, sizeof s, fill);
    for (ops = 0; ops < 32 && fz_more(in); ops++) {
        const uint8_t op = fz_u8(in);
        sfit_vec3_t x[6];
        sfit_sphere_t o;
        sfit_status_t st;
        int k;
        memset(&o, FZ_SENTINEL, sizeof o);
        switch (op % 5u) {
        case 0:
            fz_g_sample(in, &x[0]);
            FZ_CHECK(fz_status_defined(sfit_incr_add(&s, &x[0])), "garbage: incr add");
            continue;
        case 1:
            fz_g_sample(in, &x[0]);
            st = sfit_incr_update(&s, &x[0], &o);
            break;
        case 2:
            st = sfit_incr_fit(&s, &o);
            break;
        case 3:
            for (k = 0; k < 6; k++) {
                fz_g_sample(in, &x[k]);
            }
            st = sfit_incr_start(&s, x, 6u, &o);
            break;
        default:
            (void)sfit_incr_count(&s);
            FZ_CHECK(fz_status_defined(sfit_incr_reset(&s)), "garbage: incr reset");
            continue;
        }
        FZ_CHECK_OUT(st, o, "garbage: incr");
        if (st == SFIT_OK) {
            FZ_CHECK(fz_all_finite(o.center.v, 3) && fz_finite(o.radius),
                     "garbage: incr OK with a non-finite output");
        }
    }
}

static inline void fz_g_gate_stats(const sfit_gate_t *g)
{
    sfit_gate_stats_t gs;
    sfit_status_t st;
    memset(&gs, FZ_SENTINEL, sizeof gs);
    st = sfit_gate_stats(g, &gs);
    FZ_CHECK_OUT(st, gs, "garbage: gate stats");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_finite(gs.noise_var) && gs.noise_var >= 0.0f,
                 "garbage: gate noise_var not finite or negative");
    }
}

static inline void fz_g_gate(fz_in_t *in, uint8_t fill)
{
    static sfit_gate_t g; /* 1.7 kB: off the stack */
    int ops;
    (void)sfit_gate_init(&g, NULL);
    if (fill == 1u) {
        int i;
        const int k = fz_u8(in) % 160;
        for (i = 0; i < k; i++) {
            sfit_vec3_t x;
            fz_sphere_point(in, &x);
            (void)sfit_gate_add(&g, &x, NULL);
        }
    }
    fz_g_fill(in, &g, sizeof g, fill);
    for (ops = 0; ops < 32 && fz_more(in); ops++) {
        const uint8_t op = fz_u8(in);
        switch (op % 6u) {
        case 0:
        case 1: {
            sfit_vec3_t x;
            bool acc;
            sfit_status_t st;
            memset(&acc, 7, sizeof acc); /* a sentinel byte: written only on SFIT_OK */
            fz_g_sample(in, &x);
            st = sfit_gate_add(&g, &x, &acc);
            FZ_CHECK(fz_status_defined(st), "garbage: gate add");
            FZ_CHECK((st == SFIT_OK) ? (fz_byte(&acc) <= 1u) : (fz_byte(&acc) == 7u),
                     "garbage: gate add verdict");
            break;
        }
        case 2:
            FZ_CHECK(fz_status_defined(sfit_gate_refresh(&g)), "garbage: gate refresh");
            break;
        case 3: {
            sfit_result_t r;
            memset(&r, FZ_SENTINEL, sizeof r);
            fz_g_check_result(sfit_gate_fit(&g, &r), &r);
            break;
        }
        case 4: {
            const sfit_moments_t *m = sfit_gate_moments(&g);
            if (m != NULL) {
                fz_g_read_moments(in, m, fz_u8(in));
            }
            break;
        }
        default:
            FZ_CHECK(fz_status_defined(sfit_gate_reset(&g)), "garbage: gate reset");
            break;
        }
        fz_g_gate_stats(&g);
    }
}

/* Markers of a cluster at a pose given by the input (or raw floats). */
static inline size_t fz_g_markers(fz_in_t *in, const sfit_cluster_t *cl, sfit_vec3_t *x)
{
    size_t n = fz_u8(in) % (SFIT_CLUSTER_MAX_MARKERS + 2u);
    size_t i;
    for (i = 0; i < n && i < SFIT_CLUSTER_MAX_MARKERS; i++) {
        int k;
        const int mode = fz_u8(in) & 3;
        for (k = 0; k < 3; k++) {
            float p = (i < SFIT_CLUSTER_MAX_MARKERS) ? cl->pos[i].v[k] : 0.0f;
            x[i].v[k] = (mode == 0) ? fz_float(in) : p + (float)(int8_t)fz_u8(in) * 0.01f;
        }
    }
    return (n > SFIT_CLUSTER_MAX_MARKERS) ? SFIT_CLUSTER_MAX_MARKERS : n;
}

static inline void fz_g_cluster(fz_in_t *in, uint8_t fill)
{
    static const sfit_vec3_t tpl[4] = {
        {{0.0f, 0.0f, 0.0f}}, {{100.0f, 0.0f, 0.0f}}, {{0.0f, 80.0f, 0.0f}}, {{10.0f, 20.0f, 60.0f}}};
    sfit_cluster_t cl;
    sfit_cluster_track_t trk;
    sfit_pose_t pose;
    int ops;
    (void)sfit_cluster_init(&cl, tpl, 4u);
    (void)sfit_cluster_track_reset(&trk);
    fz_g_fill(in, &cl, sizeof cl, fill);
    fz_g_fill(in, &pose, sizeof pose, 0u);
    for (ops = 0; ops < 32 && fz_more(in); ops++) {
        const uint8_t op = fz_u8(in);
        sfit_vec3_t x[SFIT_CLUSTER_MAX_MARKERS], o;
        sfit_status_t st;
        if ((op & 7u) == 4u) {
            /* issue 30: the track state (garbage with op bit 3), then a frame */
            sfit_pose_t p;
            sfit_cluster_fit_t f;
            sfit_cluster_track_t before;
            const size_t n = fz_g_markers(in, &cl, x);
            if ((op & 8u) != 0u) {
                fz_g_fill(in, &trk, sizeof trk, (uint8_t)(fz_u8(in) % 3u));
            }
            before = trk;
            memset(&p, FZ_SENTINEL, sizeof p);
            memset(&f, FZ_SENTINEL, sizeof f);
            st = sfit_cluster_track(&cl, &trk, x, n, &p, &f);
            FZ_CHECK_OUT(st, p, "garbage: track pose");
            if (st == SFIT_OK) {
                const float *r = p.r.m;
                const float det = r[0] * (r[4] * r[8] - r[5] * r[7])
                                  - r[1] * (r[3] * r[8] - r[5] * r[6])
                                  + r[2] * (r[3] * r[7] - r[4] * r[6]);
                FZ_CHECK(fz_all_finite(p.r.m, 9) && fz_all_finite(p.t.v, 3) && fz_finite(f.rms),
                         "garbage: track OK with a non-finite output");
                FZ_CHECK(det > 0.9f && det < 1.1f, "garbage: track OK with an improper rotation");
                FZ_CHECK(fz_byte(&trk.valid) == 1u && fz_all_finite(trk.q, 4), "garbage: track state after OK");
                pose = p;
            } else if (st == SFIT_E_TOO_FEW) {
                FZ_CHECK(fz_byte(&trk.valid) == 0u || memcmp(&trk, &before, sizeof trk) == 0,
                         "garbage: track gap");
            } else {
                FZ_CHECK(memcmp(&trk, &before, sizeof trk) == 0,
                         "garbage: track state changed by a rejected frame");
            }
        } else if ((op & 1u) == 0u) {
            sfit_pose_t p;
            sfit_cluster_fit_t f;
            const size_t n = fz_g_markers(in, &cl, x);
            const size_t count = ((op & 2u) != 0u) ? n : (size_t)cl.count;
            memset(&p, FZ_SENTINEL, sizeof p);
            memset(&f, FZ_SENTINEL, sizeof f);
            st = sfit_cluster_register(&cl, x, (count <= n) ? count : n, &p, &f);
            FZ_CHECK_OUT(st, p, "garbage: register pose");
            if (st == SFIT_OK) {
                FZ_CHECK(fz_all_finite(p.r.m, 9) && fz_all_finite(p.t.v, 3) && fz_finite(f.rms),
                         "garbage: register OK with a non-finite output");
                pose = p;
            }
        } else {
            fz_g_sample(in, &x[0]);
            memset(&o, FZ_SENTINEL, sizeof o);
            st = ((op & 2u) != 0u) ? sfit_cluster_to_global(&pose, &x[0], &o)
                                   : sfit_cluster_to_segment(&pose, &x[0], &o);
            FZ_CHECK_OUT(st, o, "garbage: pose map");
            if (st == SFIT_OK) {
                FZ_CHECK(fz_all_finite(o.v, 3), "garbage: pose map OK with a non-finite output");
            }
        }
    }
}

static inline void fz_g_joint(fz_in_t *in, uint8_t fill)
{
    static const sfit_vec3_t tpl[4] = {
        {{0.0f, 0.0f, 0.0f}}, {{100.0f, 0.0f, 0.0f}}, {{0.0f, 80.0f, 0.0f}}, {{10.0f, 20.0f, 60.0f}}};
    static sfit_joint_t j;
    sfit_cluster_t cl;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    int ops;
    (void)sfit_cluster_init(&cl, tpl, 4u);
    cfg.n_child = 2u;
    (void)sfit_joint_init(&j, &cl, &cfg);
    if (fill == 1u) {
        int i;
        const int k = fz_u8(in) % 40;
        for (i = 0; i < k; i++) {
            sfit_vec3_t child[2];
            fz_sphere_point(in, &child[0]);
            fz_sphere_point(in, &child[1]);
            (void)sfit_joint_add(&j, tpl, 4u, child, 2u, NULL);
        }
    }
    fz_g_fill(in, &j, sizeof j, fill);
    for (ops = 0; ops < 32 && fz_more(in); ops++) {
        const uint8_t op = fz_u8(in);
        sfit_status_t st;
        switch (op % 5u) {
        case 0: {
            sfit_vec3_t par[SFIT_CLUSTER_MAX_MARKERS], child[SFIT_JOINT_MAX_CHILD];
            sfit_pose_t p;
            const size_t np = fz_g_markers(in, &j.parent, par);
            const size_t nc = fz_u8(in) % (SFIT_JOINT_MAX_CHILD + 1u);
            size_t i;
            for (i = 0; i < nc; i++) {
                fz_g_sample(in, &child[i]);
            }
            memset(&p, FZ_SENTINEL, sizeof p);
            st = sfit_joint_add(&j, par, np, child, nc, &p);
            FZ_CHECK_OUT(st, p, "garbage: joint add");
            if (st == SFIT_OK) {
                FZ_CHECK(fz_all_finite(p.r.m, 9) && fz_all_finite(p.t.v, 3),
                         "garbage: joint add OK with a non-finite pose");
            }
            break;
        }
        case 1:
        case 2: {
            sfit_joint_result_t r;
            float radii[SFIT_JOINT_MAX_CHILD];
            memset(&r, FZ_SENTINEL, sizeof r);
            memset(radii, FZ_SENTINEL, sizeof radii);
            st = sfit_joint_fit(&j, &r, radii);
            FZ_CHECK_OUT(st, r, "garbage: joint fit");
            if (st == SFIT_OK) {
                FZ_CHECK(fz_all_finite(r.fit.center.v, 3) && fz_finite(r.residual_mean)
                             && fz_finite(r.residual_max),
                         "garbage: joint fit OK with a non-finite output");
                if ((op % 5u) == 2u) {
                    sfit_vec3_t par[SFIT_CLUSTER_MAX_MARKERS], c, a;
                    const size_t np = fz_g_markers(in, &j.parent, par);
                    memset(&c, FZ_SENTINEL, sizeof c);
                    st = sfit_joint_center_at(&j, &r, par, np, &c, &a);
                    FZ_CHECK_OUT(st, c, "garbage: joint centre at");
                    if (st == SFIT_OK) {
                        FZ_CHECK(fz_all_finite(c.v, 3) && fz_all_finite(a.v, 3),
                                 "garbage: centre at OK with a non-finite output");
                    }
                }
            }
            break;
        }
        case 3: {
            sfit_mat3_t cov;
            memset(&cov, FZ_SENTINEL, sizeof cov);
            st = sfit_joint_noise_cov(&j, fz_float(in), &cov);
            FZ_CHECK_OUT(st, cov, "garbage: joint noise cov");
            if (st == SFIT_OK) {
                FZ_CHECK(fz_all_finite(cov.m, 9), "garbage: noise cov OK with a non-finite output");
            }
            break;
        }
        default:
            FZ_CHECK(fz_status_defined(sfit_joint_reset(&j)), "garbage: joint reset");
            break;
        }
    }
}

static inline void fz_g_multi(fz_in_t *in, uint8_t fill)
{
    sfit_moments_t m[3];
    int ops, i;
    for (i = 0; i < 3; i++) {
        int k;
        (void)sfit_moments_init(&m[i]);
        for (k = 0; k < 12; k++) {
            sfit_vec3_t x;
            fz_sphere_point(in, &x);
            (void)sfit_moments_add(&m[i], &x);
        }
    }
    fz_g_fill(in, &m[fz_u8(in) % 3u], sizeof m[0], fill);
    for (ops = 0; ops < 8 && fz_more(in); ops++) {
        sfit_multi_cfg_t cfg = sfit_multi_cfg_default;
        sfit_multi_result_t r;
        float radii[3];
        fz_cfg_decode(in, &cfg.fit, 0);
        cfg.weight = (sfit_multi_weight_t)(fz_u8(in) % 2u);
        memset(&r, FZ_SENTINEL, sizeof r);
        fz_g_check_multi(sfit_multi_fit(m, 1u + fz_u8(in) % 3u, &cfg, &r, radii), &r);
    }
}

static inline void fz_g_pose(fz_in_t *in, sfit_pose_t *p)
{
    int k;
    if ((fz_u8(in) & 3u) == 0u) {
        for (k = 0; k < 9; k++) {
            p->r.m[k] = fz_float(in);
        }
    } else {
        /* a rotation about z by a byte angle */
        const float a = (float)(int8_t)fz_u8(in) * 0.01f;
        const float c = 1.0f - 0.5f * a * a, s = a;
        const float n = sqrtf(c * c + s * s);
        memset(p->r.m, 0, sizeof p->r.m);
        p->r.m[0] = c / n;
        p->r.m[1] = -s / n;
        p->r.m[3] = s / n;
        p->r.m[4] = c / n;
        p->r.m[8] = 1.0f;
    }
    for (k = 0; k < 3; k++) {
        p->t.v[k] = ((fz_u8(in) & 7u) == 0u) ? fz_float(in) : (float)(int8_t)fz_u8(in);
    }
}

static inline void fz_g_pair(fz_in_t *in, uint8_t fill)
{
    static const sfit_vec3_t tp[4] = {
        {{0.0f, 0.0f, 0.0f}}, {{100.0f, 0.0f, 0.0f}}, {{0.0f, 80.0f, 0.0f}}, {{10.0f, 20.0f, 60.0f}}};
    static const sfit_vec3_t tc[3] = {{{0.0f, 0.0f, -200.0f}}, {{50.0f, 0.0f, -300.0f}}, {{0.0f, 40.0f, -250.0f}}};
    static sfit_pair_t s, before;
    sfit_cluster_t cp, cc;
    int ops;
    (void)sfit_cluster_init(&cp, tp, 4u);
    (void)sfit_cluster_init(&cc, tc, 3u);
    (void)sfit_pair_init(&s, &cp, &cc, NULL);
    if (fill == 1u) {
        int i;
        const int k = fz_u8(in) % 40;
        for (i = 0; i < k; i++) {
            sfit_pose_t a, b;
            const sfit_cluster_fit_t f = {0.5f, 3u};
            fz_g_pose(in, &a);
            fz_g_pose(in, &b);
            (void)sfit_pair_add(&s, &a, &f, &b, &f);
        }
    }
    fz_g_fill(in, &s, sizeof s, fill);
    for (ops = 0; ops < 32 && fz_more(in); ops++) {
        const uint8_t op = fz_u8(in);
        sfit_status_t st;
        before = s;
        switch (op % 4u) {
        case 0: {
            sfit_pose_t a, b;
            sfit_cluster_fit_t f;
            f.rms = fz_float(in);
            f.used = fz_u8(in) % 6u;
            fz_g_pose(in, &a);
            fz_g_pose(in, &b);
            st = sfit_pair_add(&s, &a, ((op & 4u) != 0u) ? NULL : &f, &b, &f);
            FZ_CHECK(fz_status_defined(st), "garbage: pair add status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&s, &before, sizeof s) == 0, "garbage: pair add changed the state");
            }
            break;
        }
        case 1: {
            sfit_vec3_t pm[4], cm[3];
            int i;
            for (i = 0; i < 4; i++) {
                fz_g_sample(in, &pm[i]);
            }
            for (i = 0; i < 3; i++) {
                fz_g_sample(in, &cm[i]);
            }
            st = sfit_pair_add_markers(&s, &cp, pm, 4u, &cc, cm, 3u);
            FZ_CHECK(fz_status_defined(st), "garbage: pair add_markers status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&s, &before, sizeof s) == 0,
                         "garbage: pair add_markers changed the state");
            }
            break;
        }
        case 2: {
            sfit_pair_result_t r;
            memset(&r, FZ_SENTINEL, sizeof r);
            st = sfit_pair_solve(&s, &r);
            FZ_CHECK_OUT(st, r, "garbage: pair solve");
            if (st == SFIT_OK) {
                FZ_CHECK(fz_all_finite(r.center_p.v, 3) && fz_all_finite(r.center_c.v, 3)
                             && fz_all_finite(r.axis_p.v, 3) && fz_all_finite(r.center_cov.m, 9)
                             && fz_all_finite(r.axis_cov.m, 9) && fz_finite(r.misfit)
                             && fz_finite(r.trust_ratio) && fz_finite(r.marker_var),
                         "garbage: pair solve OK with a non-finite output");
            }
            break;
        }
        default:
            FZ_CHECK(fz_status_defined(sfit_pair_reset(&s)), "garbage: pair reset");
            break;
        }
    }
}

static inline void fz_g_imu(fz_in_t *in, uint8_t fill)
{
    static sfit_imu_t s, before;
    int ops;
    (void)sfit_imu_init(&s, 200.0f, NULL);
    if (fill == 1u) {
        /* a valid state that has kept samples, then patched */
        int i;
        for (i = 0; i < 200; i++) {
            const float t = (float)i * 0.005f;
            sfit_imu_sample_t x = {{{sinf(t), 0.5f, 9.8f}}, {{cosf(3.0f * t), 1.0f, 0.2f}},
                                   {{0.3f, cosf(t), 9.7f}}, {{0.1f, sinf(2.0f * t), 2.0f}}};
            (void)sfit_imu_add(&s, &x);
        }
    }
    fz_g_fill(in, &s, sizeof s, fill);
    for (ops = 0; ops < 32 && fz_more(in); ops++) {
        const uint8_t op = fz_u8(in);
        sfit_status_t st;
        before = s;
        if ((op % 3u) != 2u) {
            sfit_imu_sample_t x;
            int k;
            for (k = 0; k < 3; k++) {
                x.acc1.v[k] = fz_float(in);
                x.gyr1.v[k] = fz_float(in);
                x.acc2.v[k] = fz_float(in);
                x.gyr2.v[k] = fz_float(in);
            }
            st = sfit_imu_add(&s, &x);
            FZ_CHECK(fz_status_defined(st), "garbage: imu add status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&s, &before, sizeof s) == 0, "garbage: imu add changed the state");
            }
        } else {
            sfit_imu_result_t r;
            memset(&r, FZ_SENTINEL, sizeof r);
            st = sfit_imu_solve(&s, &r);
            FZ_CHECK_OUT(st, r, "garbage: imu solve");
            if (st == SFIT_OK) {
                FZ_CHECK(fz_all_finite(r.r1.v, 3) && fz_all_finite(r.r2.v, 3)
                             && fz_all_finite(r.r1_cov.m, 9) && fz_all_finite(r.r2_cov.m, 9)
                             && fz_all_finite(r.axis1.v, 3) && fz_all_finite(r.axis2.v, 3)
                             && fz_finite(r.resid_rms) && fz_finite(r.line_ratio)
                             && fz_finite(r.line_off) && fz_finite(r.force_ratio),
                         "garbage: imu solve OK with a non-finite output");
            }
            FZ_CHECK(memcmp(&s, &before, sizeof s) == 0, "garbage: imu solve changed the state");
        }
    }
}

/** Run one garbage-state program. */
static inline void fz_garbage_run(const uint8_t *data, size_t size)
{
    fz_in_t in = {data, size, 0u};
    const uint8_t target = (uint8_t)(fz_u8(&in) % 8u);
    const uint8_t fill = (uint8_t)(fz_u8(&in) % 3u);
    switch (target) {
    case 0:
        fz_g_moments(&in, fill);
        break;
    case 1:
        fz_g_incr(&in, fill);
        break;
    case 2:
        fz_g_gate(&in, fill);
        break;
    case 3:
        fz_g_cluster(&in, fill);
        break;
    case 4:
        fz_g_joint(&in, fill);
        break;
    case 5:
        fz_g_multi(&in, fill);
        break;
    case 6:
        fz_g_pair(&in, fill);
        break;
    default:
        fz_g_imu(&in, fill);
        break;
    }
}

#endif /* SFIT_GARBAGE_DRIVER_H */
