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

#include "cli.h"
#include "table.h"
#include "sfit/sfit_incr.h"

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

/* -1 to go on, or the exit status (cli_parse). */
static int track_parse(int argc, char **argv, track_opts_t *o)
{
    int have_noise = 0;
    const cli_opt_t opts[] = {
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &o->json},
        {.name = "--noise-var", .kind = CLI_OPT_FLOATS, .dst = &o->cfg.noise_var, .n = 1,
         .bounds = CLI_GE_LO | CLI_LT_HI, .lo = 0.0f, .hi = 3.0e38f, .seen = &have_noise,
         .err = "--noise-var needs one finite value >= 0"},
        {.name = "--every", .kind = CLI_OPT_COUNT, .dst = &o->every,
         .err = "--every needs a whole number >= 0"},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0],
                             .src = &o->src, CLI_ONE_FILE(o->file),
                             .usage = track_usage};
    int rc;
    o->file = NULL;
    o->json = 0;
    o->every = 1ul;
    o->cfg = sfit_fit_cfg_default;
    o->cfg.eigen = true; /* the tool reports eigenvalues and the exact trust ratio */
    o->cfg.mode = SFIT_MODE_SPHERE;
    o->src.cols = NULL;
    rc = cli_parse(argc, argv, &args);
    if (have_noise) {
        o->cfg.noise = SFIT_NOISE_ISO;
    }
    return rc;
}

static void track_print(const track_opts_t *o, const sfit_sphere_t *e)
{
    if (o->json) {
        printf("{\"n\":%lu,\"center\":", (unsigned long)e->n);
        json_out_vec(stdout, e->center.v);
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
        const int prc = track_parse(argc, argv, &o);
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
        char why[TABLE_ERR_MAX];
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
                              : names_status_message(st, NAMES_CLI);
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
