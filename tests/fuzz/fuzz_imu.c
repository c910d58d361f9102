/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_imu.c
 * @brief libFuzzer harness: the joint between two IMUs (sfit_imu.h) driven
 * by a little program of hostile samples, rates, options, runs of a smooth
 * motion and garbage state bytes. After every operation:
 *  - every call returns one of the sfit_status_t values;
 *  - a rejected sample leaves the state byte for byte unchanged;
 *  - a failed solve leaves its sentinel-filled output untouched; an SFIT_OK
 *    result is finite and the solve does not change the state; a hinge has
 *    unit axes to 1e-3; UNTRUSTED is set exactly when another flag is.
 *
 * Program format: [opcode byte][operands]... (enum fz_iop below).
 */
#include "fuzz_common.h"

#include "sfit/sfit_imu.h"

#define FZ_MAX_OPS 200

enum fz_iop {
    IOP_INIT = 0, /* sel, rate (float), options (floats when sel says) */
    IOP_ADD,      /* 12 floats: acc1, gyr1, acc2, gyr2 */
    IOP_MOTION,   /* n (byte), amplitude and frequency bytes: n samples of a smooth motion */
    IOP_SOLVE,    /* - */
    IOP_GARBAGE,  /* offset (2 bytes), length, bytes: overwrite state bytes */
    IOP_NULLS,    /* every entry point with NULL pointers */
    IOP_COUNT
};

static sfit_imu_t fz_s;
static unsigned fz_t;

static void fz_check_result(const sfit_imu_result_t *r)
{
    FZ_CHECK(fz_all_finite(r->r1.v, 3) && fz_all_finite(r->r2.v, 3) &&
                 fz_all_finite(r->r1_cov.m, 9) && fz_all_finite(r->r2_cov.m, 9) &&
                 fz_all_finite(r->axis1.v, 3) && fz_all_finite(r->axis2.v, 3) &&
                 fz_all_finite(r->axis1_cov.m, 9) && fz_all_finite(r->axis2_cov.m, 9) &&
                 fz_all_finite(r->acc_bias1.v, 3) && fz_all_finite(r->acc_bias2.v, 3) &&
                 fz_finite(r->resid_rms) && fz_finite(r->noise_rms) && fz_finite(r->line_sd) &&
                 fz_finite(r->line_ratio) && fz_finite(r->line_off) && fz_finite(r->hinge_ratio) &&
                 fz_finite(r->force_ratio),
             "imu solve: a non-finite output");
    FZ_CHECK(((r->flags & SFIT_FLAG_UNTRUSTED) != 0u) == ((r->flags & ~1u) != 0u),
             "imu solve: UNTRUSTED without a reason, or a reason without it");
    if (r->hinge) {
        const float n1 = r->axis1.v[0] * r->axis1.v[0] + r->axis1.v[1] * r->axis1.v[1] +
                         r->axis1.v[2] * r->axis1.v[2];
        FZ_CHECK(fabsf(n1 - 1.0f) < 1e-3f, "imu solve: a hinge axis not unit");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in = {data, size, 0u};
    int ops;
    fz_t = 0u;
    (void)sfit_imu_init(&fz_s, 200.0f, NULL);
    for (ops = 0; ops < FZ_MAX_OPS && fz_more(&in); ops++) {
        const uint8_t op = (uint8_t)(fz_u8(&in) % IOP_COUNT);
        static sfit_imu_t before;
        sfit_status_t st;
        before = fz_s;
        switch (op) {
        case IOP_INIT: {
            sfit_imu_cfg_t cfg = sfit_imu_cfg_default;
            const uint8_t sel = fz_u8(&in);
            const float rate = ((sel & 1u) != 0u) ? fz_float(&in) : 200.0f;
            if ((sel & 2u) != 0u) {
                cfg.diff_span = fz_float(&in);
                cfg.acc_bias_sd = fz_float(&in);
                cfg.gyr_noise = fz_float(&in);
            }
            if ((sel & 4u) != 0u) {
                cfg.hinge_ratio = fz_float(&in);
                cfg.hinge_line = fz_float(&in);
                cfg.ball_line = fz_float(&in);
                cfg.max_pos_sd = fz_float(&in);
                cfg.hinge_off = fz_float(&in);
                cfg.wobble_ratio = fz_float(&in);
                cfg.hinge_wobble = fz_float(&in);
            }
            st = sfit_imu_init(&fz_s, rate, ((sel & 8u) != 0u) ? NULL : &cfg);
            FZ_CHECK(fz_status_defined(st), "imu init: status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0, "imu init: state written on failure");
            }
            break;
        }
        case IOP_ADD: {
            sfit_imu_sample_t x;
            int k;
            for (k = 0; k < 3; k++) {
                x.acc1.v[k] = fz_float(&in);
                x.gyr1.v[k] = fz_float(&in);
                x.acc2.v[k] = fz_float(&in);
                x.gyr2.v[k] = fz_float(&in);
            }
            st = sfit_imu_add(&fz_s, &x);
            FZ_CHECK(fz_status_defined(st), "imu add: status");
            if (st != SFIT_OK) {
                FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0, "imu add: rejected sample changed the state");
            }
            break;
        }
        case IOP_MOTION: {
            const unsigned n = fz_u8(&in);
            const float amp = (float)fz_u8(&in) * 0.05f, fr = (float)fz_u8(&in) * 0.05f;
            unsigned i;
            for (i = 0; i < n; i++) {
                const float t = (float)(fz_t++) * 0.005f;
                const float s1 = sinf(fr * 6.2831853f * t), c1 = cosf(fr * 4.1f * t);
                const sfit_imu_sample_t x = {{{0.5f * s1, 0.3f * c1, 9.81f}},
                                             {{amp * s1, 0.3f * amp * c1, 0.1f}},
                                             {{0.2f * c1, 9.7f, 0.4f * s1}},
                                             {{0.4f * amp * c1, amp * s1, 0.2f * amp}}};
                st = sfit_imu_add(&fz_s, &x);
                FZ_CHECK(fz_status_defined(st), "imu motion: status");
            }
            break;
        }
        case IOP_SOLVE: {
            sfit_imu_result_t r;
            memset(&r, FZ_SENTINEL, sizeof r);
            st = sfit_imu_solve(&fz_s, &r);
            FZ_CHECK_OUT(st, r, "imu solve");
            if (st == SFIT_OK) {
                fz_check_result(&r);
            }
            FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0, "imu solve: the state changed");
            break;
        }
        case IOP_GARBAGE: {
            const size_t off = ((size_t)fz_u8(&in) | ((size_t)fz_u8(&in) << 8)) % sizeof fz_s;
            const size_t len = fz_u8(&in) % 16u;
            size_t k;
            for (k = 0; k < len && off + k < sizeof fz_s; k++) {
                ((uint8_t *)&fz_s)[off + k] = fz_u8(&in);
            }
            break;
        }
        default: {
            sfit_imu_result_t r;
            sfit_imu_sample_t x;
            memset(&x, 0, sizeof x);
            FZ_CHECK(sfit_imu_init(NULL, 200.0f, NULL) == SFIT_E_ARG, "imu init NULL");
            FZ_CHECK(sfit_imu_add(NULL, &x) == SFIT_E_ARG, "imu add NULL state");
            FZ_CHECK(sfit_imu_add(&fz_s, NULL) == SFIT_E_ARG, "imu add NULL sample");
            FZ_CHECK(sfit_imu_solve(NULL, &r) == SFIT_E_ARG, "imu solve NULL state");
            FZ_CHECK(sfit_imu_solve(&fz_s, NULL) == SFIT_E_ARG, "imu solve NULL out");
            FZ_CHECK(memcmp(&fz_s, &before, sizeof fz_s) == 0, "imu NULL calls changed the state");
            break;
        }
        }
    }
    return 0;
}
