/* SPDX-License-Identifier: MIT */
/**
 * @file tt_hostile.c
 * @brief On-target: the contract edges of issue 19 on the Cortex-M4F
 * (float only; the host tests, tests/test_hostile.c, hold the double
 * references): the gate's sequence of finding 1 keeps a finite sigma^2 and
 * accepts a good circle again; a corrupted gate is SFIT_E_ARG; stats never
 * OK with NaN; an indefinite noise covariance is SFIT_E_ARG while a
 * singular PSD one passes; a spread below SFIT_MIN_SPREAD is
 * SFIT_E_DEGENERATE while radius 1e-6 at the origin is exact to 1e-5 r.
 */
#include <math.h>
#include <string.h>

#include "sfit/sfit_gate.h"
#include "tt.h"

void tt_hostile(void);

static int tt_finite(float x)
{
    return x == x && x - x == 0.0f;
}

/* The circle through (2800,-1200,900), (43,0,2700), (100,0,0): centre and
 * in-plane unit vectors, computed on the host in double and rounded. */
static const float tt_cc[3] = {1189.42123f, -493.601821f, 1373.60056f};
static const float tt_e1[3] = {-0.59814446f, 0.27101105f, -0.75417253f};
static const float tt_e2[3] = {0.69224945f, -0.29939866f, -0.656621f};
static const float tt_rc = 1821.33464f;

static void tt_gate_sequence(void)
{
    static sfit_gate_t g;
    const sfit_vec3_t stuck = {{2800.0f, -1200.0f, 900.0f}}, other = {{43.0f, 0.0f, 2700.0f}},
                      again = {{100.0f, 0.0f, 0.0f}};
    sfit_gate_cfg_t cfg = sfit_gate_cfg_default;
    sfit_gate_stats_t gs;
    int i, late = 0, finite = 1;
    bool acc = false;
    tt_case("gate sequence of issue 19 finding 1");
    cfg.k = 2.0f;
    cfg.noise_var = 1e-6f;
    cfg.refresh = 1u;
    TT_EQ_INT(sfit_gate_init(&g, &cfg), SFIT_OK);
    for (i = 0; i < 67 + 1 + 200 + 2000; i++) {
        sfit_vec3_t x;
        if (i < 67) {
            x = stuck;
        } else if (i == 67) {
            x = other;
        } else if (i < 268) {
            x = again;
        } else {
            /* the good circle, 2000 samples around it */
            const float t = 6.28318531f * (float)(i - 268) / 2000.0f;
            const float c = cosf(t), s = sinf(t);
            int k;
            for (k = 0; k < 3; k++) {
                x.v[k] = tt_cc[k] + tt_rc * (c * tt_e1[k] + s * tt_e2[k]);
            }
        }
        if (sfit_gate_add(&g, &x, &acc) != SFIT_OK || sfit_gate_stats(&g, &gs) != SFIT_OK
            || !tt_finite(gs.noise_var) || gs.noise_var < 0.0f) {
            finite = 0;
        }
        if (i >= 268 + 1000) {
            late += acc ? 1 : 0;
        }
    }
    TT_TRUE(finite);
    TT_EQ_INT(late, 1000);
}

static void tt_gate_garbage(void)
{
    static sfit_gate_t g, before;
    const sfit_vec3_t x = {{1.0f, 2.0f, 3.0f}};
    sfit_gate_stats_t gs;
    bool acc;
    unsigned char accb = 5u;
    tt_case("corrupted gate: E_ARG, unchanged");
    memcpy(&acc, &accb, 1u); /* a sentinel byte: written only on SFIT_OK */
    TT_EQ_INT(sfit_gate_init(&g, NULL), SFIT_OK);
    g.nwarm = 1000000u;
    before = g;
    TT_EQ_INT(sfit_gate_add(&g, &x, &acc), SFIT_E_ARG);
    TT_EQ_INT(sfit_gate_stats(&g, &gs), SFIT_E_ARG);
    TT_TRUE(memcmp(&g, &before, sizeof g) == 0);
    memcpy(&accb, &acc, 1u);
    TT_EQ_INT(accb, 5);
}

static void tt_stats_psd_spread(void)
{
    static const float ind[9] = {1e-3f, 1e-3f, -1e-3f, 1e-3f, 1e-3f, 1e-3f, -1e-3f, 1e-3f, 1e-3f};
    static const float dirs[7][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0},
                                     {0, 0, 1}, {0.6f, 0.8f, 0}, {0, 0.6f, -0.8f}};
    sfit_moments_t m;
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    sfit_result_t r;
    sfit_vec3_t mean, s, p[7];
    sfit_mat3_t c;
    const float v[3] = {0.3f, -0.7f, 0.648f};
    int i, j;

    tt_case("stats of a corrupted accumulator: E_RANGE");
    (void)sfit_moments_init(&m);
    for (i = 0; i < 7; i++) {
        for (j = 0; j < 3; j++) {
            p[i].v[j] = 10.0f + 50.0f * dirs[i][j];
        }
    }
    TT_EQ_INT(sfit_moments_add_block(&m, p, 7u, NULL), SFIT_OK);
    m.blk.m2[0] = NAN;
    TT_EQ_INT(sfit_moments_stats(&m, &mean, &c, &s), SFIT_E_RANGE);

    tt_case("noise covariance: indefinite E_ARG, singular PSD OK");
    (void)sfit_moments_init(&m);
    TT_EQ_INT(sfit_moments_add_block(&m, p, 7u, NULL), SFIT_OK);
    cfg.noise = SFIT_NOISE_COV;
    memcpy(cfg.noise_cov.m, ind, sizeof ind);
    TT_EQ_INT(sfit_fit_moments(&m, &cfg, &r), SFIT_E_ARG);
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            cfg.noise_cov.m[3 * i + j] = 1e-3f * v[i] * v[j];
        }
    }
    TT_EQ_INT(sfit_fit_moments(&m, &cfg, &r), SFIT_OK);

    tt_case("spread: 1e-14 DEGENERATE, 1e-6 exact");
    for (i = 0; i < 7; i++) {
        for (j = 0; j < 3; j++) {
            p[i].v[j] = 1e-14f * dirs[i][j];
        }
    }
    TT_EQ_INT(sfit_fit_points(p, 7u, NULL, &r), SFIT_E_DEGENERATE);
    for (i = 0; i < 7; i++) {
        for (j = 0; j < 3; j++) {
            p[i].v[j] = 1e-6f * dirs[i][j];
        }
    }
    TT_EQ_INT(sfit_fit_points(p, 7u, NULL, &r), SFIT_OK);
    TT_NEAR(r.radius, 1e-6f, 1e-11f);
    TT_NEAR(r.center.v[0], 0.0f, 1e-11f);
    TT_NEAR(r.center.v[2], 0.0f, 1e-11f);
}

void tt_hostile(void)
{
    tt_gate_sequence();
    tt_gate_garbage();
    tt_stats_psd_spread();
}
