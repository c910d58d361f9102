/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_fit.c
 * @brief `sfit fit`: stream a CSV into a moments accumulator and solve.
 *
 *   sfit fit [--noise-var V | --noise-cov XX,YY,ZZ,XY,XZ,YZ]
 *            [--mode auto|sphere|planar] [--json] FILE
 */
#include <errno.h>
#include <string.h>

#include "cli.h"

typedef struct fit_opts {
    const char *file;
    int json;
    sfit_fit_cfg_t cfg;
} fit_opts_t;

static void fit_usage(FILE *f)
{
    fputs("usage: sfit fit [--noise-var V | --noise-cov XX,YY,ZZ,XY,XZ,YZ]\n"
          "                [--mode auto|sphere|planar] [--json] FILE\n"
          "  FILE  CSV of x,y,z samples (optional header line); '-' reads stdin\n"
          "  --noise-var V    UGDK with isotropic measurement-noise variance V (unit^2)\n"
          "  --noise-cov ...  UGDK with a full symmetric noise covariance (unit^2)\n"
          "  --mode M         auto (default): sphere, or circle when the samples are\n"
          "                   near-planar (hinge); sphere / planar force one\n"
          "  --json           one JSON object on stdout\n",
          f);
}

static int fit_parse(int argc, char **argv, fit_opts_t *o)
{
    int i;
    o->file = NULL;
    o->json = 0;
    o->cfg = sfit_fit_cfg_default;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            return 1;
        } else if (strcmp(a, "--json") == 0) {
            o->json = 1;
        } else if (strcmp(a, "--noise-var") == 0 && i + 1 < argc) {
            if (o->cfg.noise != SFIT_NOISE_NONE
                || cli_parse_floats(argv[++i], &o->cfg.noise_var, 1) != 0
                || !(o->cfg.noise_var >= 0.0f)) {
                fprintf(stderr, "sfit: --noise-var needs one value >= 0 (not with --noise-cov)\n");
                return -1;
            }
            o->cfg.noise = SFIT_NOISE_ISO;
        } else if (strcmp(a, "--noise-cov") == 0 && i + 1 < argc) {
            float c[6];
            float *m = o->cfg.noise_cov.m;
            if (o->cfg.noise != SFIT_NOISE_NONE || cli_parse_floats(argv[++i], c, 6) != 0) {
                fprintf(stderr, "sfit: --noise-cov needs XX,YY,ZZ,XY,XZ,YZ (not with --noise-var)\n");
                return -1;
            }
            o->cfg.noise = SFIT_NOISE_COV;
            m[0] = c[0]; m[4] = c[1]; m[8] = c[2];
            m[1] = c[3]; m[3] = c[3];
            m[2] = c[4]; m[6] = c[4];
            m[5] = c[5]; m[7] = c[5];
        } else if (strcmp(a, "--mode") == 0 && i + 1 < argc) {
            const char *md = argv[++i];
            if (strcmp(md, "auto") == 0) {
                o->cfg.mode = SFIT_MODE_AUTO;
            } else if (strcmp(md, "sphere") == 0) {
                o->cfg.mode = SFIT_MODE_SPHERE;
            } else if (strcmp(md, "planar") == 0) {
                o->cfg.mode = SFIT_MODE_PLANAR;
            } else {
                fprintf(stderr, "sfit: --mode is auto, sphere or planar\n");
                return -1;
            }
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "sfit: unknown or incomplete option %s\n", a);
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

static const char *mode_name(sfit_mode_t m)
{
    return (m == SFIT_MODE_PLANAR) ? "planar" : "sphere";
}

static void print_flags_json(uint32_t flags)
{
    const char *sep = "";
    printf("[");
    if (flags & SFIT_FLAG_UNTRUSTED) {
        printf("%s\"untrusted\"", sep);
        sep = ",";
    }
    if (flags & SFIT_FLAG_FEW_SAMPLES) {
        printf("%s\"few_samples\"", sep);
        sep = ",";
    }
    if (flags & SFIT_FLAG_NEAR_PLANAR) {
        printf("%s\"near_planar\"", sep);
    }
    printf("]");
}

static void print_json(const sfit_result_t *r, const cli_input_t *in)
{
    printf("{\"status\":\"ok\",\"method\":\"%s\",\"mode\":\"%s\",\"n\":%lu,\"rejected\":%lu,"
           "\"center\":",
           r->method == SFIT_METHOD_UGDK ? "ugdk" : "gdke", mode_name(r->mode),
           (unsigned long)r->n, in->rejected);
    cli_print_vec(r->center.v);
    printf(",\"radius\":%.9g,\"eigenvalues\":", (double)r->radius);
    cli_print_vec(r->eigenvalues.v);
    printf(",\"trust_ratio\":%.9g,\"leontief_ratio\":%.9g", (double)r->trust_ratio,
           (double)r->leontief_ratio);
    if (r->mode == SFIT_MODE_PLANAR) {
        printf(",\"axis\":");
        cli_print_vec(r->axis.v);
    }
    printf(",\"flags\":");
    print_flags_json(r->flags);
    printf("}\n");
}

static void print_human(const char *file, const sfit_result_t *r, const cli_input_t *in)
{
    printf("file         %s\n", file);
    printf("samples      %lu used, %lu rejected\n", (unsigned long)r->n, in->rejected);
    printf("method       %s, %s solution\n", r->method == SFIT_METHOD_UGDK ? "UGDK" : "GDKE",
           mode_name(r->mode));
    printf("centre       %.4f %.4f %.4f\n", (double)r->center.v[0], (double)r->center.v[1],
           (double)r->center.v[2]);
    printf("radius       %.4f\n", (double)r->radius);
    if (r->mode == SFIT_MODE_PLANAR) {
        printf("axis         %.5f %.5f %.5f\n", (double)r->axis.v[0], (double)r->axis.v[1],
               (double)r->axis.v[2]);
    }
    printf("eigenvalues  %.6g %.6g %.6g (of the sample covariance C)\n",
           (double)r->eigenvalues.v[0], (double)r->eigenvalues.v[1],
           (double)r->eigenvalues.v[2]);
    if (r->method == SFIT_METHOD_UGDK) {
        printf("trust ratio  %.4g = rho(C^-1 Sigma); Leontief ratio %.4g (%s)\n",
               (double)r->trust_ratio, (double)r->leontief_ratio,
               r->leontief_ratio < 1.0f ? "< 1: condition of eq. 194 holds"
                                        : ">= 1: do not trust this fit");
    } else {
        printf("trust ratio  n/a (no noise model: GDKE is biased on partial spheres)\n");
    }
    if (r->flags & SFIT_FLAG_FEW_SAMPLES) {
        printf("warning      few samples\n");
    }
    if ((r->flags & SFIT_FLAG_NEAR_PLANAR) && r->mode == SFIT_MODE_SPHERE) {
        printf("warning      samples are near-planar: the sphere is ill-conditioned\n");
    }
}

int cli_cmd_fit(int argc, char **argv)
{
    fit_opts_t o;
    sfit_moments_t acc;
    cli_input_t in;
    sfit_result_t r;
    sfit_status_t st;

    switch (fit_parse(argc, argv, &o)) {
    case 0:
        break;
    case 1:
        fit_usage(stdout);
        return CLI_OK;
    default:
        fit_usage(stderr);
        return CLI_USAGE;
    }
    (void)sfit_moments_init(&acc);
    if (cli_read_csv(o.file, cli_add_to_moments, &acc, &in) != 0) {
        if (o.json) {
            (void)cli_json_error("io_error", "cannot open the input file");
        } else {
            fprintf(stderr, "sfit: cannot open %s: %s\n", o.file, strerror(errno));
        }
        return CLI_IO;
    }
    st = sfit_fit_solve(&acc, &o.cfg, &r);
    if (!o.json) {
        cli_report_rejects(o.file, &in);
    }
    if (st != SFIT_OK) {
        if (o.json) {
            printf("{\"status\":\"%s\",\"message\":\"%s\",\"n\":%lu,\"rejected\":%lu}\n",
                   sfit_status_str(st), cli_status_message(st), in.accepted, in.rejected);
        } else {
            fprintf(stderr, "sfit: fit failed (%s): %s\n", sfit_status_str(st),
                    cli_status_message(st));
        }
        return CLI_FAIL;
    }
    if (o.json) {
        print_json(&r, &in);
    } else {
        print_human(o.file, &r, &in);
    }
    return CLI_OK;
}
