/* SPDX-License-Identifier: MIT */
/**
 * @file skel_pair.c
 * @brief The pair of segments of `sfit skeleton`: the library's pair module
 * (sfit_pair.h: SCoRE / SARA with the errors-in-variables bias removed, the
 * marker variance from the registration residuals, its covariances, its
 * ball / hinge test and flags) on the skeleton's poses, with the default
 * options `sfit calibrate` uses; and the rule that gives a joint its type
 * when all trials together are ambiguous (docs/skeleton.md).
 */
#include <fnmatch.h>
#include <math.h>
#include <string.h>

#include "skel.h"

/* Thresholds of the skeleton's own flags (docs/skeleton.md). */
#define SKEL_NO_MOTION_RAD 0.087  /* largest rotation spread below this (5 deg): no joint */
#define SKEL_SMALL_RANGE_RAD 0.17 /* largest rotation spread below this (10 deg): flagged */
#define SKEL_MIN_FRAMES 30        /* the pair module's own min_frames default */
#define SKEL_PAIR_MIN_FRAMES 10   /* pairs seen together in fewer frames: no edge */

/* Cyclic Jacobi for a symmetric 3x3 (double): a = v diag(w) v^T,
 * eigenvalues ascending, eigenvectors in the columns of v. 0, or -1. */
int skel_eig3(const double a_in[9], double w[3], double v[9])
{
    double a[9];
    int sweep, p, q, i;
    memcpy(a, a_in, sizeof a);
    memset(v, 0, 9u * sizeof *v);
    v[0] = v[4] = v[8] = 1.0;
    for (sweep = 0; sweep < 64; sweep++) {
        const double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
        const double diag = a[0] * a[0] + a[4] * a[4] + a[8] * a[8];
        if (off <= 1e-30 * diag || off == 0.0) {
            break;
        }
        for (p = 0; p < 2; p++) {
            for (q = p + 1; q < 3; q++) {
                const double apq = a[p * 3 + q];
                double theta, t, c, s;
                if (apq == 0.0) {
                    continue;
                }
                theta = (a[q * 3 + q] - a[p * 3 + p]) / (2.0 * apq);
                t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (i = 0; i < 3; i++) { /* columns p, q of a */
                    const double aip = a[i * 3 + p], aiq = a[i * 3 + q];
                    a[i * 3 + p] = c * aip - s * aiq;
                    a[i * 3 + q] = s * aip + c * aiq;
                }
                for (i = 0; i < 3; i++) { /* rows p, q */
                    const double api = a[p * 3 + i], aqi = a[q * 3 + i];
                    a[p * 3 + i] = c * api - s * aqi;
                    a[q * 3 + i] = s * api + c * aqi;
                }
                for (i = 0; i < 3; i++) {
                    const double vip = v[i * 3 + p], viq = v[i * 3 + q];
                    v[i * 3 + p] = c * vip - s * viq;
                    v[i * 3 + q] = s * vip + c * viq;
                }
            }
        }
    }
    if (sweep == 64) {
        return -1;
    }
    for (i = 0; i < 3; i++) {
        w[i] = a[i * 4];
    }
    /* sort ascending */
    for (p = 0; p < 2; p++) {
        for (q = p + 1; q < 3; q++) {
            if (w[q] < w[p]) {
                const double tw = w[p];
                w[p] = w[q];
                w[q] = tw;
                for (i = 0; i < 3; i++) {
                    const double tv = v[i * 3 + p];
                    v[i * 3 + p] = v[i * 3 + q];
                    v[i * 3 + q] = tv;
                }
            }
        }
    }
    return 0;
}

/* What a joint can be (docs/skeleton.md): its residual is what the marker
 * noise and a little soft tissue explain, and its centre lies within reach
 * of both segments' markers. SKEL_U_* bits, 0 when the fit can be trusted. */
static unsigned judge(const skel_t *s, int a, int b, const skel_pair_res_t *o)
{
    const double noise = sqrt((double)o->lib.marker_var);
    const double ext = fmax(skel_seg_extent(&s->seg[a]), skel_seg_extent(&s->seg[b]));
    unsigned why = 0u;
    if (!((double)o->lib.misfit <= SKEL_TRUST_MISFIT)) {
        why |= SKEL_U_MISFIT;
    }
    if (!(noise > 0.0) || !(o->rms <= SKEL_TRUST_COST * noise)) {
        why |= SKEL_U_COST;
    }
    if (!(o->reach_a <= SKEL_TRUST_REACH * ext) || !(o->reach_b <= SKEL_TRUST_REACH * ext)) {
        why |= SKEL_U_REACH;
    }
    if (o->lib.reason == SFIT_PAIR_REASON_FEW_FRAMES || o->lib.reason == SFIT_PAIR_REASON_NO_NOISE) {
        why |= SKEL_U_MODULE;
    }
    return why;
}

int skel_pair_run(const skel_t *s, int a, int b, skel_jtype_t mode, int trial,
                  skel_pair_res_t *out)
{
    const skel_rec_t *r = s->rec;
    const long f0 = trial < 0 ? 0 : r->start[trial], f1 = trial < 0 ? r->nframes : r->start[trial + 1];
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    sfit_pair_t st;
    sfit_pair_result_t res;
    skel_pair_res_t o;
    sfit_status_t rc;
    long f, rejected = 0;
    int i;
    cfg.mode = mode == SKEL_BALL ? SFIT_PAIR_MODE_BALL
                                 : (mode == SKEL_HINGE ? SFIT_PAIR_MODE_HINGE : SFIT_PAIR_MODE_AUTO);
    if (sfit_pair_init(&st, &s->seg[a].tpl, &s->seg[b].tpl, &cfg) != SFIT_OK) {
        return -1;
    }
    for (f = f0; f < f1; f++) {
        const size_t ia = (size_t)f * (size_t)s->nseg + (size_t)a;
        const size_t ib = (size_t)f * (size_t)s->nseg + (size_t)b;
        sfit_cluster_fit_t fa, fb;
        if (!s->pose_ok[ia] || !s->pose_ok[ib]) {
            continue;
        }
        fa.rms = s->fit_rms[ia];
        fa.used = s->fit_used[ia];
        fb.rms = s->fit_rms[ib];
        fb.used = s->fit_used[ib];
        if (sfit_pair_add(&st, &s->fpose[ia], &fa, &s->fpose[ib], &fb) != SFIT_OK) {
            rejected++;
        }
    }
    if (st.frames < SKEL_PAIR_MIN_FRAMES) {
        return -1;
    }
    memset(&o, 0, sizeof o);
    o.n = (double)st.frames;
    o.rejected = rejected;
    o.trial = trial;
    o.type_trial = -1;
    o.type_rule = mode == SKEL_NONE ? "all_trials" : "map";
    rc = sfit_pair_solve(&st, &res);
    if (rc == SFIT_E_DEGENERATE && mode == SKEL_NONE) { /* no relative rotation at all */
        o.type = SKEL_NONE;
        o.flags = SKEL_F_NO_MOTION;
        *out = o;
        return 0;
    }
    if (rc != SFIT_OK) {
        return -1;
    }
    o.lib = res;
    for (i = 0; i < 3; i++) {
        o.ca[i] = (double)res.center_p.v[i];
        o.cb[i] = (double)res.center_c.v[i];
        o.axis_a[i] = (double)res.axis_p.v[i];
        o.s[i] = (double)res.eigenvalues.v[i] > 0.0 ? (double)res.eigenvalues.v[i] : 0.0;
    }
    for (i = 0; i < 9; i++) {
        o.cov_a[i] = (double)res.center_cov.m[i];
    }
    o.rms = (double)res.rms;
    o.type = res.mode == SFIT_PAIR_MODE_HINGE ? SKEL_HINGE : SKEL_BALL;
    if (mode != SKEL_NONE) {
        o.flags |= SKEL_F_FORCED;
    }
    if (sqrt(o.s[2]) < SKEL_NO_MOTION_RAD) {
        o.flags |= SKEL_F_NO_MOTION;
        if (mode == SKEL_NONE) {
            o.type = SKEL_NONE;
        }
    }
    if (sqrt(o.s[2]) < SKEL_SMALL_RANGE_RAD) {
        o.flags |= SKEL_F_SMALL_RANGE;
    }
    if (res.frames < SKEL_MIN_FRAMES) {
        o.flags |= SKEL_F_FEW_FRAMES;
    }
    if ((res.flags & (uint32_t)SFIT_PAIR_FLAG_AMBIGUOUS) != 0u) {
        o.flags |= SKEL_F_BORDERLINE;
    }
    {
        double w[3], v[9];
        o.sigma = skel_eig3(o.cov_a, w, v) == 0 && w[2] > 0.0 ? sqrt(w[2]) : 0.0;
    }
    o.reach_a = skel_seg_reach(&s->seg[a], o.ca);
    o.reach_b = skel_seg_reach(&s->seg[b], o.cb);
    o.why_untrusted = judge(s, a, b, &o);
    if (o.why_untrusted != 0u) {
        o.flags |= SKEL_F_UNTRUSTED;
    }
    *out = o;
    return 0;
}

static const char *base_name(const char *p)
{
    const char *q = strrchr(p, '/');
    return q != NULL ? q + 1 : p;
}

/* The joint's functional trial: the one trial the map's pattern matches,
 * else the trial where the pair turns most in its second direction
 * (frames x lambda_2: a hinge's flexion shows in lambda_2 and lambda_3, a
 * ball's in all three). -1 if none. */
static int functional_trial(const skel_t *s, int a, int b, const char *pattern)
{
    const skel_rec_t *r = s->rec;
    int t, best = -1, hits = 0;
    double most = 0.0;
    if (pattern != NULL && pattern[0] != '\0') {
        for (t = 0; t < r->nfiles; t++) {
            if (fnmatch(pattern, base_name(r->file[t]), 0) == 0) {
                best = t;
                hits++;
            }
        }
        if (hits == 1) {
            return best;
        }
        best = -1;
    }
    for (t = 0; t < r->nfiles; t++) {
        skel_pair_res_t p;
        if (skel_pair_run(s, a, b, SKEL_NONE, t, &p) == 0 && p.type != SKEL_NONE
            && p.n * p.s[1] > most) {
            most = p.n * p.s[1];
            best = t;
        }
    }
    return best;
}

int skel_pair_joint(const skel_t *s, int a, int b, skel_jtype_t force, const char *pattern,
                    skel_pair_res_t *res)
{
    skel_pair_res_t all, one;
    skel_jtype_t type = force;
    int t = -2; /* not looked for yet */
    const char *rule = "map";
    if (force == SKEL_NONE) {
        /* 1. the type: all trials together, unless the module calls them ambiguous */
        if (skel_pair_run(s, a, b, SKEL_NONE, -1, &all) != 0) {
            return -1;
        }
        type = all.type;
        rule = "all_trials";
        if ((all.flags & SKEL_F_BORDERLINE) && all.type != SKEL_NONE && s->rec->nfiles > 1) {
            /* then the joint's functional trial decides, when it can */
            t = functional_trial(s, a, b, pattern);
            if (t >= 0 && skel_pair_run(s, a, b, SKEL_NONE, t, &one) == 0
                && one.type != SKEL_NONE && !(one.flags & SKEL_F_BORDERLINE)) {
                type = one.type;
                rule = "functional_trial";
            } else {
                t = -1;
            }
        }
        if (type == SKEL_NONE || (strcmp(rule, "all_trials") == 0 && type != SKEL_HINGE)) {
            *res = all; /* decided over all trials, estimated over all trials */
            return 0;
        }
    }
    /* 2. the estimate over all trials with that type */
    if (skel_pair_run(s, a, b, type, -1, res) != 0) {
        return -1;
    }
    /* 3. a hinge whose axis all trials together do not fix (the pair module's
     * AXIS_FREE: out-of-axis motion in the other trials) is estimated on its
     * functional trial alone, where it is a hinge */
    if (type == SKEL_HINGE && (res->lib.flags & (uint32_t)SFIT_PAIR_FLAG_AXIS_FREE) != 0u
        && s->rec->nfiles > 1) {
        if (t == -2) {
            t = functional_trial(s, a, b, pattern);
        }
        if (t >= 0 && skel_pair_run(s, a, b, SKEL_HINGE, t, &one) == 0) {
            *res = one;
            res->flags |= SKEL_F_ONE_TRIAL;
        }
    }
    if (force == SKEL_NONE) {
        res->flags &= ~(unsigned)SKEL_F_FORCED;
    }
    if (strcmp(rule, "functional_trial") == 0) {
        res->flags |= SKEL_F_BORDERLINE | SKEL_F_TYPE_TRIAL;
        res->type_trial = t;
    }
    res->type_rule = rule;
    return 0;
}
