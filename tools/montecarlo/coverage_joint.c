/* SPDX-License-Identifier: MIT */
/**
 * @file coverage_joint.c
 * @brief Monte Carlo coverage of the multi-marker and joint centres'
 * reported covariances (docs/coverage.md):
 *  - multi: 4 markers (r = 80, 100, 120, 150) on caps about one centre,
 *    unbiased MGDK with the true sigma^2 (sfit_multi_fit) and
 *    sfit_multi_center_cov;
 *  - joint: a ball joint, a 4-marker parent cluster and 5 child markers,
 *    every marker with isotropic noise sigma, the per-marker noise model
 *    (SFIT_JOINT_NOISE_MARKER), sfit_joint_center_cov.
 * Fraction of trials whose true centre lies inside the reported 95 %
 * ellipsoid; results with SFIT_FLAG_UNTRUSTED are counted as flagged.
 *
 * Usage: sfit_mc_coverage_joint OUTDIR [quick]  -> OUTDIR/coverage_joint.md
 * Fixed seeds; identical output from run to run on the same platform.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit_ref_joint.h"
#include "test_util.h"
#include "cov_tally.h"
#include "mc_out.h"

#define P 4
#define K 5
#define FMAX 1000

static const double k_tpl[P][3] = {
    {70.0, 40.0, 10.0}, {-75.0, 35.0, 5.0}, {-60.0, -50.0, 30.0}, {65.0, -25.0, -45.0}};
static const double k_dk[K][3] = {{30.0, -20.0, -150.0}, {-35.0, 25.0, -220.0},
                                  {40.0, 30.0, -300.0},  {-20.0, -45.0, -380.0},
                                  {45.0, -10.0, -420.0}};
static const double k_centre[3] = {-80.0, 90.0, -70.0}; /* parent (template) frame */

static double g_par0[FMAX][P][3], g_chi0[FMAX][K][3];
static sfit_vec3_t g_parf[FMAX][P], g_chif[FMAX][K];
static sfit_joint_t g_j;

/* Rotation matrix (row-major) of angle a about axis u (any length). */
static void rot_axis_angle(const double u[3], double a, double r[9])
{
    const double n = tu_norm3(u), c = cos(a), s = sin(a);
    const double x = u[0] / n, y = u[1] / n, z = u[2] / n, t = 1.0 - c;
    r[0] = t * x * x + c;
    r[1] = t * x * y - s * z;
    r[2] = t * x * z + s * y;
    r[3] = t * x * y + s * z;
    r[4] = t * y * y + c;
    r[5] = t * y * z - s * x;
    r[6] = t * x * z - s * y;
    r[7] = t * y * z + s * x;
    r[8] = t * z * z + c;
}

/* nf frames: random parent pose 2-3 m away, child rotated about a random
 * axis by up to max_deg about the joint centre. */
static void make_motion(uint64_t seed, size_t nf, double max_deg)
{
    tu_rng_t g;
    size_t f, i;
    tu_rng_seed(&g, seed);
    for (f = 0; f < nf; f++) {
        double r[9], q[9], t[3], dir[3], n, dist;
        int k;
        for (k = 0; k < 3; k++) {
            dir[k] = tu_rng_gauss(&g);
        }
        rot_axis_angle(dir, TU_PI * tu_rng_uniform(&g), r);
        for (k = 0; k < 3; k++) {
            dir[k] = tu_rng_gauss(&g);
        }
        n = tu_norm3(dir);
        dist = 2000.0 + 1000.0 * tu_rng_uniform(&g);
        for (k = 0; k < 3; k++) {
            t[k] = dir[k] / n * dist;
            dir[k] = tu_rng_gauss(&g);
        }
        rot_axis_angle(dir, max_deg * TU_PI / 180.0 * tu_rng_uniform(&g), q);
        for (i = 0; i < P; i++) {
            ref_pose_to_global(r, t, k_tpl[i], g_par0[f][i]);
        }
        for (i = 0; i < K; i++) {
            const double zero[3] = {0.0, 0.0, 0.0};
            double y[3];
            ref_pose_to_global(q, zero, k_dk[i], y);
            for (k = 0; k < 3; k++) {
                y[k] += k_centre[k];
            }
            ref_pose_to_global(r, t, y, g_chi0[f][i]);
        }
    }
}

static void make_noisy(tu_rng_t *g, size_t nf, double sigma)
{
    size_t f, i;
    int k;
    for (f = 0; f < nf; f++) {
        for (i = 0; i < P; i++) {
            for (k = 0; k < 3; k++) {
                g_parf[f][i].v[k] = (float)(g_par0[f][i][k] + sigma * tu_rng_gauss(g));
            }
        }
        for (i = 0; i < K; i++) {
            for (k = 0; k < 3; k++) {
                g_chif[f][i].v[k] = (float)(g_chi0[f][i][k] + sigma * tu_rng_gauss(g));
            }
        }
    }
}

typedef struct jscen {
    double sigma, max_deg;
    int nf;
} jscen_t;

static const jscen_t k_jscen[] = {
    {0.5, 60.0, 100}, {0.5, 60.0, 400}, {2.0, 60.0, 100}, {2.0, 60.0, 400},
    {0.5, 30.0, 400}, {2.0, 30.0, 400}, {5.0, 60.0, 400}, {5.0, 30.0, 1000},
};

/* One trial with its covariance as a 3x3 matrix. */
static void cacc_add(cov_tally_t *a, sfit_status_t st, uint32_t flags, float trust,
                     const sfit_vec3_t *c, const sfit_mat3_t *cov, const double truth[3])
{
    cov_tally_add(a, st, flags, trust, c, cov, truth);
}

/* The row's last columns: mean trust | trials | unflagged | coverage |
 * flagged | fails | reported / MC trace. */
static void cacc_print(FILE *f, const cov_tally_t *a, int trials)
{
    const long u = cov_tally_unflagged(a);
    fprintf(f, " %.3f | %d | %ld | %.3f | %ld | %ld | %.3f |\n",
            (a->ok > 0) ? a->trust / (double)a->ok : 0.0, trials, u,
            (u > 0) ? (double)a->covered / (double)u : -1.0, a->flagged, a->failed,
            cov_tally_ratio(a));
    fflush(f);
}

/* ---- multi-marker ---- */

#define NMK 4
#define NPM 10000
static const double k_mr[NMK] = {80.0, 100.0, 120.0, 150.0};
static const double k_mc[3] = {1000.0, -2000.0, 1500.0};
static const double k_max[3] = {0.3, -0.5, 0.8};
static sfit_vec3_t g_mp[NPM];

typedef struct mscen {
    double cap, sr; /* half-angle (deg); sigma / r of the 100 mm marker */
    int n;          /* samples per marker */
} mscen_t;

static const mscen_t k_mscen[] = {
    {30.0, 0.01, 100}, {30.0, 0.02, 1000}, {60.0, 0.02, 100}, {60.0, 0.05, 1000},
    {90.0, 0.05, 100}, {90.0, 0.1, 1000},  {180.0, 0.1, 100}, {180.0, 0.2, 1000},
};

static void run_multi(FILE *f, int quick)
{
    size_t si;
    fprintf(f, "| cap (deg) | sigma / 100 mm | N per marker | mean trust | trials | unflagged | "
               "coverage | flagged | fails | reported / MC trace |\n"
               "|---|---|---|---|---|---|---|---|---|---|\n");
    for (si = 0; si < sizeof k_mscen / sizeof k_mscen[0]; si++) {
        const mscen_t *sc = &k_mscen[si];
        const double sig = sc->sr * 100.0, th = sc->cap * TU_PI / 180.0;
        const int trials = quick ? 100 : 1000;
        sfit_multi_cfg_t cfg = sfit_multi_cfg_default;
        cov_tally_t acc;
        tu_rng_t g;
        int t, p, i, k;
        memset(&acc, 0, sizeof acc);
        cfg.fit.mode = SFIT_MODE_SPHERE;
        cfg.fit.noise = SFIT_NOISE_ISO;
        cfg.fit.noise_var = (float)(sig * sig);
        tu_rng_seed(&g, 700u + (uint64_t)si);
        for (t = 0; t < trials; t++) {
            sfit_moments_t m[NMK];
            sfit_multi_result_t res;
            sfit_mat3_t cov;
            sfit_status_t st = SFIT_OK;
            memset(&res, 0, sizeof res);
            memset(&cov, 0, sizeof cov);
            for (p = 0; p < NMK && st == SFIT_OK; p++) {
                for (i = 0; i < sc->n; i++) {
                    double x[3];
                    tu_sample_cap(&g, k_mc, k_mr[p], k_max, th, sig, x);
                    for (k = 0; k < 3; k++) {
                        g_mp[i].v[k] = (float)x[k];
                    }
                }
                (void)sfit_moments_init(&m[p]);
                st = sfit_moments_add_block(&m[p], g_mp, (size_t)sc->n, NULL);
            }
            if (st == SFIT_OK) {
                st = sfit_multi_fit(m, NMK, &cfg, &res, NULL);
            }
            if (st == SFIT_OK) {
                st = sfit_multi_center_cov(m, NMK, &cfg, &res, cfg.fit.noise_var, &cov);
            }
            cacc_add(&acc, st, res.flags, res.trust_ratio, &res.center, &cov, k_mc);
        }
        fprintf(f, "| %.0f | %.3f | %d |", sc->cap, sc->sr, sc->n);
        cacc_print(f, &acc, trials);
    }
}

int main(int argc, char **argv)
{
    FILE *f;
    sfit_vec3_t tv[P];
    sfit_cluster_t cl;
    size_t si;
    int quick = (argc > 2 && strcmp(argv[2], "quick") == 0), i, k;
    if (argc < 2) {
        fprintf(stderr, "usage: sfit_mc_coverage_joint OUTDIR [quick]\n");
        return 2;
    }
    for (i = 0; i < P; i++) {
        for (k = 0; k < 3; k++) {
            tv[i].v[k] = (float)k_tpl[i][k];
        }
    }
    if (sfit_cluster_init(&cl, tv, P) != SFIT_OK) {
        return 1;
    }
    f = mc_out_open(argv[1], "coverage_joint.md");
    if (f == NULL) {
        return 1;
    }
    fprintf(f, "Multi-marker (sfit_multi_fit, unbiased MGDK with the true sigma^2, "
               "sfit_multi_center_cov):\n\n");
    run_multi(f, quick);
    fprintf(f, "\nJoint (ball, 4 parent + 5 child markers, noise on every marker, "
               "SFIT_JOINT_NOISE_MARKER, sfit_joint_center_cov):\n\n");
    fprintf(f, "| sigma (mm) | child rotation (deg) | frames | mean trust | trials | unflagged | "
               "coverage | flagged | fails | reported / MC trace |\n"
               "|---|---|---|---|---|---|---|---|---|---|\n");
    for (si = 0; si < sizeof k_jscen / sizeof k_jscen[0]; si++) {
        const jscen_t *sc = &k_jscen[si];
        const int trials = quick ? 100 : 1000;
        sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
        cov_tally_t acc;
        tu_rng_t g;
        int t;
        memset(&acc, 0, sizeof acc);
        cfg.n_child = K;
        cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
        cfg.solve.fit.mode = SFIT_MODE_SPHERE;
        cfg.solve.fit.noise = SFIT_NOISE_ISO;
        cfg.solve.fit.noise_var = (float)(sc->sigma * sc->sigma);
        make_motion(500u + (uint64_t)si, (size_t)sc->nf, sc->max_deg);
        tu_rng_seed(&g, 600u + (uint64_t)si);
        for (t = 0; t < trials; t++) {
            sfit_joint_result_t res;
            sfit_mat3_t cov;
            sfit_status_t st;
            size_t fr;
            memset(&res, 0, sizeof res);
            memset(&cov, 0, sizeof cov);
            make_noisy(&g, (size_t)sc->nf, sc->sigma);
            st = sfit_joint_init(&g_j, &cl, &cfg);
            for (fr = 0; fr < (size_t)sc->nf && st == SFIT_OK; fr++) {
                st = sfit_joint_add(&g_j, g_parf[fr], P, g_chif[fr], K, NULL);
            }
            if (st == SFIT_OK) {
                st = sfit_joint_fit(&g_j, &res, NULL);
            }
            if (st == SFIT_OK) {
                st = sfit_joint_center_cov(&g_j, &res, &g_parf[0][0], &g_chif[0][0],
                                           (size_t)sc->nf, cfg.solve.fit.noise_var, &cov);
            }
            cacc_add(&acc, st, res.fit.flags, res.fit.trust_ratio, &res.fit.center, &cov,
                     k_centre);
        }
        fprintf(f, "| %.1f | %.0f | %d |", sc->sigma, sc->max_deg, sc->nf);
        cacc_print(f, &acc, trials);
    }
    fclose(f);
    return 0;
}
