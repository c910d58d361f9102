/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_gate.c
 * @brief Outlier gate around a moments accumulator.
 *
 * Implementation notes
 * --------------------
 * The variance floor (SFIT_GATE_VAR_FLOOR_REL * r)^2 keeps exact or
 * nearly exact data from gating out its own rounding noise. The robust
 * start sorts at most SFIT_GATE_WARMUP residuals by insertion (bounded,
 * no recursion).
 */
#include "sfit/sfit_gate.h"

#include "sfit_solve.h"

/** Gate sigma is at least this fraction of the radius (rounding noise). */
#define SFIT_GATE_VAR_FLOOR_REL 1e-5f
/** Interleaved start subsets of the robust start (LTS). */
/* (subsets of 8 samples: with 5 % outliers about 2/3 of them are clean) */
#define SFIT_GATE_STARTS ((uint32_t)SFIT_GATE_WARMUP / 8u)
/** Concentration steps per start. */
#define SFIT_GATE_CSTEPS 3
/** MAD to sigma for a Gaussian. */
#define SFIT_GATE_MAD_SIGMA 1.4826f
/** Largest leverage used (a sample far off a nearly planar fit's plane). */
#define SFIT_GATE_H_MAX 1e6f
/** Largest sigma^2 the widening reaches (keeps 4 sigma^2 finite). */
#define SFIT_GATE_VAR_MAX 1e30f

const sfit_gate_cfg_t sfit_gate_cfg_default = {
    .fit = {.mode = SFIT_MODE_AUTO, .noise = SFIT_NOISE_NONE, .planar_ratio = 0.0f},
    .k = 0.0f,
    .noise_var = 0.0f,
    .refresh = 64u};

static float prv_floor(float r)
{
    const float f = SFIT_GATE_VAR_FLOOR_REL * r;
    return (f < 1e15f) ? f * f : SFIT_GATE_VAR_MAX;
}

static float prv_resid(const sfit_vec3_t *x, const sfit_vec3_t *c, float r)
{
    float d[3];
    int i;
    for (i = 0; i < 3; i++) {
        d[i] = x->v[i] - c->v[i];
    }
    return SFIT_SQRTF(sfit_i_dot3(d, d)) - r;
}

/* Median of a[0..n-1] (sorted in place, insertion sort, n <= SFIT_GATE_WARMUP). */
static float prv_median(float *a, uint32_t n)
{
    uint32_t i, j;
    for (i = 1u; i < n; i++) {
        const float v = a[i];
        for (j = i; j > 0u && a[j - 1u] > v; j--) {
            a[j] = a[j - 1u];
        }
        a[j] = v;
    }
    return ((n & 1u) != 0u) ? a[n / 2u] : 0.5f * (a[n / 2u - 1u] + a[n / 2u]);
}

/* The integers a gate indexes with: the phase and the warm-up count (a
 * garbage state, e.g. uninitialised or .noinit RAM, a state read back from
 * flash, gets E_ARG instead of a write outside `warm`). Checked on every
 * add; four integer compares. */
static int prv_index_ok(const sfit_gate_t *g)
{
    return g->phase <= 2u && g->nwarm < (uint32_t)SFIT_GATE_WARMUP
           && (g->phase == 0u || g->nwarm == 0u);
}

/* The whole state (refresh, fit, stats, moments: the calls that carry its
 * values out): indices, and the gate width, sigma^2, window sum and, in
 * phase 2, every value the test reads finite. Bit tests, no FP arithmetic.
 * sfit_gate_add() needs only prv_index_ok(): a non-finite value there makes
 * a verdict arbitrary but cannot enter the state (the window sum is
 * updated only with a finite result). */
static int prv_state_ok(const sfit_gate_t *g)
{
    int ok = prv_index_ok(g) && sfit_i_isfinite(g->cfg.k) && g->cfg.k > 1.0f
             && sfit_i_isfinite(g->cfg.noise_var) && g->cfg.noise_var >= 0.0f
             && sfit_i_isfinite(g->var) && g->var >= 0.0f && sfit_i_isfinite(g->ws2)
             && g->ws2 >= 0.0f;
    if (ok && g->phase == 2u) {
        int j;
        ok = sfit_i_sphere_finite(&g->center, g->radius) && sfit_i_finite3(g->mean.v)
             && sfit_i_isfinite(g->inv_n);
        for (j = 0; j < 6; j++) {
            ok = ok && sfit_i_isfinite(g->lw[j]);
        }
    }
    return ok;
}

sfit_status_t sfit_gate_init(sfit_gate_t *g, const sfit_gate_cfg_t *cfg)
{
    sfit_gate_cfg_t c;
    if (g == NULL) {
        return SFIT_E_ARG;
    }
    c = (cfg != NULL) ? *cfg : sfit_gate_cfg_default;
    if (sfit_i_check_cfg(&c.fit) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(c.k) || (c.k != 0.0f && !(c.k > 1.0f))) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(c.noise_var) || c.noise_var < 0.0f) {
        return SFIT_E_ARG;
    }
    if (c.k == 0.0f) {
        c.k = SFIT_GATE_K;
    }
    memset(g, 0, sizeof *g);
    g->cfg = c;
    (void)sfit_moments_init(&g->acc);
    return SFIT_OK;
}

sfit_status_t sfit_gate_reset(sfit_gate_t *g)
{
    sfit_gate_cfg_t c;
    if (g == NULL) {
        return SFIT_E_ARG;
    }
    c = g->cfg;
    return sfit_gate_init(g, &c);
}

/* Accumulate the buffered samples whose keep flag is set. */
static void prv_buffer_moments(const sfit_gate_t *g, const uint8_t *keep, sfit_moments_t *m)
{
    uint32_t i;
    (void)sfit_moments_init(m);
    for (i = 0u; i < g->nwarm; i++) {
        if (keep == NULL || keep[i] != 0u) {
            (void)sfit_moments_add(m, &g->warm[i]); /* validated on entry */
        }
    }
}

/* Leverage data of the fitted samples: mean and W = L^-1 / sqrt(N-1) for
 * C = L L^T, packed W00, W11, W22, W10, W20, W21. The leverage of a sample
 * is then h = 1/N + |W (x - m)|^2, non-negative by construction even when
 * the third pivot of a (nearly) rank-2 C is rounding noise: there W22 is
 * huge and the gate lenient across the plane, never inverted. In planar
 * mode that direction is lifted first (below). */
static sfit_status_t prv_leverage(sfit_gate_t *g, const sfit_result_t *r,
                                  const sfit_moments_t *m)
{
    sfit_vec3_t mean;
    sfit_mat3_t c, l;
    float w[6], s;
    uint32_t n = sfit_moments_count(m);
    int j;
    if (n < 2u || sfit_moments_stats(m, &mean, &c, NULL) != SFIT_OK) {
        return SFIT_E_DEGENERATE;
    }
    if (g->cfg.fit.mode == SFIT_MODE_PLANAR) {
        /* A hinge by option: the circle does not depend on the spread
         * across its plane; count that direction as if it had the largest
         * spread (C + lambda_max a a^T, a the axis) so that a sample off
         * the plane gets no leverage (else the gate opens wide across the
         * plane and lets off-plane outliers in). Not in auto mode: there a
         * planar fit is often a sphere seen on a short arc, and the
         * leverage across the plane is what lets the sweeping stream in. */
        const float *a = r->axis.v;
        const float lmax = r->eigenvalues.v[2];
        int i, k;
        for (i = 0; i < 3; i++) {
            for (k = 0; k < 3; k++) {
                c.m[3 * i + k] += lmax * a[i] * a[k];
            }
        }
    }
    if (sfit_mat3_chol(&c, &l) != SFIT_OK) {
        return SFIT_E_DEGENERATE;
    }
    s = 1.0f / SFIT_SQRTF((float)(n - 1u));
    w[0] = s / l.m[0];
    w[1] = s / l.m[4];
    w[2] = s / l.m[8];
    w[3] = -l.m[3] * w[0] / l.m[4];
    w[5] = -l.m[7] * w[1] / l.m[8];
    w[4] = -(l.m[6] * w[0] + l.m[7] * w[3]) / l.m[8];
    for (j = 0; j < 6; j++) {
        if (!sfit_i_isfinite(w[j])) {
            return SFIT_E_DEGENERATE;
        }
    }
    memcpy(g->lw, w, sizeof g->lw);
    g->mean = mean;
    g->inv_n = 1.0f / (float)n;
    return SFIT_OK;
}

/* h = 1/N + |W (x - m)|^2, at most SFIT_GATE_H_MAX (also for an overflow). */
static float prv_h(const sfit_gate_t *g, const sfit_vec3_t *x)
{
    const float *w = g->lw;
    const float d0 = x->v[0] - g->mean.v[0], d1 = x->v[1] - g->mean.v[1],
                d2 = x->v[2] - g->mean.v[2];
    const float y0 = w[0] * d0;
    const float y1 = w[3] * d0 + w[1] * d1;
    const float y2 = w[4] * d0 + w[5] * d1 + w[2] * d2;
    const float h = g->inv_n + (y0 * y0 + y1 * y1 + y2 * y2);
    return (h <= SFIT_GATE_H_MAX) ? h : SFIT_GATE_H_MAX;
}

/* Start gating from the current fit: reset the window. */
static void prv_set_fit(sfit_gate_t *g, const sfit_result_t *r, const sfit_moments_t *m)
{
    if (prv_leverage(g, r, m) != SFIT_OK) {
        memset(g->lw, 0, sizeof g->lw);
        g->inv_n = 0.0f;
    }
    g->center = r->center;
    g->radius = r->radius;
    g->phase = 2u;
    g->ws1 = 0.0f;
    g->ws2 = 0.0f;
    g->wn = 0u;
    g->since = 0u;
    g->wrej = 0u;
}

/* Fit the kept buffer samples and take every residual. */
static sfit_status_t prv_fit_keep(const sfit_gate_t *g, const uint8_t *keep, sfit_moments_t *m,
                                  sfit_result_t *fit, float *res)
{
    uint32_t i;
    sfit_status_t st;
    prv_buffer_moments(g, keep, m);
    st = sfit_fit_moments(m, &g->cfg.fit, fit);
    if (st != SFIT_OK) {
        return st;
    }
    for (i = 0u; i < g->nwarm; i++) {
        res[i] = prv_resid(&g->warm[i], &fit->center, fit->radius);
    }
    return SFIT_OK;
}

/* |res - off| of every buffered residual into g->wtmp, sorted; returns
 * their median. */
static float prv_abs_dev(sfit_gate_t *g, float off)
{
    uint32_t i;
    for (i = 0u; i < g->nwarm; i++) {
        g->wtmp[i] = SFIT_FABSF(g->wres[i] - off);
    }
    return prv_median(g->wtmp, g->nwarm); /* sorts wtmp */
}

/* Keep the buffered samples with |res - off| <= cut (g->wkeep); returns
 * how many. */
static uint32_t prv_keep_within(sfit_gate_t *g, float off, float cut)
{
    uint32_t i, nk = 0u;
    for (i = 0u; i < g->nwarm; i++) {
        g->wkeep[i] = (SFIT_FABSF(g->wres[i] - off) <= cut) ? 1u : 0u;
        nk += g->wkeep[i];
    }
    return nk;
}

/* One least-trimmed-squares start: the interleaved subset s of `starts`,
 * then SFIT_GATE_CSTEPS concentration steps keeping the h smallest
 * residuals. Leaves the final subset in g->wkeep; returns SFIT_OK with its
 * trimmed score when every fit succeeded, else the failed fit's status. */
static sfit_status_t prv_lts_start(sfit_gate_t *g, uint32_t s, uint32_t starts, uint32_t h,
                                   float *score)
{
    sfit_moments_t m;
    sfit_result_t fit;
    uint32_t i;
    int step;
    sfit_status_t st;

    for (i = 0u; i < g->nwarm; i++) {
        g->wkeep[i] = (starts == 1u || i % starts == s) ? 1u : 0u;
    }
    for (step = 0; step <= SFIT_GATE_CSTEPS; step++) {
        st = prv_fit_keep(g, g->wkeep, &m, &fit, g->wres);
        if (st != SFIT_OK) {
            return st;
        }
        (void)prv_abs_dev(g, 0.0f);
        *score = 0.0f;
        for (i = 0u; i < h; i++) {
            *score += g->wtmp[i] * g->wtmp[i];
        }
        if (step == SFIT_GATE_CSTEPS) {
            break;
        }
        (void)prv_keep_within(g, 0.0f, g->wtmp[h - 1u]);
    }
    return SFIT_OK;
}

/* k-sigma cut around the best trimmed fit (subset g->wbest), with the MAD
 * scale over all buffered samples; refits the kept samples into m / fit
 * and leaves the kept set in g->wkeep and its size in *nk. */
static sfit_status_t prv_ksigma_cut(sfit_gate_t *g, sfit_moments_t *m, sfit_result_t *fit,
                                    uint32_t *nk)
{
    float med, sr;
    sfit_status_t st = prv_fit_keep(g, g->wbest, m, fit, g->wres);

    if (st != SFIT_OK) {
        return st;
    }
    memcpy(g->wtmp, g->wres, g->nwarm * sizeof g->wres[0]);
    med = prv_median(g->wtmp, g->nwarm);
    sr = SFIT_GATE_MAD_SIGMA * prv_abs_dev(g, med);
    if (sr * sr < g->cfg.noise_var) {
        sr = SFIT_SQRTF(g->cfg.noise_var);
    }
    if (sr * sr < prv_floor(fit->radius)) {
        sr = SFIT_SQRTF(prv_floor(fit->radius));
    }
    *nk = prv_keep_within(g, med, g->cfg.k * sr);
    return (*nk > SFIT_MIN_SAMPLES) ? prv_fit_keep(g, g->wkeep, m, fit, g->wres) : SFIT_E_TOO_FEW;
}

/* No fit yet: accept the buffer ungated until a refresh succeeds. */
static sfit_status_t prv_warm_fail(sfit_gate_t *g, sfit_status_t st)
{
    uint32_t i;
    (void)sfit_moments_init(&g->acc);
    for (i = 0u; i < g->nwarm; i++) {
        (void)sfit_moments_add(&g->acc, &g->warm[i]);
    }
    g->nwarm = 0u;
    g->phase = 1u;
    g->since = 0u;
    return st;
}

/* Robust start on the warm-up buffer (see the header): least trimmed
 * squares from SFIT_GATE_STARTS interleaved subsets with
 * SFIT_GATE_CSTEPS concentration steps each, then a k-sigma cut with the
 * MAD scale of the best fit. Every fit has at least SFIT_MIN_SAMPLES
 * samples: fewer subsets when they would be smaller (an early refresh, or
 * SFIT_MIN_SAMPLES above 8), and the trimmed set h never below it. When no
 * start can be fitted, the status of the last failed fit (e.g. degenerate
 * samples) is returned. */
static sfit_status_t prv_warm_start(sfit_gate_t *g)
{
    const uint32_t nw = g->nwarm;
    const uint32_t h = ((3u * nw) / 4u < SFIT_MIN_SAMPLES) ? SFIT_MIN_SAMPLES : (3u * nw) / 4u;
    const uint32_t most = nw / SFIT_MIN_SAMPLES; /* subsets of >= SFIT_MIN_SAMPLES samples */
    const uint32_t starts = (nw < 4u * (SFIT_MIN_SAMPLES + 2u)) ? 1u
                            : (most < SFIT_GATE_STARTS)          ? most
                                                                 : SFIT_GATE_STARTS;
    const uint8_t *const keep = g->wkeep;
    const float *const res = g->wres;
    sfit_moments_t m;
    sfit_result_t fit;
    uint32_t i, s, nk = 0u, dropped = 0u;
    float best_score = -1.0f;
    int found = 0;
    sfit_status_t st = SFIT_E_TOO_FEW, fail = SFIT_E_TOO_FEW;

    for (s = 0u; s < starts; s++) {
        float score = 0.0f;
        st = prv_lts_start(g, s, starts, h, &score);
        if (st != SFIT_OK) {
            fail = st;
        } else if (!found || score < best_score) {
            found = 1;
            best_score = score;
            memcpy(g->wbest, g->wkeep, nw);
        } else {
            /* a worse start */
        }
    }
    st = found ? prv_ksigma_cut(g, &m, &fit, &nk) : fail;
    if (st != SFIT_OK) {
        return prv_warm_fail(g, st);
    }
    for (i = 0u; i < nw; i++) {
        dropped += (keep[i] != 0u) ? 0u : 1u;
    }
    g->acc = m;
    g->outliers += dropped;
    prv_set_fit(g, &fit, &g->acc);
    if (g->cfg.noise_var > 0.0f) {
        g->var = g->cfg.noise_var;
    } else {
        float s1 = 0.0f, s2 = 0.0f, v;
        for (i = 0u; i < nw; i++) {
            if (keep[i] != 0u) {
                s1 += res[i];
                s2 += res[i] * res[i];
            }
        }
        v = (s2 - s1 * s1 / (float)nk) / (float)(nk - 4u);
        g->var = (v > prv_floor(fit.radius) && v <= SFIT_GATE_VAR_MAX) ? v
                                                                       : prv_floor(fit.radius);
    }
    g->nwarm = 0u;
    return SFIT_OK;
}

sfit_status_t sfit_gate_refresh(sfit_gate_t *g)
{
    sfit_result_t fit;
    sfit_status_t st;
    if (g == NULL || !prv_state_ok(g)) {
        return SFIT_E_ARG;
    }
    if (g->phase == 0u) {
        if (g->nwarm < SFIT_MIN_SAMPLES + 1u) {
            return SFIT_E_TOO_FEW;
        }
        return prv_warm_start(g);
    }
    st = sfit_fit_moments(&g->acc, &g->cfg.fit, &fit);
    if (st != SFIT_OK) {
        g->since = 0u;
        g->wrej = 0u;
        return st;
    }
    if (g->since > 0u && (uint64_t)g->wrej * 100u > (uint64_t)g->since * SFIT_GATE_MAX_REJECT_PCT) {
        /* Rejecting too much: the noise level is not credible. Widen, but
         * never past sigma = r (a gate k r wide accepts every sample within
         * (k + 1) r of the centre): sigma^2 stays finite. */
        const float r2 = fit.radius * fit.radius;
        const float vmax = (r2 < SFIT_GATE_VAR_MAX) ? r2 : SFIT_GATE_VAR_MAX;
        const float v4 = 4.0f * g->var;
        g->var = (v4 < vmax) ? v4 : ((g->var > vmax) ? g->var : vmax);
    } else if (g->cfg.noise_var > 0.0f) {
        g->var = g->cfg.noise_var;
    } else if (g->wn >= SFIT_GATE_MIN_WINDOW) {
        const float v = g->ws2 / (float)g->wn;
        g->var = (v > prv_floor(fit.radius) && v <= SFIT_GATE_VAR_MAX) ? v
                                                                       : prv_floor(fit.radius);
    } else {
        /* keep the previous sigma^2 (0 = not known yet: ungated window) */
    }
    prv_set_fit(g, &fit, &g->acc);
    return SFIT_OK;
}

/* A sample was judged: count it, refresh when due, report the verdict. */
static sfit_status_t prv_judged(sfit_gate_t *g, bool *accepted, bool verdict)
{
    g->since++;
    if (g->cfg.refresh != 0u && g->since >= g->cfg.refresh) {
        (void)sfit_gate_refresh(g);
    }
    if (accepted != NULL) {
        *accepted = verdict;
    }
    return SFIT_OK;
}

sfit_status_t sfit_gate_add(sfit_gate_t *g, const sfit_vec3_t *x, bool *accepted)
{
    float e = 0.0f, h1 = 1.0f;
    sfit_status_t st = sfit_i_check_add(g, x);
    if (st != SFIT_OK || !prv_index_ok(g)) {
        return (st != SFIT_OK) ? st : SFIT_E_ARG;
    }
    if (g->phase == 0u) {
        g->warm[g->nwarm++] = *x;
        if (g->nwarm == (uint32_t)SFIT_GATE_WARMUP) {
            (void)prv_warm_start(g);
        }
        if (accepted != NULL) {
            *accepted = true;
        }
        return SFIT_OK;
    }
    if (g->phase == 2u) {
        e = prv_resid(x, &g->center, g->radius);
        h1 = 1.0f + prv_h(g, x);
        if (g->var > 0.0f && e * e > g->cfg.k * g->cfg.k * g->var * h1) {
            if (g->outliers == UINT32_MAX) {
                return SFIT_E_RANGE;
            }
            g->outliers++;
            g->wrej++;
            return prv_judged(g, accepted, false);
        }
    }
    st = sfit_moments_add(&g->acc, x);
    if (st != SFIT_OK) {
        return st; /* accumulator unchanged, gate untouched */
    }
    if (g->phase == 2u && g->wn < UINT32_MAX) {
        const float ws2 = g->ws2 + e * e / h1;
        if (sfit_i_isfinite(ws2)) {
            g->ws2 = ws2;
            g->wn++;
        }
    }
    return prv_judged(g, accepted, true);
}

sfit_status_t sfit_gate_fit(const sfit_gate_t *g, sfit_result_t *out)
{
    if (g == NULL || out == NULL || !prv_state_ok(g)) {
        return SFIT_E_ARG;
    }
    if (g->phase == 0u) {
        sfit_moments_t m;
        prv_buffer_moments(g, NULL, &m);
        return sfit_fit_moments(&m, &g->cfg.fit, out);
    }
    return sfit_fit_moments(&g->acc, &g->cfg.fit, out);
}

sfit_status_t sfit_gate_stats(const sfit_gate_t *g, sfit_gate_stats_t *out)
{
    if (g == NULL || out == NULL || !prv_state_ok(g)) {
        return SFIT_E_ARG;
    }
    out->accepted = (g->phase == 0u) ? g->nwarm : sfit_moments_count(&g->acc);
    out->outliers = g->outliers;
    out->gated = (g->phase == 2u && g->var > 0.0f);
    out->noise_var = (g->phase == 2u) ? g->var : 0.0f;
    return SFIT_OK;
}

const sfit_moments_t *sfit_gate_moments(const sfit_gate_t *g)
{
    return (g == NULL || g->phase == 0u || !prv_state_ok(g)) ? NULL : &g->acc;
}
