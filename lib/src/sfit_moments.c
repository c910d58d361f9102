/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_moments.c
 * @brief Streaming moments with two-level (block) summation.
 *
 * Implementation notes
 * --------------------
 * Inner level: the open block sums z = x - origin, z z^T and |z|^2 z, where
 * origin is the running mean at the block's start (the first sample for
 * the first block): each block's end moves it there (prv_rebase) and the
 * total keeps the exact residue. Near a far-away sphere x - origin is
 * exact in float (Sterbenz) and |z| is of the order of the sphere's
 * radius, so the sums carry no large offset.
 *
 * Outer level: the total keeps its sums about the origin too (the
 * origin is its mean rounded to float, the residue d; prv_rebase moves
 * the centred sums of a fold or a merge there). A full block is folded
 * into the total (prv_fold_block): the two sets of sums about the origin
 * are added and centred once about the union's mean. A solve, the
 * statistics and a merge's source fold the open block the same way (an
 * empty one as its residues or zeros: one path, one cost at every N).
 * Each fold rounds
 * the total's second moments once at the total's scale; a block's end
 * keeps that rounding's residue (Fast2Sum) as the next block's starting
 * sums, so the residues are added back instead of piling up over N/64
 * folds (test_fit: the far-offset sweep at N = 1e5 and the real
 * recordings' float-vs-double errors, docs/accuracy.md). Merging two
 * accumulators (whose means may be far apart) uses the exact
 * parallel-update formulas (for sets A, B merged into A+B with mean m,
 * a = m_A - m, b = m_B - m):
 *   n   = n_A + n_B
 *   M2  = M2_A + M2_B + (n_A n_B / n) delta delta^T,    delta = m_B - m_A
 *   M3  = M3_A + M3_B + (2 M2_A + tr(M2_A) I) a + (2 M2_B + tr(M2_B) I) b
 *         + n_A |a|^2 a + n_B |b|^2 b
 * (expand sum |y + a|^2 (y + a) over a set with sum y = 0). The total keeps
 * its mean as `origin + d` so no operation involves the large coordinate
 * except the final `origin + (d + w)` of a solve.
 */
#include "sfit/sfit_moments.h"

#include <float.h>
#include <string.h>

#include "sfit_moments_i.h"

sfit_status_t sfit_moments_init(sfit_moments_t *m)
{
    if (m == NULL) {
        return SFIT_E_ARG;
    }
    memset(m, 0, sizeof *m);
    return SFIT_OK;
}

sfit_status_t sfit_moments_reset(sfit_moments_t *m)
{
    return sfit_moments_init(m);
}

uint32_t sfit_moments_count(const sfit_moments_t *m)
{
    return (m == NULL) ? 0u : m->tot.n + m->blk.n;
}

/* out += (2 M2 + tr(M2) I) u + n |u|^2 u with u = k delta: the shift of M3
 * by u of a set with centred M2; with m2 (the set's own M2), then also
 * M2 += n u u^T: the set's sums about its mean - u (loops: off the
 * per-sample path, a block's end or a merge, and small). */
static void prv_m3_shift(const sfit_cmom_t *s, float k, const float delta[3], float out[3],
                         float *m2)
{
    /* Where M2(i, j) is in the packed XX, YY, ZZ, XY, XZ, YZ (row i, column j). */
    static const uint8_t k_packed[9] = {0u, 3u, 4u, 3u, 1u, 5u, 4u, 5u, 2u};
    float u[3], t, uu = 0.0f;
    int i, j;
    for (i = 0; i < 3; i++) {
        u[i] = k * delta[i];
        uu += u[i] * u[i];
    }
    t = (s->m2[0] + s->m2[1] + s->m2[2]) + (float)s->n * uu;
    for (i = 0; i < 3; i++) {
        float mu = 0.0f;
        for (j = 0; j < 3; j++) {
            mu += s->m2[k_packed[3 * i + j]] * u[j];
        }
        out[i] += 2.0f * mu + t * u[i];
    }
    for (i = 0; m2 != NULL && i < 3; i++) { /* after the reads of M2 above */
        const float f = (float)s->n * u[i];
        for (j = i; j < 3; j++) {
            m2[k_packed[3 * i + j]] += f * u[j];
        }
    }
}

/* max(v, 0); a NaN stays NaN (stats then says E_RANGE). */
SFIT_INLINE float prv_nonneg(float v)
{
    return (v < 0.0f) ? 0.0f : v;
}

/* a + x, and *lo := its rounding residue x - ((a + x) - a), exact when
 * |a| >= |x| (Fast2Sum). */
SFIT_INLINE float prv_add_lo(float a, float x, float *lo)
{
    const float s = a + x;
    *lo = x - (s - a);
    return s;
}

/* out := the moments of a U b centred about their mean origin + out->d
 * (out may be a; out may be b only when lo is out too: each of b's sums is
 * read before the same one of out and lo is written, so that an empty b
 * can be the zeroed out itself), and lo->m2 := the rounding residues of
 * out's M2 (lo may be b: a block's end keeps them as the next block's
 * sums; or lo is out, the residues stored first and then overwritten, so
 * that the solve's fold takes the same path and needs no scratch).
 * a holds sums about the origin with mean origin + a->d, where a->d is a
 * rebase residue (prv_rebase: at most half an ulp of the origin) or a is
 * empty; b holds raw sums of z = x - origin. One pass about the origin:
 * the union's sums about it are S2 = S2_a + S2_b and S3 = S3_a + S3_b,
 * its mean is origin + delta, delta = (n_a e + sum z) / n with e = a->d,
 * and they are centred once:
 *   M2 = S2 - (n delta) delta^T,
 *   M3 = S3 - (2 M2 + tr(M2) I) delta - n |delta|^2 delta
 * (the shift of prv_m3_shift by -delta). Every sum is about a point near
 * the samples' mean, never about the coordinate origin. */
static void prv_fold_block(const sfit_cmom_t *a, const sfit_cmom_t *b, sfit_cmom_t *out,
                           sfit_cmom_t *lo)
{
    const uint32_t n = a->n + b->n;
    const float na = (float)a->n;
    const float fn = (float)n;
    const float inv = 1.0f / fn;
    const float e0 = a->d[0], e1 = a->d[1], e2 = a->d[2];
    const float s0 = na * e0 + b->d[0], s1 = na * e1 + b->d[1], s2 = na * e2 + b->d[2];
    const float d0 = s0 * inv, d1 = s1 * inv, d2 = s2 * inv;
    const float a0 = a->m2[0], a1 = a->m2[1], a2 = a->m2[2];
    const float a3 = a->m2[3], a4 = a->m2[4], a5 = a->m2[5];
    const float q0 = b->m3[0], q1 = b->m3[1], q2 = b->m3[2];
    float t;

    /* A sum of squares about the mean is >= 0; the subtraction of two
     * nearly equal sums can round below (found by fuzz_stream). Each
     * residue is stored before the sum (lo may be out), a's sums are read
     * above (out may be a). */
    out->m2[0] = prv_nonneg(prv_add_lo(a0, b->m2[0] - s0 * d0, &lo->m2[0]));
    out->m2[1] = prv_nonneg(prv_add_lo(a1, b->m2[1] - s1 * d1, &lo->m2[1]));
    out->m2[2] = prv_nonneg(prv_add_lo(a2, b->m2[2] - s2 * d2, &lo->m2[2]));
    out->m2[3] = prv_add_lo(a3, b->m2[3] - s0 * d1, &lo->m2[3]);
    out->m2[4] = prv_add_lo(a4, b->m2[4] - s0 * d2, &lo->m2[4]);
    out->m2[5] = prv_add_lo(a5, b->m2[5] - s1 * d2, &lo->m2[5]);
    {
        const float p0 = out->m2[0], p1 = out->m2[1], p2 = out->m2[2];
        const float p3 = out->m2[3], p4 = out->m2[4], p5 = out->m2[5];
        t = (p0 + p1 + p2) + fn * (d0 * d0 + d1 * d1 + d2 * d2);
        out->m3[0] = a->m3[0] + (q0 - (2.0f * (p0 * d0 + p3 * d1 + p4 * d2) + t * d0));
        out->m3[1] = a->m3[1] + (q1 - (2.0f * (p3 * d0 + p1 * d1 + p5 * d2) + t * d1));
        out->m3[2] = a->m3[2] + (q2 - (2.0f * (p4 * d0 + p5 * d1 + p2 * d2) + t * d2));
    }
    out->d[0] = d0;
    out->d[1] = d1;
    out->d[2] = d2;
    out->n = n;
}

/* b := a U b, both means relative to the same origin (b is the result, so
 * no temporary is needed on the stack). */
static void prv_cmom_merge(const sfit_cmom_t *a, sfit_cmom_t *b)
{
    float *const delta = b->d; /* m_B - m_A, then the merged mean */
    float fa, fb, w;

    if (b->n == 0u) {
        *b = *a;
        return;
    }
    if (a->n == 0u) {
        return;
    }
    {
        const float na = (float)a->n;
        const float n = na + (float)b->n;
        fb = (float)b->n / n;
        fa = na / n;
        w = na * fb; /* n_A n_B / n */
    }
    /* Written out (no loop): fewer registers live, a smaller frame on
     * sfit_moments_add's deepest path (stack trick 7, sfit_solve.h). */
    delta[0] = b->d[0] - a->d[0];
    delta[1] = b->d[1] - a->d[1];
    delta[2] = b->d[2] - a->d[2];
    b->m3[0] = a->m3[0] + b->m3[0];
    b->m3[1] = a->m3[1] + b->m3[1];
    b->m3[2] = a->m3[2] + b->m3[2];
    prv_m3_shift(a, -fb, delta, b->m3, NULL); /* m_A - m = -fb delta */
    prv_m3_shift(b, fa, delta, b->m3, NULL);  /* m_B - m = fa delta (b's m2 and n still B's) */
    b->m2[0] = a->m2[0] + (b->m2[0] + w * delta[0] * delta[0]);
    b->m2[1] = a->m2[1] + (b->m2[1] + w * delta[1] * delta[1]);
    b->m2[2] = a->m2[2] + (b->m2[2] + w * delta[2] * delta[2]);
    b->m2[3] = a->m2[3] + (b->m2[3] + w * delta[0] * delta[1]);
    b->m2[4] = a->m2[4] + (b->m2[4] + w * delta[0] * delta[2]);
    b->m2[5] = a->m2[5] + (b->m2[5] + w * delta[1] * delta[2]);
    delta[0] = a->d[0] + fb * delta[0];
    delta[1] = a->d[1] + fb * delta[1];
    delta[2] = a->d[2] + fb * delta[2];
    b->n += a->n;
}

/* Move the origin to the mean of a centred total t about it, o' =
 * fl(origin + t->d), keep the exact residue e = d - (o' - origin) in t->d
 * (o' - origin is exact when |d| <= |origin|, Fast2Sum), and move t's
 * sums to o' (the mean is o' + e): S2 = M2 + n e e^T, S3 = M3 + (2 M2 +
 * tr(M2) I) e + n |e|^2 e (prv_m3_shift). The next block is summed about
 * o', and prv_fold_block() adds the two sets of sums as they are. The
 * n e e^T terms are (|e| / spread)^2 relative, below the sums' rounding,
 * except where the spread is of the order of the origin's ulp (near the
 * coordinate range): there a total kept centred and added as if about
 * o' failed Cauchy-Schwarz (found by a stress run of merges). The move
 * of the sums is the caller's second call (one frame less on
 * sfit_moments_add's deepest path). */
static void prv_rebase(float origin[3], sfit_cmom_t *t)
{
    int i;
    for (i = 0; i < 3; i++) {
        const float o = origin[i] + t->d[i];
        t->d[i] -= o - origin[i];
        origin[i] = o;
    }
}

/* out := tot, merged with the open block blk (raw sums; an empty one
 * folds its residues), centred. */
static void prv_total(const sfit_cmom_t *tot, const sfit_cmom_t *blk, sfit_cmom_t *out)
{
    prv_fold_block(tot, blk, out, out);
}

void sfit_i_moments_total(const sfit_moments_t *m, sfit_cmom_t *out)
{
    prv_total(&m->tot, &m->blk, out);
}

/* Fold the open block into the total and empty it (the origin stays); its
 * second-moment sums start at the fold's rounding residues (a correction
 * of the total, added back at the next fold: compensated summation). */
static void prv_close(sfit_moments_t *m)
{
    prv_fold_block(&m->tot, &m->blk, &m->tot, &m->blk);
    m->blk.n = 0u;
    m->blk.m3[0] = 0.0f;
    m->blk.m3[1] = 0.0f;
    m->blk.m3[2] = 0.0f;
    m->blk.d[0] = 0.0f;
    m->blk.d[1] = 0.0f;
    m->blk.d[2] = 0.0f;
}

/* Fold the open block into the total, empty it and move the origin to
 * the new mean (prv_rebase). */
static void prv_flush(sfit_moments_t *m)
{
    if (m->blk.n == 0u) {
        return;
    }
    prv_close(m);
    prv_rebase(m->origin, &m->tot);
    prv_m3_shift(&m->tot, 1.0f, m->tot.d, m->tot.m3, m->tot.m2);
}

/* Accumulate one already validated sample. */
static void prv_add(sfit_moments_t *m, const float x[3])
{
    sfit_cmom_t *const b = &m->blk;
    float z0, z1, z2, q00, q11, q22, q;

    if (b->n == 0u && m->tot.n == 0u) {
        memcpy(m->origin, x, sizeof m->origin); /* later blocks: prv_flush() moved it */
    }
    z0 = x[0] - m->origin[0];
    z1 = x[1] - m->origin[1];
    z2 = x[2] - m->origin[2];
    b->d[0] += z0;
    b->d[1] += z1;
    b->d[2] += z2;
    q00 = z0 * z0;
    q11 = z1 * z1;
    q22 = z2 * z2;
    b->m2[0] += q00;
    b->m2[1] += q11;
    b->m2[2] += q22;
    b->m2[3] += z0 * z1;
    b->m2[4] += z0 * z2;
    b->m2[5] += z1 * z2;
    q = q00 + q11 + q22;
    b->m3[0] += q * z0;
    b->m3[1] += q * z1;
    b->m3[2] += q * z2;
    b->n++;
    if (b->n >= SFIT_SUM_BLOCK) {
        prv_flush(m);
    }
}

sfit_status_t sfit_moments_add(sfit_moments_t *m, const sfit_vec3_t *x)
{
    sfit_status_t st = sfit_i_check_add(m, x);
    if (st == SFIT_OK && m->tot.n + m->blk.n == UINT32_MAX) { /* m not NULL here */
        st = SFIT_E_RANGE;
    }
    if (st == SFIT_OK) {
        prv_add(m, x->v);
    }
    return st;
}

sfit_status_t sfit_i_moments_of(const sfit_vec3_t *pts, size_t n, sfit_moments_t *m)
{
    (void)sfit_moments_init(m);
    return sfit_moments_add_block(m, pts, n, NULL);
}

sfit_status_t sfit_i_points_total(const sfit_vec3_t *pts, size_t n, sfit_i_total_t *out)
{
    sfit_moments_t m;
    const sfit_status_t st = sfit_i_moments_of(pts, n, &m);
    if (st == SFIT_OK) {
        prv_flush(&m); /* the mean a residue from the origin (sfit_i_moments_system) */
        out->t = m.tot;
        memcpy(out->origin, m.origin, sizeof m.origin);
    }
    return st;
}

/* The first sample of an empty accumulator is its origin (later blocks
 * start at the mean: prv_flush()). */
static void prv_open(sfit_moments_t *m, const float x[3])
{
    if (m->blk.n == 0u && m->tot.n == 0u) {
        memcpy(m->origin, x, sizeof m->origin);
    }
}

/* Accumulate k already validated samples that fit in the open block
 * (blk.n + k <= SFIT_SUM_BLOCK, k >= 1) with the sums in registers: the
 * same operations in the same order as k prv_add() calls, so the same
 * bits, without a load and a store of every sum per sample. */
static void prv_add_run(sfit_moments_t *m, const sfit_vec3_t *pts, uint32_t k)
{
    sfit_cmom_t *const b = &m->blk;
    const float o0 = m->origin[0], o1 = m->origin[1], o2 = m->origin[2];
    float d0 = b->d[0], d1 = b->d[1], d2 = b->d[2];
    float s00 = b->m2[0], s11 = b->m2[1], s22 = b->m2[2];
    float s01 = b->m2[3], s02 = b->m2[4], s12 = b->m2[5];
    float t0 = b->m3[0], t1 = b->m3[1], t2 = b->m3[2];
    uint32_t i;

    for (i = 0u; i < k; i++) {
        const float z0 = pts[i].v[0] - o0;
        const float z1 = pts[i].v[1] - o1;
        const float z2 = pts[i].v[2] - o2;
        const float q00 = z0 * z0;
        const float q11 = z1 * z1;
        const float q22 = z2 * z2;
        float q;
        d0 += z0;
        d1 += z1;
        d2 += z2;
        s00 += q00;
        s11 += q11;
        s22 += q22;
        s01 += z0 * z1;
        s02 += z0 * z2;
        s12 += z1 * z2;
        q = q00 + q11 + q22;
        t0 += q * z0;
        t1 += q * z1;
        t2 += q * z2;
    }
    b->d[0] = d0;
    b->d[1] = d1;
    b->d[2] = d2;
    b->m2[0] = s00;
    b->m2[1] = s11;
    b->m2[2] = s22;
    b->m2[3] = s01;
    b->m2[4] = s02;
    b->m2[5] = s12;
    b->m3[0] = t0;
    b->m3[1] = t1;
    b->m3[2] = t2;
    b->n += k;
    if (b->n >= SFIT_SUM_BLOCK) {
        prv_flush(m);
    }
}

/* 1 when every coordinate of x is finite and inside the coordinate range:
 * one test of the exponent field per coordinate (NaN, Inf and too large
 * all have it at or above 127 + SFIT_COORD_MAX_EXP). */
SFIT_INLINE int prv_sample_ok(const float x[3])
{
    const uint32_t lim = (uint32_t)(127 + SFIT_COORD_MAX_EXP) << 24u; /* exponent, sign out */
    uint32_t u0, u1, u2;
    memcpy(&u0, &x[0], sizeof u0);
    memcpy(&u1, &x[1], sizeof u1);
    memcpy(&u2, &x[2], sizeof u2);
    u0 <<= 1; /* sign out: |x| in the order of its bits */
    u1 <<= 1;
    u2 <<= 1;
    u0 = (u0 > u1) ? u0 : u1; /* the largest, without a branch */
    u0 = (u0 > u2) ? u0 : u2;
    return u0 < lim;
}

sfit_status_t sfit_moments_add_block(sfit_moments_t *m, const sfit_vec3_t *pts, size_t n,
                                     size_t *bad)
{
    size_t i;
    if (m == NULL || (pts == NULL && n > 0u)) {
        return SFIT_E_ARG;
    }
    /* Validate everything first so that a rejection leaves m untouched;
     * the full check (which status) only for a sample the fast one fails. */
    for (i = 0; i < n; i++) {
        if (!prv_sample_ok(pts[i].v)) {
            const sfit_status_t st = sfit_i_check_sample(pts[i].v);
            if (st != SFIT_OK) {
                if (bad != NULL) {
                    *bad = i;
                }
                return st;
            }
        }
    }
    if ((uint64_t)sfit_moments_count(m) + (uint64_t)n > (uint64_t)UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    i = 0u;
    while (i < n) {
        const size_t room = (size_t)(SFIT_SUM_BLOCK - m->blk.n); /* >= 1: a full block is flushed */
        const size_t k = (n - i < room) ? (n - i) : room;
        prv_open(m, pts[i].v);
        prv_add_run(m, &pts[i], (uint32_t)k);
        i += k;
    }
    return SFIT_OK;
}

/* 2^SFIT_COORD_MAX_EXP: the coordinate range of a sample is (-PRV_RANGE,
 * PRV_RANGE); an origin and a mean are rounded means of samples, so
 * [-PRV_RANGE, PRV_RANGE] (the float mean of samples near -2^27 can round
 * to -2^27 itself: found by fuzz_stream). */
#define PRV_RANGE ((float)(1UL << SFIT_COORD_MAX_EXP))
/* Relative slack of the checks below for the rounding of the sums. */
#define PRV_SLACK 1.00390625f /* 1 + 2^-8 */

/* 1 when the total s of an accumulator with origin `origin` is one the API
 * can build (issue 32: a merged source that is not would make dst unusable
 * for good, stats and fit E_RANGE): origin and mean origin + d inside the
 * closed coordinate range; the sums of squares 0 <= M2_ii <= n (2 range)^2 and
 * |M2_ij| <= (M2_ii + M2_jj)/2 (Cauchy-Schwarz); |M3_i| <= 4 range tr M2
 * (sum |y|^2 |y_i| <= max |y| tr M2, and |y| < 2 sqrt(3) range). Every
 * comparison fails on NaN. Given a dst built by the API, the merged totals
 * then stay finite (below 2^126 in float). */
static int prv_total_ok(const float origin[3], const sfit_cmom_t *s)
{
    const float *const m2 = s->m2;
    const float lim = (float)s->n * (4.0f * PRV_RANGE * PRV_RANGE);
    const float pair[3] = {m2[0] + m2[1], m2[0] + m2[2], m2[1] + m2[2]}; /* XY, XZ, YZ */
    const float tr = pair[0] + m2[2];
    /* absolute slack: the rounding of the shifted sums (eps tr) and their
     * underflow (n FLT_MIN): samples on a line give |M2_yz| ~ 1e-44 with
     * M2_yy = M2_zz = 0 (found by fuzz_stream) */
    const float tiny = FLT_EPSILON * tr + (float)s->n * FLT_MIN;
    int i, ok = 1;
    for (i = 0; i < 3; i++) {
        ok = ok && SFIT_FABSF(origin[i]) <= PRV_RANGE
             && SFIT_FABSF(origin[i] + s->d[i]) <= PRV_RANGE && m2[i] >= -tiny && m2[i] <= lim
             && SFIT_FABSF(m2[3 + i]) <= (0.5f * PRV_SLACK) * pair[i] + tiny
             && SFIT_FABSF(s->m3[i]) <= (4.0f * PRV_SLACK * PRV_RANGE) * tr + tiny;
    }
    return ok;
}

sfit_status_t sfit_moments_merge(sfit_moments_t *dst, const sfit_moments_t *src)
{
    sfit_cmom_t s;
    int i;

    if (dst == NULL || src == NULL) {
        return SFIT_E_ARG;
    }
    if ((uint64_t)sfit_moments_count(dst) + (uint64_t)sfit_moments_count(src)
        > (uint64_t)UINT32_MAX) {
        return SFIT_E_RANGE;
    }
    if (sfit_moments_count(src) == 0u) {
        return SFIT_OK;
    }
    sfit_i_moments_total(src, &s); /* before touching dst: they may alias */
    if (!prv_total_ok(src->origin, &s)) {
        return SFIT_E_RANGE; /* a corrupted src (garbage bytes): dst not poisoned */
    }
    if (sfit_moments_count(dst) == 0u) {
        memcpy(dst->origin, src->origin, sizeof dst->origin);
    } else {
        prv_close(dst); /* centred; dst's origin stays: s.d below is about it */
        for (i = 0; i < 3; i++) {
            s.d[i] = (src->origin[i] - dst->origin[i]) + s.d[i];
        }
    }
    prv_cmom_merge(&dst->tot, &s);
    dst->tot = s;
    prv_rebase(dst->origin, &dst->tot);
    prv_m3_shift(&dst->tot, 1.0f, dst->tot.d, dst->tot.m3, dst->tot.m2);
    return SFIT_OK;
}

void sfit_i_cmom_system(const sfit_cmom_t *t, sfit_mat3_t *c, float b[3])
{
    /* Where the packed XX, YY, ZZ, XY, XZ, YZ go in the lower triangle. */
    static const uint8_t k_lower[6] = {0u, 4u, 8u, 3u, 6u, 7u};
    const float inv = 1.0f / (float)(t->n - 1u);
    int i;
    for (i = 0; i < 6; i++) {
        c->m[k_lower[i]] = t->m2[i] * inv;
    }
    sfit_i_sym_full(c, c->m); /* in place: the upper triangle mirrored */
    for (i = 0; i < 3; i++) {
        b[i] = (0.5f * inv) * t->m3[i];
    }
}

/* One path whatever the open block holds (an empty one folds as zeros):
 * the solve costs the same at every N. */
uint32_t sfit_i_moments_system(const sfit_cmom_t *tot, const sfit_cmom_t *blk, sfit_i_msys_t *s)
{
    float *const c = s->c.m;
    sfit_cmom_t t;
    float inv;
    if (blk == NULL) {
        /* An empty set of sums (no open block) in t itself: the fold reads
         * each of b's sums before it writes the same one of out and lo. */
        memset(&t, 0, sizeof t);
        blk = &t;
    }
    prv_fold_block(tot, blk, &t, &t);
    inv = 1.0f / (float)(t.n - 1u);
    c[0] = t.m2[0] * inv;
    c[4] = t.m2[1] * inv;
    c[8] = t.m2[2] * inv;
    c[3] = t.m2[3] * inv;
    c[6] = t.m2[4] * inv;
    c[7] = t.m2[5] * inv; /* the lower triangle: what the solvers read */
    inv *= 0.5f;
    s->rhs.v[0] = inv * t.m3[0];
    s->rhs.v[1] = inv * t.m3[1];
    s->rhs.v[2] = inv * t.m3[2];
    memcpy(s->d, t.d, sizeof t.d);
    return t.n;
}

sfit_status_t sfit_moments_stats(const sfit_moments_t *m, sfit_vec3_t *mean, sfit_mat3_t *c,
                                 sfit_vec3_t *s)
{
    sfit_cmom_t t;
    sfit_vec3_t mu, sv;
    float inv, p[6];
    int i, ok;

    if (m == NULL || sfit_moments_count(m) < 2u) {
        return (m == NULL) ? SFIT_E_ARG : SFIT_E_TOO_FEW;
    }
    sfit_i_moments_total(m, &t);
    inv = 1.0f / (float)(t.n - 1u);
    for (i = 0; i < 3; i++) {
        mu.v[i] = m->origin[i] + t.d[i];
        sv.v[i] = t.m3[i] * inv;
    }
    for (i = 0; i < 6; i++) {
        p[i] = t.m2[i] * inv;
    }
    /* Finite for any accumulator the API built; a corrupted one (garbage
     * bytes) gives E_RANGE, never a NaN or Inf output. */
    ok = sfit_i_finite3(mu.v) && sfit_i_finite3(sv.v) && sfit_i_finite3(p)
         && sfit_i_finite3(&p[3]);
    if (!ok) {
        return SFIT_E_RANGE;
    }
    if (mean != NULL) {
        *mean = mu;
    }
    if (s != NULL) {
        *s = sv;
    }
    if (c != NULL) {
        sfit_i_sym_unpack(p, c);
    }
    return SFIT_OK;
}
