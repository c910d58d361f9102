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

/* The convergence threshold of the tracking step: one float epsilon. */
#define SFIT_FLT_EPS_TRACK 1.1920929e-7f

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
    size_t count;
    uint32_t nseen;
    uint8_t seen[SFIT_CLUSTER_MAX_MARKERS];
    float xr[3], dx[3], pr[3], dp[3];
} prv_frame_t;

/* Over the seen markers, centred (q measured, p template): the sum of
 * |r p - q|^2. */
static float prv_resid2(const prv_frame_t *fr, const sfit_mat3_t *r)
{
    const float *m = r->m;
    const float x0 = fr->xr[0], x1 = fr->xr[1], x2 = fr->xr[2];
    const float c0 = fr->dx[0], c1 = fr->dx[1], c2 = fr->dx[2];
    const float y0 = fr->pr[0], y1 = fr->pr[1], y2 = fr->pr[2];
    const float e0 = fr->dp[0], e1 = fr->dp[1], e2 = fr->dp[2];
    float s = 0.0f;
    size_t i;
    for (i = 0; i < fr->count; i++) {
        const float *x = fr->meas[i].v, *p = fr->tpl[i].v;
        float p0, p1, p2, f0, f1, f2;
        if (fr->seen[i] == 0u) {
            continue;
        }
        p0 = (p[0] - y0) - e0;
        p1 = (p[1] - y1) - e1;
        p2 = (p[2] - y2) - e2;
        f0 = ((m[0] * p0 + m[1] * p1) + m[2] * p2) - ((x[0] - x0) - c0);
        f1 = ((m[3] * p0 + m[4] * p1) + m[5] * p2) - ((x[1] - x1) - c1);
        f2 = ((m[6] * p0 + m[7] * p1) + m[8] * p2) - ((x[2] - x2) - c2);
        s += (f0 * f0 + f1 * f1) + f2 * f2;
    }
    return s;
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

/* 1 when a coordinate's exponent is at or above 2^SFIT_COORD_MAX_EXP (too
 * large, Inf or NaN): the cheap screen before sfit_i_check_marker(). */
SFIT_INLINE int prv_big(const float v[3])
{
    const uint32_t lim = (uint32_t)(127 + SFIT_COORD_MAX_EXP) << 23;
    uint32_t u0, u1, u2;
    memcpy(&u0, &v[0], sizeof u0);
    memcpy(&u1, &v[1], sizeof u1);
    memcpy(&u2, &v[2], sizeof u2);
    return ((u0 & 0x7F800000u) >= lim) || ((u1 & 0x7F800000u) >= lim)
           || ((u2 & 0x7F800000u) >= lim);
}

/*
 * The seen markers of a frame (NaN = occluded; Inf = error; range as for
 * samples; a template not finite or in range is a garbage struct), their
 * centroids and H = sum q p^T, in one pass: with a = x - x_ref and
 * b = p - p_ref (the first seen marker), H = sum a b^T - (sum a)(sum b)^T / n.
 * Written out in scalars: the per-frame path of sfit_cluster_track().
 */
static sfit_status_t prv_prepare(const sfit_cluster_t *cl, const sfit_vec3_t *meas, size_t count,
                                 prv_frame_t *fr, float h[9])
{
    float sa0 = 0.0f, sa1 = 0.0f, sa2 = 0.0f, sb0 = 0.0f, sb1 = 0.0f, sb2 = 0.0f;
    float m00 = 0.0f, m01 = 0.0f, m02 = 0.0f, m10 = 0.0f, m11 = 0.0f, m12 = 0.0f;
    float m20 = 0.0f, m21 = 0.0f, m22 = 0.0f, inv;
    const float *xr = NULL, *pr = NULL;
    sfit_status_t st = SFIT_OK;
    uint32_t n = 0;
    size_t i;

    if (cl == NULL || meas == NULL || !prv_count_ok(cl->count) || count != (size_t)cl->count) {
        return SFIT_E_ARG;
    }
    for (i = 0; i < count; i++) {
        const float *x = meas[i].v, *p = cl->pos[i].v;
        float a0, a1, a2, b0, b1, b2;
        fr->seen[i] = 1u;
        if (prv_big(p)) {
            return SFIT_E_ARG;
        }
        if (prv_big(x)) {
            const sfit_status_t si = sfit_i_check_marker(x, &fr->seen[i], &st);
            if (si != SFIT_OK) {
                return si;
            }
            if (fr->seen[i] == 0u) {
                continue;
            }
        }
        if (xr == NULL) {
            xr = x;
            pr = p;
        }
        n++;
        a0 = x[0] - xr[0];
        a1 = x[1] - xr[1];
        a2 = x[2] - xr[2];
        b0 = p[0] - pr[0];
        b1 = p[1] - pr[1];
        b2 = p[2] - pr[2];
        sa0 += a0;
        sa1 += a1;
        sa2 += a2;
        sb0 += b0;
        sb1 += b1;
        sb2 += b2;
        m00 += a0 * b0;
        m01 += a0 * b1;
        m02 += a0 * b2;
        m10 += a1 * b0;
        m11 += a1 * b1;
        m12 += a1 * b2;
        m20 += a2 * b0;
        m21 += a2 * b1;
        m22 += a2 * b2;
    }
    if (n < 3u) {
        return SFIT_E_TOO_FEW; /* the status rule: TOO_FEW before RANGE */
    }
    if (st != SFIT_OK) {
        return st;
    }
    inv = 1.0f / (float)n;
    fr->xr[0] = xr[0];
    fr->xr[1] = xr[1];
    fr->xr[2] = xr[2];
    fr->pr[0] = pr[0];
    fr->pr[1] = pr[1];
    fr->pr[2] = pr[2];
    sa0 *= inv;
    sa1 *= inv;
    sa2 *= inv;
    fr->dx[0] = sa0;
    fr->dx[1] = sa1;
    fr->dx[2] = sa2;
    fr->dp[0] = sb0 * inv;
    fr->dp[1] = sb1 * inv;
    fr->dp[2] = sb2 * inv;
    h[0] = m00 - sa0 * sb0;
    h[1] = m01 - sa0 * sb1;
    h[2] = m02 - sa0 * sb2;
    h[3] = m10 - sa1 * sb0;
    h[4] = m11 - sa1 * sb1;
    h[5] = m12 - sa1 * sb2;
    h[6] = m20 - sa2 * sb0;
    h[7] = m21 - sa2 * sb1;
    h[8] = m22 - sa2 * sb2;
    fr->meas = meas;
    fr->tpl = cl->pos;
    fr->count = count;
    fr->nseen = n;
    return SFIT_OK;
}

/* The full solve: R from the SVD of H (Jacobi on H^T H) and one Newton
 * step. H is scaled in place. */
static sfit_status_t prv_full(float h[9], sfit_mat3_t *r)
{
    float hmax = 0.0f, inv, a;
    float v1[3], v2[3], v3[3], u1[3], u2[3], u3[3];
    sfit_mat3_t k, vv;
    sfit_status_t st;
    int ii, jj;

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
            r->m[3 * ii + jj] = u1[ii] * v1[jj] + u2[ii] * v2[jj] + u3[ii] * v3[jj];
        }
    }
    prv_refine(h, r);
    return SFIT_OK;
}

/* 1 when every one of the n floats is finite (bit test). */
SFIT_INLINE int prv_all_finite(const float *v, int n)
{
    int i;
    for (i = 0; i < n; i++) {
        uint32_t u;
        memcpy(&u, &v[i], sizeof u);
        if ((u & 0x7F800000u) == 0x7F800000u) {
            return 0;
        }
    }
    return 1;
}

/* The translation t = x_bar - R p_bar and the residual of a rotation; the
 * outputs written when everything is finite. */
static sfit_status_t prv_finish(const prv_frame_t *fr, const sfit_mat3_t *r, sfit_pose_t *pose,
                                sfit_cluster_fit_t *fit)
{
    const float *m = r->m;
    const float p0 = fr->pr[0] + fr->dp[0], p1 = fr->pr[1] + fr->dp[1], p2 = fr->pr[2] + fr->dp[2];
    sfit_vec3_t t;

    /* t = x_bar - R p_bar, with x_bar = xr + dx and p_bar = pr + dp. */
    t.v[0] = (fr->xr[0] + fr->dx[0]) - ((m[0] * p0 + m[1] * p1) + m[2] * p2);
    t.v[1] = (fr->xr[1] + fr->dx[1]) - ((m[3] * p0 + m[4] * p1) + m[5] * p2);
    t.v[2] = (fr->xr[2] + fr->dx[2]) - ((m[6] * p0 + m[7] * p1) + m[8] * p2);
    if (prv_big(t.v) || !prv_all_finite(m, 9)) {
        return SFIT_E_RANGE;
    }
    pose->r = *r;
    pose->t = t;
    /* Residual from the centred points (no cancellation); only when asked
     * for: with finite R and in-range markers it cannot overflow. */
    if (fit != NULL) {
        fit->rms = SFIT_SQRTF(prv_resid2(fr, r) / (float)fr->nseen);
        fit->used = (uint32_t)fr->nseen;
    }
    return SFIT_OK;
}

sfit_status_t sfit_cluster_register(const sfit_cluster_t *cl, const sfit_vec3_t *meas,
                                    size_t count, sfit_pose_t *pose, sfit_cluster_fit_t *fit)
{
    prv_frame_t fr;
    float h[9];
    sfit_mat3_t r;
    sfit_status_t st = (pose == NULL) ? SFIT_E_ARG : prv_prepare(cl, meas, count, &fr, h);

    if (st == SFIT_OK) {
        st = prv_full(h, &r);
    }
    return (st == SFIT_OK) ? prv_finish(&fr, &r, pose, fit) : st;
}

/* ---- tracking: Newton steps from the previous frame's rotation ---- */

/* b = a^T h (3x3, row-major), written out. */
SFIT_INLINE void prv_mul_at_b(const float a[9], const float h[9], float b[9])
{
    const float a0 = a[0], a1 = a[1], a2 = a[2], a3 = a[3], a4 = a[4], a5 = a[5];
    const float a6 = a[6], a7 = a[7], a8 = a[8];
    const float h0 = h[0], h1 = h[1], h2 = h[2], h3 = h[3], h4 = h[4], h5 = h[5];
    const float h6 = h[6], h7 = h[7], h8 = h[8];
    b[0] = (a0 * h0 + a3 * h3) + a6 * h6;
    b[1] = (a0 * h1 + a3 * h4) + a6 * h7;
    b[2] = (a0 * h2 + a3 * h5) + a6 * h8;
    b[3] = (a1 * h0 + a4 * h3) + a7 * h6;
    b[4] = (a1 * h1 + a4 * h4) + a7 * h7;
    b[5] = (a1 * h2 + a4 * h5) + a7 * h8;
    b[6] = (a2 * h0 + a5 * h3) + a8 * h6;
    b[7] = (a2 * h1 + a5 * h4) + a8 * h7;
    b[8] = (a2 * h2 + a5 * h5) + a8 * h8;
}

/* R of a quaternion (w, x, y, z) of any non-zero length: R is a proper
 * rotation whatever |q| (s = 2 / |q|^2). */
static void prv_quat_rot(const float q[4], sfit_mat3_t *r)
{
    const float s = 2.0f / (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const float xs = q[1] * s, ys = q[2] * s, zs = q[3] * s;
    const float wx = q[0] * xs, wy = q[0] * ys, wz = q[0] * zs;
    const float xx = q[1] * xs, xy = q[1] * ys, xz = q[1] * zs;
    const float yy = q[2] * ys, yz = q[2] * zs, zz = q[3] * zs;
    r->m[0] = 1.0f - (yy + zz);
    r->m[1] = xy - wz;
    r->m[2] = xz + wy;
    r->m[3] = xy + wz;
    r->m[4] = 1.0f - (xx + zz);
    r->m[5] = yz - wx;
    r->m[6] = xz - wy;
    r->m[7] = yz + wx;
    r->m[8] = 1.0f - (xx + yy);
}

/* Unit quaternion of a rotation matrix (Shepperd: from the largest of
 * 1 + tr R, 1 + 2 R_ii - tr R, so the square root is of a number >= 1). */
static void prv_rot_quat(const sfit_mat3_t *r, float q[4])
{
    const float *m = r->m;
    const float tr = m[0] + m[4] + m[8];
    /* off[k]: the differences / sums that give the other components. */
    const float dx = m[7] - m[5], dy = m[2] - m[6], dz = m[3] - m[1];
    const float sxy = m[1] + m[3], sxz = m[2] + m[6], syz = m[5] + m[7];
    float big = tr, f, o[4];
    int k = 0, i;
    for (i = 0; i < 3; i++) {
        if (m[4 * i] > big) {
            big = m[4 * i];
            k = i + 1;
        }
    }
    f = SFIT_SQRTF(1.0f + 2.0f * big - tr); /* = 2 |q_k|; k = 0: 1 + tr */
    if (k == 0) {
        o[0] = f * f; o[1] = dx; o[2] = dy; o[3] = dz;
    } else if (k == 1) {
        o[0] = dx; o[1] = f * f; o[2] = sxy; o[3] = sxz;
    } else if (k == 2) {
        o[0] = dy; o[1] = sxy; o[2] = f * f; o[3] = syz;
    } else {
        o[0] = dz; o[1] = sxz; o[2] = syz; o[3] = f * f;
    }
    f = 0.5f / f;
    for (i = 0; i < 4; i++) {
        q[i] = o[i] * f;
    }
}

/*
 * Newton steps on tr(R^T H) from the rotation of q (see prv_refine():
 * B = R^T H, gradient g, Hessian A = tr(B) I - sym(B), step w = A^-1 g),
 * each applied as q := q (1, w/2) so that R stays a proper rotation.
 * Solved by LDL^T with pivots d_k. Accepted (returns the steps taken, R
 * of the final q in r) after a step with
 *  - A positive definite (d_k > 0): a maximum, which on SO(3) is the
 *    global one;
 *  - c = tr(B)^3 / det A <= 1 / (4 SFIT_CLUSTER_COLLINEAR_RATIO): since
 *    lambda_min(A) >= det A / tr(B)^2, s2 >= lambda_min / 2 and
 *    s1 <= tr(B), this proves s2/s1 >= 2 x the collinearity ratio, so the
 *    full solve would not call the cluster degenerate;
 *  - c |w|^2 <= FLT_EPSILON: Newton's error after the step is below
 *    (|B| / lambda_min) |w|^2 <= c |w|^2, one float epsilon.
 * Returns 0 when SFIT_CLUSTER_TRACK_STEPS steps do not get there.
 */
static uint32_t prv_track(const float h[9], float q[4], sfit_mat3_t *r)
{
    const float cmax = 0.25f / SFIT_CLUSTER_COLLINEAR_RATIO;
    uint32_t it;
    int conv = 0;

    for (it = 0u; it <= (uint32_t)SFIT_CLUSTER_TRACK_STEPS; it++) {
        float b[9], g[3], w[3], nq[4];
        float tr, a01, a02, a12, d0, d1, d2, i0, i1, i2, l10, l20, l21, e12, y1, y2, c;
        int i;
        prv_quat_rot(q, r);
        if (conv) {
            return it;
        }
        if (it == (uint32_t)SFIT_CLUSTER_TRACK_STEPS) {
            break;
        }
        prv_mul_at_b(r->m, h, b);
        g[0] = b[7] - b[5];
        g[1] = b[2] - b[6];
        g[2] = b[3] - b[1];
        tr = b[0] + b[4] + b[8];
        a01 = -0.5f * (b[1] + b[3]);
        a02 = -0.5f * (b[2] + b[6]);
        a12 = -0.5f * (b[5] + b[7]);
        d0 = tr - b[0];
        if (!(d0 > 0.0f)) {
            return 0u;
        }
        i0 = 1.0f / d0;
        l10 = a01 * i0;
        l20 = a02 * i0;
        d1 = (tr - b[4]) - l10 * a01;
        if (!(d1 > 0.0f)) {
            return 0u;
        }
        i1 = 1.0f / d1;
        e12 = a12 - l20 * a01;
        l21 = e12 * i1;
        d2 = ((tr - b[8]) - l20 * a02) - l21 * e12;
        if (!(d2 > 0.0f)) {
            return 0u;
        }
        i2 = 1.0f / d2;
        /* w/2 = A^-1 g / 2: the half-angle vector of the step */
        y1 = g[1] - l10 * g[0];
        y2 = (g[2] - l20 * g[0]) - l21 * y1;
        w[2] = 0.5f * (y2 * i2);
        w[1] = 0.5f * (y1 * i1) - l21 * w[2];
        w[0] = (0.5f * (g[0] * i0) - l10 * w[1]) - l20 * w[2];
        c = ((tr * i0) * (tr * i1)) * (tr * i2);
        /* c |w|^2 = 4 c |w/2|^2 */
        conv = c <= cmax && (4.0f * c) * sfit_i_dot3(w, w) <= SFIT_FLT_EPS_TRACK;
        /* q := q (1, w/2); |q| grows by sqrt(1 + |w/2|^2): R does not mind
         * (prv_quat_rot), the caller normalises the final q. */
        nq[0] = q[0] - ((q[1] * w[0] + q[2] * w[1]) + q[3] * w[2]);
        nq[1] = (q[1] + q[0] * w[0]) + (q[2] * w[2] - q[3] * w[1]);
        nq[2] = (q[2] + q[0] * w[1]) + (q[3] * w[0] - q[1] * w[2]);
        nq[3] = (q[3] + q[0] * w[2]) + (q[1] * w[1] - q[2] * w[0]);
        for (i = 0; i < 4; i++) {
            q[i] = nq[i];
        }
    }
    return 0u;
}

sfit_status_t sfit_cluster_track_reset(sfit_cluster_track_t *tr)
{
    if (tr == NULL) {
        return SFIT_E_ARG;
    }
    memset(tr, 0, sizeof *tr);
    tr->q[0] = 1.0f;
    return SFIT_OK;
}

/* A state the library wrote: valid's byte 0 or 1 (read as a byte:
 * sfit_i_bool_byte); with 1, a finite q with | |q|^2 - 1 | <= 2^-16 (the
 * library keeps it within a few epsilon). */
static int prv_track_ok(const sfit_cluster_track_t *tr)
{
    const unsigned v = sfit_i_bool_byte(&tr->valid);
    float n2;
    if (v == 0u) {
        return 1;
    }
    if (v != 1u) {
        return 0;
    }
    n2 = tr->q[0] * tr->q[0] + tr->q[1] * tr->q[1] + tr->q[2] * tr->q[2] + tr->q[3] * tr->q[3];
    return SFIT_FABSF(n2 - 1.0f) <= 1.52587890625e-5f; /* NaN fails */
}

sfit_status_t sfit_cluster_track(const sfit_cluster_t *cl, sfit_cluster_track_t *tr,
                                 const sfit_vec3_t *meas, size_t count, sfit_pose_t *pose,
                                 sfit_cluster_fit_t *fit)
{
    prv_frame_t fr;
    float h[9], q[4];
    sfit_mat3_t r;
    uint32_t steps = 0u;
    sfit_status_t st;
    int i;

    if (tr == NULL || pose == NULL || !prv_track_ok(tr)) {
        return SFIT_E_ARG;
    }
    st = prv_prepare(cl, meas, count, &fr, h);
    if (st == SFIT_E_TOO_FEW) {
        tr->valid = false; /* a gap: the next frame starts from nothing */
    }
    if (st != SFIT_OK) {
        return st;
    }
    for (i = 0; i < 4; i++) {
        q[i] = tr->q[i];
    }
    if (tr->valid) {
        steps = prv_track(h, q, &r);
    }
    if (steps == 0u) {
        st = prv_full(h, &r);
        if (st != SFIT_OK) {
            return st;
        }
    }
    st = prv_finish(&fr, &r, pose, fit);
    if (st != SFIT_OK) {
        return st;
    }
    if (steps == 0u) {
        prv_rot_quat(&r, q);
    }
    {
        const float n = 1.0f / SFIT_SQRTF(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (i = 0; i < 4; i++) {
            tr->q[i] = q[i] * n;
        }
    }
    tr->valid = true;
    tr->steps = steps;
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
