/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_coverage.c
 * @brief `sfit coverage`: how much of the sphere (cap) or circle (arc) the
 * samples cover, the largest noise that coverage tolerates (eq. 212/213),
 * and, given the noise, whether to rotate further.
 *
 *   sfit coverage [--cap | --arc] [--noise-var V] [--rho-max R] [--json] FILE
 */
#include <math.h>
#include <string.h>

#include "cli.h"

#include "sfit/sfit_coverage.h"

#define COV_RAD2DEG 57.29577951f

typedef struct cov_opts {
    const char *file;
    int json;
    sfit_mode_t mode;   /* AUTO, SPHERE (--cap) or PLANAR (--arc) */
    int have_noise;
    float noise_var;
    float rho_max;
    cli_src_t src;
} cov_opts_t;

typedef struct cov_out {
    sfit_coverage_kind_t kind;
    sfit_result_t fit;
    int fit_ugdk;        /* the fit used the noise model (else GDKE fallback) */
    int measurable;      /* a coverage could be estimated */
    float theta;         /* estimated half-angle, rad */
    float max_sigma;     /* sqrt(lambda_min(theta)) */
    int have_min;        /* min_theta is defined (noise given and attainable) */
    float min_theta;     /* rad */
    int rotate;          /* rotate further */
} cov_out_t;

static void cov_usage(FILE *f)
{
    fputs("usage: sfit coverage [--cap | --arc] [--noise-var V] [--rho-max R] [--cols A,B,C]\n"
          "                     [--json] FILE\n"
          "  Estimate the covered half-angle of a cap (sphere fit) or an arc (hinge,\n"
          "  planar fit) from the eigenvalues of the sample covariance, and the\n"
          "  largest noise sigma that coverage tolerates (trust ratio rho < 1).\n"
          CLI_INPUT_USAGE
          "  --cap / --arc    force the geometry (default: arc when the samples are\n"
          "                   near-planar, else cap)\n"
          "  --noise-var V    known noise variance sigma^2 (e.g. from `sfit noise`):\n"
          "                   removed from the eigenvalues, used for the unbiased fit\n"
          "                   (UGDK) and\n"
          "                   for the smallest half-angle that noise needs\n"
          "  --rho-max R      target trust ratio for that half-angle (0 < R <= 1,\n"
          "                   default 1: the limit past which the noise, not the\n"
          "                   samples' spread, decides the fit: the Leontief limit)\n"
          "  --json           one JSON object on stdout\n",
          f);
}

/* --cap / --arc (CLI_OPT_FN0). */
static const char *cov_geometry(void *dst, const char *name)
{
    sfit_mode_t *mode = (sfit_mode_t *)dst;
    const sfit_mode_t md = (name[2] == 'c') ? SFIT_MODE_SPHERE : SFIT_MODE_PLANAR;
    if (*mode != SFIT_MODE_AUTO && *mode != md) {
        return "--cap and --arc exclude each other";
    }
    *mode = md;
    return NULL;
}

/* -1 to go on, or the exit status (cli_parse). */
static int cov_parse(int argc, char **argv, cov_opts_t *o)
{
    const cli_opt_t opts[] = {
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &o->json},
        {.name = "--cap", .kind = CLI_OPT_FN0, .dst = &o->mode, .fn = cov_geometry},
        {.name = "--arc", .kind = CLI_OPT_FN0, .dst = &o->mode, .fn = cov_geometry},
        {.name = "--noise-var", .kind = CLI_OPT_FLOATS, .dst = &o->noise_var, .n = 1,
         .bounds = CLI_GE_LO | CLI_LT_HI, .lo = 0.0f, .hi = 3.0e38f, .seen = &o->have_noise,
         .err = "--noise-var needs one finite value >= 0"},
        {.name = "--rho-max", .kind = CLI_OPT_FLOATS, .dst = &o->rho_max, .n = 1,
         .bounds = CLI_GT_LO | CLI_LE_HI, .lo = 0.0f, .hi = 1.0f,
         .err = "--rho-max needs one value in (0, 1]"},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0],
                             .src = &o->src, CLI_ONE_FILE(o->file),
                             .usage = cov_usage};
    memset(o, 0, sizeof *o);
    o->mode = SFIT_MODE_AUTO;
    o->rho_max = 1.0f;
    return cli_parse(argc, argv, &args);
}

/* Fit, then the coverage figures. Returns the fit's status. */
static sfit_status_t cov_compute(const sfit_moments_t *acc, const cov_opts_t *o, cov_out_t *c)
{
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    cfg.eigen = true; /* the coverage figures need the eigenvalues */
    sfit_vec3_t eig;
    sfit_status_t st;
    int i;

    memset(c, 0, sizeof *c);
    cfg.mode = o->mode;
    if (o->have_noise) {
        cfg.noise = SFIT_NOISE_ISO;
        cfg.noise_var = o->noise_var;
    }
    st = sfit_fit_moments(acc, &cfg, &c->fit);
    c->fit_ugdk = o->have_noise;
    if (st == SFIT_E_NOT_POSDEF && o->have_noise) {
        /* The noise exceeds the spread: no trust at all. Fall back to GDKE
         * for the radius and the geometry; the coverage is then judged
         * from the eigenvalues minus the noise (usually "not measurable"). */
        cfg.noise = SFIT_NOISE_NONE;
        cfg.noise_var = 0.0f;
        st = sfit_fit_moments(acc, &cfg, &c->fit);
        c->fit_ugdk = 0;
    }
    if (st != SFIT_OK) {
        return st;
    }
    c->kind = (c->fit.mode == SFIT_MODE_PLANAR) ? SFIT_COVERAGE_ARC : SFIT_COVERAGE_CAP;
    eig = c->fit.eigenvalues;
    if (o->have_noise) {
        for (i = 0; i < 3; i++) {
            eig.v[i] -= o->noise_var; /* C0 = C - sigma^2 I: same order */
        }
    }
    if (sfit_coverage_estimate_theta(c->kind, &eig, &c->theta) == SFIT_OK
        && sfit_coverage_max_sigma(c->kind, c->theta, c->fit.radius, &c->max_sigma)
               == SFIT_OK) {
        c->measurable = 1;
    }
    if (o->have_noise) {
        const float sr = sqrtf(o->noise_var / o->rho_max) / c->fit.radius;
        c->have_min = (sfit_coverage_min_theta(c->kind, sr, &c->min_theta) == SFIT_OK);
        c->rotate = !c->measurable || !c->have_min || c->theta < c->min_theta
                    || !c->fit_ugdk || (c->fit.flags & SFIT_FLAG_UNTRUSTED) != 0u;
    }
    return SFIT_OK;
}

static void cov_json(const cov_opts_t *o, const cov_out_t *c, const cli_input_t *in)
{
    printf("{\"status\":\"ok\",\"kind\":\"%s\",\"n\":%lu,\"rejected\":%lu,\"radius\":%.9g",
           c->kind == SFIT_COVERAGE_ARC ? "arc" : "cap", (unsigned long)c->fit.n, in->rejected,
           (double)c->fit.radius);
    if (c->measurable) {
        printf(",\"half_angle_deg\":%.6g,\"max_sigma\":%.6g", (double)(c->theta * COV_RAD2DEG),
               (double)c->max_sigma);
    } else {
        printf(",\"half_angle_deg\":null,\"max_sigma\":null");
    }
    if (o->have_noise) {
        printf(",\"noise_var\":%.6g,\"rho_max\":%.6g", (double)o->noise_var, (double)o->rho_max);
        if (c->fit_ugdk) {
            printf(",\"trust_ratio\":%.6g", (double)c->fit.trust_ratio);
        } else {
            printf(",\"trust_ratio\":null");
        }
        if (c->have_min) {
            printf(",\"min_half_angle_deg\":%.6g", (double)(c->min_theta * COV_RAD2DEG));
        } else {
            printf(",\"min_half_angle_deg\":null");
        }
        printf(",\"rotate_further\":%s", c->rotate ? "true" : "false");
    }
    printf("}\n");
}

static void cov_human(const char *file, const cov_opts_t *o, const cov_out_t *c,
                      const cli_input_t *in)
{
    const char *what = (c->kind == SFIT_COVERAGE_ARC) ? "arc (hinge, planar fit)"
                                                      : "cap (sphere fit)";
    printf("file            %s\n", file);
    printf("samples         %lu used, %lu rejected\n", (unsigned long)c->fit.n, in->rejected);
    printf("geometry        %s, radius %.4f\n", what, (double)c->fit.radius);
    if (c->measurable) {
        printf("half-angle      %.2f deg (uniform %s with the same eigenvalue ratio)\n",
               (double)(c->theta * COV_RAD2DEG), c->kind == SFIT_COVERAGE_ARC ? "arc" : "cap");
        printf("max sigma       %.4g (largest noise sd with trust ratio < 1, eq. %s)\n",
               (double)c->max_sigma, c->kind == SFIT_COVERAGE_ARC ? "213" : "212");
    } else {
        printf("half-angle      not measurable above the noise\n");
    }
    if (!o->have_noise) {
        printf("hint            give --noise-var (from `sfit noise`) for a verdict\n");
        return;
    }
    printf("noise sigma     %.4g (variance %.4g)\n", (double)sqrtf(o->noise_var),
           (double)o->noise_var);
    if (c->fit_ugdk) {
        printf("trust ratio     %.4g (measured, UGDK fit)\n", (double)c->fit.trust_ratio);
    } else {
        printf("trust ratio     >= 1 (C - sigma^2 I is not positive definite)\n");
    }
    if (c->have_min) {
        printf("needed          half-angle >= %.2f deg for trust ratio <= %.3g\n",
               (double)(c->min_theta * COV_RAD2DEG), (double)o->rho_max);
    } else {
        printf("needed          no coverage suffices for this noise and radius\n");
    }
    printf("verdict         %s\n", c->rotate ? "rotate further" : "coverage sufficient");
}

int cli_cmd_coverage(int argc, char **argv)
{
    cov_opts_t o;
    cov_out_t c;
    sfit_moments_t acc;
    cli_input_t in;
    sfit_status_t st;

    {
        const int prc = cov_parse(argc, argv, &o);
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
    st = cov_compute(&acc, &o, &c);
    if (st != SFIT_OK) {
        char what[CLI_WHAT_MAX];
        (void)snprintf(what, sizeof what, "fit of %s", o.file);
        return cli_report_failure(st, what, NULL, o.json, &in);
    }
    if (o.json) {
        cov_json(&o, &c, &in);
    } else {
        cov_human(o.file, &o, &c, &in);
    }
    return CLI_OK;
}
