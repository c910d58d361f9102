/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_imu.c
 * @brief The joint between two IMUs (sfit_imu.h): sample selection while
 * streaming, Gauss-Newton at solve time.
 *
 * Implementation notes
 * --------------------
 * Kept sample: a1, w1, w1', a2, w2, w2' (18 floats), w' = (w[k+h] -
 * w[k-h]) rate / (2h). The selection score |w1|^2 + |w2|^2 uses the rates
 * only: the derivative's noise is 2h / (rate dt)... larger by far, and a
 * score on it would keep the samples whose noise happens to be large.
 *
 * Ball solve, unknowns x = (r1, r2, b1, b2) (b_i: accelerometer bias):
 * e = |a1 - b1 + G1 r1| - |a2 - b2 + G2 r2|, row of the Jacobian
 * (G1^T u1, -G2^T u2, -u1, u2) with u_i the unit joint force and
 * G^T u = w x (w x u) - w' x u. The normal matrix adds the priors
 * s^2 / sd^2 (r: 1 m; b: cfg.acc_bias_sd), s^2 the residual variance,
 * never below the one the noise predicts. Covariance s^2 (J^T J + P)^-1.
 *
 * Hinge: |w1 x j1|^2 - |w2 x j2|^2 = 0 reads w1^T J1 w1 - w2^T J2 w2 =
 * |w1|^2 - |w2|^2 with J_i = j_i j_i^T, linear in the 12 entries. Its
 * solutions are (1 - beta) j j^T + beta I for both; tr J1 = tr J2 = 1 picks
 * beta = 0 (two weighted rows). The top eigenvectors start a Gauss-Newton
 * on |w1 x j1| - |w2 x j2| in the tangent planes of the two axes.
 *
 * Check of a hinge against the accelerometers: an axis fixed in both
 * segments has the same component of the joint's specific force u_i =
 * a_i - b_i + G_i r_i on both sides, u1.j1 = u2.j2. Gauss-Newton from the
 * rates' axes fits it (prv_force_ratio); force_ratio is the rms of
 * u1.j1 - u2.j2 at the rates' axes over the rms at the fitted ones. A
 * wobble in step with the flexion turns the axis with the flexion's phase,
 * biases the rates' norms (the thigh swings at the same frequency) and
 * leaves a force residual at the rates' axes 1.4 to 12 times the fitted
 * axes' (a hinge, slow wobble: below 1.5; docs/imu.md).
 */
#include "sfit/sfit_imu.h"

#include <string.h>

#include "sfit/sfit_mat3.h"
#include "sfit_float.h"

#define IMU_NP 12u          /* unknowns of the ball solve (row stride of the matrices) */
#define IMU_NREC 27         /* floats of a kept sample */
#define IMU_MIN_USED 32u    /* kept samples a solve needs */
#define IMU_R_PRIOR 0.1f    /* prior SD of a joint position (m): holds a hinge's free line */
#define IMU_MAXABS 1e4f     /* largest accepted |value| of a sample */
#define IMU_PIVOT_EPS 1e-7f /* Cholesky: smallest pivot relative to the largest diagonal */
#define IMU_STEP_R 1e-5f    /* Gauss-Newton settled: position step (m) */
#define IMU_STEP_B 1e-4f    /* ... bias step (m/s^2) */
#define IMU_STEP_J 1e-6f    /* ... axis step (rad) */
#define IMU_UPHILL_TOL 1e-4f /* a rise of the objective below this (relative) is rounding */
#define IMU_WEIGHT_FLOOR 1e-3f /* added to |w1|^2 + |w2|^2 (rad^2/s^2): quiet samples count */
#define IMU_RNG_SEED 0x9E3779B9u
#define IMU_LINE_ITERS 40u  /* power iterations for the freest line of the position */
#define IMU_POLAR_ITERS 30u /* Newton steps of the polar factor (quadratic: a few suffice) */
#define IMU_FIXED_PASSES 3u /* best fixed axis and drift, alternately; the last: the wobble */
#define IMU_DRIFT_RIDGE 1e-3f /* ridge of the drift fit, per sample */
#define IMU_RHO_MAX 0.9f /* the wobble's lag-one autocorrelation, at most: n_eff >= n / 19 */
#define IMU_RAD2DEG 57.2957795f
#define IMU_MIN_TURN 0.1745f  /* rms turn about the fixed axis (rad, 10 degrees) a hinge from
                                 the relative rotation needs: a still joint fixes every axis */

const sfit_imu_cfg_t sfit_imu_cfg_default = {0.04f, 0.005f, 0.02f, 0.02f, 0.3f,    0.006f, 3.0f,
                                             0.07f, 8.0f,   5.0f,  0.0523f, 1.5f, 2.5f};

SFIT_INLINE void prv_cross(const float a[3], const float b[3], float c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

SFIT_INLINE float prv_dot(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static int prv_pos(float v)
{
    return sfit_i_isfinite(v) && v > 0.0f;
}

static int prv_cfg_ok(const sfit_imu_cfg_t *c)
{
    return prv_pos(c->diff_span) && prv_pos(c->gyr_noise) && prv_pos(c->acc_noise) &&
           sfit_i_isfinite(c->acc_bias_sd) && c->acc_bias_sd >= 0.0f && prv_pos(c->min_rate) &&
           prv_pos(c->max_pos_sd) && prv_pos(c->slip_ratio) && prv_pos(c->hinge_ratio) &&
           prv_pos(c->ball_line) && sfit_i_isfinite(c->hinge_line) && c->hinge_line >= c->ball_line &&
           prv_pos(c->hinge_off) && c->hinge_off <= 1.0f && sfit_i_isfinite(c->wobble_ratio) &&
           c->wobble_ratio >= 1.0f && prv_pos(c->hinge_wobble);
}

/* The counters and indices a call relies on (a garbage state is refused). */
static int prv_state_ok(const sfit_imu_t *s)
{
    return prv_pos(s->rate) && prv_pos(s->dscale) && s->h >= 1u && s->h <= (uint32_t)SFIT_IMU_DIFF_MAX &&
           s->head < 2u * s->h + 1u && s->stride >= 1u && s->wpos < s->stride &&
           s->nfull < (uint32_t)SFIT_IMU_KEEP && s->order[s->nfull] < (uint8_t)SFIT_IMU_KEEP &&
           s->nd <= s->n && s->rng != 0u && prv_cfg_ok(&s->cfg);
}

sfit_status_t sfit_imu_init(sfit_imu_t *s, float rate, const sfit_imu_cfg_t *cfg)
{
    const sfit_imu_cfg_t *c = (cfg != NULL) ? cfg : &sfit_imu_cfg_default;
    float hf;
    uint32_t i;
    if (s == NULL || !prv_pos(rate) || !prv_cfg_ok(c)) {
        return SFIT_E_ARG;
    }
    hf = c->diff_span * rate + 0.5f;
    if (!sfit_i_isfinite(hf)) {
        return SFIT_E_ARG;
    }
    memset(s, 0, sizeof *s);
    s->cfg = *c;
    s->rate = rate;
    s->h = (hf < 1.0f) ? 1u : (hf >= (float)SFIT_IMU_DIFF_MAX) ? (uint32_t)SFIT_IMU_DIFF_MAX
                                                                : (uint32_t)hf;
    {
        /* cubic Savitzky-Golay derivative: w' = rate sum_k (a k + b k^3) (w[+k] - w[-k]),
         * exact for cubics: a P2 + b P4 = 1, a P4 + b P6 = 0 (P_n = 2 sum k^n) */
        float p2 = 0.0f, p4 = 0.0f, p6 = 0.0f, a, bb = 0.0f;
        for (i = 1u; i <= s->h; i++) {
            const float k = (float)i, k2 = k * k;
            p2 += 2.0f * k2;
            p4 += 2.0f * k2 * k2;
            p6 += 2.0f * k2 * k2 * k2;
        }
        if (s->h == 1u) {
            a = 1.0f / p2; /* three points: the plain central difference */
        } else {
            a = 1.0f / (p2 - p4 * (p4 / p6));
            bb = -a * (p4 / p6);
        }
        for (i = 1u; i <= s->h; i++) {
            const float k = (float)i;
            s->dw[i - 1u] = rate * (a * k + bb * k * k * k);
        }
        s->dscale = s->dw[0];
    }
    s->stride = 1u;
    s->rng = IMU_RNG_SEED;
    s->q1[0] = 1.0f;
    s->q2[0] = 1.0f;
    for (i = 0u; i < (uint32_t)SFIT_IMU_KEEP; i++) {
        s->order[i] = (uint8_t)i;
    }
    return SFIT_OK;
}

/* A uniform number in [0, 1) from the state's xorshift generator. */
static float prv_uniform(sfit_imu_t *s)
{
    uint32_t x = s->rng;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    s->rng = x;
    return (float)(x >> 8) * (1.0f / 16777216.0f);
}

/* A pair of windows (2j, 2j+1) just closed: draw which of the two samples
 * stays when the buffer is next compacted, with the probability of its
 * window's weight (the kept sample is then still drawn from the merged
 * window in proportion to the weights); the winner goes first, with the
 * merged weight. Done at once, so that the compaction only moves bytes. */
static void prv_pair_decide(sfit_imu_t *s, uint32_t j)
{
    const uint8_t a = s->order[2u * j], b = s->order[2u * j + 1u];
    const float wsum = s->score[a] + s->score[b];
    if (prv_uniform(s) * wsum < s->score[b]) {
        s->order[2u * j] = b;
        s->order[2u * j + 1u] = a;
        s->score[b] = wsum;
    } else {
        s->score[a] = wsum;
    }
}

/* Buffer full: the winners of the decided pairs first (in time order), the
 * freed slots after them, windows twice as long. */
static void prv_compact(sfit_imu_t *s)
{
    uint8_t lose[SFIT_IMU_KEEP / 2];
    uint32_t j;
    for (j = 0u; j < (uint32_t)SFIT_IMU_KEEP / 2u; j++) {
        lose[j] = s->order[2u * j + 1u];
        s->order[j] = s->order[2u * j];
    }
    for (j = 0u; j < (uint32_t)SFIT_IMU_KEEP / 2u; j++) {
        s->order[(uint32_t)SFIT_IMU_KEEP / 2u + j] = lose[j];
    }
    s->nfull = (uint32_t)SFIT_IMU_KEEP / 2u;
    if (s->stride <= UINT32_MAX / 2u) {
        s->stride *= 2u;
    }
}

/* q <- q (x) dq, dq the rotation by the body rate (w + wl) / 2 over dt (q'
 * = q (x) (0, w) / 2), renormalised; a quaternion that lost its norm
 * restarts at the identity. */
static void prv_q_step(float q[4], const float w[3], const float wl[3], float hdt)
{
    float h[3], d[4], o[4], n2, c;
    uint32_t i;
    for (i = 0u; i < 3u; i++) {
        h[i] = 0.25f * hdt * (w[i] + wl[i]); /* half the angle */
    }
    n2 = prv_dot(h, h);
    /* cos |h| and sin |h| / |h| to the fourth order (|h| < 0.05 at 200 Hz and 20 rad/s) */
    c = 1.0f - n2 * (1.0f / 6.0f) * (1.0f - n2 * (1.0f / 20.0f));
    d[0] = 1.0f - 0.5f * n2 * (1.0f - n2 * (1.0f / 12.0f));
    d[1] = c * h[0];
    d[2] = c * h[1];
    d[3] = c * h[2];
    o[0] = q[0] * d[0] - q[1] * d[1] - q[2] * d[2] - q[3] * d[3];
    o[1] = q[0] * d[1] + q[1] * d[0] + q[2] * d[3] - q[3] * d[2];
    o[2] = q[0] * d[2] - q[1] * d[3] + q[2] * d[0] + q[3] * d[1];
    o[3] = q[0] * d[3] + q[1] * d[2] - q[2] * d[1] + q[3] * d[0];
    n2 = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] + o[3] * o[3];
    if (!(n2 > 0.5f) || !(n2 < 2.0f)) {
        o[0] = 1.0f;
        o[1] = 0.0f;
        o[2] = 0.0f;
        o[3] = 0.0f;
        n2 = 1.0f;
    }
    /* one Newton step towards 1 / sqrt(n2), n2 within rounding of 1 */
    c = 1.5f - 0.5f * n2;
    for (i = 0u; i < 4u; i++) {
        q[i] = o[i] * c;
    }
}

sfit_status_t sfit_imu_add(sfit_imu_t *s, const sfit_imu_sample_t *x)
{
    float v[12], rec[IMU_NREC], sc, q1, q2;
    const float *c;
    uint32_t len, i, k, slot;
    if (s == NULL || x == NULL || !prv_state_ok(s)) {
        return SFIT_E_ARG;
    }
    memcpy(v, x->acc1.v, sizeof x->acc1.v);
    memcpy(&v[3], x->gyr1.v, sizeof x->gyr1.v);
    memcpy(&v[6], x->acc2.v, sizeof x->acc2.v);
    memcpy(&v[9], x->gyr2.v, sizeof x->gyr2.v);
    for (i = 0u; i < 12u; i++) {
        if (!sfit_i_isfinite(v[i])) {
            return SFIT_E_NONFINITE;
        }
        if (SFIT_FABSF(v[i]) > IMU_MAXABS) {
            return SFIT_E_RANGE;
        }
    }
    if (s->n == UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    len = 2u * s->h + 1u;
    memcpy(s->ring[s->head], v, sizeof v);
    s->head = (s->head + 1u == len) ? 0u : s->head + 1u;
    s->n++;
    if (s->n < len) {
        return SFIT_OK;
    }
    /* oldest at head, newest just before it, the centre h after the oldest */
    c = s->ring[(s->head + s->h) % len];
    for (i = 0u; i < 3u; i++) {
        rec[i] = c[i];
        rec[3u + i] = c[3u + i];
        rec[6u + i] = 0.0f;
        rec[9u + i] = c[6u + i];
        rec[12u + i] = c[9u + i];
        rec[15u + i] = 0.0f;
    }
    for (k = 1u; k <= s->h; k++) {
        /* the samples k after and k before the centre */
        const float *pa = s->ring[(s->head + s->h + k) % len];
        const float *pb = s->ring[(s->head + s->h + len - k) % len];
        for (i = 0u; i < 3u; i++) {
            rec[6u + i] += s->dw[k - 1u] * (pa[3u + i] - pb[3u + i]);
            rec[15u + i] += s->dw[k - 1u] * (pa[9u + i] - pb[9u + i]);
        }
    }
    /* each sensor's orientation: the rates integrated, sample to sample */
    if (s->nd > 0u) {
        prv_q_step(s->q1, &rec[3], s->wlast, 1.0f / s->rate);
        prv_q_step(s->q2, &rec[12], &s->wlast[3], 1.0f / s->rate);
    }
    memcpy(s->wlast, &rec[3], 3u * sizeof(float));
    memcpy(&s->wlast[3], &rec[12], 3u * sizeof(float));
    memcpy(&rec[18], s->q1, sizeof s->q1);
    memcpy(&rec[22], s->q2, sizeof s->q2);
    rec[26] = (float)s->nd;
    q1 = prv_dot(&rec[3], &rec[3]);
    q2 = prv_dot(&rec[12], &rec[12]);
    sc = q1 + q2 + IMU_WEIGHT_FLOOR;
    s->wsum1 += q1;
    s->wsum2 += q2;
    s->nd++;
    slot = s->order[s->nfull];
    /* weighted reservoir of one per window: the kept sample is drawn with
     * probability proportional to its weight; score holds the window's sum */
    if (s->wpos == 0u) {
        memcpy(s->keep[slot], rec, sizeof rec);
        s->score[slot] = sc;
    } else {
        const float wsum = s->score[slot] + sc;
        if (prv_uniform(s) * wsum < sc) {
            memcpy(s->keep[slot], rec, sizeof rec);
        }
        s->score[slot] = wsum;
    }
    s->wpos++;
    if (s->wpos == s->stride) {
        s->wpos = 0u;
        s->nfull++;
        if ((s->nfull & 1u) == 0u) {
            prv_pair_decide(s, s->nfull / 2u - 1u);
        }
        if (s->nfull == (uint32_t)SFIT_IMU_KEEP) {
            prv_compact(s);
        }
    }
    return SFIT_OK;
}

/* ---- small dense algebra (row stride IMU_NP) ---- */

/* Lower Cholesky factor in place; 0 when a pivot is not positive enough. */
static int prv_chol(float *a, uint32_t n)
{
    float dmax = 0.0f;
    uint32_t i, j, k;
    for (i = 0u; i < n; i++) {
        if (a[i * IMU_NP + i] > dmax) {
            dmax = a[i * IMU_NP + i];
        }
    }
    if (!(dmax > 0.0f) || !sfit_i_isfinite(dmax)) {
        return 0;
    }
    for (j = 0u; j < n; j++) {
        float d = a[j * IMU_NP + j];
        for (k = 0u; k < j; k++) {
            d -= a[j * IMU_NP + k] * a[j * IMU_NP + k];
        }
        if (!(d > IMU_PIVOT_EPS * dmax)) {
            return 0;
        }
        d = SFIT_SQRTF(d);
        a[j * IMU_NP + j] = d;
        for (i = j + 1u; i < n; i++) {
            float t = a[i * IMU_NP + j];
            for (k = 0u; k < j; k++) {
                t -= a[i * IMU_NP + k] * a[j * IMU_NP + k];
            }
            a[i * IMU_NP + j] = t / d;
        }
    }
    return 1;
}

/* L L^T x = b, in place */
static void prv_chol_solve(const float *l, uint32_t n, float *b)
{
    uint32_t i, k, ii;
    for (i = 0u; i < n; i++) {
        float t = b[i];
        for (k = 0u; k < i; k++) {
            t -= l[i * IMU_NP + k] * b[k];
        }
        b[i] = t / l[i * IMU_NP + i];
    }
    for (ii = 0u; ii < n; ii++) {
        float t;
        i = n - 1u - ii;
        t = b[i];
        for (k = i + 1u; k < n; k++) {
            t -= l[k * IMU_NP + i] * b[k];
        }
        b[i] = t / l[i * IMU_NP + i];
    }
}

/* The 3x3 block at (off, off) of s2 A^-1 from A's factor. */
static void prv_cov_block(const float *l, uint32_t n, uint32_t off, float s2, sfit_mat3_t *c)
{
    float col[IMU_NP];
    uint32_t i, j;
    for (j = 0u; j < 3u; j++) {
        memset(col, 0, sizeof col);
        col[off + j] = 1.0f;
        prv_chol_solve(l, n, col);
        for (i = 0u; i < 3u; i++) {
            c->m[3u * i + j] = s2 * col[off + i];
        }
    }
    for (i = 0u; i < 3u; i++) { /* symmetric to the last bit */
        for (j = i + 1u; j < 3u; j++) {
            const float m = 0.5f * (c->m[3u * i + j] + c->m[3u * j + i]);
            c->m[3u * i + j] = m;
            c->m[3u * j + i] = m;
        }
    }
}

/* G r = w x (w x r) + w' x r ; G^T u = w x (w x u) - w' x u */
static void prv_g(const float w[3], const float d[3], const float r[3], float sign, float o[3])
{
    float x[3], y[3], z[3];
    uint32_t k;
    prv_cross(w, r, x);
    prv_cross(w, x, y);
    prv_cross(d, r, z);
    for (k = 0u; k < 3u; k++) {
        o[k] = y[k] + sign * z[k];
    }
}

/* The joint's specific force in each sensor's frame at x: a_i - b_i + G_i r_i. */
static void prv_force(const float *k, const float x[IMU_NP], float v1[3], float v2[3])
{
    uint32_t i;
    prv_g(&k[3], &k[6], x, 1.0f, v1);
    prv_g(&k[12], &k[15], &x[3], 1.0f, v2);
    for (i = 0u; i < 3u; i++) {
        v1[i] += k[i] - x[6u + i];
        v2[i] += k[9u + i] - x[9u + i];
    }
}

/* One sample of the ball problem: residual, row of the Jacobian (0 when a
 * joint force vanishes). */
static float prv_ball_row(const float *k, const float x[IMU_NP], float jr[IMU_NP])
{
    float v1[3], v2[3], n1, n2, i1, i2;
    uint32_t i;
    prv_force(k, x, v1, v2);
    n1 = SFIT_SQRTF(prv_dot(v1, v1));
    n2 = SFIT_SQRTF(prv_dot(v2, v2));
    if (!(n1 > 0.0f) || !(n2 > 0.0f)) {
        memset(jr, 0, IMU_NP * sizeof(float));
        return 0.0f;
    }
    i1 = 1.0f / n1;
    i2 = 1.0f / n2;
    for (i = 0u; i < 3u; i++) {
        v1[i] *= i1;
        v2[i] *= i2;
    }
    prv_g(&k[3], &k[6], v1, -1.0f, jr);
    prv_g(&k[12], &k[15], v2, -1.0f, &jr[3]);
    for (i = 0u; i < 3u; i++) {
        jr[3u + i] = -jr[3u + i];
        jr[6u + i] = -v1[i];
        jr[9u + i] = v2[i];
    }
    return n1 - n2;
}

typedef struct prv_used {
    const float *k[SFIT_IMU_KEEP];
    uint32_t n;
} prv_used_t;

/* Normal matrix (lower triangle), gradient J^T e and SSR at x. */
static float prv_ball_normal(const prv_used_t *u, const float x[IMU_NP], uint32_t np, float *a,
                             float g[IMU_NP])
{
    float ssr = 0.0f, jr[IMU_NP];
    uint32_t t, i, j;
    memset(a, 0, IMU_NP * IMU_NP * sizeof(float));
    memset(g, 0, IMU_NP * sizeof(float));
    for (t = 0u; t < u->n; t++) {
        const float e = prv_ball_row(u->k[t], x, jr);
        for (i = 0u; i < np; i++) {
            g[i] += jr[i] * e;
            for (j = 0u; j <= i; j++) {
                a[i * IMU_NP + j] += jr[i] * jr[j];
            }
        }
        ssr += e * e;
    }
    return ssr;
}

typedef struct prv_ball {
    float l[IMU_NP * IMU_NP]; /* factor of the normal matrix at x */
    float s2;                 /* the residual variance it is scaled by */
    uint32_t np;
    float x[IMU_NP];
    sfit_mat3_t c1, c2;
    float ssr, pred;
} prv_ball_t;

/* The noise variance of e the sensors' noise predicts at x. */
static float prv_pred(const sfit_imu_t *s, const prv_used_t *u, const float x[IMU_NP])
{
    const sfit_imu_cfg_t *c = &s->cfg;
    float sd, q = 0.0f, w1 = 0.0f, w2 = 0.0f;
    uint32_t t;
    for (t = 0u; t < s->h; t++) {
        q += 2.0f * s->dw[t] * s->dw[t];
    }
    sd = c->gyr_noise * SFIT_SQRTF(q);
    for (t = 0u; t < u->n; t++) {
        w1 += prv_dot(&u->k[t][3], &u->k[t][3]);
        w2 += prv_dot(&u->k[t][12], &u->k[t][12]);
    }
    w1 /= (float)u->n;
    w2 /= (float)u->n;
    return 2.0f * c->acc_noise * c->acc_noise +
           (2.0f / 3.0f) * (prv_dot(x, x) * (sd * sd + 4.0f * c->gyr_noise * c->gyr_noise * w1) +
                            prv_dot(&x[3], &x[3]) *
                                (sd * sd + 4.0f * c->gyr_noise * c->gyr_noise * w2));
}

static SFIT_I_NOINLINE sfit_status_t prv_ball_solve(const sfit_imu_t *s, const prv_used_t *u,
                                                    prv_ball_t *b)
{
    float a[IMU_NP * IMU_NP], g[IMU_NP], pr[IMU_NP], prev[IMU_NP], xprev[IMU_NP];
    float s2 = 0.0f, s2prev, ssr = 0.0f, fprev = 0.0f;
    const uint32_t np = (s->cfg.acc_bias_sd > 0.0f) ? 12u : 6u;
    uint32_t it, i;
    int settled = 0;
    memset(b, 0, sizeof *b);
    memset(prev, 0, sizeof prev);
    memset(xprev, 0, sizeof xprev);
    for (i = 0u; i < np; i++) {
        pr[i] = (i < 6u) ? 1.0f / (IMU_R_PRIOR * IMU_R_PRIOR)
                         : 1.0f / (s->cfg.acc_bias_sd * s->cfg.acc_bias_sd);
    }
    for (it = 0u; it <= (uint32_t)SFIT_IMU_GN_ITERS; it++) {
        float step_r = 0.0f, step_b = 0.0f, f;
        ssr = prv_ball_normal(u, b->x, np, a, g);
        b->pred = prv_pred(s, u, b->x);
        /* the priors' weight: the residual variance, never below the noise's
         * prediction (strong while the fit is far off: a continuation that
         * keeps the first steps near the priors) */
        s2prev = s2;
        s2 = ssr / (float)(u->n - 6u);
        if (!(s2 >= b->pred)) {
            s2 = b->pred;
        }
        if (!sfit_i_isfinite(ssr) || !sfit_i_isfinite(s2)) {
            return SFIT_E_RANGE;
        }
        b->ssr = ssr;
        f = ssr;
        for (i = 0u; i < np; i++) {
            f += s2 * pr[i] * b->x[i] * b->x[i];
        }
        if (it > 0u && !settled && f > fprev * (1.0f + IMU_UPHILL_TOL) &&
            SFIT_FABSF(s2 - s2prev) <= IMU_UPHILL_TOL * s2) {
            /* the last step went uphill (on the same objective): back to half of it */
            for (i = 0u; i < np; i++) {
                b->x[i] = 0.5f * (b->x[i] + xprev[i]);
            }
            continue;
        }
        fprev = f;
        memcpy(xprev, b->x, sizeof xprev);
        for (i = 0u; i < np; i++) {
            a[i * IMU_NP + i] += s2 * pr[i];
            g[i] = -(g[i] + s2 * pr[i] * b->x[i]);
        }
        if (!prv_chol(a, np)) {
            return SFIT_E_DEGENERATE;
        }
        if (settled) {
            break; /* the factor at the settled x gives the covariance */
        }
        prv_chol_solve(a, np, g);
        {
            /* a step that turns back on the last one overshoots (an ill-set
             * direction with a large residual): take half of it */
            float dd = 0.0f;
            for (i = 0u; i < np; i++) {
                dd += g[i] * prev[i];
            }
            for (i = 0u; i < np; i++) {
                if (dd < 0.0f) {
                    g[i] *= 0.5f;
                }
                prev[i] = g[i];
            }
        }
        for (i = 0u; i < np; i++) {
            const float d = SFIT_FABSF(g[i]);
            b->x[i] += g[i];
            if (i < 6u) {
                step_r = (d > step_r) ? d : step_r;
            } else {
                step_b = (d > step_b) ? d : step_b;
            }
        }
        if (!(step_r < 1e3f)) {
            return SFIT_E_RANGE;
        }
        settled = step_r < IMU_STEP_R && step_b < IMU_STEP_B;
    }
    if (!settled) {
        return SFIT_E_NO_CONVERGENCE;
    }
    /* the covariance with the residual variance: the noise's prediction
     * only keeps the priors from vanishing in the steps above */
    s2 = ssr / (float)(u->n - 6u);
    if (!(s2 > 0.0f)) {
        s2 = b->pred;
    }
    prv_cov_block(a, np, 0u, s2, &b->c1);
    prv_cov_block(a, np, 3u, s2, &b->c2);
    memcpy(b->l, a, sizeof a);
    b->s2 = s2;
    b->np = np;
    return SFIT_OK;
}

/* ---- hinge ---- */

static void prv_phi(const float w[3], float sign, float p[6])
{
    p[0] = sign * w[0] * w[0];
    p[1] = sign * w[1] * w[1];
    p[2] = sign * w[2] * w[2];
    p[3] = sign * 2.0f * w[0] * w[1];
    p[4] = sign * 2.0f * w[0] * w[2];
    p[5] = sign * 2.0f * w[1] * w[2];
}

static void prv_top_axis(const float q[6], float j[3])
{
    sfit_mat3_t m, v;
    sfit_vec3_t ev;
    m.m[0] = q[0];
    m.m[4] = q[1];
    m.m[8] = q[2];
    m.m[1] = m.m[3] = q[3];
    m.m[2] = m.m[6] = q[4];
    m.m[5] = m.m[7] = q[5];
    if (sfit_mat3_eig_sym(&m, &ev, &v) != SFIT_OK) {
        j[0] = 1.0f;
        j[1] = 0.0f;
        j[2] = 0.0f;
        return;
    }
    j[0] = v.m[2];
    j[1] = v.m[5];
    j[2] = v.m[8];
}

/* Start of the axes: the lifted linear problem. 0 when singular. */
static SFIT_I_NOINLINE int prv_hinge_lift(const prv_used_t *u, float j1[3], float j2[3])
{
    float a[IMU_NP * IMU_NP], b[IMU_NP], row[IMU_NP], lam = 0.0f;
    uint32_t t, i, k;
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    for (t = 0u; t < u->n; t++) {
        const float *w1 = &u->k[t][3], *w2 = &u->k[t][12];
        const float rhs = prv_dot(w1, w1) - prv_dot(w2, w2);
        prv_phi(w1, 1.0f, row);
        prv_phi(w2, -1.0f, &row[6]);
        for (i = 0u; i < IMU_NP; i++) {
            b[i] += row[i] * rhs;
            for (k = 0u; k <= i; k++) {
                a[i * IMU_NP + k] += row[i] * row[k];
            }
        }
    }
    for (i = 0u; i < IMU_NP; i++) {
        lam += a[i * IMU_NP + i];
    }
    lam /= (float)IMU_NP;
    /* lam (tr J_i - 1)^2 for both: rows (1 1 1 0 0 0) on each half */
    for (i = 0u; i < IMU_NP; i++) {
        if ((i % 6u) < 3u) {
            b[i] += lam;
            for (k = 0u; k <= i; k++) {
                if ((k % 6u) < 3u && (k / 6u) == (i / 6u)) {
                    a[i * IMU_NP + k] += lam;
                }
            }
        }
    }
    if (!prv_chol(a, IMU_NP)) {
        return 0;
    }
    prv_chol_solve(a, IMU_NP, b);
    prv_top_axis(b, j1);
    prv_top_axis(&b[6], j2);
    return 1;
}

/* Two unit vectors spanning the plane normal to the unit j. */
static void prv_tangents(const float j[3], float ta[3], float tb[3])
{
    float e[3] = {0.0f, 0.0f, 0.0f}, n;
    uint32_t m = 0u, i;
    for (i = 1u; i < 3u; i++) {
        if (SFIT_FABSF(j[i]) < SFIT_FABSF(j[m])) {
            m = i;
        }
    }
    e[m] = 1.0f;
    prv_cross(j, e, ta);
    n = SFIT_SQRTF(prv_dot(ta, ta));
    for (i = 0u; i < 3u; i++) {
        ta[i] /= n;
    }
    prv_cross(j, ta, tb);
}

/* |w x j| and its gradient in j */
static float prv_wxj(const float w[3], const float j[3], float gr[3])
{
    float c[3], nn;
    const float wj = prv_dot(w, j), ww = prv_dot(w, w);
    uint32_t i;
    prv_cross(w, j, c);
    nn = SFIT_SQRTF(prv_dot(c, c));
    for (i = 0u; i < 3u; i++) {
        gr[i] = (nn > 1e-6f) ? (ww * j[i] - wj * w[i]) / nn : 0.0f;
    }
    return nn;
}

typedef struct prv_hinge {
    float j1[3], j2[3];
    sfit_mat3_t c1, c2;
    float ratio;
} prv_hinge_t;

static void prv_axis_cov(const float *l, uint32_t off, float s2, const float ta[3],
                         const float tb[3], sfit_mat3_t *c)
{
    float col0[IMU_NP], col1[IMU_NP], cc[4];
    uint32_t i, k;
    memset(col0, 0, sizeof col0);
    memset(col1, 0, sizeof col1);
    col0[off] = 1.0f;
    col1[off + 1u] = 1.0f;
    prv_chol_solve(l, 4u, col0);
    prv_chol_solve(l, 4u, col1);
    cc[0] = s2 * col0[off];
    cc[1] = s2 * 0.5f * (col0[off + 1u] + col1[off]);
    cc[2] = cc[1];
    cc[3] = s2 * col1[off + 1u];
    for (i = 0u; i < 3u; i++) {
        for (k = 0u; k < 3u; k++) {
            c->m[3u * i + k] = ta[i] * (cc[0] * ta[k] + cc[1] * tb[k]) +
                               tb[i] * (cc[2] * ta[k] + cc[3] * tb[k]);
        }
    }
}

/* One row jr, residual e of a 4-unknown problem into a (lower) and g = -J^T e. */
static void prv_acc4(float *a, float g[4], const float jr[4], float e)
{
    uint32_t i, l;
    for (i = 0u; i < 4u; i++) {
        g[i] -= jr[i] * e;
        for (l = 0u; l <= i; l++) {
            a[i * IMU_NP + l] += jr[i] * jr[l];
        }
    }
}

/* Normal equations of the hinge problem at (j1, j2) in the tangent planes
 * (t1a, t1b), (t2a, t2b); returns the SSR, a (lower) and g = -J^T e. The
 * rates' problem |w1 x j1| = |w2 x j2| when x is NULL; else the joint
 * force's, u1.j1 = u2.j2 with u_i = a_i - b_i + G_i r_i at the ball fit x
 * (an axis fixed in both segments has the same component of the force on
 * both sides). */
static float prv_hinge_pass(const prv_used_t *u, const float *x, const float j1[3],
                            const float j2[3], float t[4][3], float *a, float g[4])
{
    float ssr = 0.0f;
    uint32_t k;
    prv_tangents(j1, t[0], t[1]);
    prv_tangents(j2, t[2], t[3]);
    memset(a, 0, 4u * IMU_NP * sizeof(float));
    memset(g, 0, 4u * sizeof(float));
    for (k = 0u; k < u->n; k++) {
        float g1[3], g2[3], jr[4], e;
        if (x == NULL) {
            e = prv_wxj(&u->k[k][3], j1, g1) - prv_wxj(&u->k[k][12], j2, g2);
        } else {
            prv_force(u->k[k], x, g1, g2);
            e = prv_dot(g1, j1) - prv_dot(g2, j2);
        }
        jr[0] = prv_dot(g1, t[0]);
        jr[1] = prv_dot(g1, t[1]);
        jr[2] = -prv_dot(g2, t[2]);
        jr[3] = -prv_dot(g2, t[3]);
        prv_acc4(a, g, jr, e);
        ssr += e * e;
    }
    return ssr;
}

static void prv_unit(float j[3])
{
    const float n = SFIT_SQRTF(prv_dot(j, j));
    uint32_t i;
    for (i = 0u; i < 3u; i++) {
        j[i] = (n > 0.0f) ? j[i] / n : ((i == 0u) ? 1.0f : 0.0f);
    }
}

/* Gauss-Newton on the axes from (j1, j2) (x: prv_hinge_pass); their SSR, or
 * -1 when it fails. */
static float prv_hinge_gn(const prv_used_t *u, const float *x, float j1[3], float j2[3])
{
    float a[4u * IMU_NP], g[4], t[4][3], ssr = -1.0f;
    uint32_t it, i;
    for (it = 0u; it < (uint32_t)SFIT_IMU_GN_ITERS; it++) {
        float step = 0.0f;
        ssr = prv_hinge_pass(u, x, j1, j2, t, a, g);
        if (!prv_chol(a, 4u)) {
            return -1.0f;
        }
        prv_chol_solve(a, 4u, g);
        for (i = 0u; i < 4u; i++) {
            step = (SFIT_FABSF(g[i]) > step) ? SFIT_FABSF(g[i]) : step;
        }
        if (!(step < 10.0f)) {
            return -1.0f;
        }
        for (i = 0u; i < 3u; i++) {
            j1[i] += g[0] * t[0][i] + g[1] * t[1][i];
            j2[i] += g[2] * t[2][i] + g[3] * t[3][i];
        }
        prv_unit(j1);
        prv_unit(j2);
        if (step < IMU_STEP_J) {
            break;
        }
    }
    return ssr;
}

/* ---- the hinge from the relative rotation ---- */

/* The rotation matrix (row-major) of the unit quaternion q (w, x, y, z). */
static void prv_qmat(const float *q, float m[9])
{
    const float w = q[0], x = q[1], y = q[2], z = q[3];
    m[0] = 1.0f - 2.0f * (y * y + z * z);
    m[1] = 2.0f * (x * y - w * z);
    m[2] = 2.0f * (x * z + w * y);
    m[3] = 2.0f * (x * y + w * z);
    m[4] = 1.0f - 2.0f * (x * x + z * z);
    m[5] = 2.0f * (y * z - w * x);
    m[6] = 2.0f * (x * z - w * y);
    m[7] = 2.0f * (y * z + w * x);
    m[8] = 1.0f - 2.0f * (x * x + y * y);
}

/* c = a b (trans_a: a^T b), 3x3 row-major */
static void prv_mm(const float a[9], const float b[9], int trans_a, float c[9])
{
    uint32_t i, j, k;
    for (i = 0u; i < 3u; i++) {
        for (j = 0u; j < 3u; j++) {
            float t = 0.0f;
            for (k = 0u; k < 3u; k++) {
                t += ((trans_a != 0) ? a[3u * k + i] : a[3u * i + k]) * b[3u * k + j];
            }
            c[3u * i + j] = t;
        }
    }
}

/* o = m v (trans: m^T v) */
static void prv_mv(const float m[9], const float v[3], int trans, float o[3])
{
    uint32_t i;
    for (i = 0u; i < 3u; i++) {
        o[i] = (trans != 0) ? m[i] * v[0] + m[3u + i] * v[1] + m[6u + i] * v[2]
                            : m[3u * i] * v[0] + m[3u * i + 1u] * v[1] + m[3u * i + 2u] * v[2];
    }
}

/* The rotation nearest b (its orthogonal polar factor, Newton's iteration
 * r <- (r + r^-T) / 2 from b scaled to unit size); 0 when b is singular or
 * a reflection. */
static int prv_polar(const float b[9], float r[9])
{
    float n = 0.0f;
    uint32_t i, it;
    for (i = 0u; i < 9u; i++) {
        n += b[i] * b[i];
    }
    if (!(n > 0.0f) || !sfit_i_isfinite(n)) {
        return 0;
    }
    n = 1.0f / SFIT_SQRTF(n / 3.0f);
    for (i = 0u; i < 9u; i++) {
        r[i] = b[i] * n;
    }
    for (it = 0u; it < IMU_POLAR_ITERS; it++) {
        float c0[3], c1[3], c2[3], x[3], y[3], z[3], det, ch = 0.0f;
        for (i = 0u; i < 3u; i++) {
            c0[i] = r[3u * i];
            c1[i] = r[3u * i + 1u];
            c2[i] = r[3u * i + 2u];
        }
        prv_cross(c1, c2, x);
        prv_cross(c2, c0, y);
        prv_cross(c0, c1, z);
        det = prv_dot(c0, x);
        if (!(det > 1e-6f)) {
            return 0;
        }
        det = 1.0f / det;
        for (i = 0u; i < 3u; i++) {
            /* r^-T has the columns x, y, z over det */
            const float a = 0.5f * (r[3u * i] + x[i] * det);
            const float bb = 0.5f * (r[3u * i + 1u] + y[i] * det);
            const float cc = 0.5f * (r[3u * i + 2u] + z[i] * det);
            ch += SFIT_FABSF(a - r[3u * i]) + SFIT_FABSF(bb - r[3u * i + 1u]) +
                  SFIT_FABSF(cc - r[3u * i + 2u]);
            r[3u * i] = a;
            r[3u * i + 1u] = bb;
            r[3u * i + 2u] = cc;
        }
        if (ch < 1e-6f) {
            return 1;
        }
    }
    return 1;
}

/* The rotation by the vector p (Rodrigues). */
static void prv_rodrigues(const float p[3], float m[9])
{
    const float a2 = prv_dot(p, p);
    /* sin a / a and (1 - cos a) / a^2 to the fourth order (a < 0.5 rad) */
    const float s = 1.0f - a2 * (1.0f / 6.0f) * (1.0f - a2 * (1.0f / 20.0f));
    const float c = 0.5f * (1.0f - a2 * (1.0f / 12.0f) * (1.0f - a2 * (1.0f / 30.0f)));
    uint32_t i, j;
    for (i = 0u; i < 3u; i++) {
        for (j = 0u; j < 3u; j++) {
            m[3u * i + j] = ((i == j) ? 1.0f - c * a2 : 0.0f) + c * p[i] * p[j];
        }
    }
    m[1] -= s * p[2];
    m[2] += s * p[1];
    m[3] += s * p[2];
    m[5] -= s * p[0];
    m[6] -= s * p[1];
    m[7] += s * p[0];
}

typedef struct prv_fixed {
    float j1[3], j2[3]; /* the best fixed axis in each sensor's frame */
    float wobble;       /* rms angle of the relative rotation off it (rad) */
    float turn;         /* rms angle of the relative rotation about it (rad) */
    float neff;         /* the kept samples' effective number for the axis's variance */
    int ok;
} prv_fixed_t;

/* R0, the rotation between the two sensors' starting orientations: the
 * joint's specific force is one physical vector, D1 u1 = R0 D2 u2, so R0 is
 * the rotation nearest sum D1 u1 (D2 u2)^T. 0 when that is singular. */
static int prv_start_rotation(const prv_used_t *u, const float *x, float r0[9])
{
    float b[9];
    uint32_t k, i, l;
    memset(b, 0, sizeof b);
    for (k = 0u; k < u->n; k++) {
        const float *q = u->k[k];
        float d1[9], d2[9], u1[3], u2[3], p1[3], p2[3];
        prv_qmat(&q[18], d1);
        prv_qmat(&q[22], d2);
        prv_force(q, x, u1, u2);
        prv_mv(d1, u1, 0, p1);
        prv_mv(d2, u2, 0, p2);
        for (i = 0u; i < 3u; i++) {
            for (l = 0u; l < 3u; l++) {
                b[3u * i + l] += p1[i] * p2[l];
            }
        }
    }
    return prv_polar(b, r0);
}

/* The best fixed axis of the mean relative rotation D1^T R0 E(tau) D2 with
 * the drift phi (E = exp(phi0 + tau phi1)): j2 the top eigenvector of M^T M,
 * j1 = M j2 normalised; turn from the middle singular value. 0 on failure. */
static int prv_best_axis(const prv_used_t *u, const float r0[9], const float phi[6], float tm,
                         float th, prv_fixed_t *f)
{
    float mm[9], st[9], n, sg;
    sfit_mat3_t sm, v;
    sfit_vec3_t ev;
    uint32_t k, i;
    memset(mm, 0, sizeof mm);
    for (k = 0u; k < u->n; k++) {
        const float *q = u->k[k];
        const float tau = (q[26] - tm) * th;
        float d1[9], d2[9], e[9], p[3], c[9], rk[9];
        prv_qmat(&q[18], d1);
        prv_qmat(&q[22], d2);
        for (i = 0u; i < 3u; i++) {
            p[i] = phi[i] + tau * phi[3u + i];
        }
        prv_rodrigues(p, e);
        prv_mm(e, d2, 0, c);
        prv_mm(r0, c, 0, rk);
        prv_mm(d1, rk, 1, c);
        for (i = 0u; i < 9u; i++) {
            mm[i] += c[i];
        }
    }
    prv_mm(mm, mm, 1, st);
    memcpy(sm.m, st, sizeof sm.m);
    if (sfit_mat3_eig_sym(&sm, &ev, &v) != SFIT_OK) {
        return 0;
    }
    /* the middle singular value of the mean rotation, the mean cosine of
     * the turn about the axis: the rms turn is about sqrt(2 (1 - it)) */
    sg = SFIT_SQRTF(SFIT_FABSF(ev.v[1])) / (float)u->n;
    f->turn = (sg < 1.0f) ? SFIT_SQRTF(2.0f * (1.0f - sg)) : 0.0f;
    f->j2[0] = v.m[2];
    f->j2[1] = v.m[5];
    f->j2[2] = v.m[8];
    prv_mv(mm, f->j2, 0, f->j1);
    n = prv_dot(f->j1, f->j1);
    if (!(n > 0.0f)) {
        return 0;
    }
    n = 1.0f / SFIT_SQRTF(n);
    for (i = 0u; i < 3u; i++) {
        f->j1[i] *= n;
    }
    return 1;
}

/* One kept sample of the drift fit at the axes (j1, j2): d = R0^T D1 j1 -
 * D2 j2 = phi(tau) x v with v = D2 j2, rows (P, tau P), P = I - v v^T, the
 * right-hand side v x d, into a (lower) and g; res = d - phi(tau) x v at the
 * drift phi so far, and returns |res|^2. */
static float prv_drift_row(const float *q, const prv_fixed_t *f, const float r0[9],
                           const float phi[6], float tau, float *a, float g[6], float res[3])
{
    float d1[9], d2[9], vv[3], aa[3], w[3], d[3], pm[9], ts[2];
    uint32_t i, l;
    prv_qmat(&q[18], d1);
    prv_qmat(&q[22], d2);
    prv_mv(d2, f->j2, 0, vv);
    prv_mv(d1, f->j1, 0, w);
    prv_mv(r0, w, 1, aa);
    for (i = 0u; i < 3u; i++) {
        d[i] = aa[i] - vv[i];
    }
    prv_cross(vv, d, w);
    for (i = 0u; i < 9u; i++) {
        pm[i] = ((i % 4u) == 0u) ? 1.0f : 0.0f;
    }
    for (i = 0u; i < 3u; i++) {
        for (l = 0u; l < 3u; l++) {
            pm[3u * i + l] -= vv[i] * vv[l];
        }
    }
    ts[0] = 1.0f;
    ts[1] = tau;
    for (i = 0u; i < 6u; i++) {
        const float ti = ts[i / 3u];
        g[i] += ti * w[i % 3u];
        for (l = 0u; l <= i; l++) {
            a[i * IMU_NP + l] += ti * ts[l / 3u] * pm[3u * (i % 3u) + (l % 3u)];
        }
    }
    prv_cross(&phi[0], vv, w);
    prv_cross(&phi[3], vv, res);
    for (i = 0u; i < 3u; i++) {
        res[i] = d[i] - w[i] - tau * res[i];
    }
    return prv_dot(res, res);
}

/* The hinge from the relative rotation of the two sensors at the kept
 * samples, R(t) = D1(t)^T R0 E(t) D2(t): D_i each sensor's integrated
 * orientation, R0 the rotation between their starts (prv_start_rotation),
 * E(t) = exp(phi0 + tau phi1) a linear drift of the integration (gyroscope
 * biases) in sensor 2's start frame. The best fixed axis is the pair
 * (j1, j2) that R(t) moves least, R(t) j2 = j1: the top singular vectors of
 * the mean of R(t). A wobble of angle A at any frequency moves it by A,
 * whatever its rate; a ball by its whole range off the axis. Passes: axis
 * with the drift so far, the drift fitted to the axis's residual
 * R0^T D1 j1 - D2 j2 = phi x D2 j2 (least squares with a small ridge: a
 * drift about the axis changes nothing); the last pass: the rms of what is
 * left (f->wobble) and, from its lag-one autocorrelation rho over the kept
 * samples (in time order), their effective number n (1 - rho) / (1 + rho):
 * a wobble that follows the flexion is one error repeated over many kept
 * samples, not independent ones. */
static SFIT_I_NOINLINE void prv_fixed_axis(const prv_used_t *u, const float *x, prv_fixed_t *f)
{
    float r0[9], phi[6], a[IMU_NP * IMU_NP], g[6], t0, t1, tm, th;
    uint32_t k, i, pass;
    memset(f, 0, sizeof *f);
    memset(phi, 0, sizeof phi);
    if (!prv_start_rotation(u, x, r0)) {
        return;
    }
    t0 = u->k[0][26];
    t1 = u->k[u->n - 1u][26];
    tm = 0.5f * (t0 + t1);
    th = (t1 > t0) ? 2.0f / (t1 - t0) : 0.0f;
    for (pass = 0u; pass < IMU_FIXED_PASSES; pass++) {
        float ss = 0.0f, lag = 0.0f, prev[3] = {0.0f, 0.0f, 0.0f};
        if (!prv_best_axis(u, r0, phi, tm, th, f)) {
            return;
        }
        memset(a, 0, sizeof a);
        memset(g, 0, sizeof g);
        for (k = 0u; k < u->n; k++) {
            float res[3];
            ss += prv_drift_row(u->k[k], f, r0, phi, (u->k[k][26] - tm) * th, a, g, res);
            lag += prv_dot(res, prev);
            memcpy(prev, res, sizeof prev);
        }
        if (pass + 1u == IMU_FIXED_PASSES) {
            float rho = (ss > 0.0f) ? lag / ss : 0.0f;
            rho = (rho > 0.0f) ? rho : 0.0f;
            rho = (rho < IMU_RHO_MAX) ? rho : IMU_RHO_MAX;
            f->wobble = SFIT_SQRTF(ss / (float)u->n);
            f->neff = (float)u->n * (1.0f - rho) / (1.0f + rho);
            f->ok = sfit_i_isfinite(f->wobble) && sfit_i_isfinite(f->neff);
            return;
        }
        for (i = 0u; i < 6u; i++) {
            a[i * IMU_NP + i] += IMU_DRIFT_RIDGE * (float)u->n;
        }
        if (!prv_chol(a, 6u)) {
            return;
        }
        prv_chol_solve(a, 6u, g);
        memcpy(phi, g, sizeof phi);
    }
}

/* The wobble's share of the axes' covariance, added to h->c1, h->c2 in the
 * plane normal to each axis (h->j1, h->j2): the wobble's variance over the
 * kept samples' effective number. Whatever the axes were found from (the
 * rates or the relative rotation), the part of the wobble in step with the
 * flexion over the trial tilts the axis the motion shows, and that part is
 * an average of the wobble over its independent samples; for the relative
 * rotation's axes it is the whole covariance. */
static void prv_wobble_cov(const prv_fixed_t *f, prv_hinge_t *h)
{
    const float v = f->wobble * f->wobble / f->neff;
    uint32_t i, k;
    for (i = 0u; i < 3u; i++) {
        for (k = 0u; k < 3u; k++) {
            const float d = (i == k) ? 1.0f : 0.0f;
            h->c1.m[3u * i + k] += v * (d - h->j1[i] * h->j1[k]);
            h->c2.m[3u * i + k] += v * (d - h->j2[i] * h->j2[k]);
        }
    }
}

/* The top eigenvector of sum w w^T of one sensor's kept rates. */
static void prv_rate_axis(const prv_used_t *u, uint32_t off, float j[3])
{
    float q[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
    uint32_t k;
    for (k = 0u; k < u->n; k++) {
        const float *w = &u->k[k][off];
        q[0] += w[0] * w[0];
        q[1] += w[1] * w[1];
        q[2] += w[2] * w[2];
        q[3] += w[0] * w[1];
        q[4] += w[0] * w[2];
        q[5] += w[1] * w[2];
    }
    prv_top_axis(q, j);
}

static SFIT_I_NOINLINE void prv_hinge_solve(const prv_used_t *u, prv_hinge_t *h)
{
    float a[4u * IMU_NP], g[4], t[4][3], st[4][2][3], best = -1.0f, ww = 0.0f, ssr;
    uint32_t k, i, big = 0u, ns = 0u;
    memset(h, 0, sizeof *h);
    memset(t, 0, sizeof t);
    memset(a, 0, sizeof a);
    /* starts: the lifted solution, the main rotation axis of each sensor, mixed */
    prv_rate_axis(u, 3u, st[0][0]);
    prv_rate_axis(u, 12u, st[0][1]);
    ns = 1u;
    if (prv_hinge_lift(u, st[1][0], st[1][1])) {
        memcpy(st[2][0], st[0][0], sizeof st[2][0]);
        memcpy(st[2][1], st[1][1], sizeof st[2][1]);
        memcpy(st[3][0], st[1][0], sizeof st[3][0]);
        memcpy(st[3][1], st[0][1], sizeof st[3][1]);
        ns = 4u;
    }
    for (k = 0u; k < ns; k++) {
        const float e = prv_hinge_gn(u, NULL, st[k][0], st[k][1]);
        if (e >= 0.0f && (best < 0.0f || e < best)) {
            best = e;
            memcpy(h->j1, st[k][0], sizeof h->j1);
            memcpy(h->j2, st[k][1], sizeof h->j2);
        }
    }
    for (k = 0u; k < u->n; k++) {
        ww += 0.5f * (prv_dot(&u->k[k][3], &u->k[k][3]) + prv_dot(&u->k[k][12], &u->k[k][12]));
    }
    ssr = (best >= 0.0f) ? prv_hinge_pass(u, NULL, h->j1, h->j2, t, a, g) : 0.0f;
    if (best < 0.0f || !(ww > 0.0f) || !prv_chol(a, 4u)) {
        memset(h, 0, sizeof *h);
        h->ratio = 1.0f; /* no hinge fit: the joint is taken for a ball */
        return;
    }
    h->ratio = SFIT_SQRTF(ssr / ww);
    /* j1's largest component positive (j2's sign: sfit_imu_solve) */
    for (i = 1u; i < 3u; i++) {
        big = (SFIT_FABSF(h->j1[i]) > SFIT_FABSF(h->j1[big])) ? i : big;
    }
    if (h->j1[big] < 0.0f) {
        for (i = 0u; i < 3u; i++) {
            h->j1[i] = -h->j1[i];
        }
    }
    {
        const float s2 = ssr / (float)(u->n - 4u);
        prv_axis_cov(a, 0u, s2, t[0], t[1], &h->c1);
        prv_axis_cov(a, 2u, s2, t[2], t[3], &h->c2);
    }
}

/* out = A C A^T, symmetric to the last bit (each pair of entries averaged). */
static void prv_sandwich(const float a[9], const sfit_mat3_t *c, float out[9])
{
    float t[9];
    uint32_t i, k, l;
    for (i = 0u; i < 3u; i++) {
        for (k = 0u; k < 3u; k++) {
            float acc = 0.0f;
            for (l = 0u; l < 3u; l++) {
                acc += a[3u * i + l] * c->m[3u * l + k];
            }
            t[3u * i + k] = acc;
        }
    }
    for (i = 0u; i < 3u; i++) {
        for (k = 0u; k <= i; k++) {
            float acc = 0.0f, acc2 = 0.0f;
            for (l = 0u; l < 3u; l++) {
                acc += t[3u * i + l] * a[3u * k + l];
                acc2 += t[3u * k + l] * a[3u * i + l];
            }
            out[3u * i + k] = 0.5f * (acc + acc2);
            out[3u * k + i] = out[3u * i + k];
        }
    }
}

/* p - (p.j) j and P C P with P = I - j j^T */
static void prv_project(const float j[3], sfit_vec3_t *p, sfit_mat3_t *c)
{
    float pm[9];
    const float d = prv_dot(p->v, j);
    uint32_t i, k;
    for (i = 0u; i < 3u; i++) {
        p->v[i] -= d * j[i];
        for (k = 0u; k < 3u; k++) {
            pm[3u * i + k] = ((i == k) ? 1.0f : 0.0f) - j[i] * j[k];
        }
    }
    prv_sandwich(pm, c, c->m);
}

/* The axis point p = r - (r.j) j nearest the sensor and its covariance: the
 * centre's covariance C projected, P C P, plus the axis's covariance Cj
 * carried through the projection, A Cj A^T with A = dp/dj = -((j.r) I + j r^T)
 * (the centre and the axis taken for independent). Without the second term
 * the covariance is singular along the axis, where the point moves by |p|
 * times the axis's error. */
static void prv_point_cov(const float j[3], const sfit_mat3_t *cj, sfit_vec3_t *p, sfit_mat3_t *c)
{
    float am[9], s[9];
    const float d = prv_dot(p->v, j);
    uint32_t i, k;
    for (i = 0u; i < 3u; i++) {
        for (k = 0u; k < 3u; k++) {
            am[3u * i + k] = -(((i == k) ? d : 0.0f) + j[i] * p->v[k]);
        }
    }
    prv_sandwich(am, cj, s);
    prv_project(j, p, c);
    for (i = 0u; i < 9u; i++) {
        c->m[i] += s[i];
    }
}

/* The trace of c, less j^T c j when j is given: the variance in the plane
 * normal to j (the trace of P c P with P = I - j j^T). */
static float prv_plane_var(const sfit_mat3_t *c, const float *j)
{
    float v = c->m[0] + c->m[4] + c->m[8];
    if (j != NULL) {
        float cj[3];
        prv_mv(c->m, j, 0, cj);
        v -= prv_dot(j, cj);
    }
    return v;
}

/* The sine of the angle between the line of the axes (j1, j2)/sqrt(2) and the
 * freest line of the joint position: the top eigenvector of the 6x6
 * covariance of (r1, r2) (power iteration from the axes' line). For a
 * hinge the accelerometers leave the position free along the true axis;
 * rates that break the hinge constraint in step with the flexion (a
 * wobble at the gait's frequency) turn the axes that |w1 x j1| = |w2 x j2|
 * finds away from it. */
static float prv_free_line_off(const prv_ball_t *b, const float j1[3], const float j2[3])
{
    float c[36], v[6], w[6], n, d;
    uint32_t i, k, it;
    for (k = 0u; k < 6u; k++) {
        float e[IMU_NP];
        memset(e, 0, sizeof e);
        e[k] = 1.0f;
        prv_chol_solve(b->l, b->np, e);
        for (i = 0u; i < 6u; i++) {
            c[6u * i + k] = e[i];
        }
    }
    for (i = 0u; i < 3u; i++) {
        v[i] = 0.70710678f * j1[i];
        v[3u + i] = 0.70710678f * j2[i];
    }
    memcpy(w, v, sizeof w);
    for (it = 0u; it < IMU_LINE_ITERS; it++) {
        float t[6];
        n = 0.0f;
        for (i = 0u; i < 6u; i++) {
            t[i] = 0.0f;
            for (k = 0u; k < 6u; k++) {
                t[i] += c[6u * i + k] * w[k];
            }
            n += t[i] * t[i];
        }
        if (!(n > 0.0f)) {
            return 0.0f;
        }
        n = 1.0f / SFIT_SQRTF(n);
        for (i = 0u; i < 6u; i++) {
            w[i] = t[i] * n;
        }
    }
    d = SFIT_FABSF(prv_dot(v, w) + prv_dot(&v[3], &w[3]));
    d = (d < 1.0f) ? d : 1.0f;
    return SFIT_SQRTF(1.0f - d * d);
}

/* The rates' axes (j1, j2 the same physical direction) against the joint's
 * specific force: the rms of u1.j1 - u2.j2 at them over its rms at the axes
 * Gauss-Newton fits to it from them (floored at the noise's prediction);
 * 1 when the force does not determine the axes (no evidence). */
static SFIT_I_NOINLINE float prv_force_ratio(const prv_used_t *u, const prv_ball_t *b,
                                             const float j1[3], const float j2[3])
{
    float a[4u * IMU_NP], g[4], t[4][3], k1[3], k2[3], q0, q1;
    memcpy(k1, j1, sizeof k1);
    memcpy(k2, j2, sizeof k2);
    q0 = prv_hinge_pass(u, b->x, k1, k2, t, a, g);
    q1 = prv_hinge_gn(u, b->x, k1, k2);
    if (!(q1 >= 0.0f)) {
        return 1.0f;
    }
    q1 = prv_hinge_pass(u, b->x, k1, k2, t, a, g);
    q1 = (q1 > b->pred * (float)u->n) ? q1 : b->pred * (float)u->n;
    return SFIT_SQRTF(q0 / q1);
}

static int prv_result_finite(const sfit_imu_result_t *r)
{
    const float *f[] = {r->r1.v, r->r2.v, r->axis1.v, r->axis2.v, r->acc_bias1.v, r->acc_bias2.v};
    const float *m[] = {r->r1_cov.m, r->r2_cov.m, r->axis1_cov.m, r->axis2_cov.m};
    uint32_t i, k;
    for (i = 0u; i < 6u; i++) {
        for (k = 0u; k < 3u; k++) {
            if (!sfit_i_isfinite(f[i][k])) {
                return 0;
            }
        }
    }
    for (i = 0u; i < 4u; i++) {
        for (k = 0u; k < 9u; k++) {
            if (!sfit_i_isfinite(m[i][k])) {
                return 0;
            }
        }
    }
    return sfit_i_isfinite(r->resid_rms) && sfit_i_isfinite(r->line_sd) &&
           sfit_i_isfinite(r->line_ratio) && sfit_i_isfinite(r->noise_rms) &&
           sfit_i_isfinite(r->hinge_ratio) && sfit_i_isfinite(r->force_ratio) &&
           sfit_i_isfinite(r->wobble_deg) &&
           sfit_i_isfinite(r->rate_rms1) &&
           sfit_i_isfinite(r->rate_rms2);
}

sfit_status_t sfit_imu_solve(const sfit_imu_t *s, sfit_imu_result_t *out)
{
    prv_used_t u;
    prv_ball_t b;
    prv_hinge_t h;
    prv_fixed_t fx;
    sfit_imu_result_t r;
    sfit_status_t st;
    uint32_t i;
    int fixed = 0;
    float sd1, sd2;
    if (s == NULL || out == NULL || !prv_state_ok(s)) {
        return SFIT_E_ARG;
    }
    u.n = s->nfull + ((s->wpos > 0u) ? 1u : 0u);
    if (u.n < IMU_MIN_USED || s->nd == 0u) {
        return SFIT_E_TOO_FEW;
    }
    for (i = 0u; i < u.n; i++) {
        const uint8_t k = s->order[i];
        if (k >= (uint8_t)SFIT_IMU_KEEP) {
            return SFIT_E_ARG;
        }
        u.k[i] = s->keep[k];
    }
    st = prv_ball_solve(s, &u, &b);
    if (st != SFIT_OK) {
        return st;
    }
    prv_hinge_solve(&u, &h);
    prv_fixed_axis(&u, b.x, &fx);
    memset(&r, 0, sizeof r);
    r.n = s->n;
    r.used = u.n;
    memcpy(r.r1.v, b.x, sizeof r.r1.v);
    memcpy(r.r2.v, &b.x[3], sizeof r.r2.v);
    memcpy(r.acc_bias1.v, &b.x[6], sizeof r.acc_bias1.v);
    memcpy(r.acc_bias2.v, &b.x[9], sizeof r.acc_bias2.v);
    r.r1_cov = b.c1;
    r.r2_cov = b.c2;
    memcpy(r.axis1.v, h.j1, sizeof r.axis1.v);
    memcpy(r.axis2.v, h.j2, sizeof r.axis2.v);
    if (fx.ok != 0) {
        prv_wobble_cov(&fx, &h); /* the rates' axes: estimation + the wobble's share */
    }
    r.axis1_cov = h.c1;
    r.axis2_cov = h.c2;
    r.hinge_ratio = h.ratio;
    {
        /* the SD of the joint position along the line (j1, +-j2): where the
         * axes would let the joint slide. Of the two signs of j2, the one
         * of the same physical axis is the freer line. */
        float best = 0.0f;
        int sg;
        for (sg = 0; sg < 2; sg++) {
            float v[IMU_NP], w[IMU_NP], var;
            const float f2 = (sg == 0) ? 0.70710678f : -0.70710678f;
            memset(v, 0, sizeof v);
            for (i = 0u; i < 3u; i++) {
                v[i] = 0.70710678f * h.j1[i];
                v[3u + i] = f2 * h.j2[i];
            }
            memcpy(w, v, sizeof w);
            prv_chol_solve(b.l, b.np, w);
            var = SFIT_FABSF(b.s2 * (prv_dot(v, w) + prv_dot(&v[3], &w[3])));
            if (var > best) {
                best = var;
                if (sg == 1) {
                    for (i = 0u; i < 3u; i++) {
                        r.axis2.v[i] = -h.j2[i];
                    }
                }
            }
        }
        r.line_sd = SFIT_SQRTF(best);
        r.line_off = prv_free_line_off(&b, h.j1, r.axis2.v);
        {
            /* the other five directions' mean variance */
            const float rest = (b.c1.m[0] + b.c1.m[4] + b.c1.m[8] + b.c2.m[0] + b.c2.m[4] +
                                b.c2.m[8] - best) / 5.0f;
            r.line_ratio = (rest > 0.0f) ? SFIT_SQRTF(best / rest) : 0.0f;
        }
    }
    r.resid_rms = SFIT_SQRTF(b.ssr / (float)u.n);
    r.noise_rms = SFIT_SQRTF(b.pred);
    r.rate_rms1 = SFIT_SQRTF(s->wsum1 / (float)s->nd);
    r.rate_rms2 = SFIT_SQRTF(s->wsum2 / (float)s->nd);
    /* a ball fixes the joint along every line; a hinge leaves it free
     * along its axis, and its rates obey the hinge constraint */
    r.wobble_deg = fx.ok ? fx.wobble * IMU_RAD2DEG : 0.0f;
    if (r.line_ratio > s->cfg.ball_line) {
        r.hinge = r.line_ratio > s->cfg.hinge_line && h.ratio < s->cfg.hinge_ratio;
    }
    if (!r.hinge && fx.ok && r.wobble_deg < s->cfg.hinge_wobble && fx.turn > IMU_MIN_TURN) {
        /* the rates' hinge test failed (a wobble faster than the flexion
         * breaks |w1 x j1| = |w2 x j2| by its rate), the relative rotation
         * holds an axis within hinge_wobble degrees: a hinge about it */
        r.hinge = true;
        fixed = 1;
        {
            /* j1's largest component positive, j2 the same physical direction */
            uint32_t big = 0u;
            float sg;
            for (i = 1u; i < 3u; i++) {
                big = (SFIT_FABSF(fx.j1[i]) > SFIT_FABSF(fx.j1[big])) ? i : big;
            }
            sg = (fx.j1[big] < 0.0f) ? -1.0f : 1.0f;
            for (i = 0u; i < 3u; i++) {
                h.j1[i] = sg * fx.j1[i];
                h.j2[i] = sg * fx.j2[i];
            }
        }
        memset(&h.c1, 0, sizeof h.c1); /* the rates' share was of their axes */
        memset(&h.c2, 0, sizeof h.c2);
        prv_wobble_cov(&fx, &h);
        memcpy(r.axis1.v, h.j1, sizeof r.axis1.v);
        memcpy(r.axis2.v, h.j2, sizeof r.axis2.v);
        r.axis1_cov = h.c1;
        r.axis2_cov = h.c2;
    }
    if (!r.hinge && r.line_ratio > s->cfg.ball_line) {
        r.flags |= (uint32_t)SFIT_IMU_FLAG_AMBIGUOUS;
    }
    r.force_ratio = prv_force_ratio(&u, &b, h.j1, r.axis2.v);
    if (r.hinge && fixed == 0 && r.line_off > s->cfg.hinge_off) {
        r.flags |= (uint32_t)SFIT_IMU_FLAG_AXIS_OFF;
    }
    if (r.hinge && fixed == 0 && r.force_ratio > s->cfg.wobble_ratio) {
        r.flags |= (uint32_t)SFIT_IMU_FLAG_WOBBLE;
    }
    /* low_variety judges what the motion fixes of the position: for a
     * hinge, the centre's variance in the plane normal to the axis (the
     * axis's own error is in the axis points' covariance, not here) */
    sd1 = prv_plane_var(&r.r1_cov, r.hinge ? r.axis1.v : NULL);
    sd2 = prv_plane_var(&r.r2_cov, r.hinge ? r.axis2.v : NULL);
    if (r.hinge) {
        prv_point_cov(r.axis1.v, &r.axis1_cov, &r.r1, &r.r1_cov);
        prv_point_cov(r.axis2.v, &r.axis2_cov, &r.r2, &r.r2_cov);
    }
    if (r.rate_rms1 < s->cfg.min_rate || r.rate_rms2 < s->cfg.min_rate) {
        r.flags |= (uint32_t)SFIT_IMU_FLAG_LOW_ROTATION;
    }
    sd1 = SFIT_SQRTF(SFIT_FABSF(sd1));
    sd2 = SFIT_SQRTF(SFIT_FABSF(sd2));
    if (!(sd1 <= s->cfg.max_pos_sd) || !(sd2 <= s->cfg.max_pos_sd)) {
        r.flags |= (uint32_t)SFIT_IMU_FLAG_LOW_VARIETY;
    }
    if (r.resid_rms > s->cfg.slip_ratio * r.noise_rms) {
        r.flags |= (uint32_t)SFIT_IMU_FLAG_SLIP;
    }
    if (r.flags != 0u) {
        r.flags |= (uint32_t)SFIT_FLAG_UNTRUSTED;
    }
    if (!prv_result_finite(&r)) {
        return SFIT_E_RANGE;
    }
    *out = r;
    return SFIT_OK;
}
