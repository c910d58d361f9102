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
#define SKEL_GROUP_SPLIT 4.0 /* two cores: merge height over the larger core's spread */
#define SKEL_GROUP_CORE 2    /* markers of a core */
#define SKEL_GROUP_JOINT 0.5 /* a joint marker: spread to the other group, over its own, in rigid levels */

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
 * most `limit` and more than `stop` clusters remain; heights of the merges
 * into h (at most n - 1). A cluster is named by its lowest marker (cl). */
static int linkage(const double *spread, int n, double limit, int stop, int *cl, double *h)
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
        if (ba < 0 || best > limit || n - nh <= stop) {
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

/* Mean spread of the pairs (with a spread) inside the markers mk[0..m-1]
 * whose side[] equals `which`; NaN without such a pair. */
static double inner_mean(const double *spread, int n, const int *mk, const int *side, int m,
                         int which)
{
    double sum = 0.0;
    long known = 0;
    int a, b;
    for (a = 0; a < m; a++) {
        for (b = a + 1; b < m; b++) {
            if (side[a] == which && side[b] == which && isfinite(spread[mk[a] * n + mk[b]])) {
                sum += spread[mk[a] * n + mk[b]];
                known++;
            }
        }
    }
    return known > 0 ? sum / (double)known : (double)NAN;
}

/* The two-cores test: a group whose last merge (average linkage inside the
 * group) joins two parts of at least SKEL_GROUP_CORE markers each, at a
 * height above SKEL_GROUP_SPLIT times the larger of the two parts' own mean
 * pair spread, is two rigid bodies: split it there, and test both parts
 * again. sub: scratch of n * n doubles; cl, h: of n. */
static void split_cores(const double *spread, int n, skel_groups_t *g, double *sub, int *cl,
                        double *h)
{
    int c;
    for (c = 0; c < g->n; c++) {
        int *mk = g->member[c];
        const int m = g->size[c];
        int a, b, np = 0, side[SKEL_MAX_MARK];
        double sum = 0.0, ip, iq, lim;
        long known = 0;
        if (m < 2 * SKEL_GROUP_CORE) {
            continue;
        }
        for (a = 0; a < m; a++) {
            for (b = 0; b < m; b++) {
                sub[a * m + b] = spread[mk[a] * n + mk[b]];
            }
        }
        (void)linkage(sub, m, HUGE_VAL, 2, cl, h);
        for (a = 0; a < m; a++) {
            side[a] = (cl[a] == cl[0]) ? 0 : 1;
            np += side[a] == 0;
        }
        if (np < SKEL_GROUP_CORE || m - np < SKEL_GROUP_CORE) {
            continue;
        }
        for (a = 0; a < m; a++) {
            for (b = 0; b < m; b++) {
                if (side[a] == 0 && side[b] == 1 && isfinite(sub[a * m + b])) {
                    sum += sub[a * m + b];
                    known++;
                }
            }
        }
        ip = inner_mean(spread, n, mk, side, m, 0);
        iq = inner_mean(spread, n, mk, side, m, 1);
        if (known == 0 || !isfinite(ip) || !isfinite(iq)) {
            continue;
        }
        lim = SKEL_GROUP_SPLIT * (ip > iq ? ip : iq);
        if (sum / (double)known <= lim || g->n >= SKEL_MAX_MARK) {
            continue;
        }
        { /* part 1 becomes a new group; part 0 stays in place (test again) */
            const int d = g->n++;
            int k0 = 0;
            g->size[d] = 0;
            for (a = 0; a < m; a++) {
                if (side[a] == 1) {
                    g->member[d][g->size[d]++] = mk[a];
                } else {
                    mk[k0++] = mk[a];
                }
            }
            g->size[c] = k0;
            g->nsplit++;
            c--;
        }
    }
}

/* Groups in order of their first marker, members ascending. */
static void sort_groups(skel_groups_t *g)
{
    int c, d, q;
    for (c = 0; c < g->n; c++) {
        for (q = 1; q < g->size[c]; q++) {
            const int v = g->member[c][q];
            for (d = q; d > 0 && g->member[c][d - 1] > v; d--) {
                g->member[c][d] = g->member[c][d - 1];
            }
            g->member[c][d] = v;
        }
    }
    for (c = 1; c < g->n; c++) {
        for (d = c; d > 0 && g->member[d][0] < g->member[d - 1][0]; d--) {
            int t[SKEL_MAX_MARK], ts = g->size[d];
            memcpy(t, g->member[d], sizeof t);
            memcpy(g->member[d], g->member[d - 1], sizeof t);
            memcpy(g->member[d - 1], t, sizeof t);
            g->size[d] = g->size[d - 1];
            g->size[d - 1] = ts;
        }
    }
}

/* Mean spread between the markers x[0..nx-1] and y[0..ny-1] (pairs with a
 * spread); NaN without one. */
static double cross_mean(const double *spread, int n, const int *x, int nx, const int *y, int ny)
{
    double sum = 0.0;
    long known = 0;
    int a, b;
    for (a = 0; a < nx; a++) {
        for (b = 0; b < ny; b++) {
            if (x[a] != y[b] && isfinite(spread[x[a] * n + y[b]])) {
                sum += spread[x[a] * n + y[b]];
                known++;
            }
        }
    }
    return known > 0 ? sum / (double)known : (double)NAN;
}

/* Median over the frames of the distance from the group's centroid to the
 * centroid of all markers seen (HUGE_VAL when never seen). buf: nframes. */
static double centre_offset(const skel_rec_t *r, const int *mk, int m, double *buf)
{
    long f, nb = 0;
    for (f = 0; f < r->nframes; f++) {
        double all[3] = {0.0, 0.0, 0.0}, gc[3] = {0.0, 0.0, 0.0}, na = 0.0, ng = 0.0, d2 = 0.0;
        int i, k;
        for (i = 0; i < r->nmark; i++) {
            const float *p = skel_rec_at(r, f, i);
            if (isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2])) {
                for (k = 0; k < 3; k++) {
                    all[k] += (double)p[k];
                }
                na += 1.0;
            }
        }
        for (i = 0; i < m; i++) {
            const float *p = skel_rec_at(r, f, mk[i]);
            if (isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2])) {
                for (k = 0; k < 3; k++) {
                    gc[k] += (double)p[k];
                }
                ng += 1.0;
            }
        }
        if (ng > 0.0) {
            for (k = 0; k < 3; k++) {
                const double d = gc[k] / ng - all[k] / na;
                d2 += d * d;
            }
            buf[nb++] = sqrt(d2);
        }
    }
    if (nb == 0) {
        return HUGE_VAL;
    }
    qsort(buf, (size_t)nb, sizeof *buf, cmp_double);
    return quantile(buf, nb, 0.5);
}

/* Joint markers (docs/skeleton.md): a marker of a group of 2 or more whose
 * mean spread to a group of 1 or 2 markers is within the threshold and at
 * most SKEL_GROUP_JOINT rigid levels above its mean spread to the rest of
 * its own group keeps its distances to both about equally well: it sits at
 * their joint, and goes to the proximal one (the lower depth in the
 * minimum spanning tree of the groups' mean spreads, grown from the group
 * nearest the centre of all markers), as anatomical landmarks at a joint
 * (epicondyles, malleoli) belong to the proximal bone. Decided on the
 * groups as they are, then applied. Returns the markers moved. */
static int joint_markers(const skel_rec_t *r, const double *spread, int n, skel_groups_t *g,
                         double *buf)
{
    int depth[SKEL_MAX_MARK], in[SKEL_MAX_MARK], dest[SKEL_MAX_MARK], of[SKEL_MAX_MARK];
    int c, d, i, root = 0, moved = 0;
    double best = HUGE_VAL;
    for (c = 0; c < g->n; c++) {
        const double off = centre_offset(r, g->member[c], g->size[c], buf);
        if (off < best) {
            best = off;
            root = c;
        }
        depth[c] = -1;
        in[c] = 0;
        for (i = 0; i < g->size[c]; i++) {
            of[g->member[c][i]] = c;
        }
    }
    depth[root] = 0;
    in[root] = 1;
    for (;;) { /* Prim: the cheapest link from the tree to a group outside */
        int bp = -1, bc = -1;
        double bw = HUGE_VAL;
        for (c = 0; c < g->n; c++) {
            if (!in[c]) {
                continue;
            }
            for (d = 0; d < g->n; d++) {
                double w;
                if (in[d]) {
                    continue;
                }
                w = cross_mean(spread, n, g->member[c], g->size[c], g->member[d], g->size[d]);
                if (isfinite(w) && w < bw) {
                    bw = w;
                    bp = c;
                    bc = d;
                }
            }
        }
        if (bc < 0) {
            break;
        }
        in[bc] = 1;
        depth[bc] = depth[bp] + 1;
    }
    for (i = 0; i < n; i++) {
        const int c0 = of[i];
        double own, bw = HUGE_VAL;
        dest[i] = -1;
        if (g->size[c0] < 2 || depth[c0] < 0) {
            continue;
        }
        own = cross_mean(spread, n, &i, 1, g->member[c0], g->size[c0]);
        if (!isfinite(own)) {
            continue;
        }
        for (d = 0; d < g->n; d++) {
            double w;
            if (d == c0 || g->size[d] > 2 || depth[d] < 0 || depth[d] >= depth[c0]) {
                continue;
            }
            w = cross_mean(spread, n, &i, 1, g->member[d], g->size[d]);
            if (isfinite(w) && w <= g->threshold && w <= own + SKEL_GROUP_JOINT * g->noise
                && w < bw) {
                bw = w;
                dest[i] = d;
            }
        }
    }
    for (i = 0; i < n; i++) { /* apply */
        if (dest[i] >= 0) {
            const int c0 = of[i];
            int k0 = 0, q;
            for (q = 0; q < g->size[c0]; q++) {
                if (g->member[c0][q] != i) {
                    g->member[c0][k0++] = g->member[c0][q];
                }
            }
            g->size[c0] = k0;
            g->member[dest[i]][g->size[dest[i]]++] = i;
            moved++;
        }
    }
    for (c = 0, d = 0; c < g->n; c++) { /* drop emptied groups */
        if (g->size[c] > 0) {
            if (d != c) {
                memcpy(g->member[d], g->member[c], sizeof g->member[d]);
                g->size[d] = g->size[c];
            }
            d++;
        }
    }
    g->n = d;
    return moved;
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
    nh = linkage(spread, n, HUGE_VAL, 1, cl, h);
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
    (void)linkage(spread, n, g->threshold, 1, cl, h);
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
    {
        double *sub = malloc((size_t)n * (size_t)n * sizeof *sub);
        if (sub == NULL) {
            (void)snprintf(why, SKEL_ERR, "out of memory");
            goto fail;
        }
        split_cores(spread, n, g, sub, cl, h);
        free(sub);
    }
    g->nmoved = joint_markers(r, spread, n, g, buf);
    sort_groups(g);
    for (i = 0; i < g->n; i++) { /* each group's largest pair spread */
        int q, u;
        g->spread[i] = 0.0;
        for (q = 0; q < g->size[i]; q++) {
            for (u = q + 1; u < g->size[i]; u++) {
                const double sp = spread[g->member[i][q] * n + g->member[i][u]];
                if (isfinite(sp) && sp > g->spread[i]) {
                    g->spread[i] = sp;
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
