/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_track.c
 * @brief `sfit track`: the incremental estimator over a CSV, one estimate
 * every K samples and one at the end.
 *
 *   sfit track [--noise-var V] [--every K] [--json] FILE
 *
 * --json prints one JSON object per line, {"n":N,"center":[x,y,z],"radius":r};
 * without it, the same as whitespace-separated columns "n cx cy cz r"
 * after a '#' header line. An estimate is printed after every K-th
 * accepted sample (when the samples so far allow one) and after the last
 * sample (unless that one was just printed). If no estimate exists at the
 * end, a JSON error object (or a message on stderr) and exit status 1.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "table.h"
#include "sfit/sfit_incr.h"

/* Entry point of the sub-command (argv[0] = "track"); the dispatcher's
 * table calls it. Declared here until cli.h lists it:
 *   int cli_cmd_track(int argc, char **argv);   -- "track", "a new centre every K samples" */

typedef struct track_opts {
    const char *file;
    int json;
    unsigned long every;
    sfit_fit_cfg_t cfg;
    cli_src_t src;
} track_opts_t;

typedef struct track_ctx {
    sfit_incr_t inc;
    const track_opts_t *o;
    uint32_t printed_n; /* n of the last printed estimate (0: none) */
} track_ctx_t;

static void track_usage(FILE *f)
{
    fputs("usage: sfit track [--noise-var V] [--every K] [--cols A,B,C] [--json] FILE\n"
          "  (the samples in time order)\n"
          CLI_INPUT_USAGE
          "  --noise-var V  UGDK with isotropic measurement-noise variance V (unit^2)\n"
          "  --every K      print an estimate after every K-th sample (default 1;\n"
          "                 0 = only at the end); always one after the last sample\n"
          "  --json         one JSON object per line: {\"n\":N,\"center\":[x,y,z],\"radius\":r}\n"
          "Constant memory: the incremental estimator (chapter 5.4), equal to the batch\n"
          "fit of the samples so far.\n",
          f);
}

static int track_parse(int argc, char **argv, track_opts_t *o)
{
    int i;
    o->file = NULL;
    o->json = 0;
    o->every = 1ul;
    o->cfg = sfit_fit_cfg_default;
    o->cfg.eigen = 1; /* the tool reports eigenvalues and the exact trust ratio */
    o->cfg.mode = SFIT_MODE_SPHERE;
    o->src.cols = NULL;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        const int io = cli_input_opt(argc, argv, &i, &o->src);
        if (io < 0) {
            return -1;
        } else if (io > 0) {
            continue;
        } else if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            return 1;
        } else if (strcmp(a, "--json") == 0) {
            o->json = 1;
        } else if (strcmp(a, "--noise-var") == 0 && i + 1 < argc) {
            if (cli_parse_floats(argv[++i], &o->cfg.noise_var, 1) != 0
                || !(o->cfg.noise_var >= 0.0f) || !(o->cfg.noise_var < 3.0e38f)) {
                fprintf(stderr, "sfit: --noise-var needs one finite value >= 0\n");
                return -1;
            }
            o->cfg.noise = SFIT_NOISE_ISO;
        } else if (strcmp(a, "--every") == 0 && i + 1 < argc) {
            const char *v = argv[++i];
            char *end;
            errno = 0;
            o->every = strtoul(v, &end, 10);
            if (v[0] == '-' || end == v || *end != '\0' || errno != 0) {
                fprintf(stderr, "sfit: --every needs a whole number >= 0\n");
                return -1;
            }
        } else if (cli_positional(a, &o->file) != 0) {
            return -1;
        }
    }
    if (o->file == NULL) {
        fprintf(stderr, "sfit: FILE missing\n");
        return -1;
    }
    return 0;
}

static void track_print(const track_opts_t *o, const sfit_sphere_t *e)
{
    if (o->json) {
        printf("{\"n\":%lu,\"center\":", (unsigned long)e->n);
        cli_print_vec(e->center.v);
        printf(",\"radius\":%.9g}\n", (double)e->radius);
    } else {
        printf("%lu %.9g %.9g %.9g %.9g\n", (unsigned long)e->n, (double)e->center.v[0],
               (double)e->center.v[1], (double)e->center.v[2], (double)e->radius);
    }
}

/* cli_sample_fn: add the sample; print at every K-th sample. */
static sfit_status_t track_sample(void *vctx, const sfit_vec3_t *x)
{
    track_ctx_t *c = (track_ctx_t *)vctx;
    const sfit_status_t st = sfit_incr_add(&c->inc, x);
    if (st != SFIT_OK) {
        return st;
    }
    if (c->o->every > 0ul && (unsigned long)c->inc.n % c->o->every == 0ul) {
        sfit_sphere_t e;
        if (sfit_incr_fit(&c->inc, &e) == SFIT_OK) {
            track_print(c->o, &e);
            c->printed_n = e.n;
        }
    }
    return SFIT_OK;
}

int cli_cmd_track(int argc, char **argv)
{
    track_opts_t o;
    track_ctx_t ctx;
    cli_input_t in;
    sfit_sphere_t e;
    sfit_status_t st;

    {
        const int prc = cli_parse_outcome(track_parse(argc, argv, &o), track_usage);
        if (prc >= 0) {
            return prc;
        }
    }
    {
        sfit_incr_cfg_t ic = sfit_incr_cfg_default;
        ic.noise = o.cfg.noise;
        ic.noise_var = o.cfg.noise_var;
        ic.noise_cov = o.cfg.noise_cov;
        st = sfit_incr_init(&ctx.inc, &ic);
    }
    if (st != SFIT_OK) {
        fprintf(stderr, "sfit: invalid noise model\n");
        return CLI_USAGE;
    }
    ctx.o = &o;
    ctx.printed_n = 0u;
    if (!o.json) {
        printf("# n center_x center_y center_z radius\n");
    }
    {
        char why[TAB_ERR_MAX];
        const int rrc = cli_read_xyz(o.file, &o.src, track_sample, &ctx, &in, why);
        if (rrc != 0) {
            return cli_input_failed(rrc, o.file, why, o.json);
        }
    }
    if (!o.json) {
        cli_report_rejects(o.file, &in);
    }
    st = sfit_incr_fit(&ctx.inc, &e);
    if (st != SFIT_OK) {
        const char *msg = (st == SFIT_E_DEGENERATE)
                              ? "degenerate geometry: samples coincident, collinear or planar"
                              : cli_status_message(st);
        if (o.json) {
            printf("{\"status\":\"%s\",\"message\":\"%s\",\"n\":%lu,\"rejected\":%lu}\n",
                   sfit_status_str(st), msg, (unsigned long)sfit_incr_count(&ctx.inc),
                   in.rejected);
        } else {
            fprintf(stderr, "sfit: no estimate (%s): %s\n", sfit_status_str(st), msg);
        }
        return CLI_FAIL;
    }
    if (e.n != ctx.printed_n) {
        track_print(&o, &e);
    }
    return CLI_OK;
}
