/* SPDX-License-Identifier: MIT */
/**
 * @file beyond.c
 * @brief Monte Carlo of the beyond-the-chapter estimators (docs/beyond.md):
 * self-calibrated UGDK and the refined geometric fit against the
 * Cramer-Rao bound, the noise estimate's bias, and reported / Monte Carlo
 * covariance traces, over caps from 35 degrees to the whole sphere and
 * sigma / r from 0.017 to 0.38.
 *
 * Usage: sfit_mc_beyond OUTDIR [quick]  -> OUTDIR/beyond_table.md
 * Fixed seeds; identical output from run to run on the same platform.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit_ref.h"
#include "test_util.h"
#include "mc_out.h"

#define NMAX 1000

static double g_xt[NMAX][3];
static sfit_vec3_t g_pf[NMAX];
static const double k_c[3] = {1200.0, -800.0, 300.0};
static const double k_axis[3] = {0.3, -0.5, 0.8};
#define K_R 100.0

typedef struct scen {
    double theta_deg; /* cap half-angle */
    double rho;       /* trust ratio (noisy C); < 0: -sigma / r instead */
    int n, trials;
} scen_t;

/* Inside sigma / r <= 0.1 first, then the corner where the bound fails. */
static const scen_t k_scen[] = {
    {35.0, 0.1, 100, 8000},   {90.0, 0.1, 100, 8000},   {120.0, -0.1, 100, 8000},
    {180.0, -0.1, 100, 8000}, {35.0, 0.3, 1000, 4000},  {60.0, 0.3, 1000, 4000},
    {180.0, 0.1, 100, 8000},  {180.0, 0.1, 1000, 4000}, {120.0, 0.1, 1000, 4000},
    {75.0, 0.3, 1000, 4000},  {90.0, 0.3, 1000, 4000},  {120.0, 0.3, 1000, 2000},
    {180.0, 0.3, 1000, 2000}, {180.0, 0.3, 100, 8000},
};

typedef struct acc {
    double mse, s[3], ss[3], rep;
} acc_t;

static void acc_add(acc_t *a, const sfit_vec3_t *c, double rep)
{
    int k;
    for (k = 0; k < 3; k++) {
        const double e = (double)c->v[k] - k_c[k];
        a->mse += e * e;
        a->s[k] += e;
        a->ss[k] += e * e;
    }
    a->rep += rep;
}

/* reported / MC covariance trace */
static double acc_cov_ratio(const acc_t *a, int t)
{
    double tr = 0.0;
    int k;
    for (k = 0; k < 3; k++) {
        tr += (a->ss[k] - a->s[k] * a->s[k] / t) / (t - 1);
    }
    return (a->rep / t) / tr;
}

static double trace3(const sfit_mat3_t *p)
{
    return (double)p->m[0] + (double)p->m[4] + (double)p->m[8];
}

int main(int argc, char **argv)
{
    FILE *f;
    size_t si;
    int quick = (argc > 2 && strcmp(argv[2], "quick") == 0);
    if (argc < 2) {
        fprintf(stderr, "usage: sfit_mc_beyond OUTDIR [quick]\n");
        return 2;
    }
    f = mc_out_open(argv[1], "beyond_table.md");
    if (f == NULL) {
        return 1;
    }
    fprintf(f, "| theta | rho | sigma/r | N | trials | selfcal RMSE/sqrt(tr CRLB) | refined | "
               "sigma_hat^2/sigma^2 | selfcal cov/MC | refined (sandwich) cov/MC | fails |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (si = 0; si < sizeof k_scen / sizeof k_scen[0]; si++) {
        const scen_t *sc = &k_scen[si];
        const double theta = sc->theta_deg * TU_PI / 180.0;
        const int trials = quick ? sc->trials / 10 : sc->trials;
        double lmin, lmax, s2, rho, crlb = 0.0, noise = 0.0, es, er;
        acc_t as, ar;
        tu_rng_t g;
        int t, i, k, bad = 0;
        ref_cap_eigs_numeric(theta, K_R, &lmin, &lmax);
        if (sc->rho < 0.0) {
            s2 = sc->rho * sc->rho * K_R * K_R;
            rho = s2 / (lmin + s2);
        } else {
            rho = sc->rho;
            s2 = rho / (1.0 - rho) * lmin;
        }
        memset(&as, 0, sizeof as);
        memset(&ar, 0, sizeof ar);
        tu_rng_seed(&g, 900u + (uint64_t)si);
        for (t = 0; t < trials; t++) {
            sfit_selfcal_result_t s;
            sfit_refine_result_t r;
            sfit_moments_t m;
            sfit_uncert_t us, ur;
            double cr[4][4];
            for (i = 0; i < sc->n; i++) {
                double x[3];
                tu_sample_cap(&g, k_c, K_R, k_axis, theta, 0.0, g_xt[i]);
                for (k = 0; k < 3; k++) {
                    x[k] = g_xt[i][k] + sqrt(s2) * tu_rng_gauss(&g);
                    g_pf[i].v[k] = (float)x[k];
                }
            }
            (void)sfit_moments_init(&m);
            {
                /* a failed step is counted with its status, never averaged */
                sfit_status_t st = sfit_moments_add_block(&m, g_pf, (size_t)sc->n, NULL);
                const char *what = "moments";
                if (st == SFIT_OK) {
                    what = "selfcal";
                    st = sfit_selfcal_points(g_pf, (size_t)sc->n, NULL, &s);
                }
                if (st == SFIT_OK) {
                    what = "uncert_moments";
                    st = sfit_uncert_moments(&m, &s.fit.center, s.fit.radius, s.noise_var,
                                             SFIT_UNCERT_NOISE_ESTIMATED, &us);
                }
                if (st == SFIT_OK) {
                    what = "refine";
                    st = sfit_refine_points(g_pf, (size_t)sc->n, &s.fit.center, NULL, &r);
                }
                if (st == SFIT_OK) {
                    what = "uncert_geometric";
                    st = sfit_uncert_geometric(g_pf, (size_t)sc->n, &r.center, &ur);
                }
                if (st != SFIT_OK) {
                    fprintf(stderr, "beyond: %.0f deg N %d trial %d: %s: %s\n", sc->theta_deg,
                            sc->n, t, what, sfit_status_str(st));
                    bad++;
                    continue;
                }
            }
            acc_add(&as, &s.fit.center, trace3(&us.center_cov));
            acc_add(&ar, &r.center, trace3(&ur.center_cov));
            noise += (double)s.noise_var / s2;
            ref_crlb_sphere((const double(*)[3])g_xt, (size_t)sc->n, k_c, K_R, s2, cr);
            crlb += cr[0][0] + cr[1][1] + cr[2][2];
        }
        t = trials - bad;
        es = sqrt(as.mse / crlb);
        er = sqrt(ar.mse / crlb);
        fprintf(f, "| %.0f | %.3f | %.3f | %d | %d | %.3f | %.3f | %.4f | %.3f | %.3f | %d |\n",
                sc->theta_deg, rho, sqrt(s2) / K_R, sc->n, t, es, er, noise / t,
                acc_cov_ratio(&as, t), acc_cov_ratio(&ar, t), bad);
        fflush(f);
        fprintf(stderr, "beyond: %.0f deg rho %.3f N %d done\n", sc->theta_deg, rho, sc->n);
    }
    fclose(f);
    return 0;
}
