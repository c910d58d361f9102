/* SPDX-License-Identifier: MIT */
/**
 * @file skel_cmd.c
 * @brief `sfit skeleton FILE... [--segments MAP]`: the skeleton found in
 * one or several trials (docs/skeleton.md). The joint-by-joint form
 * `sfit skeleton MODEL FILE` is cmd_skeleton.c.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "c3d.h"
#include "cli.h"
#include "cli_joint.h"
#include "skel.h"

typedef struct sk2_opts {
    const char *file[SKEL_MAX_FILES];
    int nfiles;
    char *segments, *root, *bvh, *trc, *svg, *html, *centres;
    long frame, step;
    int json;
} sk2_opts_t;

static void sk2_usage(FILE *f)
{
    fputs("usage: sfit skeleton FILE... [--segments MAP] [--root SEGMENT] [--step K]\n"
          "                     [--bvh OUT.bvh] [--trc OUT.trc] [--svg OUT.svg]\n"
          "                     [--html OUT.html] [--centres OUT.csv]\n"
          "                     [--frame K] [--json]\n"
          "  FILE...          C3D trials of one session, used together (each joint may\n"
          "                   move in its own functional trial)\n"
          "  --segments MAP   session model: `segment NAME M1,M2,M3[,...]` lines (joint\n"
          "                   lines name joints and may force ball / hinge; `root SEG`);\n"
          "                   without it the segments are found from the data\n"
          "  --root SEGMENT   the BVH root (default: the map's root, else the segment\n"
          "                   whose marker centroid moves least)\n"
          "  --step K         use every K-th frame of each trial (default 1)\n"
          "  --bvh OUT.bvh    the skeleton and its motion (units of the recording)\n"
          "  --trc OUT.trc    the skeleton's joint centres per frame\n"
          "  --svg OUT.svg    a picture at frame --frame K (default 0; frames counted over\n"
          "                   the trials in order, after --step)\n"
          "  --html OUT.html  a page that plays the skeleton over the markers\n"
          "  --centres OUT.csv  each joint's centre (and hinge axis) as its parent\n"
          "                   segment carries it, per frame (lab frame)\n"
          "  --json           one JSON object on stdout\n"
          "  (the joint-by-joint form: sfit skeleton MODEL FILE ..., see --help of it:\n"
          "   sfit skeleton MODEL FILE --help)\n",
          f);
}

/* The new form is wanted when one of its options is given or the first
 * argument that is not an option is a C3D file. */
int skel_cmd_wanted(int argc, char **argv)
{
    static const char *const own[] = {"--segments", "--root", "--step", "--bvh", "--trc",
                                      "--html", "--centres"};
    int i, k;
    for (i = 1; i < argc; i++) {
        for (k = 0; k < (int)(sizeof own / sizeof own[0]); k++) {
            if (strcmp(argv[i], own[k]) == 0) {
                return 1;
            }
        }
    }
    for (i = 1; i < argc; i++) {
        if (argv[i][0] == '-') {
            if (strcmp(argv[i], "--svg") == 0 || strcmp(argv[i], "--frame") == 0
                || strcmp(argv[i], "--frames") == 0 || strcmp(argv[i], "--noise-var") == 0
                || strcmp(argv[i], "--mode") == 0) {
                i++;
            }
            continue;
        }
        {
            FILE *f = fopen(argv[i], "rb");
            unsigned char buf[512];
            size_t n;
            int is;
            if (f == NULL) {
                return 0;
            }
            n = fread(buf, 1u, sizeof buf, f);
            fclose(f);
            is = c3d_sniff(buf, n);
            return is != 0;
        }
    }
    return 0;
}

static const char *step_opt(void *dst, const char *v)
{
    char *end;
    const long k = strtol(v, &end, 10);
    if (end == v || *end != '\0' || k < 1 || k > 1000000) {
        return "--step needs a whole number >= 1";
    }
    *(long *)dst = k;
    return NULL;
}

static int sk2_parse(int argc, char **argv, sk2_opts_t *o)
{
    int npos = 0;
    const cli_opt_t opts[] = {
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &o->json},
        {.name = "--segments", .kind = CLI_OPT_STRING, .dst = &o->segments, .needs = 1},
        {.name = "--root", .kind = CLI_OPT_STRING, .dst = &o->root, .needs = 1},
        {.name = "--bvh", .kind = CLI_OPT_STRING, .dst = &o->bvh, .needs = 1},
        {.name = "--trc", .kind = CLI_OPT_STRING, .dst = &o->trc, .needs = 1},
        {.name = "--svg", .kind = CLI_OPT_STRING, .dst = &o->svg, .needs = 1},
        {.name = "--html", .kind = CLI_OPT_STRING, .dst = &o->html, .needs = 1},
        {.name = "--centres", .kind = CLI_OPT_STRING, .dst = &o->centres, .needs = 1},
        {.name = "--step", .kind = CLI_OPT_FN, .dst = &o->step, .fn = step_opt, .needs = 1},
        {.name = "--frame", .kind = CLI_OPT_INDEX, .dst = &o->frame, .needs = 1,
         .err = "--frame needs a whole number >= 0"},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0],
                             .pos = o->file, .max_pos = SKEL_MAX_FILES, .min_pos = 1,
                             .npos = &npos, .extra = "too many files",
                             .missing = "FILE missing", .usage = sk2_usage};
    int rc;
    memset(o, 0, sizeof *o);
    o->step = 1;
    rc = cli_parse(argc, argv, &args);
    o->nfiles = npos;
    return rc;
}

static const char *type_name(skel_jtype_t t)
{
    return t == SKEL_BALL ? "ball" : (t == SKEL_HINGE ? "hinge" : "none");
}

static void print_flags(unsigned fl)
{
    static const char *const nm[] = {"no-motion", "small-range", "few-frames", "borderline",
                                     "forced",    "type-from-trial", "one-trial"};
    int k;
    for (k = 0; k < 7; k++) { /* untrusted: with its reasons, by the caller */
        if (fl & (1u << k)) {
            printf(" [%s]", nm[k]);
        }
    }
}

/* The pair module's members of `sfit joint --json` (joint_run.c): flags by
 * name, center_cov, axis_cov (hinge), the noise figure and its source, the
 * reason by name, misfit. */
static void pair_json(const skel_pair_res_t *p)
{
    static joint_run_out_t jo;
    memset(&jo, 0, sizeof jo);
    jo.pair_used = 1;
    jo.pair = p->lib;
    jo.pair_rejected = p->rejected;
    printf(",\"pair_flags\":");
    cli_joint_print_flags_json(&jo);
    cli_joint_print_pair_json(&jo);
}

static void jvec(const double *v, int n)
{
    int i;
    printf("[");
    for (i = 0; i < n; i++) {
        printf("%s%.9g", i ? "," : "", v[i]);
    }
    printf("]");
}

/* 1 when the map's joint k joins two segments the found tree joins. */
static int map_joint_in_tree(const skel_t *s, const skel_map_t *map, int k)
{
    int j;
    for (j = 0; j < s->njoint; j++) {
        const char *p = s->seg[s->joint[j].parent].name, *c = s->seg[s->joint[j].child].name;
        if ((strcmp(map->jpar[k], p) == 0 && strcmp(map->jchi[k], c) == 0)
            || (strcmp(map->jpar[k], c) == 0 && strcmp(map->jchi[k], p) == 0)) {
            return 1;
        }
    }
    return 0;
}

static int fail(const sk2_opts_t *o, const char *why)
{
    if (o->json) {
        printf("{\"status\":\"error\",\"message\":");
        json_out_str(stdout, why, 0);
        printf("}\n");
    } else {
        fprintf(stderr, "sfit: %s\n", why);
    }
    return CLI_FAIL;
}

int skel_cmd(int argc, char **argv)
{
    sk2_opts_t o;
    skel_map_t *map = NULL;
    skel_rec_t rec;
    skel_groups_t *grp = NULL;
    skel_t *s = NULL;
    char why[SKEL_ERR];
    const char *names[SKEL_MAX_MARK];
    int nnames = 0, k, i, rc = CLI_OK, intree;
    {
        const int prc = sk2_parse(argc, argv, &o);
        if (prc >= 0) {
            return prc;
        }
    }
    memset(&rec, 0, sizeof rec);
    s = calloc(1u, sizeof *s);
    grp = calloc(1u, sizeof *grp);
    if (s == NULL || grp == NULL) {
        free(s);
        free(grp);
        return fail(&o, "out of memory");
    }
    if (o.segments != NULL) {
        map = calloc(1u, sizeof *map);
        if (map == NULL) {
            rc = fail(&o, "out of memory");
            goto done;
        }
        k = skel_map_load(o.segments, map, why);
        if (k != 0) {
            rc = cli_input_failed(k, o.segments, why, o.json);
            goto done;
        }
        for (k = 0; k < map->nseg; k++) {
            for (i = 0; i < map->nm[k] && nnames < SKEL_MAX_MARK; i++) {
                names[nnames++] = map->mk[k][i];
            }
        }
    }
    if (skel_rec_load(&rec, o.file, o.nfiles, names, nnames, o.step, why) != 0) {
        rc = fail(&o, why);
        rc = CLI_IO;
        goto done;
    }
    s->rec = &rec;
    if (map != NULL) {
        s->nseg = map->nseg;
        for (k = 0; k < map->nseg; k++) {
            skel_seg_t *g = &s->seg[k];
            g->vpar = -1;
            (void)snprintf(g->name, sizeof g->name, "%s", map->seg[k]);
            g->nm = map->nm[k];
            for (i = 0; i < g->nm; i++) {
                int m;
                for (m = 0; m < rec.nmark && strcmp(rec.label[m], map->mk[k][i]) != 0; m++) {
                }
                g->mk[i] = m;
            }
        }
    }
    if (map == NULL) {
        intree = skel_from_data(s, grp, o.root, why);
        if (intree < 0) {
            rc = fail(&o, why);
            goto done;
        }
    } else {
        if (skel_poses(s, why) != 0) {
            rc = fail(&o, why);
            goto done;
        }
        if (s->nseg < 2) {
            rc = fail(&o, "fewer than two segments with a pose: no joint");
            goto done;
        }
        intree = skel_tree(s, map, o.root, why);
    }
    if (intree < 0 || skel_motion(s, why) != 0) {
        rc = fail(&o, why);
        goto done;
    }
    if (o.frame >= rec.nframes) {
        (void)snprintf(why, sizeof why, "frame %ld: the trials have %ld frames", o.frame,
                       rec.nframes);
        rc = fail(&o, why);
        rc = CLI_USAGE;
        goto done;
    }
    if (o.bvh != NULL && skel_write_bvh(s, o.bvh) != 0) {
        rc = CLI_IO;
    }
    if (o.trc != NULL && skel_write_trc(s, o.trc) != 0) {
        rc = CLI_IO;
    }
    if (o.svg != NULL && skel_write_svg(s, o.svg, o.frame) != 0) {
        rc = CLI_IO;
    }
    if (o.centres != NULL && skel_write_centres(s, o.centres) != 0) {
        rc = CLI_IO;
    }
    if (o.html != NULL && skel_write_html(s, o.html) != 0) {
        rc = CLI_IO;
    }
    if (rc == CLI_IO) {
        goto done;
    }
    if (o.json) {
        printf("{\"status\":\"ok\",\"files\":%d,\"frames\":%ld,\"step\":%ld,\"dropped\":%ld,"
               "\"units\":",
               o.nfiles, rec.nframes, o.step, rec.dropped);
        json_out_str(stdout, rec.units, 0);
        printf(",\"segments_from\":\"%s\",\"frame\":%ld,\"trial_start\":[", map != NULL ? "map" : "data", o.frame);
        for (k = 0; k < o.nfiles; k++) {
            printf("%s%ld", k ? "," : "", rec.start[k]);
        }
        printf("]");
        if (map == NULL) {
            printf(",\"grouping\":{\"noise\":%.6g,\"threshold\":%.6g,\"gap\":", grp->noise,
                   grp->threshold);
            if (isfinite(grp->gap_lo)) {
                printf("[%.6g,%.6g]", grp->gap_lo, grp->gap_hi);
            } else {
                printf("null");
            }
            printf(",\"groups\":[");
            for (k = 0; k < grp->n; k++) {
                printf("%s{\"spread\":%.6g,\"markers\":[", k ? "," : "", grp->spread[k]);
                for (i = 0; i < grp->size[k]; i++) {
                    printf("%s", i ? "," : "");
                    json_out_str(stdout, rec.label[grp->member[k][i]], 0);
                }
                printf("]}");
            }
            printf("]}");
        }
        printf(",\"segments\":[");
        for (k = 0; k < s->nseg; k++) {
            printf("%s{\"name\":", k ? "," : "");
            json_out_str(stdout, s->seg[k].name, 0);
            printf(",\"frames_with_pose\":%ld,\"markers\":[", s->seg[k].seen);
            for (i = 0; i < s->seg[k].nm; i++) {
                printf("%s", i ? "," : "");
                json_out_str(stdout, s->seg[k].mk[i] < rec.nmark ? rec.label[s->seg[k].mk[i]] : "?", 0);
            }
            /* the template (segment frame) its poses come from: the first npose
             * markers (a 2-marker group's third point is its joint centre) */
            printf("],\"template\":[");
            for (i = 0; s->seg[k].tpl_ok && i < s->seg[k].npose; i++) {
                const float *v = s->seg[k].tpl.pos[i].v;
                printf("%s[%.9g,%.9g,%.9g]", i ? "," : "", (double)v[0], (double)v[1],
                       (double)v[2]);
            }
            printf("]}");
        }
        printf("],\"root\":");
        json_out_str(stdout, s->seg[s->root].name, 0);
        printf(",\"root_rule\":\"%s\",\"pairs\":[", s->root_named ? "named" : "moves_least");
        {
            int first = 1, a, b;
            for (a = 0; a < s->nseg; a++) {
                for (b = a + 1; b < s->nseg; b++) {
                    const skel_pair_res_t *p = &s->pair[a][b];
                    if (!s->pair_ok[a][b]) {
                        continue;
                    }
                    printf("%s{\"a\":", first ? "" : ",");
                    first = 0;
                    json_out_str(stdout, s->seg[a].name, 0);
                    printf(",\"b\":");
                    json_out_str(stdout, s->seg[b].name, 0);
                    printf(",\"type\":\"%s\",\"cost\":%.6g,\"rotation_spread_deg\":[%.4g,%.4g,%.4g],"
                           "\"frames\":%.0f,\"reason\":\"%s\",\"flags\":",
                           type_name(p->type), p->rms, sqrt(p->s[0]) * 57.29577951308232,
                           sqrt(p->s[1]) * 57.29577951308232, sqrt(p->s[2]) * 57.29577951308232,
                           p->n, names_pair_reason(p->lib.reason));
                    names_flags_json(stdout, NAMES_SKEL, p->flags);
                    printf(",\"untrusted_why\":");
                    names_flags_json(stdout, NAMES_SKEL_WHY, p->why_untrusted);
                    printf(",\"reach\":[%.6g,%.6g],\"misfit\":%.6g,\"noise\":%.6g", p->reach_a,
                           p->reach_b, (double)p->lib.misfit, sqrt((double)p->lib.marker_var));
                    printf("}");
                }
            }
        }
        printf("],\"joints\":[");
        for (k = 0; k < s->njoint; k++) {
            const skel_joint_t *j = &s->joint[k];
            printf("%s{\"name\":", k ? "," : "");
            json_out_str(stdout, j->name, 0);
            printf(",\"parent\":");
            json_out_str(stdout, s->seg[j->parent].name, 0);
            printf(",\"child\":");
            json_out_str(stdout, s->seg[j->child].name, 0);
            printf(",\"type\":\"%s\",\"center_parent\":", type_name(j->pr.type));
            jvec(j->pr.ca, 3);
            if (j->pr.type == SKEL_HINGE) {
                printf(",\"axis_parent\":");
                jvec(j->pr.axis_a, 3);
            }
            printf(",\"cost\":%.6g,\"sigma\":%.6g,\"cov_parent\":", j->pr.rms, j->pr.sigma);
            jvec(j->pr.cov_a, 9);
            {
                const double *q = s->pose_ok[(size_t)o.frame * (size_t)s->nseg + (size_t)j->parent]
                                      ? &s->pose[((size_t)o.frame * (size_t)s->nseg
                                                  + (size_t)j->parent) * 12u]
                                      : NULL;
                printf(",\"center_lab\":");
                if (q != NULL) {
                    double c[3], cl[9], rcv[9];
                    int a, b, m;
                    for (a = 0; a < 3; a++) {
                        c[a] = q[9 + a];
                        for (b = 0; b < 3; b++) {
                            c[a] += q[a * 3 + b] * j->pr.ca[b];
                            rcv[a * 3 + b] = 0.0;
                            for (m = 0; m < 3; m++) {
                                rcv[a * 3 + b] += q[a * 3 + m] * j->pr.cov_a[m * 3 + b];
                            }
                        }
                    }
                    for (a = 0; a < 3; a++) {
                        for (b = 0; b < 3; b++) {
                            cl[a * 3 + b] = 0.0;
                            for (m = 0; m < 3; m++) {
                                cl[a * 3 + b] += rcv[a * 3 + m] * q[b * 3 + m];
                            }
                        }
                    }
                    jvec(c, 3);
                    printf(",\"cov_lab\":");
                    jvec(cl, 9);
                    if (j->pr.type == SKEL_HINGE) {
                        double ax[3];
                        for (a = 0; a < 3; a++) {
                            ax[a] = q[a * 3] * j->pr.axis_a[0] + q[a * 3 + 1] * j->pr.axis_a[1]
                                    + q[a * 3 + 2] * j->pr.axis_a[2];
                        }
                        printf(",\"axis_lab\":");
                        jvec(ax, 3);
                    }
                } else {
                    printf("null");
                }
            }
            /* the pair module's result, written as `sfit joint --json` writes it */
            pair_json(&j->pr);
            printf(",\"type_rule\":\"%s\",\"type_trial\":", j->pr.type_rule);
            if (j->pr.type_trial >= 0) {
                json_out_str(stdout, rec.file[j->pr.type_trial], 0);
            } else {
                printf("null");
            }
            printf(",\"trials_used\":");
            if (j->pr.trial >= 0) {
                printf("[");
                json_out_str(stdout, rec.file[j->pr.trial], 0);
                printf("]");
            } else {
                printf("\"all\"");
            }
            printf(",\"lag1\":%.4g,\"inflation\":%.4g,\"frames\":%.0f,\"flags\":", j->lag1,
                   j->infl, j->pr.n);
            names_flags_json(stdout, NAMES_SKEL, j->pr.flags);
            printf(",\"untrusted_why\":");
            names_flags_json(stdout, NAMES_SKEL_WHY, j->pr.why_untrusted);
            printf(",\"reach\":[%.6g,%.6g]", j->pr.reach_a, j->pr.reach_b);
            printf(",\"bvh_distance\":");
            if (j->bvh_frames > 0) {
                printf("{\"median\":%.6g,\"p95\":%.6g,\"frames\":%ld}", j->bvh_med, j->bvh_p95,
                       j->bvh_frames);
            } else {
                printf("null");
            }
            printf("}");
        }
        printf("],\"map_joints_not_in_tree\":[");
        if (map != NULL) {
            int first = 1;
            for (k = 0; k < map->njoint; k++) {
                if (!map_joint_in_tree(s, map, k)) {
                    printf("%s", first ? "" : ",");
                    json_out_str(stdout, map->jname[k], 0);
                    first = 0;
                }
            }
        }
        printf("],\"not_in_tree\":[");
        {
            int first = 1;
            for (k = 0; k < s->nseg; k++) {
                if (k != s->root && s->parent_joint[k] < 0) {
                    printf("%s", first ? "" : ",");
                    json_out_str(stdout, s->seg[k].name, 0);
                    first = 0;
                }
            }
        }
        printf("]}\n");
    } else {
        printf("trials       %d file(s), %ld frames (every %ld), %d markers, units %s\n",
               o.nfiles, rec.nframes, o.step, rec.nmark, rec.units[0] ? rec.units : "?");
        if (rec.dropped > 0) {
            printf("dropped      %ld samples not finite or beyond 2^%d (taken as unseen)\n",
                   rec.dropped, SFIT_COORD_MAX_EXP);
        }
        if (map == NULL) {
            printf("groups       found from the data: rigid level %.3g, threshold %.3g %s (spread "
                   "of pair distances)\n",
                   grp->noise, grp->threshold, rec.units);
            for (k = 0; k < grp->n; k++) {
                printf("  group %-4d", k + 1);
                for (i = 0; i < grp->size[k]; i++) {
                    printf(" %s", rec.label[grp->member[k][i]]);
                }
                printf("  (spread %.3g)%s\n", grp->spread[k],
                       grp->size[k] < 2 ? " 1 marker: no pose"
                                        : (grp->size[k] == 2 ? " 2 markers: posed with a joint centre"
                                                             : ""));
            }
        }
        for (k = 0; k < s->nseg; k++) {
            printf("segment      %-10s", s->seg[k].name);
            for (i = 0; i < s->seg[k].nm; i++) {
                printf(" %s", s->seg[k].mk[i] < rec.nmark ? rec.label[s->seg[k].mk[i]] : "?");
            }
            if (s->seg[k].vpar >= 0) {
                printf(" + the centre they turn about in %s (sphere route, cost %.3g)",
                       s->seg[s->seg[k].vpar].name, s->seg[k].vcost);
            }
            printf("  (%ld frames with a pose)\n", s->seg[k].seen);
        }
        printf("root         %s (%s)\n", s->seg[s->root].name,
               s->root_named ? "named" : "the segment that moves least");
        for (k = 0; k < s->njoint; k++) {
            const skel_joint_t *j = &s->joint[k];
            printf("joint        %-10s %s -> %s, %s, cost %.3g %s, +-%.3g (1 sigma), %.0f frames",
                   j->name, s->seg[j->parent].name, s->seg[j->child].name, type_name(j->pr.type),
                   j->pr.rms, rec.units, j->pr.sigma, j->pr.n);
            print_flags(j->pr.flags);
            if (j->pr.why_untrusted != 0u) {
                static const char *const wn[] = {"misfit", "cost", "reach", "module"};
                int w, first = 1;
                printf(" [untrusted:");
                for (w = 0; w < 4; w++) {
                    if (j->pr.why_untrusted & (1u << w)) {
                        printf("%s %s", first ? "" : ",", wn[w]);
                        first = 0;
                    }
                }
                printf("]");
            }
            printf("\n  centre       %.3f %.3f %.3f (%s template frame: origin at its markers' "
                   "centroid, lab axes at the first frame that sees them all)\n",
                   j->pr.ca[0], j->pr.ca[1], j->pr.ca[2], s->seg[j->parent].name);
            if (j->bvh_frames > 0) {
                printf("  bvh          its forward kinematics %.3g %s from this centre (median), "
                       "%.3g (95th percentile)\n",
                       j->bvh_med, rec.units, j->bvh_p95);
            }
            if (j->pr.type == SKEL_HINGE) {
                printf("  axis         %.5f %.5f %.5f\n", j->pr.axis_a[0], j->pr.axis_a[1],
                       j->pr.axis_a[2]);
            }
            if (j->pr.type_trial >= 0) {
                printf("  type         %s: all trials together are ambiguous; decided on %s\n",
                       type_name(j->pr.type), rec.file[j->pr.type_trial]);
            }
            if (j->pr.trial >= 0) {
                printf("  estimated on %s alone (all trials together do not fix the hinge axis)\n",
                       rec.file[j->pr.trial]);
            }
            printf("  pair module  marker noise sigma %.3g %s (from the registration residuals), "
                   "misfit %.3g, 1 sigma %.3g before x%.3g for the slow residual (lag-1 %.3f)%s%s\n",
                   sqrt((double)j->pr.lib.marker_var), rec.units, (double)j->pr.lib.misfit,
                   j->pr.sigma / sqrt(j->infl), sqrt(j->infl), j->lag1,
                   (j->pr.lib.flags & (uint32_t)SFIT_FLAG_UNTRUSTED) ? ", untrusted: " : "",
                   (j->pr.lib.flags & (uint32_t)SFIT_FLAG_UNTRUSTED)
                       ? names_pair_reason(j->pr.lib.reason)
                       : "");
        }
        for (k = 0; k < s->nseg; k++) {
            if (k != s->root && s->parent_joint[k] < 0) {
                printf("not in tree  %s (no joint to the others)\n", s->seg[k].name);
            }
        }
        for (k = 0; map != NULL && k < map->njoint; k++) {
            if (!map_joint_in_tree(s, map, k)) {
                printf("map joint    %s (%s - %s) is not in the tree found\n", map->jname[k],
                       map->jpar[k], map->jchi[k]);
            }
        }
        if (o.bvh != NULL) {
            printf("bvh          %s (units %s)\n", o.bvh, rec.units);
        }
        if (o.trc != NULL) {
            printf("trc          %s\n", o.trc);
        }
        if (o.svg != NULL) {
            printf("picture      %s (frame %ld)\n", o.svg, o.frame);
        }
        if (o.html != NULL) {
            printf("page         %s\n", o.html);
        }
    }
done:
    skel_free(s);
    skel_rec_free(&rec);
    free(s);
    free(grp);
    free(map);
    return rc;
}
