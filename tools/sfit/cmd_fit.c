/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_fit.c
 * @brief `sfit fit`: stream a CSV into a moments accumulator and solve; with
 * several files (one marker each), the common centre of the markers (MGDK).
 *
 *   sfit fit [--noise-var V|auto | --noise-cov XX,YY,ZZ,XY,XZ,YZ] [--refine]
 *            [--gate K] [--mode auto|sphere|planar] [--weight equal|samples]
 *            [--json] FILE [FILE ...]
 *
 * One FILE: the JSON also carries "noise_var" (given or estimated, null
 * without a noise model), "center_cov" (3x3, rows, as `sfit joint`'s) and
 * "radius_var" (null without an isotropic noise variance or for a circle),
 * "iterations" (self-calibration or refinement; 0 for a direct solve) and
 * "outliers" (samples rejected by --gate). --noise-var auto and --refine
 * keep the samples in memory (the library works on a caller-owned array).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "refine.h"
#include "table.h"
#include "sfit/sfit_gate.h"
#include "sfit/sfit_multi.h"
#include "sfit/sfit_refine.h"
#include "sfit/sfit_selfcal.h"
#include "sfit/sfit_uncert.h"

typedef struct fit_opts {
    const char *file;   /* first FILE */
    const char **files; /* every FILE (nfiles of them) */
    int nfiles;
    int json;
    sfit_fit_cfg_t cfg;
    sfit_multi_weight_t weight;
    int auto_noise; /* --noise-var auto */
    int refine;     /* --refine */
    float gate_k;   /* --gate K (0 = no gate) */
    cli_src_t src;  /* --cols */
} fit_opts_t;

static void fit_usage(FILE *f)
{
    fputs("usage: sfit fit [--noise-var V|auto | --noise-cov XX,YY,ZZ,XY,XZ,YZ] [--refine]\n"
          "                [--gate K] [--mode auto|sphere|planar] [--weight equal|samples]\n"
          "                [--cols A,B,C] [--json] FILE [FILE ...]\n"
          "  The fit is algebraic: GDKE (the default, exact without noise) or, given the\n"
          "  noise, UGDK (GDKE with the bias that noise puts on a partial sphere removed).\n"
          CLI_INPUT_USAGE
          "        several FILEs: one marker each, common centre of all (MGDK: the\n"
          "        multi-marker form of GDKE, one centre and a radius per marker)\n"
          "  --noise-var V    UGDK with isotropic measurement-noise variance V (unit^2)\n"
          "  --noise-var auto self-calibrated UGDK: V estimated from the radial residuals\n"
          "  --refine         self-calibrated start, geometric (orthogonal-distance) fit\n"
          "  --gate K         reject samples farther than K sigma from the running fit\n"
          "                   (outlier gate; not with auto / --refine)\n"
          "  (one FILE: the JSON adds noise_var, center_cov, radius_var, iterations,\n"
          "   outliers; --noise-var auto / --refine / --gate need one FILE)\n"
          "  --noise-cov ...  UGDK with a full symmetric noise covariance (unit^2)\n"
          "  --mode M         auto (default): sphere, or circle when the samples are\n"
          "                   near-planar (hinge); sphere / planar force one\n"
          "  --weight W       several FILEs: equal (default: every marker counts once,\n"
          "                   however many samples it has) or samples (weight N_p - 1:\n"
          "                   least squares over all samples together)\n"
          "  --json           one JSON object on stdout\n",
          f);
}

/* --noise-var V|auto (CLI_OPT_FN): one noise model. */
static const char *fit_noise_var(void *dst, const char *v)
{
    fit_opts_t *o = (fit_opts_t *)dst;
    const int given = o->cfg.noise != SFIT_NOISE_NONE || o->auto_noise;
    if (strcmp(v, "auto") == 0) {
        if (given) {
            return "--noise-var auto: noise model given twice";
        }
        o->auto_noise = 1;
        return NULL;
    }
    if (given || cli_parse_floats(v, &o->cfg.noise_var, 1) != 0 || !(o->cfg.noise_var >= 0.0f)
        || !(o->cfg.noise_var < 3.0e38f)) {
        return "--noise-var needs one finite value >= 0 (not with --noise-cov)";
    }
    o->cfg.noise = SFIT_NOISE_ISO;
    return NULL;
}

/* --noise-cov XX,YY,ZZ,XY,XZ,YZ (CLI_OPT_FN). */
static const char *fit_noise_cov(void *dst, const char *v)
{
    fit_opts_t *o = (fit_opts_t *)dst;
    float c[6];
    float *m = o->cfg.noise_cov.m;
    int i;
    if (o->cfg.noise != SFIT_NOISE_NONE || o->auto_noise || cli_parse_floats(v, c, 6) != 0) {
        return "--noise-cov needs XX,YY,ZZ,XY,XZ,YZ (not with --noise-var)";
    }
    for (i = 0; i < 6; i++) {
        if (!(c[i] > -3.0e38f && c[i] < 3.0e38f)) {
            return "--noise-cov needs XX,YY,ZZ,XY,XZ,YZ (not with --noise-var)";
        }
    }
    o->cfg.noise = SFIT_NOISE_COV;
    m[0] = c[0]; m[4] = c[1]; m[8] = c[2];
    m[1] = c[3]; m[3] = c[3];
    m[2] = c[4]; m[6] = c[4];
    m[5] = c[5]; m[7] = c[5];
    return NULL;
}

/* --weight equal|samples (CLI_OPT_FN). */
static const char *fit_weight(void *dst, const char *v)
{
    sfit_multi_weight_t *w = (sfit_multi_weight_t *)dst;
    if (strcmp(v, "equal") == 0) {
        *w = SFIT_MULTI_WEIGHT_EQUAL;
    } else if (strcmp(v, "samples") == 0) {
        *w = SFIT_MULTI_WEIGHT_SAMPLES;
    } else {
        return "--weight is equal or samples";
    }
    return NULL;
}

/* The combinations the options exclude; 0 or -1 (message printed). */
static int fit_check(const fit_opts_t *o)
{
    const char *msg = NULL;
    if ((o->auto_noise || o->refine || o->gate_k > 0.0f) && o->nfiles > 1) {
        msg = "--noise-var auto, --refine and --gate take one FILE";
    } else if (o->gate_k > 0.0f && (o->auto_noise || o->refine)) {
        msg = "--gate does not combine with --noise-var auto / --refine";
    } else if ((o->auto_noise || o->refine) && o->cfg.mode == SFIT_MODE_PLANAR) {
        msg = "--noise-var auto / --refine fit spheres (not --mode planar)";
    }
    if (msg != NULL) {
        fprintf(stderr, "sfit: %s\n", msg);
        return -1;
    }
    return 0;
}

/* -1 to go on, or the exit status (cli_parse). o->files has argc slots. */
static int fit_parse(int argc, char **argv, fit_opts_t *o)
{
    const cli_opt_t opts[] = {
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &o->json},
        {.name = "--refine", .kind = CLI_OPT_FLAG, .dst = &o->refine},
        {.name = "--gate", .kind = CLI_OPT_FLOATS, .dst = &o->gate_k, .n = 1,
         .bounds = CLI_GT_LO | CLI_LT_HI, .lo = 1.0f, .hi = 3.0e38f,
         .err = "--gate needs one finite value K > 1 (sigmas)"},
        {.name = "--noise-var", .kind = CLI_OPT_FN, .dst = o, .fn = fit_noise_var},
        {.name = "--noise-cov", .kind = CLI_OPT_FN, .dst = o, .fn = fit_noise_cov},
        {.name = "--mode", .kind = CLI_OPT_MODE, .dst = &o->cfg.mode,
         .err = "--mode is auto, sphere or planar"},
        {.name = "--weight", .kind = CLI_OPT_FN, .dst = &o->weight, .fn = fit_weight},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0],
                             .src = &o->src, .pos = o->files, .max_pos = argc,
                             .min_pos = 1, .npos = &o->nfiles, .missing = "FILE missing",
                             .usage = fit_usage};
    int rc;
    o->nfiles = 0;
    o->json = 0;
    o->cfg = sfit_fit_cfg_default;
    o->cfg.eigen = true; /* the tool reports eigenvalues and the exact trust ratio */
    o->weight = SFIT_MULTI_WEIGHT_EQUAL;
    o->auto_noise = 0;
    o->refine = 0;
    o->gate_k = 0.0f;
    o->src.cols = NULL;
    rc = cli_parse(argc, argv, &args);
    o->file = o->files[0];
    if (rc < 0 && fit_check(o) != 0) {
        rc = cli_parse_outcome(-1, fit_usage);
    }
    return rc;
}

static const char *mode_name(sfit_mode_t m)
{
    return (m == SFIT_MODE_PLANAR) ? "planar" : "sphere";
}

/* What the single-file fit adds to sfit_result_t. */
typedef struct fit_extra {
    int refined;          /* geometric refinement done */
    int has_noise;        /* noise_var meaningful */
    float noise_var;      /* given or estimated sigma^2 */
    int noise_estimated;  /* from the samples */
    int has_uncert;       /* u valid */
    sfit_uncert_t u;
    unsigned long iterations;
    unsigned long outliers;
    int capped;           /* self-calibration hit its cap */
} fit_extra_t;

static const char *method_name(const sfit_result_t *r, const fit_extra_t *x)
{
    if (x->refined) {
        return "geometric";
    }
    return r->method == SFIT_METHOD_UGDK ? "ugdk" : "gdke";
}

/* ,"eigenvalues":[..],"trust_ratio":..,"leontief_ratio":..[,"axis":[..]],"flags":[..]
 * of a single or a common-centre fit. */
static void print_solution_json(const sfit_vec3_t *eig, float trust, float leontief,
                                sfit_mode_t mode, const sfit_vec3_t *axis, uint32_t flags)
{
    printf(",\"eigenvalues\":");
    json_out_vec(stdout, eig->v);
    printf(",\"trust_ratio\":%.9g,\"leontief_ratio\":%.9g", (double)trust, (double)leontief);
    if (mode == SFIT_MODE_PLANAR) {
        printf(",\"axis\":");
        json_out_vec(stdout, axis->v);
    }
    printf(",\"flags\":");
    names_flags_json(stdout, NAMES_FIT, flags);
}

static void print_json(const sfit_result_t *r, const cli_input_t *in, const fit_extra_t *x)
{
    printf("{\"status\":\"ok\",\"method\":\"%s\",\"mode\":\"%s\",\"n\":%lu,\"rejected\":%lu,"
           "\"missing\":%lu,\"center\":",
           method_name(r, x), mode_name(r->mode), (unsigned long)r->n, in->rejected,
           in->missing);
    json_out_vec(stdout, r->center.v);
    printf(",\"radius\":%.9g", (double)r->radius);
    print_solution_json(&r->eigenvalues, r->trust_ratio, r->leontief_ratio, r->mode, &r->axis,
                        r->flags);
    cli_print_noise_json(x->has_noise, x->noise_var, x->noise_estimated);
    if (x->has_uncert) {
        printf(",\"center_cov\":");
        json_out_mat(stdout, &x->u.center_cov);
        printf(",\"radius_var\":%.9g", (double)x->u.radius_var);
    } else {
        printf(",\"center_cov\":null,\"radius_var\":null");
    }
    printf(",\"iterations\":%lu,\"outliers\":%lu,\"noise_capped\":%s}\n", x->iterations,
           x->outliers, x->capped ? "true" : "false");
}

/* What the Leontief ratio says, from the float itself (never from a rounded
 * print) and from the flags: "< 1" is printed only when it is < 1, and
 * "holds" only when the fit is not flagged untrusted either. */
static const char *leontief_words(const sfit_result_t *r)
{
    if (!(r->leontief_ratio < 1.0f)) {
        return ">= 1: the noise is too large for the spread of the samples; do not trust this fit";
    }
    if ((r->flags & SFIT_FLAG_UNTRUSTED) != 0u) {
        return "< 1, but the fit is flagged untrusted: see the warnings";
    }
    return "< 1: the spread of the samples is large enough for the noise";
}

/* The reasons of SFIT_FLAG_UNTRUSTED, one warning line each. */
static void print_untrusted(const sfit_result_t *r)
{
    if ((r->flags & SFIT_FLAG_UNTRUSTED) == 0u) {
        return;
    }
    printf("untrusted    the centre covariance does not describe this fit's error:\n");
    if (!(r->leontief_ratio < 1.0f)) {
        printf("  reason     Leontief ratio >= 1 (noise swamps the weakest direction)\n");
    }
    if ((r->flags & SFIT_SELFCAL_FLAG_CAPPED) != 0u) {
        printf("  reason     noise_capped: the estimated noise hit its cap (trust ratio %.2g); "
               "the data cannot separate noise from geometry\n",
               (double)SFIT_SELFCAL_MAX_TRUST);
    }
    if ((r->flags & SFIT_FLAG_COV_LIMIT) != 0u) {
        printf("  reason     cov_limit: trust ratio above %.2g, or fewer than %u samples "
               "(docs/coverage.md)\n",
               (double)SFIT_COV_MAX_TRUST, (unsigned)SFIT_COV_MIN_SAMPLES);
    }
}

static void print_human(const char *file, const sfit_result_t *r, const cli_input_t *in,
                        const fit_extra_t *x)
{
    printf("file         %s\n", file);
    printf("samples      %lu used, %lu rejected", (unsigned long)r->n, in->rejected);
    if (in->missing > 0u) {
        printf(", %lu missing (blank cells)", in->missing);
    }
    if (x->outliers > 0u) {
        printf(", %lu outliers gated out", x->outliers);
    }
    printf("\nmethod       %s, %s solution%s\n",
           x->refined ? "geometric (refined)" : (r->method == SFIT_METHOD_UGDK ? "UGDK" : "GDKE"),
           mode_name(r->mode), x->noise_estimated && !x->refined ? ", self-calibrated noise" : "");
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
        printf("trust ratio  %.9g = rho(C^-1 Sigma); Leontief ratio %.9g (%s)\n",
               (double)r->trust_ratio, (double)r->leontief_ratio,
               leontief_words(r));
    } else {
        printf("trust ratio  n/a (no noise model: GDKE is biased on partial spheres)\n");
    }
    if (x->has_noise) {
        printf("noise var    %.6g (sigma %.4g, %s)\n", (double)x->noise_var,
               sqrt((double)x->noise_var), x->noise_estimated ? "estimated" : "given");
    }
    if (x->has_uncert) {
        printf("centre SD    %.4g %.4g %.4g (radius SD %.4g)\n", sqrt((double)x->u.center_cov.m[0]),
               sqrt((double)x->u.center_cov.m[4]), sqrt((double)x->u.center_cov.m[8]),
               sqrt((double)x->u.radius_var));
    }
    if (x->iterations > 0u) {
        printf("iterations   %lu\n", x->iterations);
    }
    print_untrusted(r);
    if (r->flags & SFIT_FLAG_FEW_SAMPLES) {
        printf("warning      few samples\n");
    }
    if ((r->flags & SFIT_FLAG_NEAR_PLANAR) && r->mode == SFIT_MODE_SPHERE) {
        printf("warning      samples are near-planar: the sphere is ill-conditioned\n");
    }
    if (r->flags & SFIT_FLAG_ROUNDING) {
        printf("warning      float rounding: a small cap (or a far centre) for float; the centre "
               "may be more than 1e-4 r from a double-precision fit\n");
    }
}

/* ---- several FILEs: one marker each, common centre (sfit_multi_fit) ---- */

static void print_multi_json(const fit_opts_t *o, const sfit_multi_result_t *r,
                             const sfit_moments_t *acc, const float *radii,
                             const cli_input_t *all)
{
    int k;
    printf("{\"status\":\"ok\",\"method\":\"%s\",\"mode\":\"%s\",\"weight\":\"%s\","
           "\"n\":%lu,\"rejected\":%lu,\"missing\":%lu,\"center\":",
           r->method == SFIT_METHOD_UGDK ? "ugdk" : "gdke", mode_name(r->mode),
           o->weight == SFIT_MULTI_WEIGHT_SAMPLES ? "samples" : "equal",
           (unsigned long)r->n_total, all->rejected, all->missing);
    json_out_vec(stdout, r->center.v);
    print_solution_json(&r->eigenvalues, r->trust_ratio, r->leontief_ratio, r->mode, &r->axis,
                        r->flags);
    printf(",\"markers\":[");
    for (k = 0; k < o->nfiles; k++) {
        printf("%s{\"file\":", k > 0 ? "," : "");
        json_out_str(stdout, o->files[k], 0);
        printf(",\"n\":%lu,\"radius\":", (unsigned long)sfit_moments_count(&acc[k]));
        if (radii[k] > 0.0f) {
            printf("%.9g}", (double)radii[k]);
        } else {
            printf("null}");
        }
    }
    printf("]}\n");
}

static void print_multi_human(const fit_opts_t *o, const sfit_multi_result_t *r,
                              const sfit_moments_t *acc, const float *radii,
                              const cli_input_t *all)
{
    double ss = 0.0;
    int k, nsingle = 0;
    printf("markers      %lu used", (unsigned long)r->markers);
    if (r->skipped > 0u) {
        printf(", %lu skipped (fewer than %u samples)", (unsigned long)r->skipped,
               (unsigned)SFIT_MIN_SAMPLES);
    }
    printf("\nsamples      %lu used, %lu rejected\n", (unsigned long)r->n_total, all->rejected);
    printf("method       %s, %s solution, %s weights\n",
           r->method == SFIT_METHOD_UGDK ? "unbiased MGDK (C'_p = C_p - Sigma)" : "MGDK",
           mode_name(r->mode), o->weight == SFIT_MULTI_WEIGHT_SAMPLES ? "N_p - 1" : "equal");
    printf("centre       %.4f %.4f %.4f\n", (double)r->center.v[0], (double)r->center.v[1],
           (double)r->center.v[2]);
    if (r->mode == SFIT_MODE_PLANAR) {
        printf("axis         %.5f %.5f %.5f\n", (double)r->axis.v[0], (double)r->axis.v[1],
               (double)r->axis.v[2]);
    }
    printf("eigenvalues  %.6g %.6g %.6g (of sum_p w_p C_p)\n", (double)r->eigenvalues.v[0],
           (double)r->eigenvalues.v[1], (double)r->eigenvalues.v[2]);
    if (r->method == SFIT_METHOD_UGDK) {
        printf("trust ratio  %.9g = rho(A^-1 M Sigma), A = sum_p w_p C_p; Leontief ratio %.9g "
               "(%s)\n",
               (double)r->trust_ratio, (double)r->leontief_ratio,
               !(r->leontief_ratio < 1.0f) ? ">= 1: do not trust this fit"
               : (r->flags & SFIT_FLAG_UNTRUSTED) != 0u ? "< 1, but flagged untrusted"
                                                        : "< 1: the spread of the samples is large enough for the noise");
    }
    printf("per marker   radius; the marker's own fit (same options) and its distance from\n"
           "             the common %s:\n",
           r->mode == SFIT_MODE_PLANAR ? "axis" : "centre");
    printf("  %7s %10s %34s %9s  %s\n", "n", "radius", "single-marker centre", "distance",
           "file");
    for (k = 0; k < o->nfiles; k++) {
        sfit_result_t one;
        sfit_status_t st;
        printf("  %7lu ", (unsigned long)sfit_moments_count(&acc[k]));
        if (!(radii[k] > 0.0f)) {
            printf("%10s %34s %9s  %s\n", "skipped", "", "", o->files[k]);
            continue;
        }
        printf("%10.4f ", (double)radii[k]);
        st = sfit_fit_moments(&acc[k], &o->cfg, &one);
        if (st != SFIT_OK) {
            printf("%34s %9s  %s\n", sfit_status_str(st), "", o->files[k]);
        } else {
            double e[3], d2 = 0.0, ea = 0.0;
            int i;
            for (i = 0; i < 3; i++) {
                e[i] = (double)one.center.v[i] - (double)r->center.v[i];
                ea += e[i] * (double)r->axis.v[i];
            }
            for (i = 0; i < 3; i++) {
                if (r->mode == SFIT_MODE_PLANAR) {
                    e[i] -= ea * (double)r->axis.v[i]; /* distance from the axis */
                }
                d2 += e[i] * e[i];
            }
            ss += d2;
            nsingle++;
            printf("%11.4f %11.4f %11.4f %9.4f  %s%s\n", (double)one.center.v[0],
                   (double)one.center.v[1], (double)one.center.v[2], sqrt(d2), o->files[k],
                   one.mode == SFIT_MODE_PLANAR ? " (planar)" : "");
        }
    }
    if (nsingle > 0) {
        printf("scatter      RMS distance of the single-marker centres from the common "
               "%s: %.4f\n",
               r->mode == SFIT_MODE_PLANAR ? "axis" : "centre", sqrt(ss / (double)nsingle));
    }
    if (r->flags & SFIT_FLAG_FEW_SAMPLES) {
        printf("warning      a marker has few samples\n");
    }
    if ((r->flags & SFIT_FLAG_NEAR_PLANAR) && r->mode == SFIT_MODE_SPHERE) {
        printf("warning      the summed covariance is near-planar: the sphere is "
               "ill-conditioned\n");
    }
}

static int fit_multi(const fit_opts_t *o)
{
    sfit_moments_t *acc;
    float *radii;
    sfit_multi_cfg_t mc;
    sfit_multi_result_t r;
    sfit_status_t st;
    cli_input_t all; /* the files' counts summed */
    int k, rc = CLI_OK;

    memset(&all, 0, sizeof all);
    acc = (sfit_moments_t *)calloc((size_t)o->nfiles, sizeof *acc);
    radii = (float *)calloc((size_t)o->nfiles, sizeof *radii);
    if (acc == NULL || radii == NULL) {
        free(acc);
        free(radii);
        fprintf(stderr, "sfit: out of memory\n");
        return CLI_FAIL;
    }
    for (k = 0; k < o->nfiles; k++) {
        cli_input_t in;
        rc = cli_read_moments(o->files[k], &o->src, o->json, &acc[k], &in);
        if (rc != 0) {
            goto done;
        }
        all.accepted += in.accepted;
        all.rejected += in.rejected;
        all.missing += in.missing;
    }
    mc.fit = o->cfg;
    mc.weight = o->weight;
    st = sfit_multi_fit(acc, (size_t)o->nfiles, &mc, &r, radii);
    if (st != SFIT_OK) {
        rc = cli_report_failure(st, "common-centre fit", NULL, o->json, &all);
    } else if (o->json) {
        print_multi_json(o, &r, acc, radii, &all);
    } else {
        print_multi_human(o, &r, acc, radii, &all);
    }
done:
    free(acc);
    free(radii);
    return rc;
}

/* Sample sink of the single-file path: moments, optionally a copy of the
 * samples (auto / refine), or the outlier gate. */
typedef struct fit_sink {
    sfit_moments_t acc;
    sfit_vec3_t *pts;
    size_t n, cap;
    int store;
    sfit_gate_t *gate;
} fit_sink_t;

static sfit_status_t fit_sink_add(void *ctx, const sfit_vec3_t *x)
{
    fit_sink_t *k = (fit_sink_t *)ctx;
    sfit_status_t st;
    if (k->gate != NULL) {
        return sfit_gate_add(k->gate, x, NULL); /* an outlier is counted, not rejected */
    }
    if (k->store && k->n == k->cap) {
        size_t nc = (k->cap == 0u) ? 1024u : 2u * k->cap;
        sfit_vec3_t *np = (sfit_vec3_t *)realloc(k->pts, nc * sizeof *np);
        if (np == NULL) {
            return SFIT_E_RANGE;
        }
        k->pts = np;
        k->cap = nc;
    }
    st = sfit_moments_add(&k->acc, x);
    if (st == SFIT_OK && k->store) {
        k->pts[k->n++] = *x;
    }
    return st;
}

/* Fit the single file's samples as the options say. */
static sfit_status_t fit_single(const fit_opts_t *o, fit_sink_t *k, sfit_result_t *r,
                                fit_extra_t *x)
{
    const sfit_moments_t *acc = &k->acc;
    sfit_status_t st;

    memset(x, 0, sizeof *x);
    if (k->gate != NULL) {
        sfit_gate_stats_t gs;
        st = sfit_gate_fit(k->gate, r);
        (void)sfit_gate_stats(k->gate, &gs);
        x->outliers = gs.outliers;
        acc = sfit_gate_moments(k->gate);
    } else if (o->refine) {
        /* the library's recipe, one call and one flat result: the
         * geometric sphere, its covariance, the start's summary and verdict */
        sfit_refine_result_t rf;
        sfit_refined_cfg_t rc = sfit_refined_cfg_default;
        rc.selfcal.planar_ratio = o->cfg.planar_ratio;
        st = sfit_refine_fit(k->pts, k->n, &rc, &rf);
        if (st != SFIT_OK) {
            return st;
        }
        refine_parts(&rf, r, &x->u);
        x->refined = 1;
        x->has_noise = 1;
        x->noise_var = rf.noise_var;
        x->noise_estimated = 1;
        x->iterations = rf.iterations;
        x->capped = (rf.flags & SFIT_SELFCAL_FLAG_CAPPED) != 0u;
        x->has_uncert = 1;
        return SFIT_OK;
    } else if (o->auto_noise) {
        sfit_selfcal_result_t sc;
        sfit_selfcal_cfg_t scc = sfit_selfcal_cfg_default;
        scc.planar_ratio = o->cfg.planar_ratio;
        st = sfit_selfcal_points(k->pts, k->n, &scc, &sc);
        if (st == SFIT_OK) {
            *r = sc.fit;
            x->has_noise = 1;
            x->noise_var = sc.noise_var;
            x->noise_estimated = 1;
            x->iterations = sc.iterations;
            x->capped = (sc.flags & SFIT_SELFCAL_FLAG_CAPPED) != 0u;
            /* the self-calibration's own sandwich covariance */
            x->has_uncert = (sfit_uncert_selfcal(k->pts, k->n, &r->center, r->radius,
                                                 x->noise_var, &x->u) == SFIT_OK);
            return SFIT_OK;
        }
    } else {
        st = sfit_fit_moments(acc, &o->cfg, r);
    }
    if (st != SFIT_OK) {
        return st;
    }
    if (!o->auto_noise && o->cfg.noise == SFIT_NOISE_ISO) {
        x->has_noise = 1;
        x->noise_var = o->cfg.noise_var;
    }
    if (x->has_noise && r->mode == SFIT_MODE_SPHERE && acc != NULL) {
        x->has_uncert = (sfit_uncert_moments(acc, &r->center, r->radius, x->noise_var,
                                             SFIT_UNCERT_NOISE_KNOWN,
                                             &x->u) == SFIT_OK);
    }
    return SFIT_OK;
}

int cli_cmd_fit(int argc, char **argv)
{
    fit_opts_t o;
    fit_sink_t sink;
    sfit_gate_t gate;
    fit_extra_t extra;
    cli_input_t in;
    sfit_result_t r;
    sfit_status_t st;
    int prc;

    o.files = (const char **)calloc((size_t)argc + 1u, sizeof *o.files);
    if (o.files == NULL) {
        fprintf(stderr, "sfit: out of memory\n");
        return CLI_FAIL;
    }
    prc = fit_parse(argc, argv, &o);
    if (prc >= 0 || o.nfiles > 1) {
        if (prc < 0) {
            prc = fit_multi(&o);
        }
        free(o.files);
        return prc;
    }
    free(o.files);
    o.files = NULL;
    memset(&sink, 0, sizeof sink);
    (void)sfit_moments_init(&sink.acc);
    sink.store = o.auto_noise || o.refine;
    if (o.gate_k > 0.0f) {
        sfit_gate_cfg_t gc = sfit_gate_cfg_default;
        gc.fit = o.cfg;
        gc.k = o.gate_k;
        if (o.cfg.noise == SFIT_NOISE_ISO) {
            gc.noise_var = o.cfg.noise_var;
        }
        if (sfit_gate_init(&gate, &gc) != SFIT_OK) {
            fprintf(stderr, "sfit: invalid gate options\n");
            return CLI_USAGE;
        }
        sink.gate = &gate;
    }
    {
        char why[TABLE_ERR_MAX];
        const int rrc = cli_read_xyz(o.file, &o.src, fit_sink_add, &sink, &in, why);
        if (rrc != 0) {
            free(sink.pts);
            return cli_input_failed(rrc, o.file, why, o.json);
        }
    }
    st = fit_single(&o, &sink, &r, &extra);
    free(sink.pts);
    if (!o.json) {
        cli_report_rejects(o.file, &in);
    }
    if (st != SFIT_OK) {
        char what[CLI_WHAT_MAX];
        (void)snprintf(what, sizeof what, "fit of %s", o.file);
        return cli_report_failure(st, what, NULL, o.json, &in);
    }
    if (o.json) {
        print_json(&r, &in, &extra);
    } else {
        print_human(o.file, &r, &in, &extra);
    }
    return CLI_OK;
}
