/* SPDX-License-Identifier: MIT */
/** @file cli_common.c  CSV streaming and output helpers of the `sfit` tool. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

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

int cli_read_csv(const char *path, cli_sample_fn fn, void *ctx, cli_input_t *in)
{
    char buf[CLI_LINE_MAX];
    unsigned long lineno = 0;
    FILE *f = (strcmp(path, "-") == 0) ? stdin : fopen(path, "r");

    memset(in, 0, sizeof *in);
    if (f == NULL) {
        return -1;
    }
    while (fgets(buf, sizeof buf, f) != NULL) {
        sfit_vec3_t x;
        const size_t len = strlen(buf);
        const int toolong = (len == sizeof buf - 1u && buf[len - 1u] != '\n');
        sfit_status_t st;
        lineno++;
        if (toolong) { /* swallow the rest of the line */
            int ch;
            do {
                ch = fgetc(f);
            } while (ch != '\n' && ch != EOF);
        }
        if (buf[strspn(buf, " \t\r\n")] == '\0') {
            continue; /* blank line */
        }
        if (toolong || cli_parse_floats(buf, x.v, 3) != 0) {
            if (lineno == 1u && !toolong) {
                continue; /* header */
            }
            in->lines++;
            note_reject(in, lineno, "does not parse as x,y,z");
            continue;
        }
        in->lines++;
        st = fn(ctx, &x);
        if (st == SFIT_OK) {
            in->accepted++;
        } else {
            note_reject(in, lineno,
                        st == SFIT_E_NONFINITE ? "not finite"
                        : st == SFIT_E_RANGE   ? "out of range"
                                               : sfit_status_str(st));
        }
    }
    if (f != stdin) {
        fclose(f);
    }
    return 0;
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
}

const char *cli_status_message(sfit_status_t st)
{
    switch (st) {
    case SFIT_E_TOO_FEW: return "fewer than 4 valid samples";
    case SFIT_E_DEGENERATE:
        return "degenerate geometry: samples coincident, collinear, or planar "
               "(try --mode planar)";
    case SFIT_E_NOT_POSDEF:
        return "C - Sigma_hat is not positive definite: the noise model is larger "
               "than the spread of the samples";
    case SFIT_E_NO_CONVERGENCE: return "the iteration did not converge within its bound";
    case SFIT_E_RANGE: return "value out of the supported float range";
    case SFIT_E_ARG: return "invalid option value";
    case SFIT_E_NONFINITE: return "non-finite value";
    case SFIT_OK: return "ok";
    default: return "unknown error";
    }
}

void cli_print_vec(const float *v)
{
    printf("[%.9g,%.9g,%.9g]", (double)v[0], (double)v[1], (double)v[2]);
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

int cli_positional(const char *arg, const char **file)
{
    if (arg[0] == '-' && arg[1] != '\0') {
        fprintf(stderr, "sfit: unknown or incomplete option %s\n", arg);
        return -1;
    }
    if (*file != NULL) {
        fprintf(stderr, "sfit: one FILE expected\n");
        return -1;
    }
    *file = arg;
    return 0;
}

int cli_read_moments(const char *file, int json, sfit_moments_t *acc, cli_input_t *in)
{
    (void)sfit_moments_init(acc);
    if (cli_read_csv(file, cli_add_to_moments, acc, in) != 0) {
        return cli_open_failed(file, json);
    }
    if (!json) {
        cli_report_rejects(file, in);
    }
    return 0;
}

int cli_report_failure(sfit_status_t st, const char *what, const char *message, int json,
                       const cli_input_t *in)
{
    const char *msg = (message != NULL) ? message : cli_status_message(st);
    if (json) {
        printf("{\"status\":\"%s\",\"message\":\"%s\",\"n\":%lu,\"rejected\":%lu}\n",
               sfit_status_str(st), msg, in->accepted, in->rejected);
    } else {
        fprintf(stderr, "sfit: %s failed (%s): %s\n", what, sfit_status_str(st), msg);
    }
    return CLI_FAIL;
}
