/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_fit.c
 * @brief `sfit fit`: stream a CSV into a moments accumulator and solve; with
 * several files (one marker each), the common centre of the markers (MGDK).
 *
 *   sfit fit [--noise-var V | --noise-cov XX,YY,ZZ,XY,XZ,YZ]
 *            [--mode auto|sphere|planar] [--weight equal|samples] [--json]
 *            FILE [FILE ...]
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "sfit/sfit_multi.h"

typedef struct fit_opts {
    const char *file;   /* first FILE */
    const char **files; /* every FILE (nfiles of them) */
    int nfiles;
    int json;
    sfit_fit_cfg_t cfg;
    sfit_multi_weight_t weight;
} fit_opts_t;

static void fit_usage(FILE *f)
{
    fputs("usage: sfit fit [--noise-var V | --noise-cov XX,YY,ZZ,XY,XZ,YZ]\n"
          "                [--mode auto|sphere|planar] [--weight equal|samples] [--json]\n"
          "                FILE [FILE ...]\n"
          "  FILE  CSV of x,y,z samples (optional header line); '-' reads stdin\n"
          "        several FILEs: one marker each, common centre of all (MGDK)\n"
          "  --noise-var V    UGDK with isotropic measurement-noise variance V (unit^2)\n"
          "  --noise-cov ...  UGDK with a full symmetric noise covariance (unit^2)\n"
          "  --mode M         auto (default): sphere, or circle when the samples are\n"
          "                   near-planar (hinge); sphere / planar force one\n"
          "  --weight W       several FILEs: equal (default, eq. 220: every marker\n"
          "                   counts once) or samples (weight N_p - 1: joint least squares)\n"
          "  --json           one JSON object on stdout\n",
          f);
}

static int fit_parse(int argc, char **argv, fit_opts_t *o)
{
    int i;
    o->file = NULL;
    o->nfiles = 0;
    o->json = 0;
    o->cfg = sfit_fit_cfg_default;
    o->weight = SFIT_MULTI_WEIGHT_EQUAL;
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
        } else if (strcmp(a, "--weight") == 0 && i + 1 < argc) {
            const char *w = argv[++i];
            if (strcmp(w, "equal") == 0) {
                o->weight = SFIT_MULTI_WEIGHT_EQUAL;
            } else if (strcmp(w, "samples") == 0) {
                o->weight = SFIT_MULTI_WEIGHT_SAMPLES;
            } else {
                fprintf(stderr, "sfit: --weight is equal or samples\n");
                return -1;
            }
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "sfit: unknown or incomplete option %s\n", a);
            return -1;
        } else {
            if (o->file == NULL) {
                o->file = a;
            }
            o->files[o->nfiles++] = a;
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
        sep = ",";
    }
    if (flags & SFIT_MULTI_FLAG_SKIPPED) {
        printf("%s\"skipped_markers\"", sep);
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

/* A JSON string literal (quotes, backslashes and control characters escaped). */
static void print_json_string(const char *str)
{
    const unsigned char *c = (const unsigned char *)str;
    putchar('"');
    for (; *c != '\0'; c++) {
        if (*c == '"' || *c == '\\') {
            printf("\\%c", *c);
        } else if (*c < 0x20u) {
            printf("\\u%04x", (unsigned)*c);
        } else {
            putchar(*c);
        }
    }
    putchar('"');
}

/* ---- several FILEs: one marker each, common centre (sfit_multi_solve) ---- */

static void print_multi_json(const fit_opts_t *o, const sfit_multi_result_t *r,
                             const sfit_moments_t *acc, const float *radii,
                             unsigned long rejected)
{
    int k;
    printf("{\"status\":\"ok\",\"method\":\"%s\",\"mode\":\"%s\",\"weight\":\"%s\","
           "\"n\":%lu,\"rejected\":%lu,\"center\":",
           r->method == SFIT_METHOD_UGDK ? "ugdk" : "gdke", mode_name(r->mode),
           o->weight == SFIT_MULTI_WEIGHT_SAMPLES ? "samples" : "equal",
           (unsigned long)r->n_total, rejected);
    cli_print_vec(r->center.v);
    printf(",\"eigenvalues\":");
    cli_print_vec(r->eigenvalues.v);
    printf(",\"trust_ratio\":%.9g,\"leontief_ratio\":%.9g", (double)r->trust_ratio,
           (double)r->leontief_ratio);
    if (r->mode == SFIT_MODE_PLANAR) {
        printf(",\"axis\":");
        cli_print_vec(r->axis.v);
    }
    printf(",\"flags\":");
    print_flags_json(r->flags);
    printf(",\"markers\":[");
    for (k = 0; k < o->nfiles; k++) {
        printf("%s{\"file\":", k > 0 ? "," : "");
        print_json_string(o->files[k]);
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
                              unsigned long rejected)
{
    double ss = 0.0;
    int k, nsingle = 0;
    printf("markers      %lu used", (unsigned long)r->markers);
    if (r->skipped > 0u) {
        printf(", %lu skipped (fewer than %u samples)", (unsigned long)r->skipped,
               (unsigned)SFIT_MIN_SAMPLES);
    }
    printf("\nsamples      %lu used, %lu rejected\n", (unsigned long)r->n_total, rejected);
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
        printf("trust ratio  %.4g = rho(A^-1 M Sigma), A = sum_p w_p C_p; Leontief ratio %.4g "
               "(%s)\n",
               (double)r->trust_ratio, (double)r->leontief_ratio,
               r->leontief_ratio < 1.0f ? "< 1: condition of eq. 194 holds"
                                        : ">= 1: do not trust this fit");
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
        st = sfit_fit_solve(&acc[k], &o->cfg, &one);
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
    unsigned long accepted = 0, rejected = 0;
    int k, rc = CLI_OK;

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
        (void)sfit_moments_init(&acc[k]);
        if (cli_read_csv(o->files[k], cli_add_to_moments, &acc[k], &in) != 0) {
            if (o->json) {
                (void)cli_json_error("io_error", "cannot open an input file");
            } else {
                fprintf(stderr, "sfit: cannot open %s: %s\n", o->files[k], strerror(errno));
            }
            rc = CLI_IO;
            goto done;
        }
        if (!o->json) {
            cli_report_rejects(o->files[k], &in);
        }
        accepted += in.accepted;
        rejected += in.rejected;
    }
    mc.fit = o->cfg;
    mc.weight = o->weight;
    st = sfit_multi_solve(acc, (size_t)o->nfiles, &mc, &r, radii);
    if (st != SFIT_OK) {
        if (o->json) {
            printf("{\"status\":\"%s\",\"message\":\"%s\",\"n\":%lu,\"rejected\":%lu}\n",
                   sfit_status_str(st), cli_status_message(st), accepted, rejected);
        } else {
            fprintf(stderr, "sfit: common-centre fit failed (%s): %s\n", sfit_status_str(st),
                    cli_status_message(st));
        }
        rc = CLI_FAIL;
        goto done;
    }
    if (o->json) {
        print_multi_json(o, &r, acc, radii, rejected);
    } else {
        print_multi_human(o, &r, acc, radii, rejected);
    }
done:
    free(acc);
    free(radii);
    return rc;
}

int cli_cmd_fit(int argc, char **argv)
{
    fit_opts_t o;
    sfit_moments_t acc;
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
    if (prc != 0 || o.nfiles > 1) {
        if (prc == 0) {
            prc = fit_multi(&o);
            free(o.files);
            return prc;
        }
        free(o.files);
        if (prc == 1) {
            fit_usage(stdout);
            return CLI_OK;
        }
        fit_usage(stderr);
        return CLI_USAGE;
    }
    free(o.files);
    o.files = NULL;
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
