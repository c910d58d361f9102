/* SPDX-License-Identifier: MIT */
/**
 * @file skel_tree.c
 * @brief Segment poses, the joint cost of every pair, the tree (minimum
 * spanning tree), the root, and the skeleton's motion (docs/skeleton.md).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit_joint.h"
#include "sfit/sfit_mat3.h"
#include "skel.h"

/* ------------------------------------------------------------ 3x3 help */

static void mat_tmul(const double a[9], const double b[9], double c[9]) /* c = a^T b */
{
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            c[i * 3 + j] = a[0 * 3 + i] * b[0 * 3 + j] + a[1 * 3 + i] * b[1 * 3 + j]
                           + a[2 * 3 + i] * b[2 * 3 + j];
        }
    }
}

static void mat_mul(const double a[9], const double b[9], double c[9]) /* c = a b */
{
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            c[i * 3 + j] = a[i * 3 + 0] * b[0 * 3 + j] + a[i * 3 + 1] * b[1 * 3 + j]
                           + a[i * 3 + 2] * b[2 * 3 + j];
        }
    }
}

static void mat_vec(const double a[9], const double x[3], double y[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        y[i] = a[i * 3 + 0] * x[0] + a[i * 3 + 1] * x[1] + a[i * 3 + 2] * x[2];
    }
}

/* Nearest rotation by Newton's polar iteration R <- (R + R^-T) / 2. */
static void orthonormalize(double r[9])
{
    int it, i;
    for (it = 0; it < 3; it++) {
        double inv_t[9], det;
        /* cofactor matrix / det = R^-T */
        inv_t[0] = r[4] * r[8] - r[5] * r[7];
        inv_t[1] = r[5] * r[6] - r[3] * r[8];
        inv_t[2] = r[3] * r[7] - r[4] * r[6];
        inv_t[3] = r[2] * r[7] - r[1] * r[8];
        inv_t[4] = r[0] * r[8] - r[2] * r[6];
        inv_t[5] = r[1] * r[6] - r[0] * r[7];
        inv_t[6] = r[1] * r[5] - r[2] * r[4];
        inv_t[7] = r[2] * r[3] - r[0] * r[5];
        inv_t[8] = r[0] * r[4] - r[1] * r[3];
        det = r[0] * inv_t[0] + r[1] * inv_t[1] + r[2] * inv_t[2];
        for (i = 0; i < 9; i++) {
            r[i] = 0.5 * (r[i] + inv_t[i] / det);
        }
    }
}

void skel_free(skel_t *s)
{
    free(s->pose_ok);
    free(s->pose);
    free(s->rel);
    free(s->root_t);
    free(s->jc);
    free(s->ends);
    free(s->fit_rms);
    free(s->fit_used);
    free(s->fpose);
    s->fpose = NULL;
    s->fit_rms = NULL;
    s->fit_used = NULL;
    s->pose_ok = NULL;
    s->pose = s->rel = s->root_t = s->jc = s->ends = NULL;
}

/* --------------------------------------------------------------- poses */

int skel_poses(skel_t *s, char *why)
{
    const skel_rec_t *r = s->rec;
    const long nf = r->nframes;
    sfit_vec3_t *fr;
    int k;
    s->pose_ok = calloc((size_t)nf * (size_t)s->nseg, 1u);
    s->pose = calloc((size_t)nf * (size_t)s->nseg * 12u, sizeof *s->pose);
    s->fit_rms = calloc((size_t)nf * (size_t)s->nseg, sizeof *s->fit_rms);
    s->fit_used = calloc((size_t)nf * (size_t)s->nseg, 1u);
    s->fpose = calloc((size_t)nf * (size_t)s->nseg, sizeof *s->fpose);
    fr = malloc((size_t)nf * SFIT_CLUSTER_MAX_MARKERS * sizeof *fr);
    if (s->pose_ok == NULL || s->pose == NULL || s->fit_rms == NULL || s->fit_used == NULL
        || s->fpose == NULL || fr == NULL) {
        free(fr);
        (void)snprintf(why, SKEL_ERR, "out of memory");
        return -1;
    }
    for (k = 0; k < s->nseg; k++) {
        skel_seg_t *g = &s->seg[k];
        const int nreal = g->nm < SFIT_CLUSTER_MAX_MARKERS ? g->nm : SFIT_CLUSTER_MAX_MARKERS;
        const int np = (g->vpar >= 0 && nreal < SFIT_CLUSTER_MAX_MARKERS) ? nreal + 1 : nreal;
        long f, moves = 0;
        double path = 0.0;
        int i;
        sfit_status_t st;
        g->npose = np;
        for (f = 0; f < nf; f++) {
            for (i = 0; i < nreal; i++) {
                const float *p = skel_rec_at(r, f, g->mk[i]);
                fr[f * np + i].v[0] = p[0];
                fr[f * np + i].v[1] = p[1];
                fr[f * np + i].v[2] = p[2];
            }
            if (np > nreal) { /* the joint centre carried by the segment vpar */
                const unsigned char ok = s->pose_ok[(size_t)f * (size_t)s->nseg + (size_t)g->vpar];
                const double *q = &s->pose[((size_t)f * (size_t)s->nseg + (size_t)g->vpar) * 12u];
                for (i = 0; i < 3; i++) {
                    fr[f * np + nreal].v[i] =
                        ok ? (float)(q[i * 3] * g->vc[0] + q[i * 3 + 1] * g->vc[1]
                                     + q[i * 3 + 2] * g->vc[2] + q[9 + i])
                           : NAN;
                }
            }
        }
        st = sfit_cluster_from_frames(&g->tpl, fr, (size_t)nf, (size_t)np, NULL);
        g->tpl_ok = (st == SFIT_OK);
        g->seen = 0;
        if (!g->tpl_ok) {
            continue;
        }
        for (f = 0; f < nf; f++) {
            sfit_pose_t po;
            sfit_cluster_fit_t fit;
            if (sfit_cluster_register(&g->tpl, &fr[f * np], (size_t)np, &po, &fit) == SFIT_OK) {
                s->fit_rms[(size_t)f * (size_t)s->nseg + (size_t)k] = fit.rms;
                s->fit_used[(size_t)f * (size_t)s->nseg + (size_t)k] = (unsigned char)fit.used;
                s->fpose[(size_t)f * (size_t)s->nseg + (size_t)k] = po;
                double *q = &s->pose[((size_t)f * (size_t)s->nseg + (size_t)k) * 12u];
                for (i = 0; i < 9; i++) {
                    q[i] = (double)po.r.m[i];
                }
                orthonormalize(q);
                for (i = 0; i < 3; i++) {
                    q[9 + i] = (double)po.t.v[i];
                }
                s->pose_ok[(size_t)f * (size_t)s->nseg + (size_t)k] = 1u;
                g->seen++;
            }
        }
        /* mean speed of the origin over consecutive frames of a trial */
        {
            int t;
            for (t = 0; t < r->nfiles; t++) {
                for (f = r->start[t] + 1; f < r->start[t + 1]; f++) {
                    if (s->pose_ok[(size_t)f * (size_t)s->nseg + (size_t)k]
                        && s->pose_ok[(size_t)(f - 1) * (size_t)s->nseg + (size_t)k]) {
                        const double *a = &s->pose[((size_t)f * (size_t)s->nseg + (size_t)k) * 12u];
                        const double *b = a - (size_t)s->nseg * 12u;
                        path += sqrt((a[9] - b[9]) * (a[9] - b[9]) + (a[10] - b[10]) * (a[10] - b[10])
                                     + (a[11] - b[11]) * (a[11] - b[11]));
                        moves++;
                    }
                }
            }
        }
        g->speed = moves > 0 ? path / (double)moves : HUGE_VAL;
    }
    free(fr);
    return 0;
}

static const double *pose_at(const skel_t *s, long f, int k)
{
    return s->pose_ok[(size_t)f * (size_t)s->nseg + (size_t)k]
               ? &s->pose[((size_t)f * (size_t)s->nseg + (size_t)k) * 12u]
               : NULL;
}

/* ------------------------------------------------------ 2-marker groups */

/* Sphere route of group g's markers in segment a's frame: centre and cost. */
static int sphere_route(const skel_t *s, int a, const int *mk, int nmk, double c[3],
                        double *cost, double *radius)
{
    const skel_rec_t *r = s->rec;
    const skel_seg_t *ga = &s->seg[a];
    const int np = ga->nm < SFIT_CLUSTER_MAX_MARKERS ? ga->nm : SFIT_CLUSTER_MAX_MARKERS;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_t *j = malloc(sizeof *j);
    sfit_joint_result_t res;
    sfit_vec3_t par[SFIT_CLUSTER_MAX_MARKERS], chi[SFIT_JOINT_MAX_CHILD];
    double sum[SFIT_JOINT_MAX_CHILD], sum2 = 0.0, cnt[SFIT_JOINT_MAX_CHILD], tot = 0.0;
    long f;
    int i, k, pass;
    if (j == NULL || np > ga->npose || nmk > SFIT_JOINT_MAX_CHILD) {
        free(j);
        return -1;
    }
    cfg.n_child = (uint32_t)nmk;
    if (sfit_joint_init(j, &ga->tpl, &cfg) != SFIT_OK) {
        free(j);
        return -1;
    }
    for (f = 0; f < r->nframes; f++) {
        sfit_pose_t po;
        for (i = 0; i < np; i++) {
            const float *p = skel_rec_at(r, f, ga->mk[i]);
            par[i].v[0] = p[0];
            par[i].v[1] = p[1];
            par[i].v[2] = p[2];
        }
        for (k = 0; k < nmk; k++) {
            const float *p = skel_rec_at(r, f, mk[k]);
            chi[k].v[0] = p[0];
            chi[k].v[1] = p[1];
            chi[k].v[2] = p[2];
        }
        (void)sfit_joint_add(j, par, (size_t)np, chi, (size_t)nmk, &po);
    }
    if (sfit_joint_fit(j, &res, NULL) != SFIT_OK) {
        free(j);
        return -1;
    }
    free(j);
    for (i = 0; i < 3; i++) {
        c[i] = (double)res.fit.center.v[i];
    }
    /* cost: RMS of |x - c| about its mean, per marker, x in a's frame */
    for (k = 0; k < nmk; k++) {
        sum[k] = cnt[k] = 0.0;
    }
    for (pass = 0; pass < 2; pass++) {
        for (f = 0; f < r->nframes; f++) {
            const double *q = pose_at(s, f, a);
            if (q == NULL) {
                continue;
            }
            for (k = 0; k < nmk; k++) {
                const float *p = skel_rec_at(r, f, mk[k]);
                double d[3], x[3], dd;
                if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
                    continue;
                }
                for (i = 0; i < 3; i++) {
                    d[i] = (double)p[i] - q[9 + i];
                }
                for (i = 0; i < 3; i++) { /* R^T d - c */
                    x[i] = q[0 * 3 + i] * d[0] + q[1 * 3 + i] * d[1] + q[2 * 3 + i] * d[2] - c[i];
                }
                dd = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
                if (pass == 0) {
                    sum[k] += dd;
                    cnt[k] += 1.0;
                } else {
                    sum2 += (dd - sum[k]) * (dd - sum[k]);
                    tot += 1.0;
                }
            }
        }
        for (k = 0; k < nmk && pass == 0; k++) {
            sum[k] = cnt[k] > 0.0 ? sum[k] / cnt[k] : 0.0;
        }
    }
    if (!(tot > 0.0)) {
        return -1;
    }
    *cost = sqrt(sum2 / tot);
    *radius = 0.0;
    for (k = 0; k < nmk; k++) {
        *radius = sum[k] > *radius ? sum[k] : *radius;
    }
    return 0;
}

/* The largest distance between two of a segment's own markers in its
 * template (not a 2-marker segment's joint-centre point). */
double skel_seg_extent(const skel_seg_t *g)
{
    double best = 0.0;
    int i, j, k;
    for (i = 0; i < g->nm && i < g->npose; i++) {
        for (j = i + 1; j < g->nm && j < g->npose; j++) {
            double d2 = 0.0;
            for (k = 0; k < 3; k++) {
                const double d = (double)g->tpl.pos[i].v[k] - (double)g->tpl.pos[j].v[k];
                d2 += d * d;
            }
            best = d2 > best ? d2 : best;
        }
    }
    return sqrt(best);
}

/* Distance from c (segment frame) to the nearest of the segment's own markers. */
double skel_seg_reach(const skel_seg_t *g, const double c[3])
{
    double best = HUGE_VAL;
    int i, k;
    for (i = 0; i < g->nm && i < g->npose; i++) {
        double d2 = 0.0;
        for (k = 0; k < 3; k++) {
            const double d = (double)g->tpl.pos[i].v[k] - c[k];
            d2 += d * d;
        }
        best = d2 < best ? d2 : best;
    }
    return sqrt(best);
}

int skel_attach(skel_t *s, const skel_groups_t *g, char *why)
{
    const int nposed = s->nseg;
    int k, a, added = 0;
    for (k = 0; k < g->n; k++) {
        int best = -1;
        double bc[3] = {0.0, 0.0, 0.0}, bcost = HUGE_VAL;
        if (g->size[k] != 2 || nposed + added >= SKEL_MAX_SEG) {
            continue;
        }
        for (a = 0; a < nposed; a++) {
            double c[3], cost, radius;
            /* what a joint can be: the markers keep their distance to the centre
             * within SKEL_ATTACH_COST times the rigid level, and the centre lies
             * within reach of a's markers and of the pair's (SKEL_TRUST_REACH
             * times a's marker extent); else the group is left out */
            if (s->seg[a].tpl_ok && s->seg[a].vpar < 0
                && sphere_route(s, a, g->member[k], 2, c, &cost, &radius) == 0
                && isfinite(cost) && cost <= SKEL_ATTACH_COST * g->noise
                && radius <= SKEL_TRUST_REACH * skel_seg_extent(&s->seg[a])
                && skel_seg_reach(&s->seg[a], c) <= SKEL_TRUST_REACH * skel_seg_extent(&s->seg[a])
                && cost < bcost) {
                bcost = cost;
                best = a;
                memcpy(bc, c, sizeof bc);
            }
        }
        if (best >= 0) {
            /* s->nseg stays at nposed until every group is placed: the per-frame
             * arrays (pose_ok, pose) are laid out frames x nposed until the poses
             * are computed again below */
            skel_seg_t *ng = &s->seg[nposed + added];
            memset(ng, 0, sizeof *ng);
            (void)snprintf(ng->name, sizeof ng->name, "seg%d", nposed + added + 1);
            ng->nm = 2;
            ng->mk[0] = g->member[k][0];
            ng->mk[1] = g->member[k][1];
            ng->vpar = best;
            memcpy(ng->vc, bc, sizeof bc);
            ng->vcost = bcost;
            added++;
        }
    }
    if (added > 0) { /* poses again, with the new segments */
        skel_free(s);
        s->nseg = nposed + added;
        if (skel_poses(s, why) != 0) {
            return -1;
        }
    }
    return added;
}

/* ---------------------------------------------------------------- tree */

static int find_seg(const skel_t *s, const char *name)
{
    int k;
    for (k = 0; k < s->nseg; k++) {
        if (strcmp(s->seg[k].name, name) == 0) {
            return k;
        }
    }
    return -1;
}

static int uf_find(int *p, int x)
{
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

/* Residual autocorrelation of a joint (lag 1, within trials) -> variance inflation. */
static void joint_inflation(skel_t *s, skel_joint_t *j)
{
    const skel_rec_t *r = s->rec;
    double num = 0.0, den = 0.0, mean[3] = {0.0, 0.0, 0.0}, cnt = 0.0;
    int t, i, pass;
    for (pass = 0; pass < 2; pass++) {
        for (t = 0; t < r->nfiles; t++) {
            double prev[3];
            if (j->pr.trial >= 0 && t != j->pr.trial) { /* the trials the joint used */
                continue;
            }
            int have = 0;
            long f;
            for (f = r->start[t]; f < r->start[t + 1]; f++) {
                const double *pp = pose_at(s, f, j->parent), *pc = pose_at(s, f, j->child);
                double a[3], b[3], e[3];
                if (pp == NULL || pc == NULL) {
                    have = 0;
                    continue;
                }
                mat_vec(pp, j->pr.ca, a);
                mat_vec(pc, j->pr.cb, b);
                for (i = 0; i < 3; i++) {
                    e[i] = a[i] + pp[9 + i] - b[i] - pc[9 + i];
                }
                if (pass == 0) {
                    for (i = 0; i < 3; i++) {
                        mean[i] += e[i];
                    }
                    cnt += 1.0;
                    continue;
                }
                for (i = 0; i < 3; i++) {
                    e[i] -= mean[i];
                    den += e[i] * e[i];
                    if (have) {
                        num += e[i] * prev[i];
                    }
                    prev[i] = e[i];
                }
                have = 1;
            }
        }
        if (pass == 0 && cnt > 0.0) {
            for (i = 0; i < 3; i++) {
                mean[i] /= cnt;
            }
        }
    }
    j->lag1 = den > 0.0 ? num / den : 0.0;
    {
        double rho = j->lag1 < 0.0 ? 0.0 : (j->lag1 > 0.99 ? 0.99 : j->lag1);
        j->infl = (1.0 + rho) / (1.0 - rho);
    }
    /* the slow residual inflates the noise part only: the pair's model part
     * (skin motion with the joint angle) is already a correlated error */
    {
        sfit_mat3_t m;
        sfit_vec3_t w;
        for (i = 0; i < 9; i++) {
            const double model = (double)j->pr.lib.center_cov_model.m[i];
            j->pr.cov_a[i] = (j->pr.cov_a[i] - model) * j->infl + model;
            m.m[i] = (float)j->pr.cov_a[i];
        }
        if (sfit_mat3_eig_sym(&m, &w, NULL) == SFIT_OK) {
            j->pr.sigma = sqrt(w.v[2] > 0.0f ? (double)w.v[2] : 0.0);
        } else {
            j->pr.sigma *= sqrt(j->infl);
        }
    }
}

int skel_tree(skel_t *s, const skel_map_t *map, const char *root, char *why)
{
    typedef struct edge {
        double w;
        int a, b;
        int untrusted; /* trusted joints first (docs/skeleton.md) */
    } edge_t;
    edge_t edges[SKEL_MAX_SEG * SKEL_MAX_SEG / 2];
    int ne = 0, a, b, i, k;
    int uf[SKEL_MAX_SEG], adj[SKEL_MAX_SEG][SKEL_MAX_SEG];
    int queue[SKEL_MAX_SEG], qh = 0, qt = 0, seen[SKEL_MAX_SEG];
    memset(adj, 0, sizeof adj);
    for (a = 0; a < s->nseg; a++) {
        for (b = a + 1; b < s->nseg; b++) {
            s->pair_ok[a][b] = 0;
            if (!s->seg[a].tpl_ok || !s->seg[b].tpl_ok) {
                continue;
            }
            if (skel_pair_run(s, a, b, SKEL_NONE, -1, &s->pair[a][b]) != 0) {
                continue;
            }
            s->pair_ok[a][b] = 1;
            if (s->pair[a][b].type != SKEL_NONE) {
                edges[ne].untrusted = (s->pair[a][b].flags & SKEL_F_UNTRUSTED) != 0u;
                edges[ne].w = s->pair[a][b].rms;
                edges[ne].a = a;
                edges[ne].b = b;
                ne++;
            }
        }
    }
    /* Kruskal over the trusted pairs first, then the untrusted ones (their
     * joints keep SKEL_F_UNTRUSTED); by cost within each; ties by the lower
     * segment indices (edges already in that order) */
    for (i = 1; i < ne; i++) { /* insertion sort, stable */
        const edge_t e = edges[i];
        k = i - 1;
        while (k >= 0
               && (edges[k].untrusted > e.untrusted
                   || (edges[k].untrusted == e.untrusted && edges[k].w > e.w))) {
            edges[k + 1] = edges[k];
            k--;
        }
        edges[k + 1] = e;
    }
    for (a = 0; a < s->nseg; a++) {
        uf[a] = a;
    }
    for (i = 0; i < ne; i++) {
        const int ra = uf_find(uf, edges[i].a), rb = uf_find(uf, edges[i].b);
        if (ra != rb) {
            uf[ra] = rb;
            adj[edges[i].a][edges[i].b] = adj[edges[i].b][edges[i].a] = 1;
        }
    }
    /* root */
    s->root = -1;
    s->root_named = 0;
    if (root == NULL || root[0] == '\0') {
        root = (map != NULL && map->root[0] != '\0') ? map->root : NULL;
    }
    if (root != NULL) {
        s->root = find_seg(s, root);
        if (s->root < 0) {
            (void)snprintf(why, SKEL_ERR, "root %s: no such segment", root);
            return -1;
        }
        s->root_named = 1;
    } else {
        double best = HUGE_VAL;
        for (a = 0; a < s->nseg; a++) {
            if (s->seg[a].tpl_ok && s->seg[a].speed < best) {
                best = s->seg[a].speed;
                s->root = a;
            }
        }
    }
    if (s->root < 0 || !s->seg[s->root].tpl_ok) {
        (void)snprintf(why, SKEL_ERR, "no segment has a pose");
        return -1;
    }
    /* breadth first from the root */
    memset(seen, 0, sizeof seen);
    for (a = 0; a < s->nseg; a++) {
        s->parent_joint[a] = -1;
    }
    s->njoint = 0;
    queue[qt++] = s->root;
    seen[s->root] = 1;
    while (qh < qt) {
        const int p = queue[qh++];
        s->order[qh - 1] = p;
        for (b = 0; b < s->nseg; b++) {
            if (adj[p][b] && !seen[b]) {
                skel_joint_t *j = &s->joint[s->njoint];
                skel_jtype_t force = SKEL_NONE;
                const char *pattern = NULL;
                memset(j, 0, sizeof *j);
                j->parent = p;
                j->child = b;
                memcpy(j->name, s->seg[b].name, sizeof j->name);
                if (map != NULL) {
                    for (k = 0; k < map->njoint; k++) {
                        if ((strcmp(map->jpar[k], s->seg[p].name) == 0
                             && strcmp(map->jchi[k], s->seg[b].name) == 0)
                            || (strcmp(map->jpar[k], s->seg[b].name) == 0
                                && strcmp(map->jchi[k], s->seg[p].name) == 0)) {
                            (void)snprintf(j->name, sizeof j->name, "%s", map->jname[k]);
                            pattern = map->jtrial[k];
                            force = strcmp(map->jtype[k], "ball") == 0
                                        ? SKEL_BALL
                                        : (strcmp(map->jtype[k], "hinge") == 0 ? SKEL_HINGE
                                                                               : SKEL_NONE);
                        }
                    }
                }
                if (skel_pair_joint(s, p, b, force, pattern, &j->pr) != 0) {
                    (void)snprintf(why, SKEL_ERR, "joint %s: cannot solve", j->name);
                    return -1;
                }
                joint_inflation(s, j);
                s->parent_joint[b] = s->njoint++;
                seen[b] = 1;
                queue[qt++] = b;
            }
        }
    }
    for (a = qt; a < SKEL_MAX_SEG; a++) {
        s->order[a] = -1;
    }
    return qt; /* segments in the tree */
}

/* ------------------------------------------------- segments from data */

int skel_from_data(skel_t *s, skel_groups_t *grp, const char *root, char *why)
{
    int k, q, intree;
    if (skel_group(s->rec, grp, why) != 0) {
        return -1;
    }
    s->nseg = 0;
    for (k = 0; k < grp->n; k++) {
        if (grp->size[k] >= 3 && s->nseg < SKEL_MAX_SEG) {
            skel_seg_t *g = &s->seg[s->nseg];
            memset(g, 0, sizeof *g);
            (void)snprintf(g->name, sizeof g->name, "seg%d", s->nseg + 1);
            g->nm = grp->size[k];
            memcpy(g->mk, grp->member[k], (size_t)g->nm * sizeof g->mk[0]);
            g->vpar = -1;
            s->nseg++;
        }
    }
    if (skel_poses(s, why) != 0 || skel_attach(s, grp, why) < 0) {
        return -1;
    }
    if (s->nseg < 2) {
        (void)snprintf(why, SKEL_ERR, "fewer than two segments with a pose: no joint");
        return -1;
    }
    intree = skel_tree(s, NULL, root, why);
    if (intree < 0) {
        return -1;
    }
    /* names: seg1 the root, then down the tree, then those not in the tree */
    for (q = 0; q < s->nseg && s->order[q] >= 0; q++) {
        (void)snprintf(s->seg[s->order[q]].name, SKEL_NAME, "seg%d", q + 1);
    }
    for (k = 0; k < s->nseg; k++) {
        if (k != s->root && s->parent_joint[k] < 0) {
            (void)snprintf(s->seg[k].name, SKEL_NAME, "seg%d", ++q);
        }
    }
    for (k = 0; k < s->njoint; k++) {
        memcpy(s->joint[k].name, s->seg[s->joint[k].child].name, SKEL_NAME);
    }
    return intree;
}

/* --------------------------------------------------------------- motion */

static int cmp_dbl(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Per joint: distance from the BVH's forward kinematics (s->jc) to the
 * centre its parent carries (t_p + R_p ca) in the frames where the parent
 * has a pose; median and 95th percentile (nearest rank). The difference is
 * the sum of the ancestors' joint residuals (docs/skeleton.md). */
static int bvh_distance(skel_t *s, char *why)
{
    const long nf = s->rec->nframes;
    double *d = malloc((size_t)(nf > 0 ? nf : 1) * sizeof *d);
    int k, i;
    if (d == NULL) {
        (void)snprintf(why, SKEL_ERR, "out of memory");
        return -1;
    }
    for (k = 0; k < s->njoint; k++) {
        skel_joint_t *j = &s->joint[k];
        long f, n = 0;
        for (f = 0; f < nf; f++) {
            const double *p = pose_at(s, f, j->parent);
            const double *b = &s->jc[((size_t)f * (size_t)s->njoint + (size_t)k) * 3u];
            double c[3], e2 = 0.0;
            if (p == NULL) {
                continue;
            }
            mat_vec(p, j->pr.ca, c);
            for (i = 0; i < 3; i++) {
                const double e = b[i] - (c[i] + p[9 + i]);
                e2 += e * e;
            }
            if (isfinite(e2)) {
                d[n++] = sqrt(e2);
            }
        }
        j->bvh_frames = n;
        if (n == 0) {
            j->bvh_med = j->bvh_p95 = (double)NAN;
            continue;
        }
        qsort(d, (size_t)n, sizeof *d, cmp_dbl);
        j->bvh_med = (n % 2 == 1) ? d[n / 2] : 0.5 * (d[n / 2 - 1] + d[n / 2]);
        {
            long r = (long)ceil(0.95 * (double)n); /* nearest rank */
            j->bvh_p95 = d[(r < 1 ? 1 : r) - 1];
        }
    }
    free(d);
    return 0;
}

int skel_motion(skel_t *s, char *why)
{
    const long nf = s->rec->nframes;
    const int ns = s->nseg;
    double last[SKEL_MAX_SEG][12];
    int have[SKEL_MAX_SEG];
    long f;
    int q, k, i;
    s->rel = malloc((size_t)nf * (size_t)ns * 9u * sizeof *s->rel);
    s->root_t = malloc((size_t)nf * 3u * sizeof *s->root_t);
    s->jc = malloc((size_t)nf * (size_t)(s->njoint > 0 ? s->njoint : 1) * 3u * sizeof *s->jc);
    s->ends = malloc((size_t)nf * (size_t)ns * 3u * sizeof *s->ends);
    if (s->rel == NULL || s->root_t == NULL || s->jc == NULL || s->ends == NULL) {
        (void)snprintf(why, SKEL_ERR, "out of memory");
        return -1;
    }
    /* the first valid pose of each segment stands in for the frames before it */
    for (k = 0; k < ns; k++) {
        have[k] = 0;
        for (f = 0; f < nf && !have[k]; f++) {
            const double *p = pose_at(s, f, k);
            if (p != NULL) {
                memcpy(last[k], p, sizeof last[k]);
                have[k] = 1;
            }
        }
    }
    /* end sites: the leaf segment's template origin (its markers' centroid) */
    for (k = 0; k < ns; k++) {
        s->leaf[k] = (k == s->root || s->parent_joint[k] >= 0);
        for (i = 0; i < s->njoint; i++) {
            if (s->joint[i].parent == k) {
                s->leaf[k] = 0;
            }
        }
        const int j = s->parent_joint[k];
        for (i = 0; i < 3; i++) {
            s->end_site[k][i] = j >= 0 ? -s->joint[j].pr.cb[i] : 0.0;
        }
    }
    for (f = 0; f < nf; f++) {
        double g[SKEL_MAX_SEG][9], pos[SKEL_MAX_SEG][3];
        for (k = 0; k < ns; k++) {
            const double *p = pose_at(s, f, k);
            if (p != NULL) {
                memcpy(last[k], p, sizeof last[k]);
            }
        }
        for (q = 0; q < ns && s->order[q] >= 0; q++) {
            const int c = s->order[q];
            const int j = s->parent_joint[c];
            double *rel = &s->rel[((size_t)f * (size_t)ns + (size_t)c) * 9u];
            if (!have[c]) {
                (void)snprintf(why, SKEL_ERR, "segment %s has no pose", s->seg[c].name);
                return -1;
            }
            if (j < 0) {
                memcpy(rel, last[c], 9u * sizeof *rel);
                memcpy(g[c], rel, sizeof g[c]);
                for (i = 0; i < 3; i++) {
                    pos[c][i] = last[c][9 + i];
                    s->root_t[f * 3 + i] = pos[c][i];
                }
            } else {
                const int p = s->joint[j].parent;
                const int jp = s->parent_joint[p];
                double off[3], w[3];
                mat_tmul(last[p], last[c], rel);
                mat_mul(g[p], rel, g[c]);
                for (i = 0; i < 3; i++) {
                    off[i] = s->joint[j].pr.ca[i] - (jp >= 0 ? s->joint[jp].pr.cb[i] : 0.0);
                }
                mat_vec(g[p], off, w);
                for (i = 0; i < 3; i++) {
                    pos[c][i] = pos[p][i] + w[i];
                    s->jc[((size_t)f * (size_t)s->njoint + (size_t)j) * 3u + (size_t)i] = pos[c][i];
                }
            }
        }
        for (k = 0; k < ns; k++) {
            double *e = &s->ends[((size_t)f * (size_t)ns + (size_t)k) * 3u];
            e[0] = e[1] = e[2] = (double)NAN;
        }
        for (q = 0; q < ns && s->order[q] >= 0; q++) {
            const int c = s->order[q];
            if (s->leaf[c]) {
                double w[3];
                double *e = &s->ends[((size_t)f * (size_t)ns + (size_t)c) * 3u];
                mat_vec(g[c], s->end_site[c], w);
                for (i = 0; i < 3; i++) {
                    e[i] = pos[c][i] + w[i];
                }
            }
        }
    }
    return bvh_distance(s, why);
}

/* --------------------------------------------------------------- euler */

void skel_euler_zxy(const double r[9], double deg[3])
{
    const double rad = 180.0 / 3.14159265358979323846;
    double sx = r[7];
    double x, y, z;
    if (sx > 1.0) {
        sx = 1.0;
    } else if (sx < -1.0) {
        sx = -1.0;
    }
    x = asin(sx);
    if (fabs(sx) < 1.0 - 1e-12) {
        z = atan2(-r[1], r[4]);
        y = atan2(-r[6], r[8]);
    } else { /* gimbal lock: y = 0 */
        y = 0.0;
        z = atan2(r[3], r[0]);
    }
    deg[0] = z * rad;
    deg[1] = x * rad;
    deg[2] = y * rad;
}
