/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_multi.c
 * @brief MGDK / unbiased MGDK: the common centre of several markers.
 *
 * Implementation notes
 * --------------------
 * Derivation (see sfit_multi.h): for marker p with mean m_p and y = x - m_p,
 *   |x - c|^2 = |y|^2 - 2 y^T (c - m_p) + |c - m_p|^2,
 * so with r_p^2 set to its optimum mean_i |x_pi - c|^2 the residuals are
 * e_i = (|y_i|^2 - mean |y|^2) - 2 y_i^T (c - m_p) and
 *   sum_i e_i^2 = const - 4 (N_p-1) (c - m_p)^T S_p
 *                       + 4 (N_p-1) (c - m_p)^T C_p (c - m_p).
 * Its gradient is 4 (N_p-1) (2 C_p (c - m_p) - S_p) (eq. 219 without the
 * N_p - 1); weighting marker p by w_p / (N_p - 1) and summing gives
 *   A (c - o) = b,  A = sum w_p C'_p,  b = sum w_p (C'_p (m_p - o) + S_p/2)
 * for any reference point o. o is the first used marker's mean, held as
 * origin_1 + d_1; m_p - o = (origin_p - origin_1) + (d_p - d_1) is small.
 *
 * The system is handed to sfit_i_solve() as c = sum w_p C_p and
 * sigma = (sum w_p) Sigma_hat, exactly the single-marker problem when
 * M = 1 (w_1 = 1, m_1 - o = 0): the centre origin_1 + (d_1 + w) and the
 * radius are then computed by the same float operations as sfit_fit_moments()
 * in sphere mode.
 *
 * Planar: the pseudo-inverse gives the solution with no component along
 * the axis a relative to o; the centre is moved along a to the weighted
 * mean of the marker means (a^T (mbar - o)). Radii use the in-plane parts:
 * tr C'_p - a^T C'_p a and |P (m_p - c)|^2.
 *
 * No storage per marker: the accumulators are read in three passes
 * (counts, sums, radii), each sfit_i_moments_total() being O(1).
 */
#include "sfit/sfit_multi.h"

#include <string.h>

#include "sfit_solve.h"

const sfit_multi_cfg_t sfit_multi_cfg_default = {
    .fit = {.mode = SFIT_MODE_AUTO, .noise = SFIT_NOISE_NONE, .planar_ratio = 0.0f},
    .weight = SFIT_MULTI_WEIGHT_EQUAL};

/* The markers of one call: the reference point o = origin_ref + d_ref
 * (the first used marker's mean), the configuration's Sigma_hat and the
 * per-marker noise models (NULL: Sigma_hat for every marker). */
typedef struct prv_set {
    const sfit_moments_t *markers;
    size_t count;
    const float *origin_ref; /* NULL until a used marker is seen */
    float d_ref[3];
    sfit_mat3_t sg_cfg;
    const sfit_multi_noise_t *noise;
} prv_set_t;

static void prv_set_init(prv_set_t *set, const sfit_moments_t *markers, size_t count,
                         const sfit_multi_cfg_t *cfg, const sfit_multi_noise_t *noise)
{
    memset(set, 0, sizeof *set);
    set->markers = markers;
    set->count = count;
    set->noise = noise;
    sfit_i_sigma(cfg->fit.noise, cfg->fit.noise_var, &cfg->fit.noise_cov, &set->sg_cfg);
}

/* o := the mean of marker p (its total t). */
static void prv_set_ref(prv_set_t *set, size_t p, const sfit_cmom_t *t)
{
    int i;
    set->origin_ref = set->markers[p].origin;
    for (i = 0; i < 3; i++) {
        set->d_ref[i] = t->d[i];
    }
}

/* Per-marker quantities relative to the reference o. */
typedef struct prv_marker {
    sfit_mat3_t c; /* C_p */
    float s2[3];   /* S_p / 2 */
    float dm[3];   /* m_p - o */
    uint32_t n;
} prv_marker_t;

static void prv_marker(const sfit_moments_t *m, const prv_set_t *set, prv_marker_t *pm)
{
    sfit_cmom_t t;
    int i;
    sfit_i_moments_total(m, &t);
    sfit_i_cmom_system(&t, &pm->c, pm->s2);
    for (i = 0; i < 3; i++) {
        pm->dm[i] = (m->origin[i] - set->origin_ref[i]) + (t.d[i] - set->d_ref[i]);
    }
    pm->n = t.n;
}

/* 1 with pm filled when the marker has enough samples to be used. */
static int prv_used(const sfit_moments_t *m, const prv_set_t *set, prv_marker_t *pm)
{
    if (sfit_moments_count(m) < SFIT_MIN_SAMPLES) {
        return 0;
    }
    prv_marker(m, set, pm);
    return 1;
}


/* The next used marker at or after *p, with pm filled; 0 when none is left. */
static int prv_next(const prv_set_t *set, size_t *p, prv_marker_t *pm)
{
    while (*p < set->count) {
        if (prv_used(&set->markers[*p], set, pm)) {
            return 1;
        }
        (*p)++;
    }
    return 0;
}

/* Noise of marker p: Sigma_p (full) and t_p/2; the configuration's
 * Sigma_hat and no skew when there is no per-marker model. */
static const sfit_mat3_t *prv_noise(const prv_set_t *set, size_t p, sfit_mat3_t *buf,
                                    float half_skew[3])
{
    const sfit_multi_noise_t *const noise = set->noise;
    int i;
    if (noise == NULL) {
        for (i = 0; i < 3; i++) {
            half_skew[i] = 0.0f; /* not read; defined for every path */
        }
        return &set->sg_cfg;
    }
    sfit_i_sigma(SFIT_NOISE_COV, 0.0f, &noise[p].cov, buf);
    for (i = 0; i < 3; i++) {
        half_skew[i] = 0.5f * noise[p].skew.v[i];
    }
    return buf;
}

/* r_p^2 of one marker for the centre offset wc (= c - o), in the plane
 * normal to axis when axis is not NULL. Turns pm->c into C'_p = C_p - sg. */
static float prv_radius2(prv_marker_t *pm, const sfit_mat3_t *sg, const float wc[3],
                         const float *axis)
{
    float *const cp = pm->c.m;
    float e[3], tr;
    int i;
    for (i = 0; i < 9; i++) {
        cp[i] -= sg->m[i];
    }
    tr = cp[0] + cp[4] + cp[8];
    for (i = 0; i < 3; i++) {
        e[i] = pm->dm[i] - wc[i];
    }
    if (axis != NULL) {
        float ca[3], ea;
        for (i = 0; i < 3; i++) {
            ca[i] = sfit_i_dot3(&cp[3 * i], axis);
        }
        tr -= sfit_i_dot3(axis, ca);
        ea = sfit_i_dot3(e, axis);
        for (i = 0; i < 3; i++) {
            e[i] -= ea * axis[i];
        }
    }
    return ((float)(pm->n - 1u) / (float)pm->n) * tr + sfit_i_dot3(e, e);
}

/* What the radius passes read. */
typedef struct prv_radii {
    const prv_set_t *set;
    const float *wc;
    const sfit_i_solution_t *sol;
} prv_radii_t;

/* The radius of every marker (0 for an unused one): checked (out NULL:
 * SFIT_E_NOT_POSDEF for r_p^2 <= 0, SFIT_E_RANGE when not finite) or
 * written to out (after a successful check). */
static sfit_status_t prv_radii(const prv_radii_t *rc, float *out)
{
    size_t p;
    for (p = 0u; p < rc->set->count; p++) {
        prv_marker_t pm;
        sfit_mat3_t sg;
        float half_skew[3], r2 = 0.0f;
        if (prv_used(&rc->set->markers[p], rc->set, &pm)) {
            r2 = prv_radius2(&pm, prv_noise(rc->set, p, &sg, half_skew), rc->wc,
                             (rc->sol->mode == SFIT_MODE_PLANAR) ? rc->sol->axis.v : NULL);
            if (out == NULL && !(r2 > 0.0f)) {
                return SFIT_E_NOT_POSDEF;
            }
            if (out == NULL && !sfit_i_isfinite(r2)) {
                return SFIT_E_RANGE;
            }
        }
        if (out != NULL) {
            out[p] = (r2 > 0.0f) ? SFIT_SQRTF(r2) : 0.0f;
        }
    }
    return SFIT_OK;
}

/* The fit with Sigma_hat from cfg (noise NULL) or one noise model per
 * marker (validated by the caller). */
static sfit_status_t prv_fit(const sfit_moments_t *markers, size_t count,
                             const sfit_multi_cfg_t *cfg, const sfit_multi_noise_t *noise,
                             sfit_multi_result_t *out, float *radii)
{
    sfit_i_system_t sys;
    sfit_i_solution_t sol;
    sfit_multi_result_t r;
    prv_radii_t rc_radii;
    prv_set_t set;
    sfit_mat3_t sg, sg_sum;
    prv_marker_t pm;
    float half_skew[3];
    float wc[3], dbar[3] = {0.0f, 0.0f, 0.0f}, sw = 0.0f, scale = 0.0f;
    uint64_t n_total = 0u, sum_n1 = 0u;
    uint32_t used = 0u, skipped = 0u, flags = 0u;
    size_t p;
    int i;
    sfit_status_t st;

    if (count == 0u) {
        return SFIT_E_TOO_FEW;
    }
    prv_set_init(&set, markers, count, cfg, noise);

    /* Pass 1: which markers are used, counts, reference point, scale. */
    for (p = 0u; p < count; p++) {
        const uint32_t n = sfit_moments_count(&markers[p]);
        sfit_cmom_t t;
        float sc;
        if (n < SFIT_MIN_SAMPLES) {
            skipped++;
            continue;
        }
        sfit_i_moments_total(&markers[p], &t);
        if (set.origin_ref == NULL) {
            prv_set_ref(&set, p, &t);
        }
        sc = sfit_i_coincident_scale(markers[p].origin, t.d);
        if (sc > scale) {
            scale = sc;
        }
        if (n < SFIT_FEW_SAMPLES) {
            flags |= (uint32_t)SFIT_FLAG_FEW_SAMPLES;
        }
        used++;
        n_total += n;
        sum_n1 += (uint64_t)(n - 1u);
    }
    if (used == 0u) {
        return SFIT_E_TOO_FEW;
    }
    if (n_total > (uint64_t)UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    if (skipped > 0u) {
        flags |= (uint32_t)SFIT_MULTI_FLAG_SKIPPED;
    }

    /* Pass 2: A = sum w_p C_p, b = sum w_p (C'_p (m_p - o) + S_p/2). */
    memset(&sys, 0, sizeof sys);
    memset(&sg_sum, 0, sizeof sg_sum);
    for (p = 0u; prv_next(&set, &p, &pm); p++) {
        const sfit_mat3_t *sgp;
        float w;
        w = sfit_i_multi_weight(cfg, pm.n, used, sum_n1);
        sw += w;
        sgp = prv_noise(&set, p, &sg, half_skew);
        for (i = 0; i < 9; i++) {
            sys.ms.c.m[i] += w * pm.c.m[i];
        }
        if (noise != NULL) { /* one Sigma_hat: (sum w_p) Sigma_hat below */
            for (i = 0; i < 9; i++) {
                sg_sum.m[i] += w * sgp->m[i];
            }
            for (i = 0; i < 3; i++) {
                pm.s2[i] -= half_skew[i];
            }
        }
        for (i = 0; i < 3; i++) {
            const float *ci = &pm.c.m[3 * i];
            const float *si = &sgp->m[3 * i];
            const float t = pm.s2[i] + ((ci[0] - si[0]) * pm.dm[0] + (ci[1] - si[1]) * pm.dm[1]
                                        + (ci[2] - si[2]) * pm.dm[2]);
            sys.ms.rhs.v[i] += w * t;
            dbar[i] += w * pm.dm[i];
        }
    }
    for (i = 0; i < 9; i++) {
        /* one Sigma_hat: (sum w_p) Sigma_hat, as the single-marker fit */
        sg_sum.m[i] = (noise != NULL) ? sg_sum.m[i] : sw * set.sg_cfg.m[i];
    }
    sys.sigma.m = &sg_sum;
    sys.noisy = (noise != NULL || cfg->fit.noise != SFIT_NOISE_NONE) ? (int)SFIT_NOISE_COV
                                                                     : (int)SFIT_NOISE_NONE;
    sys.scale = scale;

    st = sfit_i_solve(&sys, cfg->fit.mode, cfg->fit.planar_ratio, &sol);
    if (st != SFIT_OK) {
        return st;
    }
    for (i = 0; i < 3; i++) {
        wc[i] = sol.w.v[i];
    }
    if (sol.mode == SFIT_MODE_PLANAR) {
        /* Along the axis: the weighted mean of the marker means (w itself
         * has no axial component beyond rounding: it is a combination of
         * the two kept eigenvectors). */
        float k;
        for (i = 0; i < 3; i++) {
            dbar[i] /= sw;
        }
        k = sfit_i_dot3(sol.axis.v, dbar);
        for (i = 0; i < 3; i++) {
            wc[i] += k * sol.axis.v[i];
        }
    }

    /* Pass 3: every radius must be real before anything is written. */
    {
        const prv_radii_t rc = {&set, wc, &sol};
        st = prv_radii(&rc, NULL);
        if (st != SFIT_OK) {
            return st;
        }
        if (radii != NULL) { /* pass 4 (after the centre's check below) */
            rc_radii = rc;
        }
    }

    memset(&r, 0, sizeof r);
    for (i = 0; i < 3; i++) {
        r.center.v[i] = set.origin_ref[i] + (set.d_ref[i] + wc[i]);
    }
    if (!sfit_i_finite3(r.center.v)) {
        return SFIT_E_RANGE;
    }
    r.n_total = (uint32_t)n_total;
    r.markers = used;
    r.skipped = skipped;
    sfit_i_solution_out(&sol, &r.eigenvalues, &r.axis, &r.leontief_ratio, &r.trust_ratio);
    r.flags = (uint32_t)sol.flags | flags | sfit_i_cov_limit(r.trust_ratio, r.n_total);
    r.method = sys.noisy ? SFIT_METHOD_UGDK : SFIT_METHOD_GDKE;
    r.mode = sol.mode;

    /* Pass 4: write the radii (all checked above). */
    if (radii != NULL) {
        (void)prv_radii(&rc_radii, radii);
    }
    *out = r;
    return SFIT_OK;
}

/* Arguments shared by the entry points (*cfg NULL: the defaults): SFIT_OK
 * or SFIT_E_ARG. */
static sfit_status_t prv_check(const sfit_moments_t *markers, const sfit_multi_cfg_t **cfg,
                               const sfit_multi_result_t *out)
{
    if (*cfg == NULL) {
        *cfg = &sfit_multi_cfg_default;
    }
    if (markers == NULL || out == NULL || sfit_i_check_multi_cfg(*cfg) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    return SFIT_OK;
}

sfit_status_t sfit_multi_fit(const sfit_moments_t *markers, size_t count,
                               const sfit_multi_cfg_t *cfg, sfit_multi_result_t *out,
                               float *radii)
{
    return (prv_check(markers, &cfg, out) != SFIT_OK)
               ? SFIT_E_ARG
               : prv_fit(markers, count, cfg, NULL, out, radii);
}

sfit_status_t sfit_multi_fit_noise(const sfit_moments_t *markers, size_t count,
                                   const sfit_multi_cfg_t *cfg, const sfit_multi_noise_t *noise,
                                   sfit_multi_result_t *out, float *radii)
{
    size_t p;
    if (noise == NULL || prv_check(markers, &cfg, out) != SFIT_OK
        || cfg->fit.noise != SFIT_NOISE_NONE) {
        return SFIT_E_ARG;
    }
    for (p = 0u; p < count; p++) {
        if (sfit_i_check_noise(SFIT_NOISE_COV, 0.0f, &noise[p].cov) != SFIT_OK
            || !sfit_i_finite3(noise[p].skew.v)) {
            return SFIT_E_ARG;
        }
    }
    return prv_fit(markers, count, cfg, noise, out, radii);
}

sfit_status_t sfit_multi_center_cov(const sfit_moments_t *markers, size_t count,
                                    const sfit_multi_cfg_t *cfg, const sfit_multi_result_t *res,
                                    float noise_var, sfit_mat3_t *cov)
{
    prv_set_t set;
    sfit_mat3_t a, m;
    prv_marker_t pm;
    float co[3];
    const float v75 = 7.5f * noise_var;
    uint64_t sum_n1 = 0u;
    uint32_t used = 0u;
    size_t p;
    int i;

    if (res == NULL || cov == NULL || prv_check(markers, &cfg, res) != SFIT_OK) {
        return SFIT_E_ARG;
    }
    if (!sfit_i_isfinite(noise_var) || !sfit_i_finite3(res->center.v)
        || !sfit_i_finite3(res->axis.v)
        || (res->mode != SFIT_MODE_SPHERE && res->mode != SFIT_MODE_PLANAR)) {
        return SFIT_E_NONFINITE;
    }
    if (noise_var < 0.0f) {
        return SFIT_E_ARG;
    }
    used = sfit_i_multi_used(markers, count, &sum_n1);
    prv_set_init(&set, markers, count, cfg, NULL);
    for (p = 0u; p < count && set.origin_ref == NULL; p++) { /* the first used marker */
        if (sfit_moments_count(&markers[p]) >= SFIT_MIN_SAMPLES) {
            sfit_cmom_t tot;
            sfit_i_moments_total(&markers[p], &tot);
            prv_set_ref(&set, p, &tot);
        }
    }
    if (set.origin_ref == NULL) { /* no marker has SFIT_MIN_SAMPLES samples (used == 0) */
        return SFIT_E_TOO_FEW;
    }
    for (i = 0; i < 3; i++) { /* c - o */
        co[i] = (res->center.v[i] - set.origin_ref[i]) - set.d_ref[i];
    }
    /* A = sum w_p C'_p, M / sigma^2 = sum w_p^2 [(r_p^2 + 7.5 sigma^2) / (N_p - 1) C'_p
     *   + sigma^2 N_p / (N_p - 1)^2 (r_p^2 I + a_p a_p^T)], a_p = m_p - c: the
     * second-order term of sfit_uncert_moments() (known sigma^2) per marker */
    memset(&a, 0, sizeof a);
    memset(&m, 0, sizeof m);
    for (p = 0u; prv_next(&set, &p, &pm); p++) {
        const float w = sfit_i_multi_weight(cfg, pm.n, used, sum_n1);
        const float r2 = prv_radius2(&pm, &set.sg_cfg, co, NULL); /* pm.c is C'_p now */
        const float n1 = (float)(pm.n - 1u);
        const float ww = w * w / n1;
        const float f = ww * (r2 + v75);
        const float g = ww * ((float)pm.n / n1) * noise_var;
        float ap[3], ga[3];
        int j;
        for (i = 0; i < 3; i++) {
            ap[i] = pm.dm[i] - co[i];
            ga[i] = g * ap[i];
        }
        for (i = 0; i < 3; i++) { /* lower triangles (C'_p is symmetric) */
            for (j = 0; j <= i; j++) {
                a.m[3 * i + j] += w * pm.c.m[3 * i + j];
                m.m[3 * i + j] += f * pm.c.m[3 * i + j] + ga[i] * ap[j];
            }
            m.m[4 * i] += g * r2;
        }
    }
    sfit_i_sym_full(&a, a.m);
    sfit_i_sym_full(&m, m.m);
    return sfit_i_center_cov(&a, res->mode, &res->axis, &m, noise_var, cov);
}
