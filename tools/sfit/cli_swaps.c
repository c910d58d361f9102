/* SPDX-License-Identifier: MIT */
/** @file cli_swaps.c  The label-swap check of a joint's two clusters, printed (cli_joint.h). */
#include <stdio.h>
#include <string.h>

#include "cli_joint.h"
#include "frames.h"

#define RUNS_JSON_MAX 64 /* runs listed per swap in the JSON */
#define RUNS_TEXT_MAX 4  /* in the text */

/* The labels a candidate moves, as given and true: "labels":[..],"true":[..] */
static void json_moved(const swaps_cand_t *c, int m, const char *const *names)
{
    int u, k = 0;
    printf("\"labels\":[");
    for (u = 0; u < m; u++) {
        if (c->lab[u] != u) {
            printf("%s", k++ > 0 ? "," : "");
            json_out_str(stdout, names[u], 0);
        }
    }
    printf("],\"true\":[");
    k = 0;
    for (u = 0; u < m; u++) {
        if (c->lab[u] != u) {
            printf("%s", k++ > 0 ? "," : "");
            json_out_str(stdout, names[c->lab[u]], 0);
        }
    }
    printf("]");
}

static void json_runs(const swaps_t *s, int st)
{
    long runs[RUNS_JSON_MAX][2];
    const long n = swaps_runs(s, st, runs, RUNS_JSON_MAX);
    long k;
    printf("\"runs\":[");
    for (k = 0; k < n && k < RUNS_JSON_MAX; k++) {
        printf("%s[%ld,%ld]", k > 0 ? "," : "", runs[k][0], runs[k][1]);
    }
    printf("],\"nruns\":%ld", n);
}

static void json_cluster(const swaps_t *s, const char *const *names, int repair)
{
    int u, c, k;
    printf("{\"markers\":[");
    for (u = 0; u < s->m; u++) {
        printf("%s", u > 0 ? "," : "");
        json_out_str(stdout, names[u], 0);
    }
    printf("],\"checked\":%s", s->checked ? "true" : "false");
    if (!s->checked) {
        printf(",\"why\":\"%s\"}", swaps_why(s->why));
        return;
    }
    printf(",\"frames_checked\":%ld,\"noise\":%.6g,\"decidable_above\":%.6g,"
           "\"no_fit_above\":%.6g,\"swapped_frames\":%ld,\"swaps\":[",
           s->frames_checked, s->scale, s->decide, s->misfit, s->frames_swapped);
    for (c = 1, k = 0; c < s->ncand; c++) {
        if (s->cand[c].count > 0) {
            printf("%s{", k++ > 0 ? "," : "");
            json_moved(&s->cand[c], s->m, names);
            printf(",\"count\":%ld,", s->cand[c].count);
            json_runs(s, c);
            printf(",\"action\":\"%s\"}", repair ? "repaired" : "detected");
        }
    }
    printf("],\"rejected\":{\"count\":%ld,\"no_fit\":{\"count\":%ld,",
           s->frames_no_fit + s->frames_ambiguous, s->frames_no_fit);
    json_runs(s, SWAPS_NO_FIT);
    printf("},\"ambiguous\":{\"count\":%ld,", s->frames_ambiguous);
    json_runs(s, SWAPS_AMBIGUOUS);
    printf("}");
    printf(",\"action\":\"%s\"},\"undecidable\":[", repair ? "rejected" : "detected");
    for (c = 1, k = 0; c < s->ncand; c++) {
        if (!s->cand[c].decidable) {
            printf("%s{", k++ > 0 ? "," : "");
            json_moved(&s->cand[c], s->m, names);
            printf(",\"pattern_change\":%.6g}", s->cand[c].pattern);
        }
    }
    printf("]}");
}

void cli_swaps_json(const swaps_joint_t *s, const char *const *names, int np)
{
    printf(",\"label_swaps\":{\"repair\":%s,\"z\":%g,\"parent\":", s->repair ? "true" : "false",
           SWAPS_Z);
    json_cluster(&s->parent, names, s->repair);
    printf(",\"child\":");
    json_cluster(&s->child, names + np, s->repair);
    printf("}");
}

/* "A<->B" or "A->B->C" (the point labelled A is B, ...) */
static void text_moved(const swaps_cand_t *c, int m, const char *const *names)
{
    int u;
    for (u = 0; u < m; u++) {
        if (c->lab[u] != u) {
            break;
        }
    }
    if (u == m) {
        return;
    }
    if (c->moved == 2) {
        printf("%s<->%s", names[u], names[c->lab[u]]);
    } else {
        printf("%s->%s->%s", names[u], names[c->lab[u]], names[c->lab[c->lab[u]]]);
    }
}

static void text_runs(const swaps_t *s, int st)
{
    long runs[RUNS_TEXT_MAX][2], k;
    const long n = swaps_runs(s, st, runs, RUNS_TEXT_MAX);
    for (k = 0; k < n && k < RUNS_TEXT_MAX; k++) {
        if (runs[k][0] == runs[k][1]) {
            printf("%s%ld", k > 0 ? ", " : "", runs[k][0]);
        } else {
            printf("%s%ld-%ld", k > 0 ? ", " : "", runs[k][0], runs[k][1]);
        }
    }
    if (n > RUNS_TEXT_MAX) {
        printf(", ... (%ld runs)", n);
    }
}

static void text_cluster(const swaps_t *s, const char *const *names, const char *what,
                         int repair, const char *units, const char *lead, const char *indent)
{
    int c;
    printf("%s%s: ", lead, what);
    if (!s->checked) {
        printf("not checked (%s)\n", swaps_why(s->why));
        return;
    }
    if (s->frames_swapped == 0 && s->frames_no_fit + s->frames_ambiguous == 0) {
        printf("none in %ld frames (distance noise %.3g %s)\n", s->frames_checked, s->scale,
               units);
    } else {
        printf("%ld frames checked (distance noise %.3g %s)\n", s->frames_checked, s->scale,
               units);
    }
    for (c = 1; c < s->ncand; c++) {
        if (s->cand[c].count > 0) {
            printf("%s  ", indent);
            text_moved(&s->cand[c], s->m, names);
            printf(" in %ld frames (", s->cand[c].count);
            text_runs(s, c);
            printf("): %s\n", repair ? "repaired (labels exchanged back)" : "NOT repaired");
        }
    }
    if (s->frames_no_fit > 0) {
        printf("%s  %ld frames fit no labelling (", indent, s->frames_no_fit);
        text_runs(s, SWAPS_NO_FIT);
        printf("): %s\n", repair ? "rejected" : "NOT rejected");
    }
    if (s->frames_ambiguous > 0) {
        printf("%s  %ld frames fit two relabellings alike (", indent, s->frames_ambiguous);
        text_runs(s, SWAPS_AMBIGUOUS);
        printf("): %s\n", repair ? "rejected" : "NOT rejected");
    }
    for (c = 1; c < s->ncand; c++) {
        if (!s->cand[c].decidable) {
            printf("%s  undecidable: ", indent);
            text_moved(&s->cand[c], s->m, names);
            printf(" changes the distances by %.3g %s < %.3g: such a swap cannot be seen\n",
                   s->cand[c].pattern, units, s->decide);
        }
    }
}

/* checked, and nothing to say */
static int quiet(const swaps_t *s)
{
    int c;
    if (!s->checked || s->frames_swapped > 0 || s->frames_no_fit + s->frames_ambiguous > 0) {
        return 0;
    }
    for (c = 1; c < s->ncand; c++) {
        if (!s->cand[c].decidable) {
            return 0;
        }
    }
    return 1;
}

void cli_swaps_human(const swaps_joint_t *s, const char *const *names, int np,
                           const char *units, const char *lead, const char *indent)
{
    if (quiet(&s->parent) && quiet(&s->child)) {
        printf("%snone found (parent %ld, child %ld frames checked)\n", lead,
               s->parent.frames_checked, s->child.frames_checked);
        return;
    }
    text_cluster(&s->parent, names, "parent", s->repair, units, lead, indent);
    text_cluster(&s->child, names + np, "child", s->repair, units, indent, indent);
}
