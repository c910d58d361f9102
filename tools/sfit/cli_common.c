/* SPDX-License-Identifier: MIT */
/** @file cli_common.c  Input layer and output helpers of the `sfit` tool. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "table.h"
#include "sfit/sfit_multi.h"

int cli_parse_floats(const char *s, float *out, int n)
{
    int i;
    const char *p = s;
    for (i = 0; i < n; i++) {
        char *end;
        out[i] = strtof(p, &end);
        if (end == p) {
            return -1;
        }
        p = end;
        while (*p == ' ' || *p == '\t') {
            p++;
        }
        if (i < n - 1) {
            if (*p != ',') {
                return -1;
            }
            p++;
        }
    }
    while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') {
        p++;
    }
    return (*p == '\0') ? 0 : -1;
}

static void note_reject(cli_input_t *in, unsigned long line, const char *why)
{
    if (in->rejected < CLI_REPORT_MAX) {
        in->bad_line[in->rejected] = line;
        in->bad_why[in->rejected] = why;
    }
    in->rejected++;
}

int cli_input_opt(int argc, char **argv, int *i, cli_src_t *src)
{
    if (strcmp(argv[*i], "--cols") != 0) {
        return 0;
    }
    if (*i + 1 >= argc || argv[*i + 1][0] == '\0') {
        fprintf(stderr, "sfit: --cols needs a list of column names or 1-based indices\n");
        return -1;
    }
    src->cols = argv[++*i];
    return 1;
}

int cli_read_xyz(const char *path, const cli_src_t *src, cli_sample_fn fn, void *ctx,
                 cli_input_t *in, char *why)
{
    table_t t;
    float v[3];
    int rc;

    memset(in, 0, sizeof *in);
    if (table_open_file(&t, path) != 0) {
        return -1;
    }
    if (table_start(&t) != 0 || table_select(&t, src->cols, 3) != 0) {
        (void)snprintf(why, TABLE_ERR_MAX, "%s", t.err);
        table_close(&t);
        return -2;
    }
    while ((rc = table_next(&t, v)) != TABLE_EOF) {
        sfit_status_t st;
        sfit_vec3_t x;
        in->lines++;
        if (rc == TABLE_ROW_BAD) {
            note_reject(in, t.lineno, t.why);
            continue;
        }
        if (t.blank > 0) {
            in->missing++;
            continue;
        }
        x.v[0] = v[0];
        x.v[1] = v[1];
        x.v[2] = v[2];
        st = fn(ctx, &x);
        if (st == SFIT_OK) {
            in->accepted++;
        } else {
            note_reject(in, t.lineno,
                        st == SFIT_E_NONFINITE ? "not finite"
                        : st == SFIT_E_RANGE   ? "out of range"
                                               : sfit_status_str(st));
        }
    }
    table_close(&t);
    return 0;
}

int cli_input_failed(int rc, const char *file, const char *why, int json)
{
    if (rc == -1) {
        return cli_open_failed(file, json);
    }
    if (json) {
        printf("{\"status\":\"format_error\",\"message\":");
        json_out_str(stdout, why, 0);
        printf("}\n");
    } else {
        fprintf(stderr, "sfit: %s: %s\n", file, why);
    }
    return CLI_IO;
}

sfit_status_t cli_add_to_moments(void *ctx, const sfit_vec3_t *x)
{
    return sfit_moments_add((sfit_moments_t *)ctx, x);
}

void cli_report_rejects(const char *file, const cli_input_t *in)
{
    unsigned long i;
    for (i = 0; i < in->rejected && i < CLI_REPORT_MAX; i++) {
        fprintf(stderr, "sfit: %s:%lu rejected: %s\n", file, in->bad_line[i], in->bad_why[i]);
    }
    if (in->rejected > CLI_REPORT_MAX) {
        fprintf(stderr, "sfit: ... %lu rejected lines in all\n", in->rejected);
    }
    if (in->missing > 0u) {
        fprintf(stderr, "sfit: %s: %lu rows with a blank cell skipped (missing samples)\n", file,
                in->missing);
    }
}

void cli_print_noise_json(int has_noise, float noise_var, int estimated)
{
    if (has_noise) {
        printf(",\"noise_var\":%.9g,\"noise_estimated\":%s", (double)noise_var,
               estimated ? "true" : "false");
    } else {
        printf(",\"noise_var\":null,\"noise_estimated\":false");
    }
}

int cli_json_error(const char *status, const char *message)
{
    printf("{\"status\":\"%s\",\"message\":\"%s\"}\n", status, message);
    return CLI_FAIL;
}

int cli_open_failed(const char *file, int json)
{
    if (json) {
        (void)cli_json_error("io_error", "cannot open an input file");
    } else {
        fprintf(stderr, "sfit: cannot open %s: %s\n", file, strerror(errno));
    }
    return CLI_IO;
}

int cli_parse_outcome(int parse_rc, void (*usage)(FILE *))
{
    if (parse_rc == 0) {
        return -1;
    }
    if (parse_rc == 1) {
        usage(stdout);
        return CLI_OK;
    }
    usage(stderr);
    return CLI_USAGE;
}

int cli_parse_mode(const char *s, sfit_mode_t *mode)
{
    if (strcmp(s, "auto") == 0) {
        *mode = SFIT_MODE_AUTO;
    } else if (strcmp(s, "sphere") == 0) {
        *mode = SFIT_MODE_SPHERE;
    } else if (strcmp(s, "planar") == 0) {
        *mode = SFIT_MODE_PLANAR;
    } else {
        return -1;
    }
    return 0;
}

static int in_bounds(float x, const cli_opt_t *o)
{
    return !(((o->bounds & CLI_GE_LO) != 0u && !(x >= o->lo))
             || ((o->bounds & CLI_GT_LO) != 0u && !(x > o->lo))
             || ((o->bounds & CLI_LE_HI) != 0u && !(x <= o->hi))
             || ((o->bounds & CLI_LT_HI) != 0u && !(x < o->hi)));
}

/* Take the value v of option o: NULL, or the message of a bad value. */
static const char *take_value(const cli_opt_t *o, char *v)
{
    char *end;
    int k;
    switch (o->kind) {
    case CLI_OPT_FLOATS:
        if (cli_parse_floats(v, (float *)o->dst, o->n) != 0) {
            return o->err;
        }
        for (k = 0; k < o->n; k++) {
            if (!in_bounds(((const float *)o->dst)[k], o)) {
                return o->err;
            }
        }
        return NULL;
    case CLI_OPT_COUNT:
        errno = 0;
        *(unsigned long *)o->dst = strtoul(v, &end, 10);
        return (v[0] == '-' || end == v || *end != '\0' || errno != 0) ? o->err : NULL;
    case CLI_OPT_INDEX:
        errno = 0;
        *(long *)o->dst = strtol(v, &end, 10);
        return (*end != '\0' || end == v || *(long *)o->dst < 0 || errno != 0) ? o->err : NULL;
    case CLI_OPT_MODE:
        return (cli_parse_mode(v, (sfit_mode_t *)o->dst) != 0) ? o->err : NULL;
    case CLI_OPT_STRING:
        *(char **)o->dst = v;
        return NULL;
    case CLI_OPT_FN:
        return o->fn(o->dst, v);
    case CLI_OPT_FLAG:
    case CLI_OPT_FN0:
    default:
        return "internal error: option without a value";
    }
}

static int parse_args(int argc, char **argv, const cli_args_t *a)
{
    unsigned long given = 0ul; /* bit k: opts[k] taken */
    int i, npos = 0;
    size_t k;
    for (i = 1; i < argc; i++) {
        char *s = argv[i];
        const char *msg = NULL;
        const cli_opt_t *o = NULL;
        const int io = (a->src != NULL) ? cli_input_opt(argc, argv, &i, a->src) : 0;
        if (io != 0) {
            if (io < 0) {
                return -1;
            }
            continue;
        }
        if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0) {
            return 1;
        }
        for (k = 0; k < a->nopts && o == NULL; k++) {
            if (strcmp(s, a->opts[k].name) == 0) {
                o = &a->opts[k];
                given |= 1ul << k; /* only read once the loop is over */
            }
        }
        if (o != NULL && o->kind == CLI_OPT_FLAG) {
            *(int *)o->dst = 1;
        } else if (o != NULL && o->kind == CLI_OPT_FN0) {
            msg = o->fn(o->dst, o->name);
        } else if (o != NULL && i + 1 < argc) {
            msg = take_value(o, argv[++i]);
        } else if (o != NULL && o->needs) {
            fprintf(stderr, "sfit: %s needs a value\n", s);
            return -1;
        } else if (s[0] == '-' && s[1] != '\0') {
            fprintf(stderr, "sfit: unknown or incomplete option %s\n", s);
            return -1;
        } else if (npos < a->max_pos) {
            a->pos[npos++] = s;
        } else {
            fprintf(stderr, "sfit: %s\n", a->extra);
            return -1;
        }
        if (msg != NULL) {
            fprintf(stderr, "sfit: %s\n", msg);
            return -1;
        }
        if (o != NULL && o->seen != NULL) {
            *o->seen = 1;
        }
    }
    if (a->npos != NULL) {
        *a->npos = npos;
    }
    for (k = 0; k < a->nopts; k++) {
        if (a->opts[k].required && (given & (1ul << k)) == 0ul) {
            fprintf(stderr, "sfit: %s\n", a->required);
            return -1;
        }
    }
    if (npos < a->min_pos) {
        fprintf(stderr, "sfit: %s\n", a->missing);
        return -1;
    }
    return 0;
}

int cli_parse(int argc, char **argv, const cli_args_t *a)
{
    return cli_parse_outcome(parse_args(argc, argv, a), a->usage);
}

int cli_read_moments(const char *file, const cli_src_t *src, int json, sfit_moments_t *acc,
                     cli_input_t *in)
{
    char why[TABLE_ERR_MAX];
    int rc;
    (void)sfit_moments_init(acc);
    rc = cli_read_xyz(file, src, cli_add_to_moments, acc, in, why);
    if (rc != 0) {
        return cli_input_failed(rc, file, why, json);
    }
    if (!json) {
        cli_report_rejects(file, in);
    }
    return 0;
}

int cli_report_failure(sfit_status_t st, const char *what, const char *message, int json,
                       const cli_input_t *in)
{
    const char *msg = (message != NULL) ? message : names_status_message(st, NAMES_CLI);
    if (json) {
        printf("{\"status\":\"%s\",\"message\":\"%s\",\"n\":%lu,\"rejected\":%lu}\n",
               sfit_status_str(st), msg, in->accepted, in->rejected);
    } else {
        fprintf(stderr, "sfit: %s failed (%s): %s (%lu samples read, %lu rejected)\n", what,
                sfit_status_str(st), msg, in->accepted, in->rejected);
    }
    return CLI_FAIL;
}
