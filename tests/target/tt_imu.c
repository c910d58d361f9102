/* SPDX-License-Identifier: MIT */
/**
 * @file tt_imu.c
 * @brief On-target: the joint between two IMUs (sfit_imu.h) on exact
 * signals of a hip-like ball joint and a hinge (tests/ref/sfit_ref_imu.c,
 * double), against the truth and against the double batch Gauss-Newton
 * over every sample with the library's derivative (a cubic over 17
 * samples); the statuses and a rejected sample leaving the state unchanged.
 * Tolerances as on the host (tests/test_imu.c, exact cases): 1 mm.
 */
#include <math.h>
#include <string.h>

#include "sfit/sfit_imu.h"
#include "sfit_ref_imu.h"
#include "tt.h"

void tt_imu(void);

#define TT_IN 2000 /* 10 s at 200 Hz */
#define TT_IRATE 200.0

static double tt_a[2][TT_IN][3], tt_w[2][TT_IN][3];
static sfit_imu_t tt_s, tt_s0;

static void tt_fac(ref_imu_motion_t *m, int i, double x, double y, double z, double off,
                   double a0, double f0, double p0, double a1, double f1, double p1)
{
    const double n = sqrt(x * x + y * y + z * z);
    m->axis[i][0] = x / n;
    m->axis[i][1] = y / n;
    m->axis[i][2] = z / n;
    m->off[i] = off;
    m->amp[i][0] = a0;
    m->freq[i][0] = f0;
    m->ph[i][0] = p0;
    m->amp[i][1] = a1;
    m->freq[i][1] = f1;
    m->ph[i][1] = p1;
}

static void tt_motion(ref_imu_motion_t *m, int hinge)
{
    static const double c1[9] = {0.36, 0.48, -0.8, -0.8, 0.6, 0.0, 0.48, 0.64, 0.6};
    static const double c2[9] = {0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0};
    const double d = 3.14159265358979 / 180.0, f = 0.95;
    memset(m, 0, sizeof *m);
    m->nf1 = 3;
    m->nf2 = 3;
    memcpy(m->c1, c1, sizeof c1);
    memcpy(m->c2, c2, sizeof c2);
    m->r1[0] = 0.12;
    m->r1[1] = -0.2;
    m->r1[2] = 0.05;
    m->r2[0] = -0.03;
    m->r2[1] = 0.08;
    m->r2[2] = 0.27;
    m->pos0[2] = 0.9;
    m->vel[0] = 1.2;
    m->pamp[1][0] = 0.04;
    m->pfreq[1][0] = f;
    m->pamp[2][0] = 0.03;
    m->pfreq[2][0] = 2.0 * f;
    tt_fac(m, 0, 0, 0, 1, 0, 12 * d, f, 0.3, 3 * d, 2 * f, 1.1);
    tt_fac(m, 1, 1, 0, 0, 0, 12 * d, 0.7 * f, 2.0, 4 * d, 1.6 * f, 0.2);
    tt_fac(m, 2, 0, 1, 0, 0, 20 * d, f, 4.0, 3 * d, 2 * f, 0.7);
    if (hinge) {
        tt_fac(m, 3, 0.1, 1, -0.15, 35 * d, 35 * d, f, 1.0, 0, f, 0);
        m->nf2 = 1;
    } else {
        tt_fac(m, 3, 0, 1, 0, 10 * d, 25 * d, f, 1.0, 3 * d, 2 * f, 0.4);
        tt_fac(m, 4, 1, 0, 0, 0, 12 * d, f, 2.5, 4 * d, 2 * f, 5.0);
        tt_fac(m, 5, 0, 0, 1, 0, 12 * d, f, 0.8, 4 * d, 2 * f, 3.3);
    }
}

static void tt_signals(const ref_imu_motion_t *m)
{
    int k;
    for (k = 0; k < TT_IN; k++) {
        double a[2][3], w[2][3], dw[2][3];
        ref_imu_synth(m, (double)k / TT_IRATE, a, w, dw);
        memcpy(tt_a[0][k], a[0], sizeof a[0]);
        memcpy(tt_a[1][k], a[1], sizeof a[1]);
        memcpy(tt_w[0][k], w[0], sizeof w[0]);
        memcpy(tt_w[1][k], w[1], sizeof w[1]);
    }
}

static void tt_sample(int k, sfit_imu_sample_t *x)
{
    int i;
    for (i = 0; i < 3; i++) {
        x->acc1.v[i] = (float)tt_a[0][k][i];
        x->gyr1.v[i] = (float)tt_w[0][k][i];
        x->acc2.v[i] = (float)tt_a[1][k][i];
        x->gyr2.v[i] = (float)tt_w[1][k][i];
    }
}

static sfit_status_t tt_run(sfit_imu_result_t *r)
{
    sfit_imu_sample_t x;
    int k, bad = 0;
    if (sfit_imu_init(&tt_s, (float)TT_IRATE, NULL) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    for (k = 0; k < TT_IN; k++) {
        tt_sample(k, &x);
        bad += sfit_imu_add(&tt_s, &x) != SFIT_OK;
    }
    TT_EQ_INT(bad, 0);
    return sfit_imu_solve(&tt_s, r);
}

static double tt_dist(const sfit_vec3_t *a, const double *b)
{
    const double x = (double)a->v[0] - b[0], y = (double)a->v[1] - b[1],
                 z = (double)a->v[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

void tt_imu(void)
{
    ref_imu_motion_t m;
    sfit_imu_result_t r;
    sfit_imu_sample_t x;
    double q1[3], q2[3], cov[36], rms;

    tt_case("imu ball: truth and the double batch GN");
    tt_motion(&m, 0);
    tt_signals(&m);
    TT_EQ_INT(tt_run(&r), SFIT_OK);
    TT_TRUE(!r.hinge);
    TT_TRUE((r.flags & SFIT_FLAG_UNTRUSTED) == 0u);
    TT_TRUE(tt_dist(&r.r1, m.r1) < 1e-3);
    TT_TRUE(tt_dist(&r.r2, m.r2) < 1e-3);
    TT_EQ_INT(ref_imu_ball_gn((const double(*)[3])tt_a[0], (const double(*)[3])tt_w[0],
                              (const double(*)[3])tt_a[1], (const double(*)[3])tt_w[1], TT_IN,
                              TT_IRATE, -8, q1, q2, cov, &rms),
              0);
    TT_TRUE(tt_dist(&r.r1, q1) < 1e-3);
    TT_TRUE(tt_dist(&r.r2, q2) < 1e-3);

    tt_case("imu hinge: the axis");
    tt_motion(&m, 1);
    tt_signals(&m);
    TT_EQ_INT(tt_run(&r), SFIT_OK);
    TT_TRUE(r.hinge);
    /* exact hinge: the freest line of the position is the axes' line */
    TT_TRUE((r.flags & SFIT_IMU_FLAG_AXIS_OFF) == 0u);
    TT_TRUE(r.line_off >= 0.0f && r.line_off < 0.0523f);
    /* ... and its axes fit the accelerometers */
    TT_TRUE((r.flags & SFIT_IMU_FLAG_WOBBLE) == 0u);
    TT_TRUE(r.force_ratio >= 0.0f && r.force_ratio < 1.5f);
    {
        /* the axis in sensor 1: c1^T times the hinge factor's axis */
        double j[3], d;
        int i;
        for (i = 0; i < 3; i++) {
            j[i] = m.c1[i] * m.axis[3][0] + m.c1[3 + i] * m.axis[3][1] + m.c1[6 + i] * m.axis[3][2];
        }
        d = fabs((double)r.axis1.v[0] * j[0] + (double)r.axis1.v[1] * j[1] +
                 (double)r.axis1.v[2] * j[2]);
        TT_TRUE(d > cos(0.1 * 3.14159265358979 / 180.0));
    }

    tt_case("imu statuses, rejected sample");
    TT_EQ_INT(sfit_imu_init(NULL, 200.0f, NULL), SFIT_E_ARG);
    TT_EQ_INT(sfit_imu_init(&tt_s, -1.0f, NULL), SFIT_E_ARG);
    TT_EQ_INT(sfit_imu_init(&tt_s, 200.0f, NULL), SFIT_OK);
    TT_EQ_INT(sfit_imu_solve(&tt_s, &r), SFIT_E_TOO_FEW);
    tt_sample(0, &x);
    TT_EQ_INT(sfit_imu_add(&tt_s, &x), SFIT_OK);
    tt_s0 = tt_s;
    x.gyr2.v[2] = (float)NAN;
    TT_EQ_INT(sfit_imu_add(&tt_s, &x), SFIT_E_NONFINITE);
    TT_TRUE(memcmp(&tt_s, &tt_s0, sizeof tt_s) == 0);
}
