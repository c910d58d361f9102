/* SPDX-License-Identifier: MIT */
/**
 * @file skel_group.c
 * @brief Segments found from the data: markers grouped by the spread of
 * their pairwise distances over the recording (docs/skeleton.md).
 *
 * Spread of a pair: the interdecile range (10th to 90th percentile) of its
 * distance over the frames where both markers are seen; a pair seen
 * together in fewer than SKEL_GROUP_MIN_COMMON frames has no spread.
 * The rigid level b: for every marker the smallest spread to another
 * marker (a marker shares its segment with at least one other), and the
 * median of those over the markers: what a rigid pair shows (noise and
 * skin motion); at least SKEL_GROUP_FLOOR times the median distance
 * between markers (noise-free data, whose rigid spread is float rounding). Clustering: average linkage (the spread between two groups
 * is the mean spread of their pairs with a spread), merging the closest two
 * groups while that is at most the threshold; ties by the lowest marker
 * indices, so the result is deterministic. Threshold: SKEL_GROUP_CUT * b,
 * a fixed multiple of the rigid level (no count given, no gap search: on
 * full-body recordings the merge heights have no clean gap, the largest
 * ratio between consecutive heights fell between limbs and merged forearm
 * and hand; docs/skeleton.md gives the adjusted Rand index of this rule on
 * the shared recordings).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "skel.h"

#define SKEL_GROUP_MIN_COMMON 10
#define SKEL_GROUP_CUT 4.0
#define SKEL_GROUP_FLOOR 1e-3

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* q-quantile of sorted v[0..n-1] (linear interpolation) */
static double quantile(const double *v, long n, double q)
{
    const double pos = q * (double)(n - 1);
    const long i = (long)floor(pos);
    const double w = pos - (double)i;
    if (i + 1 >= n) {
        return v[n - 1];
    }
    return v[i] * (1.0 - w) + v[i + 1] * w;
}

static double dist(const float *a, const float *b)
{
    const double dx = (double)a[0] - (double)b[0], dy = (double)a[1] - (double)b[1],
                 dz = (double)a[2] - (double)b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* Average linkage: merge the closest two clusters while their spread is at
 * most `limit`; heights of the merges into h (at most n - 1). */
static int linkage(const double *spread, int n, double limit, int *cl, double *h)
{
    int i, j, a, b, nh = 0;
    for (i = 0; i < n; i++) {
        cl[i] = i;
    }
    for (;;) {
        int ba = -1, bb = -1;
        double best = HUGE_VAL;
        for (i = 0; i < n; i++) {
            if (cl[i] != i) {
                continue;
            }
            for (j = i + 1; j < n; j++) {
                double sum = 0.0;
                long known = 0;
                if (cl[j] != j) {
                    continue;
                }
                for (a = 0; a < n; a++) {
                    if (cl[a] != i) {
                        continue;
                    }
                    for (b = 0; b < n; b++) {
                        if (cl[b] == j && isfinite(spread[a * n + b])) {
                            sum += spread[a * n + b];
                            known++;
                        }
                    }
                }
                if (known > 0 && sum / (double)known < best) {
                    best = sum / (double)known;
                    ba = i;
                    bb = j;
                }
            }
        }
        if (ba < 0 || best > limit) {
            return nh;
        }
        h[nh++] = best;
        for (a = 0; a < n; a++) {
            if (cl[a] == bb) {
                cl[a] = ba;
            }
        }
    }
}

int skel_group(const skel_rec_t *r, skel_groups_t *g, char *why)
{
    const int n = r->nmark;
    double *spread = NULL, *buf = NULL, *mins = NULL, *h = NULL;
    int *cl = NULL; /* cluster of each marker */
    long nmins = 0;
    int i, j, k, nh;
    memset(g, 0, sizeof *g);
    spread = malloc((size_t)n * (size_t)n * sizeof *spread);
    buf = malloc((size_t)r->nframes * sizeof *buf);
    mins = malloc((size_t)n * sizeof *mins);
    h = malloc((size_t)n * sizeof *h);
    cl = malloc((size_t)n * sizeof *cl);
    if (spread == NULL || buf == NULL || mins == NULL || h == NULL || cl == NULL) {
        (void)snprintf(why, SKEL_ERR, "out of memory");
        goto fail;
    }
    for (i = 0; i < n; i++) {
        spread[i * n + i] = (double)NAN;
        for (j = i + 1; j < n; j++) {
            long m = 0, f;
            for (f = 0; f < r->nframes; f++) {
                const double d = dist(skel_rec_at(r, f, i), skel_rec_at(r, f, j));
                if (isfinite(d)) {
                    buf[m++] = d;
                }
            }
            spread[i * n + j] = spread[j * n + i] = (double)NAN;
            if (m >= SKEL_GROUP_MIN_COMMON) {
                qsort(buf, (size_t)m, sizeof *buf, cmp_double);
                spread[i * n + j] = spread[j * n + i] = quantile(buf, m, 0.9)
                                                        - quantile(buf, m, 0.1);
            }
        }
    }
    for (i = 0; i < n; i++) {
        double best = HUGE_VAL;
        for (j = 0; j < n; j++) {
            if (isfinite(spread[i * n + j]) && spread[i * n + j] < best) {
                best = spread[i * n + j];
            }
        }
        if (best < HUGE_VAL) {
            mins[nmins++] = best;
        }
    }
    if (nmins == 0) {
        (void)snprintf(why, SKEL_ERR, "no two markers seen together in %d frames",
                       SKEL_GROUP_MIN_COMMON);
        goto fail;
    }
    qsort(mins, (size_t)nmins, sizeof *mins, cmp_double);
    g->noise = quantile(mins, nmins, 0.5);
    {   /* floor: a thousandth of the median marker spacing (noise-free data) */
        double *med = malloc((size_t)n * (size_t)n * sizeof *med);
        long nm = 0;
        if (med != NULL) {
            for (i = 0; i < n; i++) {
                for (j = i + 1; j < n; j++) {
                    long m = 0, f;
                    if (!isfinite(spread[i * n + j])) {
                        continue;
                    }
                    for (f = 0; f < r->nframes; f++) {
                        const double d = dist(skel_rec_at(r, f, i), skel_rec_at(r, f, j));
                        if (isfinite(d)) {
                            buf[m++] = d;
                        }
                    }
                    qsort(buf, (size_t)m, sizeof *buf, cmp_double);
                    med[nm++] = quantile(buf, m, 0.5);
                }
            }
            if (nm > 0) {
                qsort(med, (size_t)nm, sizeof *med, cmp_double);
                if (g->noise < SKEL_GROUP_FLOOR * quantile(med, nm, 0.5)) {
                    g->noise = SKEL_GROUP_FLOOR * quantile(med, nm, 0.5);
                }
            }
            free(med);
        }
    }
    nh = linkage(spread, n, HUGE_VAL, cl, h);
    g->threshold = SKEL_GROUP_CUT * g->noise;
    g->gap_lo = g->gap_hi = (double)NAN;
    for (k = 0; k < nh; k++) { /* the merge heights either side of the cut */
        if (h[k] <= g->threshold) {
            g->gap_lo = (isfinite(g->gap_lo) && g->gap_lo > h[k]) ? g->gap_lo : h[k];
        } else if (!isfinite(g->gap_hi) || h[k] < g->gap_hi) {
            g->gap_hi = h[k];
        }
    }
    if (!isfinite(g->gap_lo) || !isfinite(g->gap_hi)) {
        g->gap_lo = g->gap_hi = (double)NAN;
    }
    (void)linkage(spread, n, g->threshold, cl, h);
    for (i = 0; i < n; i++) {
        if (cl[i] == i) {
            const int c = g->n++;
            g->size[c] = 0;
            g->spread[c] = 0.0;
            for (k = 0; k < n; k++) {
                if (cl[k] == i) {
                    int q;
                    for (q = 0; q < g->size[c]; q++) {
                        const double sp = spread[k * n + g->member[c][q]];
                        if (isfinite(sp) && sp > g->spread[c]) {
                            g->spread[c] = sp;
                        }
                    }
                    g->member[c][g->size[c]++] = k;
                }
            }
        }
    }
    free(spread);
    free(buf);
    free(mins);
    free(h);
    free(cl);
    return 0;
fail:
    free(spread);
    free(buf);
    free(mins);
    free(h);
    free(cl);
    return -1;
}
