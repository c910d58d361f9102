/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_pair.c
 * @brief libFuzzer harness: the pair of segments (sfit_pair.h) driven by a
 * little program of hostile poses, residuals, templates, options, marker
 * frames and garbage state bytes. After every operation:
 *  - every call returns one of the sfit_status_t values;
 *  - a rejected frame leaves the state byte for byte unchanged, an accepted
 *    one increments the frame count by one;
 *  - a failed solve leaves its sentinel-filled output untouched; an SFIT_OK
 *    result is finite, its axes are unit to 1e-3, its mode is ball or hinge,
 *    UNTRUSTED is set exactly when a reason is given.
 *
 * Program format: [opcode byte][operands]... (enum fz_pop below).
 */
#include "fuzz_common.h"

#include "sfit/sfit_cluster.h"
#include "sfit/sfit_pair.h"

#define FZ_MAX_OPS 160

enum fz_pop {
    POP_INIT = 0,  /* config bytes: sfit_pair_init */
    POP_ADD,       /* two poses (rotation from bytes or hostile), two residuals */
    POP_ADD_MARKERS, /* two marker frames: sfit_pair_add_markers */
    POP_SOLVE,     /* - */
    POP_GARBAGE,   /* offset, length, bytes: overwrite state bytes */
    POP_RESET,     /* - */
    POP_NULLS,     /* every entry point with NULL pointers */
    POP_COUNT
};

static const sfit_vec3_t fz_ptpl[4] = {
    {{120.0f, 60.0f, 0.0f}}, {{-120.0f, 60.0f, 0.0f}}, {{-40.0f, -100.0f, 20.0f}}, {{40.0f, -100.0f, 30.0f}}};
static const sfit_vec3_t fz_ctpl[4] = {
    {{30.0f, 0.0f, -200.0f}}, {{-30.0f, 40.0f, -250.0f}}, {{40.0f, -10.0f, -300.0f}}, {{0.0f, 50.0f, -350.0f}}};

static sfit_cluster_t fz_pcl, fz_ccl;
static sfit_pair_t fz_s;

/* Rotation about a byte-chosen axis by a byte-chosen angle (float). */
static void fz_rot(fz_in_t *in, float r[9])
{
    const float ax = (float)(int8_t)fz_u8(in), ay = (float)(int8_t)fz_u8(in);
    const float az = (float)(int8_t)fz_u8(in) + 0.5f;
    const float ang = (float)(int8_t)fz_u8(in) * 0.0245f; /* +-180 degrees */
    const float n = sqrtf(ax * ax + ay * ay + az * az);
    const float x = ax / n, y = ay / n, z = az / n, c = cosf(ang), s = sinf(ang), C = 1.0f - c;
    r[0] = c + x * x * C;     r[1] = x * y * C - z * s; r[2] = x * z * C + y * s;
    r[3] = y * x * C + z * s; r[4] = c + y * y * C;     r[5] = y * z * C - x * s;
    r[6] = z * x * C - y * s; r[7] = z * y * C + x * s; r[8] = c + z * z * C;
}

static void fz_pose(fz_in_t *in, sfit_pose_t *p)
{
    const uint8_t sel = fz_u8(in);
    int k;
    if ((sel & 7u) == 0u) {
        for (k = 0; k < 9; k++) {
            p->r.m[k] = fz_float(in);
        }
        for (k = 0; k < 3; k++) {
            p->t.v[k] = fz_float(in);
        }
        return;
    }
    fz_rot(in, p->r.m);
    for (k = 0; k < 3; k++) {
        p->t.v[k] = (float)(int8_t)fz_u8(in) * (((sel & 8u) != 0u) ? 30.0f : 3.0f);
    }
}

/* NULL, or a residual (mostly valid). */
static const sfit_cluster_fit_t *fz_fit(fz_in_t *in, sfit_cluster_fit_t *f)
{
    const uint8_t sel = fz_u8(in);
    if ((sel & 3u) == 0u) {
        return NULL;
    }
    if ((sel & 3u) == 1u) {
        f->rms = fz_float(in);
        f->used = fz_u8(in);
        return f;
    }
    f->rms = (float)fz_u8(in) / 64.0f;
    f->used = 3u + (uint32_t)(fz_u8(in) % 2u);
    return f;
}

static void fz_check_result(sfit_status_t st, const sfit_pair_result_t *r)
{
    FZ_CHECK_OUT(st, *r, "pair solve");
    if (st == SFIT_OK) {
        const float na = r->axis_p.v[0] * r->axis_p.v[0] + r->axis_p.v[1] * r->axis_p.v[1]
                         + r->axis_p.v[2] * r->axis_p.v[2];
        FZ_CHECK(fz_all_finite(r->center_p.v, 3) && fz_all_finite(r->center_c.v, 3)
                     && fz_all_finite(r->axis_p.v, 3) && fz_all_finite(r->axis_c.v, 3)
                     && fz_all_finite(r->center_cov.m, 9) && fz_all_finite(r->axis_cov.m, 9)
                     && fz_all_finite(r->eigenvalues.v, 3) && fz_finite(r->trust_ratio)
                     && fz_finite(r->misfit) && fz_finite(r->rms) && fz_finite(r->marker_var),
                 "pair solve OK with a non-finite output");
        FZ_CHECK(na > 0.999f && na < 1.001f, "pair solve: axis not unit");
        FZ_CHECK(r->mode == SFIT_PAIR_MODE_BALL || r->mode == SFIT_PAIR_MODE_HINGE,
                 "pair solve: mode");
        FZ_CHECK(((r->flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u)
                     == (r->reason != SFIT_PAIR_REASON_NONE),
                 "pair solve: untrusted flag and reason disagree");
    }
}

static void fz_null_calls(void)
{
    sfit_pair_result_t r;
    sfit_pose_t p;
    sfit_vec3_t x[4];
    memset(&p, 0, sizeof p);
    memset(x, 0, sizeof x);
    FZ_CHECK(sfit_pair_init(NULL, &fz_pcl, &fz_ccl, NULL) == SFIT_E_ARG, "pair init NULL");
    FZ_CHECK(sfit_pair_init(&fz_s, NULL, &fz_ccl, NULL) == SFIT_E_ARG, "pair init NULL tpl");
    FZ_CHECK(sfit_pair_add(NULL, &p, NULL, &p, NULL) == SFIT_E_ARG, "pair add NULL");
    FZ_CHECK(sfit_pair_add(&fz_s, NULL, NULL, &p, NULL) == SFIT_E_ARG, "pair add NULL pose");
    FZ_CHECK(sfit_pair_add_markers(&fz_s, &fz_pcl, NULL, 4u, &fz_ccl, x, 4u) == SFIT_E_ARG,
             "pair add_markers NULL");
    FZ_CHECK(sfit_pair_solve(NULL, &r) == SFIT_E_ARG, "pair solve NULL");
    FZ_CHECK(sfit_pair_solve(&fz_s, NULL) == SFIT_E_ARG, "pair solve NULL out");
    FZ_CHECK(sfit_pair_reset(NULL) == SFIT_E_ARG, "pair reset NULL");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in = {data, size, 0u};
    int ops;
    (void)sfit_cluster_init(&fz_pcl, fz_ptpl, 4u);
    (void)sfit_cluster_init(&fz_ccl, fz_ctpl, 4u);
    (void)sfit_pair_init(&fz_s, &fz_pcl, &fz_ccl, NULL);
    for (ops = 0; ops < FZ_MAX_OPS && fz_more(&in); ops++) {
        const uint8_t op = (uint8_t)(fz_u8(&in) % POP_COUNT);
        static sfit_pair_t before;
        sfit_status_t st;
        before = fz_s;
        switch (op) {
        case POP_INIT: {
            sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
            const uint8_t sel = fz_u8(&in);
            cfg.method = (sfit_pair_method_t)(fz_u8(&in) % 4u);
            cfg.mode = (sfit_pair_mode_t)(fz_u8(&in) % 4u);
            cfg.noise = (sfit_pair_noise_t)(fz_u8(&in) % 3u);
            if ((sel & 1u) != 0u) {
                cfg.marker_var = fz_float(&in);
            }
            if ((sel & 2u) != 0u) {
                cfg.hinge_ratio = fz_float(&in);
                cfg.max_trust = fz_float(&in);
            }
            if ((sel & 4u) != 0u) {
                cfg.max_misfit = fz_float(&in);
                cfg.axis_tol = fz_float(&in);
                cfg.wobble = fz_float(&in);
            }
            cfg.min_frames = fz_u8(&in);
            st = sfit_pair_init(&fz_s, &fz_pcl, &fz_ccl, ((sel & 8u) != 0u) ? NULL : &cfg);
            FZ_CHECK(fz_status_defined(st), "pair init: status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0, "pair init: state written on failure");
            }
            break;
        }
        case POP_ADD: {
            sfit_pose_t pp, pc;
            sfit_cluster_fit_t fp, fc;
            const sfit_cluster_fit_t *a, *b;
            fz_pose(&in, &pp);
            fz_pose(&in, &pc);
            a = fz_fit(&in, &fp);
            b = fz_fit(&in, &fc);
            st = sfit_pair_add(&fz_s, &pp, a, &pc, b);
            FZ_CHECK(fz_status_defined(st), "pair add: status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0, "pair add: state changed by a rejected frame");
            } else {
                FZ_CHECK(fz_s.frames == before.frames + 1u, "pair add: frame count");
            }
            break;
        }
        case POP_ADD_MARKERS: {
            sfit_vec3_t pm[4], cm[4];
            float rp[9], rc[9];
            int i, k;
            fz_rot(&in, rp);
            fz_rot(&in, rc);
            for (i = 0; i < 4; i++) {
                const uint8_t sel = fz_u8(&in);
                for (k = 0; k < 3; k++) {
                    pm[i].v[k] = rp[3 * k] * fz_ptpl[i].v[0] + rp[3 * k + 1] * fz_ptpl[i].v[1]
                                 + rp[3 * k + 2] * fz_ptpl[i].v[2] + 1500.0f;
                    cm[i].v[k] = rc[3 * k] * fz_ctpl[i].v[0] + rc[3 * k + 1] * fz_ctpl[i].v[1]
                                 + rc[3 * k + 2] * fz_ctpl[i].v[2] + 1300.0f;
                }
                if ((sel & 7u) == 0u) {
                    pm[i].v[sel % 3u] = fz_float(&in);
                } else if ((sel & 7u) == 1u) {
                    cm[i].v[(sel >> 3) % 3u] = fz_float(&in);
                } else if ((sel & 7u) == 2u) {
                    cm[i].v[0] += ldexpf((float)(int8_t)fz_u8(&in), -6);
                }
            }
            st = sfit_pair_add_markers(&fz_s, &fz_pcl, pm, 4u, &fz_ccl, cm,
                                       4u - (size_t)(fz_u8(&in) % 8u == 0u));
            FZ_CHECK(fz_status_defined(st), "pair add_markers: status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0,
                         "pair add_markers: state changed by a rejected frame");
            } else {
                FZ_CHECK(fz_s.frames == before.frames + 1u, "pair add_markers: frame count");
            }
            break;
        }
        case POP_SOLVE: {
            sfit_pair_result_t r;
            memset(&r, FZ_SENTINEL, sizeof r);
            st = sfit_pair_solve(&fz_s, &r);
            fz_check_result(st, &r);
            FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0, "pair solve: state changed");
            break;
        }
        case POP_GARBAGE: {
            const size_t off = ((size_t)fz_u8(&in) | ((size_t)fz_u8(&in) << 8)) % sizeof fz_s;
            const size_t len = 1u + fz_u8(&in) % 8u;
            size_t k;
            for (k = 0; k < len && off + k < sizeof fz_s; k++) {
                ((unsigned char *)&fz_s)[off + k] = fz_u8(&in);
            }
            break;
        }
        case POP_RESET:
            st = sfit_pair_reset(&fz_s);
            FZ_CHECK(fz_status_defined(st), "pair reset: status");
            if (st == SFIT_OK) {
                FZ_CHECK(fz_s.frames == 0u, "pair reset: frames");
            } else {
                FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0, "pair reset: state written on failure");
            }
            break;
        default:
            fz_null_calls();
            break;
        }
    }
    return 0;
}
