/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_noise.c
 * @brief `sfit noise`: calibrate the measurement noise on a known sphere
 * (chapter eq. 177) and predict the spread of the estimate (eq. 190).
 *
 *   sfit noise --center X,Y,Z --radius R [--json] FILE
 */
#include <math.h>
#include <string.h>

#include "cli.h"
#include "sfit/sfit_noise.h"

/* Also declared in cli.h once the command is registered there. */

typedef struct noise_opts {
    const char *file;
    int json;
    int have_center;
    int have_radius;
    sfit_vec3_t center;
    float radius;
} noise_opts_t;

static void noise_usage(FILE *f)
{
    fputs("usage: sfit noise --center X,Y,Z --radius R [--json] FILE\n"
          "  Estimate the measurement-noise variance from samples of a sphere whose\n"
          "  centre and radius are known (a calibration jig; R = 0: a fixed point).\n"
          "  FILE  CSV of x,y,z samples (optional header line); '-' reads stdin\n"
          "  --center X,Y,Z   known centre\n"
          "  --radius R       known radius (>= 0)\n"
          "  --json           one JSON object on stdout\n"
          "  noise_var is sigma^2 per axis (unit^2), unbiased, reported unclamped\n"
          "  (it can be negative by chance); noise_var_std is its predicted standard\n"
          "  deviation 2 s2 (3 s2 + 2 R^2) / (9 N), square-rooted (Gaussian noise).\n",
          f);
}

static int noise_parse(int argc, char **argv, noise_opts_t *o)
{
    int i;
    memset(o, 0, sizeof *o);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            return 1;
        } else if (strcmp(a, "--json") == 0) {
            o->json = 1;
        } else if (strcmp(a, "--center") == 0 && i + 1 < argc) {
            if (cli_parse_floats(argv[++i], o->center.v, 3) != 0) {
                fprintf(stderr, "sfit: --center needs X,Y,Z\n");
                return -1;
            }
            o->have_center = 1;
        } else if (strcmp(a, "--radius") == 0 && i + 1 < argc) {
            if (cli_parse_floats(argv[++i], &o->radius, 1) != 0 || !(o->radius >= 0.0f)) {
                fprintf(stderr, "sfit: --radius needs one value >= 0\n");
                return -1;
            }
            o->have_radius = 1;
        } else if (cli_positional(a, &o->file) != 0) {
            return -1;
        }
    }
    if (!o->have_center || !o->have_radius) {
        fprintf(stderr, "sfit: --center and --radius are required\n");
        return -1;
    }
    if (o->file == NULL) {
        fprintf(stderr, "sfit: FILE missing\n");
        return -1;
    }
    return 0;
}

static void noise_human(const char *file, const sfit_noise_est_t *e, const cli_input_t *in)
{
    printf("file          %s\n", file);
    printf("samples       %lu used, %lu rejected\n", (unsigned long)e->n, in->rejected);
    printf("noise trace   %.6g (Tr Sigma, unit^2)\n", (double)e->noise_trace);
    printf("noise var     %.6g +- %.3g (sigma^2 per axis, unit^2)\n", (double)e->noise_var,
           (double)e->noise_var_std);
    if (e->noise_var > 0.0f) {
        printf("noise sigma   %.6g\n", (double)sqrtf(e->noise_var));
    }
    if (e->flags & SFIT_NOISE_FLAG_NEGATIVE) {
        printf("warning       negative estimate (reported unclamped): the noise is below\n"
               "              the calibration's resolution\n");
    } else if (e->flags & SFIT_NOISE_FLAG_IMPRECISE) {
        printf("warning       estimate below twice its standard deviation: use more\n"
               "              samples or a smaller calibration radius\n");
    }
}

int cli_cmd_noise(int argc, char **argv)
{
    noise_opts_t o;
    sfit_moments_t acc;
    cli_input_t in;
    sfit_noise_est_t e;
    sfit_status_t st;

    {
        const int prc = cli_parse_outcome(noise_parse(argc, argv, &o), noise_usage);
        if (prc >= 0) {
            return prc;
        }
    }
    {
        const int rrc = cli_read_moments(o.file, o.json, &acc, &in);
        if (rrc != 0) {
            return rrc;
        }
    }
    st = sfit_moments_calibrate(&acc, &o.center, o.radius, &e);
    if (st != SFIT_OK) {
        return cli_report_failure(st, "noise calibration",
                                  (st == SFIT_E_TOO_FEW) ? "no valid sample" : NULL, o.json, &in);
    }
    if (o.json) {
        printf("{\"status\":\"ok\",\"n\":%lu,\"noise_var\":%.9g,\"noise_var_std\":%.9g,"
               "\"noise_trace\":%.9g,\"negative\":%s,\"rejected\":%lu}\n",
               (unsigned long)e.n, (double)e.noise_var, (double)e.noise_var_std,
               (double)e.noise_trace,
               (e.flags & SFIT_NOISE_FLAG_NEGATIVE) ? "true" : "false", in.rejected);
    } else {
        noise_human(o.file, &e, &in);
    }
    return CLI_OK;
}
