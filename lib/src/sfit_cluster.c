/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_cluster.c
 * @brief Rigid cluster pose (Kabsch with the reflection correction) on the
 * 3x3 Jacobi kernel.
 *
 * Implementation notes
 * --------------------
 * Least squares: minimise sum_i |R p_i + t - x_i|^2. For any R the best t
 * puts the template centroid on the measured centroid, t = x_bar - R p_bar;
 * with the centred points p_i, q_i the cost is
 *   sum |p_i|^2 + sum |q_i|^2 - 2 tr(R^T H),   H = sum q_i p_i^T,
 * so R maximises tr(R^T H). With the SVD H = U S V^T (s1 >= s2 >= s3 >= 0)
 * the maximum over proper rotations is R = U diag(1, 1, d) V^T,
 * d = det(U) det(V) (Umeyama 1991). Writing U' = [u1 u2 u1 x u2] (det +1)
 * and V' = [v1 v2 v1 x v2] (det +1) this is exactly R = U' V'^T:
 *   R = u1 v1^T + u2 v2^T + (u1 x u2)(v1 x v2)^T,
 * whatever the sign of det H, and s3 is never used. v1, v2 are the two
 * largest eigen-directions of H^T H (Jacobi), u_k = H v_k / s_k; u2 is
 * re-orthogonalised against u1 (Gram-Schmidt) so U' is orthonormal to
 * rounding. H is divided by its largest entry first: H^T H then lies in
 * [0, 9 M^2] whatever the units, and cannot overflow.
 *
 * Float: the sums run over differences from the first seen marker (exact
 * for nearby markers however far from the origin), so the centred points
 * carry the markers' relative precision, not that of 3 m.
 *
 * Calls into other modules are gathered in prv_eig() (sfit_mat3) and the
 * internal sample check (sfit_float.h).
 */
#include "sfit/sfit_cluster.h"

#include <string.h>

#include "sfit/sfit_mat3.h"
#include "sfit_float.h"

/* ---- the only calls into other modules ---- */
static sfit_status_t prv_eig(const sfit_mat3_t *a, sfit_vec3_t *w, sfit_mat3_t *v)
{
    return sfit_mat3_eig_sym(a, w, v);
}

static sfit_status_t prv_chol(const sfit_mat3_t *a, sfit_mat3_t *l)
{
    return sfit_mat3_chol(a, l);
}

static sfit_status_t prv_chol_solve(const sfit_mat3_t *l, const sfit_vec3_t *b, sfit_vec3_t *x)
{
    return sfit_mat3_chol_solve(l, b, x);
}

static int prv_count_ok(size_t count)
{
    return count >= 3u && count <= (size_t)SFIT_CLUSTER_MAX_MARKERS;
}

/* Centroid of the points flagged in `seen` as ref + d (ref = first seen). */
static void prv_centroid(const sfit_vec3_t *x, size_t count, const uint8_t *seen, float ref[3],
                         float d[3])
{
    float s[3] = {0.0f, 0.0f, 0.0f};
    float n = 0.0f;
    size_t i;
    int k, have = 0;
    for (i = 0; i < count; i++) {
        if (seen[i] == 0u) {
            continue;
        }
        if (!have) {
            for (k = 0; k < 3; k++) {
                ref[k] = x[i].v[k];
            }
            have = 1;
        }
        for (k = 0; k < 3; k++) {
            s[k] += x[i].v[k] - ref[k];
        }
        n += 1.0f;
    }
    for (k = 0; k < 3; k++) {
        d[k] = s[k] / n;
    }
}

/* Centred point: (x - ref) - d. */
static void prv_centred(const float x[3], const float ref[3], const float d[3], float out[3])
{
    int k;
    for (k = 0; k < 3; k++) {
        out[k] = (x[k] - ref[k]) - d[k];
    }
}

/* The seen markers of a frame and their centroids (ref + d). */
typedef struct prv_frame {
    const sfit_vec3_t *meas, *tpl;
    const uint8_t *seen;
    size_t count;
    const float *xr, *dx, *pr, *dp;
} prv_frame_t;

/* Over the seen markers, centred (q measured, p template): h = sum q p^T
 * (r NULL; returns 0), or the sum of |r p - q|^2 (h NULL). */
SFIT_INLINE float prv_pairs(const prv_frame_t *fr, const sfit_mat3_t *r, float h[9])
{
    float e2 = 0.0f;
    size_t i;
    int ii, jj;
    for (ii = 0; h != NULL && ii < 9; ii++) {
        h[ii] = 0.0f;
    }
    for (i = 0; i < fr->count; i++) {
        float p[3], q[3];
        if (fr->seen[i] == 0u) {
            continue;
        }
        prv_centred(fr->meas[i].v, fr->xr, fr->dx, q);
        prv_centred(fr->tpl[i].v, fr->pr, fr->dp, p);
        for (ii = 0; ii < 3; ii++) {
            if (r != NULL) {
                const float e = sfit_i_dot3(&r->m[3 * ii], p) - q[ii];
                e2 += e * e;
            }
            for (jj = 0; h != NULL && jj < 3; jj++) {
                h[3 * ii + jj] += q[ii] * p[jj];
            }
        }
    }
    return e2;
}

static void prv_cross(const float a[3], const float b[3], float c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}


/*
 * Collinearity / coincidence test of a symmetric 3x3 whose eigenvalues are
 * proportional to the singular values (power `pw` = 1) or their squares
 * (pw = 2) of the point spread: SFIT_OK or SFIT_E_DEGENERATE, or the
 * eigen-solver's status. Writes the eigenvectors when v is not NULL.
 */
static sfit_status_t prv_spread_check(const sfit_mat3_t *a, int pw, sfit_mat3_t *v)
{
    sfit_vec3_t w;
    float ratio = SFIT_CLUSTER_COLLINEAR_RATIO;
    sfit_status_t st = prv_eig(a, &w, v);
    if (st != SFIT_OK) {
        return st;
    }
    if (pw == 2) {
        ratio = ratio * ratio;
    }
    if (!(w.v[2] > 0.0f) || !(w.v[1] >= ratio * w.v[2])) {
        return SFIT_E_DEGENERATE;
    }
    return SFIT_OK;
}

/* Check every point (all must be finite) and centre them on their centroid
 * (shifted sums). Writes the centred points to out (may alias in). */
static sfit_status_t prv_centre_all(const sfit_vec3_t *in, size_t count, sfit_vec3_t *out)
{
    uint8_t seen[SFIT_CLUSTER_MAX_MARKERS];
    float ref[3], d[3];
    sfit_mat3_t sc;
    sfit_status_t st = SFIT_OK;
    size_t i;
    int k, l;

    memset(seen, 0, sizeof seen);
    for (i = 0; i < count; i++) {
        sfit_status_t si = sfit_i_check_sample(in[i].v);
        if (si == SFIT_E_NONFINITE) {
            return si;
        }
        if (si != SFIT_OK) {
            st = si;
        }
        seen[i] = 1u;
    }
    if (st != SFIT_OK) {
        return st;
    }
    prv_centroid(in, count, seen, ref, d);
    memset(&sc, 0, sizeof sc);
    for (i = 0; i < count; i++) {
        float p[3];
        prv_centred(in[i].v, ref, d, p);
        for (k = 0; k < 3; k++) {
            for (l = 0; l < 3; l++) {
                sc.m[3 * k + l] += p[k] * p[l];
            }
            out[i].v[k] = p[k];
        }
    }
    return prv_spread_check(&sc, 1, NULL);
}

/*
 * One Newton step on tr(R^T H) over rotations R = R0 exp([w]x): with
 * B = R0^T H, gradient g = (B32 - B23, B13 - B31, B21 - B12) and Hessian
 * tr(B) I - sym(B), w = (tr(B) I - sym(B))^-1 g, R = R0 (I + W + W^2/2)
 * (orthogonal to O(|w|^4)). R0 from H^T H carries the squared condition
 * (error ~ eps s1^2 / (s2 (s2 + s3))); the step brings it to
 * ~ eps s1 / (s2 + s3). Skipped when the Hessian is not positive definite
 * (an ambiguous optimum) or the step is not small.
 */
static void prv_refine(const float h[9], sfit_mat3_t *r)
{
    sfit_mat3_t b, hess, l, e, rn;
    sfit_vec3_t g, w;
    float tr, w2;
    int i, j, k;

    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            b.m[3 * i + j] = r->m[i] * h[j] + r->m[3 + i] * h[3 + j] + r->m[6 + i] * h[6 + j];
        }
    }
    g.v[0] = b.m[7] - b.m[5];
    g.v[1] = b.m[2] - b.m[6];
    g.v[2] = b.m[3] - b.m[1];
    tr = b.m[0] + b.m[4] + b.m[8];
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            hess.m[3 * i + j] = -0.5f * (b.m[3 * i + j] + b.m[3 * j + i]);
        }
        hess.m[4 * i] += tr;
    }
    if (prv_chol(&hess, &l) != SFIT_OK) {
        return;
    }
    if (prv_chol_solve(&l, &g, &w) != SFIT_OK) {
        return; /* not finite: no step */
    }
    w2 = sfit_i_dot3(w.v, w.v);
    if (!(w2 < 1e-2f)) {
        return;
    }
    /* E = I + W + W^2/2, W^2 = w w^T - |w|^2 I. */
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            e.m[3 * i + j] = 0.5f * w.v[i] * w.v[j];
        }
        e.m[4 * i] += 1.0f - 0.5f * w2;
    }
    e.m[1] -= w.v[2];
    e.m[2] += w.v[1];
    e.m[3] += w.v[2];
    e.m[5] -= w.v[0];
    e.m[6] -= w.v[1];
    e.m[7] += w.v[0];
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            float sum = 0.0f;
            for (k = 0; k < 3; k++) {
                sum += r->m[3 * i + k] * e.m[3 * k + j];
            }
            rn.m[3 * i + j] = sum;
        }
    }
    *r = rn;
}

/* A template from count points: validated (finite, in range, not
 * collinear), stored as given (centred = 0) or about their centroid. */
static sfit_status_t prv_store(sfit_cluster_t *cl, const sfit_vec3_t *pts, size_t count,
                               int centred)
{
    sfit_vec3_t tmp[SFIT_CLUSTER_MAX_MARKERS];
    const sfit_status_t st = (cl == NULL || pts == NULL || !prv_count_ok(count))
                                 ? SFIT_E_ARG
                                 : prv_centre_all(pts, count, tmp);
    size_t i;

    if (st != SFIT_OK) {
        return st;
    }
    memset(cl, 0, sizeof *cl);
    cl->count = (uint32_t)count;
    for (i = 0; i < count; i++) {
        cl->pos[i] = centred ? tmp[i] : pts[i];
    }
    return SFIT_OK;
}

sfit_status_t sfit_cluster_init(sfit_cluster_t *cl, const sfit_vec3_t *tpl, size_t count)
{
    return prv_store(cl, tpl, count, 0);
}

sfit_status_t sfit_cluster_from_frame(sfit_cluster_t *cl, const sfit_vec3_t *pts, size_t count)
{
    return prv_store(cl, pts, count, 1);
}

sfit_status_t sfit_cluster_from_frames(sfit_cluster_t *cl, const sfit_vec3_t *frames,
                                       size_t nframes, size_t count, size_t *used)
{
    sfit_cluster_t ref;
    sfit_vec3_t mean[SFIT_CLUSTER_MAX_MARKERS];
    float cnt[SFIT_CLUSTER_MAX_MARKERS];
    size_t f, f0 = 0, i, nused = 1;
    sfit_status_t st = SFIT_E_TOO_FEW;
    int k;

    if (cl == NULL || frames == NULL || nframes == 0u || !prv_count_ok(count)) {
        return SFIT_E_ARG;
    }
    /* Reference: the first complete, valid frame. */
    for (f = 0; f < nframes; f++) {
        st = sfit_cluster_from_frame(&ref, &frames[f * count], count);
        if (st == SFIT_OK || st == SFIT_E_NO_CONVERGENCE) {
            f0 = f;
            break;
        }
    }
    if (st != SFIT_OK) {
        return (st == SFIT_E_NO_CONVERGENCE) ? st : SFIT_E_TOO_FEW;
    }
    for (i = 0; i < count; i++) {
        mean[i] = ref.pos[i];
        cnt[i] = 1.0f;
    }
    /* Running means (mean += (x - mean)/n) in the reference's frame. */
    for (f = f0 + 1u; f < nframes; f++) {
        const sfit_vec3_t *fr = &frames[f * count];
        sfit_pose_t pose;
        if (sfit_cluster_register(&ref, fr, count, &pose, NULL) != SFIT_OK) {
            continue;
        }
        for (i = 0; i < count; i++) {
            sfit_vec3_t xs;
            if (sfit_i_has_nan3(fr[i].v)) {
                continue;
            }
            if (sfit_cluster_to_segment(&pose, &fr[i], &xs) != SFIT_OK) {
                continue; /* not reached: a registered pose, a finite sample */
            }
            cnt[i] += 1.0f;
            for (k = 0; k < 3; k++) {
                mean[i].v[k] += (xs.v[k] - mean[i].v[k]) / cnt[i];
            }
        }
        nused++;
    }
    /* Origin at the centroid of the averaged markers. */
    st = sfit_cluster_from_frame(&ref, mean, count);
    if (st != SFIT_OK) {
        return st;
    }
    *cl = ref;
    if (used != NULL) {
        *used = nused;
    }
    return SFIT_OK;
}

sfit_status_t sfit_cluster_register(const sfit_cluster_t *cl, const sfit_vec3_t *meas,
                                    size_t count, sfit_pose_t *pose, sfit_cluster_fit_t *fit)
{
    uint8_t seen[SFIT_CLUSTER_MAX_MARKERS];
    float xr[3], dx[3], pr[3], dp[3];
    prv_frame_t fr;
    float h[9], hmax, inv, e2;
    float v1[3], v2[3], v3[3], u1[3], u2[3], u3[3], a;
    sfit_mat3_t k, vv, r;
    sfit_vec3_t t;
    sfit_status_t st = SFIT_OK;
    size_t i, nseen = 0;
    int ii, jj;

    memset(seen, 0, sizeof seen);
    if (cl == NULL || meas == NULL || pose == NULL || !prv_count_ok(cl->count)
        || count != (size_t)cl->count) {
        return SFIT_E_ARG;
    }
    /* Seen markers: NaN = occluded; Inf = error; range as for samples. A
     * template that is not finite or in range is a garbage struct. */
    for (i = 0; i < count; i++) {
        sfit_status_t si;
        if (sfit_i_check_sample(cl->pos[i].v) != SFIT_OK) {
            return SFIT_E_ARG;
        }
        si = sfit_i_check_marker(meas[i].v, &seen[i], &st);
        if (si != SFIT_OK) {
            return si;
        }
        nseen += seen[i];
    }
    if (nseen < 3u) {
        return SFIT_E_TOO_FEW; /* the status rule: TOO_FEW before RANGE */
    }
    if (st != SFIT_OK) {
        return st;
    }
    prv_centroid(meas, count, seen, xr, dx);
    prv_centroid(cl->pos, count, seen, pr, dp);

    fr.meas = meas;
    fr.tpl = cl->pos;
    fr.seen = seen;
    fr.count = count;
    fr.xr = xr;
    fr.dx = dx;
    fr.pr = pr;
    fr.dp = dp;
    (void)prv_pairs(&fr, NULL, h); /* H = sum q p^T */
    hmax = 0.0f;
    for (ii = 0; ii < 9; ii++) {
        const float ah = SFIT_FABSF(h[ii]);
        if (ah > hmax) {
            hmax = ah;
        }
    }
    if (!sfit_i_isfinite(hmax)) {
        return SFIT_E_RANGE;
    }
    if (!(hmax > 0.0f)) {
        return SFIT_E_DEGENERATE; /* coincident markers */
    }
    inv = 1.0f / hmax;
    for (ii = 0; ii < 9; ii++) {
        h[ii] *= inv;
    }
    /* K = H^T H (symmetric; the lower triangle is what the kernel reads). */
    for (ii = 0; ii < 3; ii++) {
        for (jj = 0; jj <= ii; jj++) {
            const float s = h[ii] * h[jj] + h[3 + ii] * h[3 + jj] + h[6 + ii] * h[6 + jj];
            k.m[3 * ii + jj] = s;
            k.m[3 * jj + ii] = s;
        }
    }
    st = prv_spread_check(&k, 2, &vv);
    if (st != SFIT_OK) {
        return st;
    }
    for (ii = 0; ii < 3; ii++) {
        v1[ii] = vv.m[3 * ii + 2];
        v2[ii] = vv.m[3 * ii + 1];
    }
    for (ii = 0; ii < 3; ii++) {
        u1[ii] = h[3 * ii] * v1[0] + h[3 * ii + 1] * v1[1] + h[3 * ii + 2] * v1[2];
        u2[ii] = h[3 * ii] * v2[0] + h[3 * ii + 1] * v2[1] + h[3 * ii + 2] * v2[2];
    }
    if (!sfit_i_unit3(u1, &a)) {
        return SFIT_E_DEGENERATE;
    }
    a = sfit_i_dot3(u1, u2);
    for (ii = 0; ii < 3; ii++) {
        u2[ii] -= a * u1[ii];
    }
    if (!sfit_i_unit3(u2, &a)) {
        return SFIT_E_DEGENERATE;
    }
    prv_cross(u1, u2, u3);
    prv_cross(v1, v2, v3);
    for (ii = 0; ii < 3; ii++) {
        for (jj = 0; jj < 3; jj++) {
            r.m[3 * ii + jj] = u1[ii] * v1[jj] + u2[ii] * v2[jj] + u3[ii] * v3[jj];
        }
    }
    prv_refine(h, &r);
    /* t = x_bar - R p_bar, with x_bar = xr + dx and p_bar = pr + dp. */
    for (ii = 0; ii < 3; ii++) {
        float rp = 0.0f;
        for (jj = 0; jj < 3; jj++) {
            rp += r.m[3 * ii + jj] * (pr[jj] + dp[jj]);
        }
        t.v[ii] = (xr[ii] + dx[ii]) - rp;
    }
    /* Residual from the centred points (no cancellation). */
    e2 = SFIT_SQRTF(prv_pairs(&fr, &r, NULL) / (float)nseen);
    if (!sfit_i_isfinite(e2) || sfit_i_check_sample(t.v) != SFIT_OK) {
        return SFIT_E_RANGE;
    }
    for (ii = 0; ii < 9; ii++) {
        if (!sfit_i_isfinite(r.m[ii])) {
            return SFIT_E_RANGE;
        }
    }
    pose->r = r;
    pose->t = t;
    if (fit != NULL) {
        fit->rms = e2;
        fit->used = (uint32_t)nseen;
    }
    return SFIT_OK;
}

/* Write a mapped point only when it is finite: a pose or point holding NaN
 * or Inf gives E_NONFINITE, a finite one that overflows E_RANGE. */
static sfit_status_t prv_map_out(const sfit_pose_t *pose, const sfit_vec3_t *in, const float y[3],
                                 sfit_vec3_t *out)
{
    int i;
    if (!sfit_i_finite3(y)) {
        int ok = sfit_i_finite3(in->v) && sfit_i_finite3(pose->t.v);
        for (i = 0; i < 9; i++) {
            ok = ok && sfit_i_isfinite(pose->r.m[i]);
        }
        return ok ? SFIT_E_RANGE : SFIT_E_NONFINITE;
    }
    for (i = 0; i < 3; i++) {
        out->v[i] = y[i];
    }
    return SFIT_OK;
}

/* One point map: to the global frame, R x + t (inverse = 0), or to the
 * segment frame, R^T (x - t) (inverse = 1). */
SFIT_INLINE sfit_status_t prv_map(const sfit_pose_t *pose, const sfit_vec3_t *x, int inverse,
                                  sfit_vec3_t *out)
{
    const float *r;
    const int si = inverse ? 1 : 3, sk = inverse ? 3 : 1;
    float d[3], y[3];
    int i;
    if (pose == NULL || x == NULL || out == NULL) {
        return SFIT_E_ARG;
    }
    r = pose->r.m;
    for (i = 0; i < 3; i++) {
        d[i] = inverse ? x->v[i] - pose->t.v[i] : x->v[i];
    }
    for (i = 0; i < 3; i++) {
        const float *ri = &r[si * i];
        const float v = ri[0] * d[0] + ri[sk] * d[1] + ri[2 * sk] * d[2];
        y[i] = inverse ? v : v + pose->t.v[i];
    }
    return prv_map_out(pose, x, y, out);
}

sfit_status_t sfit_cluster_to_global(const sfit_pose_t *pose, const sfit_vec3_t *xs,
                                     sfit_vec3_t *xg)
{
    return prv_map(pose, xs, 0, xg);
}

sfit_status_t sfit_cluster_to_segment(const sfit_pose_t *pose, const sfit_vec3_t *xg,
                                      sfit_vec3_t *xs)
{
    return prv_map(pose, xg, 1, xs);
}
