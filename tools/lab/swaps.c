/* SPDX-License-Identifier: MIT */
/** @file swaps.c  Label swaps within a rigid cluster (swaps.h). No I/O. */
#include "swaps.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Distances of one frame: d[u][v] (NaN = a marker not seen). Passed without
 * const: C99 does not convert double (*)[8] to const double (*)[8]. */
typedef double dist_t[SWAPS_MAX_MARKERS][SWAPS_MAX_MARKERS];

static int seen(const sfit_vec3_t *p)
{
    return isfinite(p->v[0]) && isfinite(p->v[1]) && isfinite(p->v[2]);
}

/* Distances of frame f; returns the markers seen. */
static int frame_dist(const sfit_vec3_t *xyz, long f, int stride, int off, int m, dist_t d)
{
    const sfit_vec3_t *row = xyz + (size_t)f * (size_t)stride + (size_t)off;
    int u, v, n = 0;
    for (u = 0; u < m; u++) {
        n += seen(&row[u]);
    }
    for (u = 0; u < m; u++) {
        d[u][u] = 0.0;
        for (v = u + 1; v < m; v++) {
            double s = 0.0;
            int i;
            if (!seen(&row[u]) || !seen(&row[v])) {
                d[u][v] = d[v][u] = (double)NAN;
                continue;
            }
            for (i = 0; i < 3; i++) {
                const double e = (double)row[u].v[i] - (double)row[v].v[i];
                s += e * e;
            }
            d[u][v] = d[v][u] = sqrt(s);
        }
    }
    return n;
}

/* The distances of a frame packed (pairs u < v in order) and back: the
 * frames' distances are computed once and kept (dc). */
static void dist_put(dist_t d, int m, double *row)
{
    int u, v, k = 0;
    for (u = 0; u < m; u++) {
        for (v = u + 1; v < m; v++) {
            row[k++] = d[u][v];
        }
    }
}

static void dist_get(const double *row, int m, dist_t d)
{
    int u, v, k = 0;
    for (u = 0; u < m; u++) {
        d[u][u] = 0.0;
        for (v = u + 1; v < m; v++) {
            d[u][v] = d[v][u] = row[k++];
        }
    }
}

/* The candidates: as given, every exchange of two labels, both rotations
 * of every three labels (lab[u]: the marker the point labelled u is). */
static int make_cands(int m, swaps_cand_t *c)
{
    int n = 0, i, j, k, u;
    memset(c, 0, sizeof *c * SWAPS_MAX_CAND);
    for (u = 0; u < m; u++) {
        c[0].lab[u] = (unsigned char)u;
    }
    n = 1;
    for (i = 0; i < m; i++) {
        for (j = i + 1; j < m; j++) {
            c[n] = c[0];
            c[n].lab[i] = (unsigned char)j;
            c[n].lab[j] = (unsigned char)i;
            c[n++].moved = 2;
        }
    }
    for (i = 0; i < m; i++) {
        for (j = i + 1; j < m; j++) {
            for (k = j + 1; k < m; k++) {
                c[n] = c[0]; /* i is j, j is k, k is i */
                c[n].lab[i] = (unsigned char)j;
                c[n].lab[j] = (unsigned char)k;
                c[n].lab[k] = (unsigned char)i;
                c[n++].moved = 3;
                c[n] = c[0]; /* i is k, k is j, j is i */
                c[n].lab[i] = (unsigned char)k;
                c[n].lab[k] = (unsigned char)j;
                c[n].lab[j] = (unsigned char)i;
                c[n++].moved = 3;
            }
        }
    }
    return n;
}

/* sum over the pairs seen in d (and with a reference) of (a - b)^2, and
 * how many pairs; a = d[u][v] (use_d) or ref[la u][la v]; b = ref[lb u][lb v]. */
static double pair_ss(dist_t d, dist_t ref, int m, const unsigned char *la,
                      const unsigned char *lb, int use_d, int *npairs)
{
    double s = 0.0;
    int u, v, n = 0;
    for (u = 0; u < m; u++) {
        for (v = u + 1; v < m; v++) {
            double a, b;
            if (isnan(d[u][v])) {
                continue;
            }
            a = use_d ? d[u][v] : ref[la[u]][la[v]];
            b = ref[lb[u]][lb[v]];
            if (isnan(a) || isnan(b)) {
                continue;
            }
            s += (a - b) * (a - b);
            n++;
        }
    }
    if (npairs != NULL) {
        *npairs = n;
    }
    return s;
}

/* The k-th smallest of x[0..n-1] (0-based; x reordered so that x[k] holds
 * it, smaller values before, larger after): Hoare's selection, expected
 * O(n) where a sort was O(n log n). The values hold no NaN. */
static double select_kth(double *x, size_t n, size_t k)
{
    size_t lo = 0u, hi = n - 1u;
    while (lo < hi) {
        const double pivot = x[lo + (hi - lo) / 2u];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (x[i] < pivot) {
                i++;
            }
            while (x[j] > pivot) {
                j--;
            }
            if (i <= j) {
                const double t = x[i];
                x[i] = x[j];
                x[j] = t;
                i++;
                if (j == 0u) {
                    break;
                }
                j--;
            }
        }
        /* [lo, j] <= pivot <= [i, hi]; between them: the pivot's value */
        if (k <= j && j != (size_t)-1) {
            hi = j;
        } else if (k >= i) {
            lo = i;
        } else {
            break;
        }
    }
    return x[k];
}

/* Median of n values (reordered in place); NaN when n == 0. The same
 * order statistics as a sort gives, so the same value. */
static double median(double *x, size_t n)
{
    double hi, lo;
    size_t i;
    if (n == 0u) {
        return (double)NAN;
    }
    hi = select_kth(x, n, n / 2u);
    if (n % 2u) {
        return hi;
    }
    lo = x[0]; /* the largest of the lower half x[0 .. n/2 - 1] */
    for (i = 1u; i < n / 2u; i++) {
        if (x[i] > lo) {
            lo = x[i];
        }
    }
    return 0.5 * (lo + hi);
}

/* Which relabellings a frame can tell from the labels as given depends
 * only on its markers seen (against a fixed reference and threshold):
 * computed once per set of markers seen and kept here. */
typedef struct ok_cache {
    int prune; /* every pair of the reference known: see best_label */
    unsigned char known[1u << SWAPS_MAX_MARKERS];
    /* squared distance of each relabelling's pattern from the labels as
     * given, over the pairs seen */
    double pat[1u << SWAPS_MAX_MARKERS][SWAPS_MAX_CAND];
} ok_cache_t;

/* Start the cache for reference ref. */
static void cache_reset(ok_cache_t *oc, dist_t ref, int m)
{
    int u, v;
    memset(oc->known, 0, sizeof oc->known);
    oc->prune = 1;
    for (u = 0; u < m; u++) {
        for (v = u + 1; v < m; v++) {
            oc->prune &= !isnan(ref[u][v]);
        }
    }
}

/* The markers of d that are in a pair seen (a pair is seen when both are). */
static unsigned seen_mask(dist_t d, int m)
{
    unsigned mask = 0u;
    int u, v;
    for (u = 0; u < m; u++) {
        for (v = u + 1; v < m; v++) {
            if (!isnan(d[u][v])) {
                mask |= (1u << u) | (1u << v);
            }
        }
    }
    return mask;
}

/* Best labelling of frame d against ref: the least cost among the labels
 * as given and the relabellings whose pattern (over the pairs seen) is at
 * least `decide` from it. Returns the candidate index; *cost its cost,
 * *np the pairs, *rival 1 if another decidable relabelling lies within
 * `decide` of the winner. oc: the cache for this ref and decide. */
static int best_label(dist_t d, dist_t ref, int m, const swaps_cand_t *c,
                      int nc, double decide, ok_cache_t *oc, double *cost, int *np,
                      int *rival)
{
    const unsigned mask = seen_mask(d, m);
    double *pat = oc->pat[mask];
    double best_cost = pair_ss(d, ref, m, NULL, c[0].lab, 1, np);
    int best = 0, k;
    const double dd = decide * decide;
    /* no need to compute a cost that cannot win: with every pair of ref
     * known, the three sums run over the same pairs (those d sees) and
     * the triangle inequality sqrt(e_k) >= sqrt(pat_k) - sqrt(e_0) holds,
     * so pat_k > 4.5 e_0 (a margin far beyond rounding) gives e_k > e_0
     * >= the best so far */
    const double far = oc->prune ? 4.5 * best_cost : (double)INFINITY;
    if (!oc->known[mask]) {
        pat[0] = 0.0;
        for (k = 1; k < nc; k++) {
            pat[k] = pair_ss(d, ref, m, c[k].lab, c[0].lab, 0, NULL);
        }
        oc->known[mask] = 1u;
    }
    for (k = 1; k < nc; k++) {
        double e;
        if (!(pat[k] >= dd) || pat[k] > far) {
            continue;
        }
        e = pair_ss(d, ref, m, NULL, c[k].lab, 1, NULL);
        if (e < best_cost) {
            best_cost = e;
            best = k;
        }
    }
    *rival = 0;
    if (best != 0) {
        for (k = 1; k < nc && !*rival; k++) {
            if (k != best && pat[k] >= dd
                && pair_ss(d, ref, m, c[k].lab, c[best].lab, 0, NULL) < dd) {
                *rival = 1;
            }
        }
    }
    *cost = best_cost;
    return best;
}

/* Per-pair median of the frames' distances, relabelled by lab[k] (NULL:
 * as given), over frames fr[0..n-1]; buf holds n * SWAPS_MAX_PAIRS
 * values. Pairs never seen get NaN. */
static void pair_medians(const double *dc, int m, size_t n, const int *lab,
                         const swaps_cand_t *c, double *buf, dist_t ref)
{
    size_t cnt[SWAPS_MAX_MARKERS][SWAPS_MAX_MARKERS];
    size_t k;
    int a, b, u, v;
    memset(cnt, 0, sizeof cnt);
    for (k = 0; k < n; k++) {
        dist_t d;
        const unsigned char *l = c[lab != NULL ? lab[k] : 0].lab;
        dist_get(dc + k * SWAPS_MAX_PAIRS, m, d);
        for (u = 0; u < m; u++) {
            for (v = u + 1; v < m; v++) {
                if (!isnan(d[u][v])) { /* true labels (l[u], l[v]), in order */
                    a = l[u] < l[v] ? l[u] : l[v];
                    b = l[u] < l[v] ? l[v] : l[u];
                    buf[(size_t)(a * m - a * (a + 1) / 2 + (b - a - 1)) * n + cnt[a][b]++] =
                        d[u][v];
                }
            }
        }
    }
    for (a = 0; a < m; a++) {
        ref[a][a] = 0.0;
        for (b = a + 1; b < m; b++) {
            ref[a][b] = ref[b][a] =
                median(buf + (size_t)(a * m - a * (a + 1) / 2 + (b - a - 1)) * n, cnt[a][b]);
        }
    }
}

/* Pooled robust scale: 1.4826 median |d - R| over the frames' pairs seen,
 * relabelled by lab (NULL: as given); at least the floor. */
static double pooled_scale(const double *dc, int m, size_t n, const int *lab,
                           const swaps_cand_t *c, dist_t ref, double *buf)
{
    size_t k, cnt = 0;
    double med_ref, s;
    double rd[SWAPS_MAX_PAIRS];
    size_t nr = 0;
    int u, v;
    for (k = 0; k < n; k++) {
        dist_t d;
        const unsigned char *l = c[lab != NULL ? lab[k] : 0].lab;
        dist_get(dc + k * SWAPS_MAX_PAIRS, m, d);
        for (u = 0; u < m; u++) {
            for (v = u + 1; v < m; v++) {
                const double r = ref[l[u]][l[v]];
                if (!isnan(d[u][v]) && !isnan(r)) {
                    buf[cnt++] = fabs(d[u][v] - r);
                }
            }
        }
    }
    for (u = 0; u < m; u++) {
        for (v = u + 1; v < m; v++) {
            if (!isnan(ref[u][v])) {
                rd[nr++] = ref[u][v];
            }
        }
    }
    med_ref = median(rd, nr);
    s = 1.4826 * median(buf, cnt);
    if (!(s >= SWAPS_SCALE_FLOOR * med_ref)) {
        s = SWAPS_SCALE_FLOOR * med_ref;
    }
    return s;
}

const char *swaps_why(int why)
{
    switch (why) {
    case SWAPS_WHY_CHECKED:
        return "checked";
    case SWAPS_WHY_FEW_MARKERS:
        return "fewer than 3 markers";
    case SWAPS_WHY_FEW_FRAMES:
        return "too few frames with 3 markers seen";
    default:
        return "degenerate: the markers keep no distance apart";
    }
}

void swaps_free(swaps_t *s)
{
    free(s->status);
    s->status = NULL;
}

long swaps_runs(const swaps_t *s, int st, long (*runs)[2], long max)
{
    long f, n = 0, start = -1;
    if (s->status == NULL) {
        return 0;
    }
    for (f = 0; f <= s->nframes; f++) {
        const int here = (f < s->nframes) && s->status[f] == st;
        if (here && start < 0) {
            start = f;
        } else if (!here && start >= 0) {
            if (n < max) {
                runs[n][0] = start;
                runs[n][1] = f - 1;
            }
            n++;
            start = -1;
        }
    }
    return n;
}

/* Steps 1-3 of swaps_run on the frames fr (buffers allocated by it). */
static void checked(sfit_vec3_t *xyz, int stride, int off, int m, long first, long last,
                    int repair, swaps_t *out, long *fr, int *lab, double *buf, ok_cache_t *oc,
                    double *dc)
{
    size_t n = 0, na, k;
    dist_t anchor;
    double s0;
    long f;
    int c;

    for (f = first; f <= last; f++) {
        dist_t d;
        if (frame_dist(xyz, f, stride, off, m, d) >= 3) {
            dist_put(d, m, dc + n * SWAPS_MAX_PAIRS);
            fr[n++] = f;
        }
    }
    if ((long)n < SWAPS_MIN_FRAMES) {
        return;
    }
    /* 1. the anchor: the start of the range, as given */
    na = (n < (size_t)SWAPS_ANCHOR) ? n : (size_t)SWAPS_ANCHOR;
    pair_medians(dc, m, na, NULL, out->cand, buf, anchor);
    {
        dist_t all; /* pairs the anchor never sees: their median over all frames */
        int u, v, gap = 0;
        for (u = 0; u < m; u++) {
            for (v = u + 1; v < m; v++) {
                gap |= isnan(anchor[u][v]);
            }
        }
        if (gap) {
            pair_medians(dc, m, n, NULL, out->cand, buf, all);
            for (u = 0; u < m; u++) {
                for (v = u + 1; v < m; v++) {
                    if (isnan(anchor[u][v])) {
                        anchor[u][v] = anchor[v][u] = all[u][v];
                    }
                }
            }
        }
    }
    s0 = pooled_scale(dc, m, na, NULL, out->cand, anchor, buf);
    if (!(s0 > 0.0) || !isfinite(s0)) { /* markers on one point: nothing to tell */
        out->why = SWAPS_WHY_DEGENERATE;
        return;
    }
    /* 2. provisional labels, reference and scale */
    cache_reset(oc, anchor, m);
    for (k = 0; k < n; k++) {
        dist_t d;
        double cost;
        int np, rival;
        dist_get(dc + k * SWAPS_MAX_PAIRS, m, d);
        lab[k] = best_label(d, anchor, m, out->cand, out->ncand, 2.0 * SWAPS_Z * s0, oc,
                            &cost, &np, &rival);
    }
    pair_medians(dc, m, n, lab, out->cand, buf, out->ref);
    out->scale = pooled_scale(dc, m, n, lab, out->cand, out->ref, buf);
    if (!(out->scale > 0.0) || !isfinite(out->scale)) {
        out->why = SWAPS_WHY_DEGENERATE;
        return;
    }
    out->decide = 2.0 * SWAPS_Z * out->scale;
    for (c = 0; c < out->ncand; c++) {
        dist_t full;
        int u, v;
        for (u = 0; u < m; u++) {
            for (v = 0; v < m; v++) {
                full[u][v] = 0.0; /* every pair "seen" */
            }
        }
        out->cand[c].pattern =
            sqrt(pair_ss(full, out->ref, m, out->cand[c].lab, out->cand[0].lab, 0, NULL));
        out->cand[c].decidable = c == 0 || out->cand[c].pattern >= out->decide;
    }
    /* no fit: farther from the best labelling than half the nearest
     * decidable relabelling is from the labels as given, and than z s RMS */
    out->misfit = 0.0;
    for (c = 1; c < out->ncand; c++) {
        if (out->cand[c].decidable && (out->misfit == 0.0 || out->cand[c].pattern < out->misfit)) {
            out->misfit = out->cand[c].pattern;
        }
    }
    out->misfit *= 0.5;
    /* 3. the decision, frame by frame */
    cache_reset(oc, out->ref, m); /* another reference and threshold */
    out->checked = 1;
    out->why = SWAPS_WHY_CHECKED;
    out->repaired = repair != 0;
    for (k = 0; k < n; k++) {
        dist_t d;
        double cost;
        int np, rival, b;
        sfit_vec3_t *row = xyz + (size_t)fr[k] * (size_t)stride + (size_t)off;
        dist_get(dc + k * SWAPS_MAX_PAIRS, m, d);
        b = best_label(d, out->ref, m, out->cand, out->ncand, out->decide, oc, &cost, &np,
                       &rival);
        out->frames_checked++;
        if (np > 0 && cost > (double)np * SWAPS_Z * SWAPS_Z * out->scale * out->scale
            && cost > out->misfit * out->misfit) {
            out->status[fr[k]] = SWAPS_NO_FIT;
            out->frames_no_fit++;
        } else if (rival) {
            out->status[fr[k]] = SWAPS_AMBIGUOUS;
            out->frames_ambiguous++;
        } else {
            out->status[fr[k]] = (signed short)b;
            out->cand[b].count++;
            if (b != 0) {
                out->frames_swapped++;
            }
        }
        if (!repair) {
            continue;
        }
        if (out->status[fr[k]] < 0) {
            int u, i;
            for (u = 0; u < m; u++) {
                for (i = 0; i < 3; i++) {
                    row[u].v[i] = NAN;
                }
            }
        } else if (b != 0) {
            sfit_vec3_t tmp[SWAPS_MAX_MARKERS];
            int u;
            memcpy(tmp, row, (size_t)m * sizeof *row); /* lab is a permutation: all rewritten */
            for (u = 0; u < m; u++) {
                tmp[out->cand[b].lab[u]] = row[u];
            }
            memcpy(row, tmp, (size_t)m * sizeof *row);
        }
    }
}

int swaps_run(sfit_vec3_t *xyz, long nframes, int stride, int off, int m, long first,
                  long last, int repair, swaps_t *out)
{
    long *fr = NULL, f;
    int *lab = NULL;
    double *buf = NULL;
    ok_cache_t *oc = NULL;
    double *dc = NULL; /* the distances of frame fr[k] at dc + k MAX_PAIRS */
    int rc = -1;

    memset(out, 0, sizeof *out);
    out->m = m;
    if (xyz == NULL || nframes < 0 || m < 1 || m > SWAPS_MAX_MARKERS || off < 0
        || off + m > stride) {
        return -1;
    }
    if (last < 0 || last >= nframes) {
        last = nframes - 1;
    }
    if (first < 0) {
        first = 0;
    }
    out->first = first;
    out->last = last;
    out->nframes = nframes;
    out->status = malloc(((size_t)nframes + 1u) * sizeof *out->status);
    if (out->status == NULL) {
        return -1;
    }
    for (f = 0; f < nframes; f++) {
        out->status[f] = SWAPS_UNCHECKED;
    }
    out->ncand = make_cands(m, out->cand);
    out->why = SWAPS_WHY_FEW_MARKERS;
    if (m < 3) {
        return 0;
    }
    out->why = SWAPS_WHY_FEW_FRAMES;
    if (first > last) {
        return 0;
    }
    /* the frames with >= 3 markers seen */
    fr = malloc(((size_t)(last - first) + 1u) * sizeof *fr);
    lab = malloc(((size_t)(last - first) + 1u) * sizeof *lab);
    buf = malloc(((size_t)(last - first) + 1u) * SWAPS_MAX_PAIRS * sizeof *buf);
    oc = malloc(sizeof *oc);
    dc = malloc(((size_t)(last - first) + 1u) * SWAPS_MAX_PAIRS * sizeof *dc);
    if (fr != NULL && lab != NULL && buf != NULL && oc != NULL && dc != NULL) {
        checked(xyz, stride, off, m, first, last, repair, out, fr, lab, buf, oc, dc);
        rc = 0;
    }
    free(fr);
    free(lab);
    free(buf);
    free(oc);
    free(dc);
    return rc;
}

