/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_cli.c
 * @brief `sfit`: the host command-line tool (CSV samples -> sphere/circle fit).
 *
 *   sfit fit [--noise-var V | --noise-cov XX,YY,ZZ,XY,XZ,YZ]
 *            [--mode auto|sphere|planar] [--json] FILE
 *
 * FILE is CSV (`-` = standard input): an optional header line, then x,y,z per
 * line. Samples stream into one sfit_moments_t, exactly as a firmware would
 * feed them; a line that does not parse, or holds a value the library
 * rejects, is counted and reported and the fit goes on.
 *
 * Exit status: 0 ok, 1 the fit failed, 2 usage error, 3 file error.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit.h"

#define CLI_LINE_MAX 1024
#define CLI_REPORT_MAX 10 /* rejected lines listed in the human summary */

typedef struct cli_opts {
    const char *file;
    int json;
    sfit_fit_cfg_t cfg;
} cli_opts_t;

typedef struct cli_input {
    sfit_moments_t acc;
    unsigned long lines;    /* data lines seen (header excluded) */
    unsigned long rejected; /* lines that did not parse or were rejected */
    unsigned long bad_line[CLI_REPORT_MAX];
    const char *bad_why[CLI_REPORT_MAX];
} cli_input_t;

static void usage(FILE *f)
{
    fputs("usage: sfit fit [--noise-var V | --noise-cov XX,YY,ZZ,XY,XZ,YZ]\n"
          "                [--mode auto|sphere|planar] [--json] FILE\n"
          "  FILE  CSV of x,y,z samples (optional header line); '-' reads stdin\n"
          "  --noise-var V    UGDK with isotropic measurement noise variance V (unit^2)\n"
          "  --noise-cov ...  UGDK with a full symmetric noise covariance\n"
          "  --mode M         auto (default): sphere, or circle when the samples are\n"
          "                   near-planar (hinge); sphere / planar force one\n"
          "  --json           one JSON object on stdout\n",
          f);
}

/* Parse exactly n comma-separated floats from s; 0 on success. */
static int parse_floats(const char *s, float *out, int n)
{
    int i;
    const char *p = s;
    for (i = 0; i < n; i++) {
        char *end;
        errno = 0;
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

/* Stream a CSV file into in->acc. Returns 0, or -1 if the file can't be read. */
static int read_csv(const char *path, cli_input_t *in)
{
    char buf[CLI_LINE_MAX];
    unsigned long lineno = 0;
    FILE *f = (strcmp(path, "-") == 0) ? stdin : fopen(path, "r");
    if (f == NULL) {
        return -1;
    }
    (void)sfit_moments_init(&in->acc);
    while (fgets(buf, sizeof buf, f) != NULL) {
        sfit_vec3_t x;
        size_t len = strlen(buf);
        int toolong = (len == sizeof buf - 1u && buf[len - 1u] != '\n');
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
        if (toolong || parse_floats(buf, x.v, 3) != 0) {
            if (lineno == 1u && !toolong) {
                continue; /* header */
            }
            in->lines++;
            note_reject(in, lineno, "does not parse as x,y,z");
            continue;
        }
        in->lines++;
        st = sfit_moments_add(&in->acc, &x);
        if (st != SFIT_OK) {
            note_reject(in, lineno, st == SFIT_E_NONFINITE ? "not finite" : "out of range");
        }
    }
    if (f != stdin) {
        fclose(f);
    }
    return 0;
}

static const char *mode_name(sfit_mode_t m)
{
    return (m == SFIT_MODE_PLANAR) ? "planar" : "sphere";
}

static const char *status_message(sfit_status_t st)
{
    switch (st) {
    case SFIT_E_TOO_FEW: return "fewer than 4 valid samples";
    case SFIT_E_DEGENERATE:
        return "degenerate geometry: samples coincident, collinear, or planar "
               "(try --mode planar)";
    case SFIT_E_NOT_POSDEF:
        return "C - Sigma_hat is not positive definite: the noise model is larger "
               "than the spread of the samples";
    case SFIT_E_NO_CONVERGENCE: return "eigen-solver did not converge";
    case SFIT_E_RANGE: return "result out of float range";
    case SFIT_E_ARG: return "invalid option value";
    case SFIT_E_NONFINITE: return "non-finite value";
    case SFIT_OK: return "ok";
    default: return "unknown error";
    }
}

static void print_vec(const float *v)
{
    printf("[%.9g,%.9g,%.9g]", (double)v[0], (double)v[1], (double)v[2]);
}

static int cmd_fit(const cli_opts_t *o)
{
    static cli_input_t in; /* large-ish; static keeps main's stack small */
    sfit_result_t r;
    sfit_status_t st;
    unsigned long i;

    memset(&in, 0, sizeof in);
    if (read_csv(o->file, &in) != 0) {
        if (o->json) {
            printf("{\"status\":\"io_error\",\"message\":\"cannot open %s\"}\n", o->file);
        } else {
            fprintf(stderr, "sfit: cannot open %s: %s\n", o->file, strerror(errno));
        }
        return 3;
    }
    st = sfit_fit_solve(&in.acc, &o->cfg, &r);
    if (o->json) {
        if (st != SFIT_OK) {
            printf("{\"status\":\"%s\",\"message\":\"%s\",\"n\":%lu,\"rejected\":%lu}\n",
                   sfit_status_str(st), status_message(st),
                   (unsigned long)sfit_moments_count(&in.acc), in.rejected);
            return 1;
        }
        printf("{\"status\":\"ok\",\"method\":\"%s\",\"mode\":\"%s\",\"n\":%lu,\"rejected\":%lu,"
               "\"center\":",
               r.method == SFIT_METHOD_UGDK ? "ugdk" : "gdke", mode_name(r.mode),
               (unsigned long)r.n, in.rejected);
        print_vec(r.center.v);
        printf(",\"radius\":%.9g,\"eigenvalues\":", (double)r.radius);
        print_vec(r.eigenvalues.v);
        printf(",\"trust_ratio\":%.9g", (double)r.trust_ratio);
        if (r.mode == SFIT_MODE_PLANAR) {
            printf(",\"axis\":");
            print_vec(r.axis.v);
        }
        printf(",\"flags\":[%s%s%s]}\n",
               (r.flags & SFIT_FLAG_UNTRUSTED) ? "\"untrusted\"" : "",
               (r.flags & SFIT_FLAG_FEW_SAMPLES)
                   ? ((r.flags & SFIT_FLAG_UNTRUSTED) ? ",\"few_samples\"" : "\"few_samples\"")
                   : "",
               (r.flags & SFIT_FLAG_NEAR_PLANAR)
                   ? ((r.flags & (SFIT_FLAG_UNTRUSTED | SFIT_FLAG_FEW_SAMPLES))
                          ? ",\"near_planar\""
                          : "\"near_planar\"")
                   : "");
        return 0;
    }
    for (i = 0; i < in.rejected && i < CLI_REPORT_MAX; i++) {
        fprintf(stderr, "sfit: %s:%lu rejected: %s\n", o->file, in.bad_line[i], in.bad_why[i]);
    }
    if (in.rejected > CLI_REPORT_MAX) {
        fprintf(stderr, "sfit: ... %lu rejected lines in all\n", in.rejected);
    }
    if (st != SFIT_OK) {
        fprintf(stderr, "sfit: fit failed (%s): %s\n", sfit_status_str(st), status_message(st));
        return 1;
    }
    printf("file         %s\n", o->file);
    printf("samples      %lu used, %lu rejected\n", (unsigned long)r.n, in.rejected);
    printf("method       %s, %s solution\n", r.method == SFIT_METHOD_UGDK ? "UGDK" : "GDKE",
           mode_name(r.mode));
    printf("centre       %.4f %.4f %.4f\n", (double)r.center.v[0], (double)r.center.v[1],
           (double)r.center.v[2]);
    printf("radius       %.4f\n", (double)r.radius);
    if (r.mode == SFIT_MODE_PLANAR) {
        printf("axis         %.5f %.5f %.5f\n", (double)r.axis.v[0], (double)r.axis.v[1],
               (double)r.axis.v[2]);
    }
    printf("eigenvalues  %.6g %.6g %.6g (of the sample covariance C)\n",
           (double)r.eigenvalues.v[0], (double)r.eigenvalues.v[1], (double)r.eigenvalues.v[2]);
    if (r.method == SFIT_METHOD_UGDK) {
        printf("trust ratio  %.4g (%s)\n", (double)r.trust_ratio,
               r.trust_ratio < 1.0f ? "< 1: Leontief condition holds" : ">= 1: do not trust");
    } else {
        printf("trust ratio  n/a (no noise model; GDKE is biased on partial spheres)\n");
    }
    if (r.flags & SFIT_FLAG_FEW_SAMPLES) {
        printf("warning      few samples\n");
    }
    if ((r.flags & SFIT_FLAG_NEAR_PLANAR) && r.mode == SFIT_MODE_SPHERE) {
        printf("warning      samples are near-planar: the sphere is ill-conditioned\n");
    }
    return 0;
}

static int parse_args(int argc, char **argv, cli_opts_t *o)
{
    int i;
    o->file = NULL;
    o->json = 0;
    o->cfg = sfit_fit_cfg_default;
    for (i = 2; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--json") == 0) {
            o->json = 1;
        } else if (strcmp(a, "--noise-var") == 0 && i + 1 < argc) {
            if (o->cfg.noise != SFIT_NOISE_NONE || parse_floats(argv[++i], &o->cfg.noise_var, 1)
                || !(o->cfg.noise_var >= 0.0f)) {
                fprintf(stderr, "sfit: --noise-var needs one value >= 0 (and excludes --noise-cov)\n");
                return -1;
            }
            o->cfg.noise = SFIT_NOISE_ISO;
        } else if (strcmp(a, "--noise-cov") == 0 && i + 1 < argc) {
            float c[6];
            if (o->cfg.noise != SFIT_NOISE_NONE || parse_floats(argv[++i], c, 6)) {
                fprintf(stderr, "sfit: --noise-cov needs XX,YY,ZZ,XY,XZ,YZ (and excludes --noise-var)\n");
                return -1;
            }
            o->cfg.noise = SFIT_NOISE_COV;
            o->cfg.noise_cov.m[0] = c[0]; o->cfg.noise_cov.m[4] = c[1]; o->cfg.noise_cov.m[8] = c[2];
            o->cfg.noise_cov.m[1] = c[3]; o->cfg.noise_cov.m[3] = c[3];
            o->cfg.noise_cov.m[2] = c[4]; o->cfg.noise_cov.m[6] = c[4];
            o->cfg.noise_cov.m[5] = c[5]; o->cfg.noise_cov.m[7] = c[5];
        } else if (strcmp(a, "--mode") == 0 && i + 1 < argc) {
            const char *m = argv[++i];
            if (strcmp(m, "auto") == 0) {
                o->cfg.mode = SFIT_MODE_AUTO;
            } else if (strcmp(m, "sphere") == 0) {
                o->cfg.mode = SFIT_MODE_SPHERE;
            } else if (strcmp(m, "planar") == 0) {
                o->cfg.mode = SFIT_MODE_PLANAR;
            } else {
                fprintf(stderr, "sfit: --mode is auto, sphere or planar\n");
                return -1;
            }
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "sfit: unknown option %s\n", a);
            return -1;
        } else if (o->file == NULL) {
            o->file = a;
        } else {
            fprintf(stderr, "sfit: one FILE expected\n");
            return -1;
        }
    }
    if (o->file == NULL) {
        fprintf(stderr, "sfit: FILE missing\n");
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    cli_opts_t o;
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    if (strcmp(argv[1], "fit") != 0) {
        fprintf(stderr, "sfit: unknown command '%s'\n", argv[1]);
        usage(stderr);
        return 2;
    }
    if (parse_args(argc, argv, &o) != 0) {
        if (o.json) { /* keep --json callers machine-readable */
            printf("{\"status\":\"usage\",\"message\":\"invalid command line\"}\n");
        }
        usage(stderr);
        return 2;
    }
    return cmd_fit(&o);
}
