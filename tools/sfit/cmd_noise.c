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

typedef struct noise_opts {
    const char *file;
    int json;
    sfit_vec3_t center;
    float radius;
    cli_src_t src;
} noise_opts_t;

static void noise_usage(FILE *f)
{
    fputs("usage: sfit noise --center X,Y,Z --radius R [--cols A,B,C] [--json] FILE\n"
          "  Estimate the measurement-noise variance from samples of a sphere whose\n"
          "  centre and radius are known (a calibration jig; R = 0: a fixed point).\n"
          CLI_INPUT_USAGE
          "  --center X,Y,Z   known centre\n"
          "  --radius R       known radius (>= 0)\n"
          "  --json           one JSON object on stdout\n"
          "  noise_var is sigma^2 per axis (unit^2), unbiased, reported unclamped\n"
          "  (it can be negative by chance); noise_var_std is its predicted standard\n"
          "  deviation 2 s2 (3 s2 + 2 R^2) / (9 N), square-rooted (Gaussian noise).\n",
          f);
}

/* -1 to go on, or the exit status (cli_parse). */
static int noise_parse(int argc, char **argv, noise_opts_t *o)
{
    const cli_opt_t opts[] = {
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &o->json},
        {.name = "--center", .kind = CLI_OPT_FLOATS, .dst = &o->center, .n = 3, /* its v[3] */
         .bounds = CLI_GT_LO | CLI_LT_HI, .lo = -3.0e38f, .hi = 3.0e38f, .required = 1,
         .err = "--center needs X,Y,Z (finite)"},
        {.name = "--radius", .kind = CLI_OPT_FLOATS, .dst = &o->radius, .n = 1,
         .bounds = CLI_GE_LO | CLI_LT_HI, .lo = 0.0f, .hi = 3.0e38f, .required = 1,
         .err = "--radius needs one finite value >= 0"},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0],
                             .src = &o->src, CLI_ONE_FILE(o->file),
                             .required = "--center and --radius are required",
                             .usage = noise_usage};
    memset(o, 0, sizeof *o);
    return cli_parse(argc, argv, &args);
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
        const int prc = noise_parse(argc, argv, &o);
        if (prc >= 0) {
            return prc;
        }
    }
    {
        const int rrc = cli_read_moments(o.file, &o.src, o.json, &acc, &in);
        if (rrc != 0) {
            return rrc;
        }
    }
    st = sfit_noise_calibrate(&acc, &o.center, o.radius, &e);
    if (st != SFIT_OK) {
        char what[CLI_WHAT_MAX];
        (void)snprintf(what, sizeof what, "noise calibration of %s", o.file);
        return cli_report_failure(st, what,
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
