/* SPDX-License-Identifier: MIT */
/**
 * @file mc.c
 * @brief Monte Carlo validation harness: the float library (GDKE, UGDK)
 * against a double-precision maximum-likelihood (orthogonal-distance) fit
 * and the Cramer-Rao lower bound (CRLB), on full spheres and caps.
 *
 * Usage: sfit_mc OUTDIR [quick] [EXPERIMENT...]   (OUTDIR must exist)
 *   EXPERIMENT: scenarios | sigma | capbias | compare   (default: all)
 *   quick: fewer trials (a smoke run; the committed figures use the full run)
 *
 * Every experiment uses fixed seeds derived from its parameters, so each
 * CSV regenerates bit-for-bit on the same platform, whatever subset is run.
 *
 * Model: N samples uniform on a cap of half-angle theta (180 deg = full
 * sphere) of a sphere of radius r = 100 mm, centre c0 = (2100, -1500, 900)
 * mm (|c0| = 2731 mm, far from the origin as in motion capture), axis
 * (1, 2, 3)/sqrt(14), plus isotropic Gaussian noise sigma. The samples are
 * rounded to float once; the float library and the double fit see exactly
 * the same numbers.
 *
 * CRLB: for a given set of true positions the CRLB of (c, r) is
 * sigma^2 (sum J_i^T J_i)^-1, J_i = [u_i^T, 1], u_i the true unit normal
 * (tests/ref ref_crlb_sphere). On a cap the positions are random, so each
 * trial has its own bound. For an unbiased estimator
 * E[|c_hat - c0|^2 | positions] >= tr CRLB_c(positions); averaging over the
 * positions, the total MSE over the trials is bounded by the MEAN of the
 * per-trial traces. The harness therefore compares RMSE (sqrt of the mean
 * of |c_hat - c0|^2, i.e. bias^2 + variance) with sqrt(mean tr CRLB_c).
 *
 * rho: the population trust ratio rho = sigma^2 / (lambda_min(C0) + sigma^2)
 * = rho(C^-1 Sigma) with C = C0 + sigma^2 I the covariance of the noisy
 * samples (the library's trust_ratio), lambda_min(C0) = r^2 sin^4(theta/2)/3
 * for a cap, r^2/3 for the sphere. rho0 = sigma^2 / lambda_min(C0) is the
 * Leontief ratio of eq. 194 (the library's leontief_ratio).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit_ref.h"
#include "test_util.h"
#include "mc_out.h"

#define MC_NMAX 10000
#define MC_R0 100.0

static const double k_c0[3] = {2100.0, -1500.0, 900.0};
static const double k_axis[3] = {0.267261241912424, 0.534522483824849, 0.801783725737273};

static double g_true[MC_NMAX][3];  /* noise-free positions */
static double g_x[MC_NMAX][3];     /* noisy samples, float-rounded, as doubles */
static sfit_vec3_t g_f[MC_NMAX];   /* the same samples as floats */
static double g_n[3], g_e1[3], g_e2[3]; /* frame: axis, two lateral directions */
static int g_quick;

/* ------------------------------------------------------------ helpers */

static double deg2rad(double d)
{
    return d * TU_PI / 180.0;
}

/** lambda_min(C0) of the uniform distribution on the cap (axial variance;
 *  r^2/3 for the full sphere, where all three are equal). */
static double lmin0(double theta_deg, double r)
{
    const double s = sin(deg2rad(theta_deg) / 2.0);
    return theta_deg >= 180.0 ? r * r / 3.0 : r * r * s * s * s * s / 3.0;
}

/** Distance from the centre to the mean of the cap samples (along the axis). */
static double cap_offset(double theta_deg, double r)
{
    return theta_deg >= 180.0 ? 0.0 : r * (1.0 + cos(deg2rad(theta_deg))) / 2.0;
}

static double rho_trust(double theta_deg, double sigma)
{
    return sigma * sigma / (lmin0(theta_deg, MC_R0) + sigma * sigma);
}

static uint64_t mc_seed(unsigned exp, unsigned a, unsigned b, unsigned c)
{
    return UINT64_C(0x5F17A11D00000000) ^ ((uint64_t)exp << 48) ^ ((uint64_t)a << 32) ^
           ((uint64_t)b << 16) ^ (uint64_t)c;
}

/** Draws n samples; fills g_true, g_x, g_f. */
static void draw(tu_rng_t *g, size_t n, double theta_deg, double sigma)
{
    size_t i;
    const double th = theta_deg >= 180.0 ? TU_PI : deg2rad(theta_deg);
    int k;
    for (i = 0; i < n; ++i) {
        double p[3];
        tu_sample_cap(g, k_c0, MC_R0, k_axis, th, 0.0, g_true[i]);
        p[0] = g_true[i][0];
        p[1] = g_true[i][1];
        p[2] = g_true[i][2];
        tu_add_noise(g, sigma, p);
        for (k = 0; k < 3; ++k) {
            volatile float t = (float)p[k]; /* round once, through memory */
            g_f[i].v[k] = t;
            g_x[i][k] = (double)t;
        }
    }
}

/* ------------------------------------------------- fit of one trial */

enum { EST_GDKE = 0, EST_UGDK = 1, EST_GEO = 2, EST_COUNT = 3 };
static const char *const k_est_name[EST_COUNT] = {"gdke", "ugdk", "geo"};

typedef struct {
    int ok[EST_COUNT];
    double c[EST_COUNT][3];
    double r[EST_COUNT];
    double trust;        /* UGDK's trust_ratio (rho(C^-1 Sigma), measured C) */
    double crlb_tr;      /* tr CRLB of the centre, true positions */
    double crlb_rr;      /* CRLB of the radius */
    double crlb_c[3][3]; /* centre block */
} trial_t;

static void fit_trial(size_t n, double sigma, int with_geo, trial_t *t)
{
    sfit_fit_cfg_t cg = sfit_fit_cfg_default, cu = sfit_fit_cfg_default;
    sfit_result_t rg, ru;
    double crlb[4][4];
    int k, j;

    memset(t, 0, sizeof *t);
    cg.mode = SFIT_MODE_SPHERE;
    cu.mode = SFIT_MODE_SPHERE;
    cu.noise = SFIT_NOISE_ISO;
    cu.noise_var = (float)(sigma * sigma);
    cg.eigen = true; /* the table reports the exact trust ratio */
    cu.eigen = true;
    if (sfit_fit_points(g_f, n, &cg, &rg) == SFIT_OK) {
        t->ok[EST_GDKE] = 1;
        for (k = 0; k < 3; ++k) {
            t->c[EST_GDKE][k] = (double)rg.center.v[k];
        }
        t->r[EST_GDKE] = (double)rg.radius;
    }
    if (sfit_fit_points(g_f, n, &cu, &ru) == SFIT_OK) {
        t->ok[EST_UGDK] = 1;
        for (k = 0; k < 3; ++k) {
            t->c[EST_UGDK][k] = (double)ru.center.v[k];
        }
        t->r[EST_UGDK] = (double)ru.radius;
        t->trust = (double)ru.trust_ratio;
    }
    if (with_geo) {
        /* Started from UGDK (else GDKE, else the sample mean), as a user
         * would; the LM fit then finds the nearest minimum of the
         * orthogonal-distance cost. */
        double c0[3], r0, rr;
        int src = t->ok[EST_UGDK] ? EST_UGDK : EST_GDKE;
        if (t->ok[src]) {
            memcpy(c0, t->c[src], sizeof c0);
            r0 = t->r[src];
        } else {
            c0[0] = c0[1] = c0[2] = 0.0;
            for (j = 0; j < (int)n; ++j) {
                for (k = 0; k < 3; ++k) {
                    c0[k] += g_x[j][k] / (double)n;
                }
            }
            r0 = MC_R0;
        }
        if (ref_fit_geometric(REF_C3(g_x), n, c0, r0, t->c[EST_GEO], &rr, NULL) == 0) {
            t->ok[EST_GEO] = 1;
            t->r[EST_GEO] = rr;
        }
    }
    ref_crlb_sphere(REF_C3(g_true), n, k_c0, MC_R0, sigma * sigma, crlb);
    t->crlb_tr = crlb[0][0] + crlb[1][1] + crlb[2][2];
    t->crlb_rr = crlb[3][3];
    for (k = 0; k < 3; ++k) {
        for (j = 0; j < 3; ++j) {
            t->crlb_c[k][j] = crlb[k][j];
        }
    }
}

/* ----------------------------------------------------- accumulators */

typedef struct {
    long n;          /* successful trials */
    long fails;
    double s[3], s2[3];     /* error components in the frame (axial, lat1, lat2) */
    double sa, sa2, sb, sb2, sab; /* a = |e|^2, b = tr CRLB_c (same trials) */
    double sr, sr2, scr;    /* radius error, its square; CRLB_rr */
    double strust;
} acc_t;

typedef struct {
    double bias[3], se[3];  /* axial, lateral 1, lateral 2 (mm) */
    double bias_norm;       /* |mean error| (mm) */
    double rmse, crlb, ratio, ratio_se;
    double rbias, rbias_se, rrmse, rcrlb;
    double trust;
} stats_t;

static void acc_add(acc_t *a, const trial_t *t, int est)
{
    double e[3], f[3], a2;
    int k;
    if (!t->ok[est]) {
        a->fails++;
        return;
    }
    for (k = 0; k < 3; ++k) {
        e[k] = t->c[est][k] - k_c0[k];
    }
    f[0] = tu_dot3(e, g_n);
    f[1] = tu_dot3(e, g_e1);
    f[2] = tu_dot3(e, g_e2);
    a2 = tu_dot3(e, e);
    a->n++;
    for (k = 0; k < 3; ++k) {
        a->s[k] += f[k];
        a->s2[k] += f[k] * f[k];
    }
    a->sa += a2;
    a->sa2 += a2 * a2;
    a->sb += t->crlb_tr;
    a->sb2 += t->crlb_tr * t->crlb_tr;
    a->sab += a2 * t->crlb_tr;
    a->sr += t->r[est] - MC_R0;
    a->sr2 += (t->r[est] - MC_R0) * (t->r[est] - MC_R0);
    a->scr += t->crlb_rr;
    a->strust += t->trust;
}

static void acc_stats(const acc_t *a, stats_t *s)
{
    const double n = (double)a->n;
    double ma, mb, r2, va, vb, cab, vq;
    int k;
    memset(s, 0, sizeof *s);
    if (a->n < 2) {
        return;
    }
    for (k = 0; k < 3; ++k) {
        const double m = a->s[k] / n;
        s->bias[k] = m;
        s->se[k] = sqrt(fmax(a->s2[k] / n - m * m, 0.0) / (n - 1.0));
    }
    s->bias_norm = sqrt(tu_dot3(s->bias, s->bias));
    ma = a->sa / n;
    mb = a->sb / n;
    s->rmse = sqrt(ma);
    s->crlb = sqrt(mb);
    r2 = ma / mb;
    s->ratio = sqrt(r2);
    /* Delta method: R^2 = mean(a)/mean(b); Var(R^2) ~ Var(a - R^2 b) /
     * (T mean(b)^2); SE(R) = SE(R^2) / (2 R). */
    va = a->sa2 / n - ma * ma;
    vb = a->sb2 / n - mb * mb;
    cab = a->sab / n - ma * mb;
    vq = fmax(va - 2.0 * r2 * cab + r2 * r2 * vb, 0.0);
    s->ratio_se = sqrt(vq / (n - 1.0)) / mb / (2.0 * s->ratio);
    s->rbias = a->sr / n;
    s->rbias_se = sqrt(fmax(a->sr2 / n - s->rbias * s->rbias, 0.0) / (n - 1.0));
    s->rrmse = sqrt(a->sr2 / n);
    s->rcrlb = sqrt(a->scr / n);
    s->trust = a->strust / n;
}

/** x, with a magnitude that prints as 0.000 made +0 (no "-0.000"). */
static double z3(double x)
{
    return fabs(x) < 5e-4 ? 0.0 : x;
}

static FILE *open_out(const char *dir, const char *name)
{
    FILE *f = mc_out_open(dir, name);
    if (f == NULL) {
        exit(1);
    }
    return f;
}

/* ------------------------------------------------- 1. the scenarios */

static const double k_thetas[] = {180.0, 90.0, 60.0, 45.0, 30.0};
static const double k_sigmas[] = {0.5, 2.0, 5.0};
static const size_t k_ns[] = {10, 30, 100, 300, 1000, 3000, 10000};
#define N_THETA (sizeof k_thetas / sizeof k_thetas[0])
#define N_SIGMA (sizeof k_sigmas / sizeof k_sigmas[0])
#define N_N (sizeof k_ns / sizeof k_ns[0])

static stats_t g_sc[N_THETA][N_SIGMA][N_N][EST_COUNT];
static long g_sc_T[N_THETA][N_SIGMA][N_N][EST_COUNT];
static long g_sc_fail[N_THETA][N_SIGMA][N_N][EST_COUNT];

/** Axial CRLB per sample (N * CRLB_axax / sigma^2) from a large noise-free
 *  pilot draw: sizes the trial counts. */
static double pilot_axial(double theta_deg)
{
    tu_rng_t g;
    double crlb[4][4], a = 0.0;
    int j, k;
    tu_rng_seed(&g, mc_seed(9, (unsigned)theta_deg, 0, 0));
    draw(&g, MC_NMAX, theta_deg, 0.0);
    ref_crlb_sphere(REF_C3(g_true), MC_NMAX, k_c0, MC_R0, 1.0, crlb);
    for (j = 0; j < 3; ++j) {
        for (k = 0; k < 3; ++k) {
            a += g_n[j] * crlb[j][k] * g_n[k];
        }
    }
    return a * MC_NMAX;
}

/* Trial counts. N < 1000: 2000 trials (the SE of RMSE/sqrt(tr CRLB) is
 * about 0.7/sqrt(T) of it when one direction dominates: 1.6 %). N >= 1000:
 * enough that the axial bias has SE <= 0.01 sigma (the |bias| <= 0.03 sigma
 * claim must be resolvable), between 1000 and 20000. The geometric fit
 * (long double LM, ~50x the cost) runs on the first T_geo of them. */
static long trials_lib(size_t n, double axial_per_sample)
{
    long t = 2000;
    if (n >= 1000) {
        const double need = axial_per_sample / (double)n / (0.01 * 0.01);
        t = (long)ceil(need);
        t = t < 1000 ? 1000 : (t > 20000 ? 20000 : t);
    }
    return g_quick ? (t / 10 < 50 ? 50 : t / 10) : t;
}

static long trials_geo(size_t n)
{
    long t = n <= 300 ? 1000 : (n <= 1000 ? 500 : 200);
    return g_quick ? t / 10 : t;
}

static void run_scenarios(const char *dir)
{
    FILE *f = open_out(dir, "scenarios.csv");
    size_t a, b, c;
    int e;
    fprintf(f, "theta,sigma,N,estimator,trials,fails,rho,rho0,bias_ax,se_ax,bias_l1,se_l1,"
               "bias_l2,se_l2,bias_norm,rmse,sqrt_crlb,ratio,ratio_se,rbias,rbias_se,rrmse,"
               "sqrt_crlb_r,mean_trust\n");
    for (a = 0; a < N_THETA; ++a) {
        const double ax = pilot_axial(k_thetas[a]);
        for (b = 0; b < N_SIGMA; ++b) {
            const double sg = k_sigmas[b];
            for (c = 0; c < N_N; ++c) {
                const size_t n = k_ns[c];
                const long T = trials_lib(n, ax), Tg = trials_geo(n);
                acc_t acc[EST_COUNT];
                tu_rng_t g;
                long t;
                memset(acc, 0, sizeof acc);
                tu_rng_seed(&g, mc_seed(1, (unsigned)a, (unsigned)b, (unsigned)c));
                for (t = 0; t < T; ++t) {
                    trial_t tr;
                    draw(&g, n, k_thetas[a], sg);
                    fit_trial(n, sg, t < Tg, &tr);
                    for (e = 0; e < EST_COUNT; ++e) {
                        if (e != EST_GEO || t < Tg) {
                            acc_add(&acc[e], &tr, e);
                        }
                    }
                }
                for (e = 0; e < EST_COUNT; ++e) {
                    stats_t *s = &g_sc[a][b][c][e];
                    acc_stats(&acc[e], s);
                    g_sc_T[a][b][c][e] = acc[e].n + acc[e].fails;
                    g_sc_fail[a][b][c][e] = acc[e].fails;
                    fprintf(f,
                            "%g,%g,%zu,%s,%ld,%ld,%.6g,%.6g,%.6g,%.4g,%.6g,%.4g,%.6g,%.4g,%.6g,"
                            "%.6g,%.6g,%.5f,%.5f,%.6g,%.4g,%.6g,%.6g,%.6g\n",
                            k_thetas[a], sg, n, k_est_name[e], acc[e].n + acc[e].fails,
                            acc[e].fails, rho_trust(k_thetas[a], sg),
                            sg * sg / lmin0(k_thetas[a], MC_R0), s->bias[0], s->se[0], s->bias[1],
                            s->se[1], s->bias[2], s->se[2], s->bias_norm, s->rmse, s->crlb,
                            s->ratio, s->ratio_se, s->rbias, s->rbias_se, s->rrmse, s->rcrlb,
                            s->trust);
                }
                fflush(f);
                fprintf(stderr, "scenario theta %g sigma %g N %zu: T %ld/%ld, UGDK ratio %.3f\n",
                        k_thetas[a], sg, n, T, Tg, g_sc[a][b][c][EST_UGDK].ratio);
            }
        }
    }
    fclose(f);
}

static const char *geom_name(double theta, char *buf, size_t len)
{
    if (theta >= 180.0) {
        snprintf(buf, len, "sphere");
    } else {
        snprintf(buf, len, "cap %g°", theta);
    }
    return buf;
}

/** The Markdown results table and the claim checks (from the scenarios). */
static void write_table_and_claims(const char *dir)
{
    FILE *k = open_out(dir, "claims.md");
    size_t a, b, c;
    int n_fail1 = 0, n_chk1 = 0, n_fail1b = 0, n_chk1b = 0, n_fail2 = 0, n_chk2 = 0, pass;
    char gb[32];

    /* results_table.md: N = 100, 1000, 10000; results_table_n1000.md: the
     * compact version (N = 1000 only). */
    for (pass = 0; pass < 2; ++pass) {
        FILE *f = open_out(dir, pass == 0 ? "results_table.md" : "results_table_n1000.md");
        fprintf(f, "| geometry | σ (mm) | ρ | N | GDKE axial bias (mm) | GDKE RMSE/√trCRLB | "
                   "UGDK axial bias (mm) | UGDK RMSE/√trCRLB | ML axial bias (mm) | "
                   "ML RMSE/√trCRLB |\n");
        fprintf(f, "|---|---|---|---|---|---|---|---|---|---|\n");
        for (a = 0; a < N_THETA; ++a) {
            for (b = 0; b < N_SIGMA; ++b) {
                for (c = 0; c < N_N; ++c) {
                    const stats_t *s = g_sc[a][b][c];
                    int e;
                    if (pass == 0 ? (k_ns[c] != 100 && k_ns[c] != 1000 && k_ns[c] != 10000)
                                  : k_ns[c] != 1000) {
                        continue;
                    }
                    fprintf(f, "| %s | %g | %.3g | %zu |", geom_name(k_thetas[a], gb, sizeof gb),
                            k_sigmas[b], rho_trust(k_thetas[a], k_sigmas[b]), k_ns[c]);
                    for (e = 0; e < EST_COUNT; ++e) {
                        char fl[48] = "";
                        if (g_sc_fail[a][b][c][e] > 0) {
                            snprintf(fl, sizeof fl, " (%ld/%ld failed)", g_sc_fail[a][b][c][e],
                                     g_sc_T[a][b][c][e]);
                        }
                        fprintf(f, " %.3f ± %.3f | %.3f ± %.3f%s |", z3(s[e].bias[0]), s[e].se[0],
                                s[e].ratio, s[e].ratio_se, fl);
                    }
                    fprintf(f, "\n");
                }
            }
        }
        fclose(f);
    }

    fprintf(k, "## Claim 1a: UGDK RMSE/sqrt(tr CRLB) <= 1.10 where rho <= 0.1, N >= 100\n\n");
    fprintf(k, "| geometry | σ | ρ | N | trials | ratio ± SE | holds |\n|---|---|---|---|---|---|---|\n");
    for (a = 0; a < N_THETA; ++a) {
        for (b = 0; b < N_SIGMA; ++b) {
            const double rho = rho_trust(k_thetas[a], k_sigmas[b]);
            if (rho > 0.1) {
                continue;
            }
            for (c = 0; c < N_N; ++c) {
                const stats_t *s = &g_sc[a][b][c][EST_UGDK];
                int ok;
                if (k_ns[c] < 100) {
                    continue;
                }
                ok = s->ratio <= 1.10 && g_sc_fail[a][b][c][EST_UGDK] == 0;
                n_chk1++;
                n_fail1 += !ok;
                fprintf(k, "| %s | %g | %.3g | %zu | %ld | %.3f ± %.3f | %s |\n",
                        geom_name(k_thetas[a], gb, sizeof gb), k_sigmas[b], rho, k_ns[c],
                        g_sc_T[a][b][c][EST_UGDK], s->ratio, s->ratio_se, ok ? "yes" : "**NO**");
            }
        }
    }
    fprintf(k, "\n%d of %d scenarios hold.\n\n", n_chk1 - n_fail1, n_chk1);

    fprintf(k, "## Claim 1b: UGDK |bias| <= 0.03 sigma where rho <= 0.1, N >= 1000\n\n"
               "Bias components in the cap frame (axial, two lateral), with their standard "
               "errors; \"holds\" when every component is within 0.03 sigma + 2 SE (the trial "
               "counts make SE <= 0.01 sigma along the axis).\n\n");
    fprintf(k, "| geometry | σ | ρ | N | trials | axial / σ | lateral 1 / σ | lateral 2 / σ | "
               "holds |\n|---|---|---|---|---|---|---|---|---|\n");
    for (a = 0; a < N_THETA; ++a) {
        for (b = 0; b < N_SIGMA; ++b) {
            const double rho = rho_trust(k_thetas[a], k_sigmas[b]), sg = k_sigmas[b];
            if (rho > 0.1) {
                continue;
            }
            for (c = 0; c < N_N; ++c) {
                const stats_t *s = &g_sc[a][b][c][EST_UGDK];
                int ok = 1, j;
                if (k_ns[c] < 1000) {
                    continue;
                }
                for (j = 0; j < 3; ++j) {
                    ok = ok && fabs(s->bias[j]) <= 0.03 * sg + 2.0 * s->se[j];
                }
                n_chk1b++;
                n_fail1b += !ok;
                fprintf(k, "| %s | %g | %.3g | %zu | %ld | %.4f ± %.4f | %.4f ± %.4f | "
                           "%.4f ± %.4f | %s |\n",
                        geom_name(k_thetas[a], gb, sizeof gb), sg, rho, k_ns[c],
                        g_sc_T[a][b][c][EST_UGDK], s->bias[0] / sg, s->se[0] / sg,
                        s->bias[1] / sg, s->se[1] / sg, s->bias[2] / sg, s->se[2] / sg,
                        ok ? "yes" : "**NO**");
            }
        }
    }
    fprintf(k, "\n%d of %d scenarios hold.\n\n", n_chk1b - n_fail1b, n_chk1b);

    fprintf(k, "## Claim 2: GDKE cap bias = rho r (1 + cos theta)/2 within 5 %% + 3 SE\n\n"
               "rho = sigma^2 / (lambda_min(C0) + sigma^2) (population trust ratio; the "
               "library's mean trust_ratio is shown next to it). Bias along the cap axis, "
               "towards the samples.\n\n");
    fprintf(k, "| cap | σ | ρ | mean trust_ratio | N | trials | predicted (mm) | measured (mm) "
               "| (meas - pred)/pred | holds |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for (a = 0; a < N_THETA; ++a) {
        if (k_thetas[a] >= 180.0) {
            continue;
        }
        for (b = 0; b < N_SIGMA; ++b) {
            const double rho = rho_trust(k_thetas[a], k_sigmas[b]);
            const double pred = rho * cap_offset(k_thetas[a], MC_R0);
            for (c = 0; c < N_N; ++c) {
                const stats_t *s = &g_sc[a][b][c][EST_GDKE];
                int ok;
                if (k_ns[c] != 1000 && k_ns[c] != 10000) {
                    continue;
                }
                ok = fabs(s->bias[0] - pred) <= 0.05 * pred + 3.0 * s->se[0];
                if (k_ns[c] == 10000) {
                    n_chk2++;
                    n_fail2 += !ok;
                }
                fprintf(k, "| %g° | %g | %.4f | %.4f | %zu | %ld | %.4g | %.4g ± %.2g | %+.4f | %s%s |\n",
                        k_thetas[a], k_sigmas[b], rho, g_sc[a][b][c][EST_UGDK].trust, k_ns[c],
                        g_sc_T[a][b][c][EST_GDKE], pred, s->bias[0], s->se[0],
                        (s->bias[0] - pred) / pred, ok ? "yes" : "**NO**",
                        k_ns[c] == 10000 ? "" : " (info)");
            }
        }
    }
    fprintf(k, "\n%d of %d cap scenarios hold at N = 10000 (N = 1000 rows show the O(1/N) "
               "part).\n", n_chk2 - n_fail2, n_chk2);
    fclose(k);
    fprintf(stderr, "claims: 1a %d/%d, 1b %d/%d, 2 %d/%d hold\n", n_chk1 - n_fail1, n_chk1,
            n_chk1b - n_fail1b, n_chk1b, n_chk2 - n_fail2, n_chk2);
}

/* ------------------------------------ 2. sigma sweep towards r (Fig. 21) */

static void run_sigma(const char *dir)
{
    static const double thetas[] = {180.0, 60.0};
    static const double sigmas[] = {1, 2, 3, 5, 7, 10, 14, 20, 28, 40, 57.7, 80, 100};
    const size_t n = 1000;
    const long T = g_quick ? 30 : 300;
    FILE *f = open_out(dir, "sigma.csv");
    size_t a, b;
    int e;
    fprintf(f, "theta,sigma,N,estimator,trials,fails,rho0,sigma_leontief,rmse,sqrt_crlb,ratio,"
               "ratio_se,bias_ax,se_ax\n");
    for (a = 0; a < 2; ++a) {
        for (b = 0; b < sizeof sigmas / sizeof sigmas[0]; ++b) {
            const double sg = sigmas[b];
            acc_t acc[EST_COUNT];
            tu_rng_t g;
            long t;
            memset(acc, 0, sizeof acc);
            tu_rng_seed(&g, mc_seed(2, (unsigned)a, (unsigned)b, 0));
            for (t = 0; t < T; ++t) {
                trial_t tr;
                draw(&g, n, thetas[a], sg);
                fit_trial(n, sg, 1, &tr);
                for (e = 0; e < EST_COUNT; ++e) {
                    acc_add(&acc[e], &tr, e);
                }
            }
            for (e = 0; e < EST_COUNT; ++e) {
                stats_t s;
                acc_stats(&acc[e], &s);
                fprintf(f, "%g,%g,%zu,%s,%ld,%ld,%.6g,%.6g,%.6g,%.6g,%.5f,%.5f,%.6g,%.4g\n",
                        thetas[a], sg, n, k_est_name[e], acc[e].n + acc[e].fails, acc[e].fails,
                        sg * sg / lmin0(thetas[a], MC_R0), sqrt(lmin0(thetas[a], MC_R0)), s.rmse,
                        s.crlb, s.ratio, s.ratio_se, s.bias[0], s.se[0]);
            }
            fflush(f);
            fprintf(stderr, "sigma sweep theta %g sigma %g done\n", thetas[a], sg);
        }
    }
    fclose(f);
}

/* -------------------------------------- 3. GDKE cap bias versus sigma */

static void run_capbias(const char *dir)
{
    static const double thetas[] = {90.0, 60.0, 45.0, 30.0};
    static const double sigmas[] = {0.5, 1, 1.5, 2, 3, 4, 5, 7, 10};
    const size_t n = 10000;
    const long T = g_quick ? 20 : 200;
    FILE *f = open_out(dir, "capbias.csv");
    size_t a, b;
    fprintf(f, "theta,sigma,N,trials,rho,rho0,mean_trust,pred_trust,pred_rho0,bias_ax,se_ax,"
               "bias_ugdk,se_ugdk\n");
    for (a = 0; a < sizeof thetas / sizeof thetas[0]; ++a) {
        for (b = 0; b < sizeof sigmas / sizeof sigmas[0]; ++b) {
            const double sg = sigmas[b], off = cap_offset(thetas[a], MC_R0);
            const double rho = rho_trust(thetas[a], sg);
            const double rho0 = sg * sg / lmin0(thetas[a], MC_R0);
            acc_t acc[EST_COUNT];
            stats_t sg_g, sg_u;
            tu_rng_t g;
            long t;
            memset(acc, 0, sizeof acc);
            tu_rng_seed(&g, mc_seed(3, (unsigned)a, (unsigned)b, 0));
            for (t = 0; t < T; ++t) {
                trial_t tr;
                draw(&g, n, thetas[a], sg);
                fit_trial(n, sg, 0, &tr);
                acc_add(&acc[EST_GDKE], &tr, EST_GDKE);
                acc_add(&acc[EST_UGDK], &tr, EST_UGDK);
            }
            acc_stats(&acc[EST_GDKE], &sg_g);
            acc_stats(&acc[EST_UGDK], &sg_u);
            fprintf(f, "%g,%g,%zu,%ld,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4g,%.6g,%.4g\n", thetas[a],
                    sg, n, T, rho, rho0, sg_u.trust, rho * off, rho0 * off, sg_g.bias[0],
                    sg_g.se[0], sg_u.bias[0], sg_u.se[0]);
            fflush(f);
        }
        fprintf(stderr, "cap bias theta %g done\n", thetas[a]);
    }
    fclose(f);
}

/* ------------------- 4. one-hundred-sample comparison (Fig. 18, Fig. 20) */

/** 2x2 covariance of the centre in the (lateral 1, axial) plane. */
static void project2(double c3[3][3], double p[2][2])
{
    const double *u[2];
    int i, j, k, l;
    u[0] = g_e1;
    u[1] = g_n;
    for (i = 0; i < 2; ++i) {
        for (j = 0; j < 2; ++j) {
            double s = 0.0;
            for (k = 0; k < 3; ++k) {
                for (l = 0; l < 3; ++l) {
                    s += u[i][k] * c3[k][l] * u[j][l];
                }
            }
            p[i][j] = s;
        }
    }
}

/** Writes the 95 % ellipse (chi^2_2 = 5.991) of covariance p around (x, y). */
static void write_ellipse(FILE *f, const char *tag, double x, double y, double p[2][2])
{
    const double l11 = sqrt(p[0][0]), l21 = p[1][0] / l11;
    const double l22 = sqrt(fmax(p[1][1] - l21 * l21, 0.0)), k = sqrt(5.991);
    int i;
    for (i = 0; i <= 200; ++i) {
        const double t = 2.0 * TU_PI * i / 200.0, u = cos(t), v = sin(t);
        fprintf(f, "%s,%.6g,%.6g\n", tag, x + k * l11 * u, y + k * (l21 * u + l22 * v));
    }
}

static void run_compare(const char *dir)
{
    const double theta = 45.0, sg = 5.0;
    const size_t n = 100;
    const int T = 100;
    FILE *fs = open_out(dir, "compare_trials.csv");
    FILE *fe = open_out(dir, "compare_ellipses.csv");
    FILE *f1 = open_out(dir, "ellipse_one.csv");
    double mc[3][3] = {{0}}, p[2][2];
    tu_rng_t g;
    int t, e, j, k;

    fprintf(fs, "trial,estimator,lateral,axial,radius_err\n");
    fprintf(fe, "curve,lateral,axial\n");
    tu_rng_seed(&g, mc_seed(4, 45, 5, 100));
    for (t = 0; t < T; ++t) {
        trial_t tr;
        draw(&g, n, theta, sg);
        fit_trial(n, sg, 1, &tr);
        for (e = 0; e < EST_COUNT; ++e) {
            double d[3];
            if (!tr.ok[e]) {
                fprintf(stderr, "compare: trial %d %s failed\n", t, k_est_name[e]);
                continue;
            }
            for (k = 0; k < 3; ++k) {
                d[k] = tr.c[e][k] - k_c0[k];
            }
            fprintf(fs, "%d,%s,%.6g,%.6g,%.6g\n", t, k_est_name[e], tu_dot3(d, g_e1),
                    tu_dot3(d, g_n), tr.r[e] - MC_R0);
        }
        for (j = 0; j < 3; ++j) {
            for (k = 0; k < 3; ++k) {
                mc[j][k] += tr.crlb_c[j][k] / T;
            }
        }
        if (t == 0) {
            /* Fig. 18: the first data set alone, its UGDK estimate and the
             * 95 % ellipse of the CRLB evaluated where a user can: at the
             * fitted sphere (sample directions from the UGDK centre). */
            double est[4][4], xp[100][3], pc[3][3], q[2][2], d[3];
            size_t i;
            for (i = 0; i < n; ++i) {
                double u[3], len;
                for (k = 0; k < 3; ++k) {
                    u[k] = g_x[i][k] - tr.c[EST_UGDK][k];
                }
                len = tu_norm3(u);
                for (k = 0; k < 3; ++k) {
                    xp[i][k] = tr.c[EST_UGDK][k] + tr.r[EST_UGDK] * u[k] / len;
                }
            }
            ref_crlb_sphere(REF_C3(xp), n, tr.c[EST_UGDK], tr.r[EST_UGDK], sg * sg, est);
            for (j = 0; j < 3; ++j) {
                for (k = 0; k < 3; ++k) {
                    pc[j][k] = est[j][k];
                }
            }
            project2(pc, q);
            fprintf(f1, "what,lateral,axial\n");
            fprintf(f1, "truth,0,0\n");
            for (e = 0; e < EST_COUNT; ++e) {
                for (k = 0; k < 3; ++k) {
                    d[k] = tr.c[e][k] - k_c0[k];
                }
                fprintf(f1, "%s,%.6g,%.6g\n", k_est_name[e], tu_dot3(d, g_e1), tu_dot3(d, g_n));
            }
            for (k = 0; k < 3; ++k) {
                d[k] = tr.c[EST_UGDK][k] - k_c0[k];
            }
            write_ellipse(f1, "ellipse", tu_dot3(d, g_e1), tu_dot3(d, g_n), q);
            fprintf(stderr, "Fig 18 data set: UGDK trust %.3f (rho0 %.3f)\n", tr.trust,
                    tr.trust / (1.0 - tr.trust));
        }
    }
    project2(mc, p);
    write_ellipse(fe, "crlb95", 0.0, 0.0, p);
    fprintf(fe, "predicted_gdke_bias,0,%.6g\n", rho_trust(theta, sg) * cap_offset(theta, MC_R0));
    fclose(fs);
    fclose(fe);
    fclose(f1);
}

/* --------------------------------------------------------------- main */

int main(int argc, char **argv)
{
    const char *dir;
    int i, all = 1, sc = 0, sgm = 0, cb = 0, cmp = 0;
    if (argc < 2) {
        fprintf(stderr, "usage: sfit_mc OUTDIR [quick] [scenarios|sigma|capbias|compare]...\n");
        return 2;
    }
    dir = argv[1];
    for (i = 2; i < argc; ++i) {
        if (strcmp(argv[i], "quick") == 0) {
            g_quick = 1;
        } else if (strcmp(argv[i], "scenarios") == 0) {
            sc = 1;
            all = 0;
        } else if (strcmp(argv[i], "sigma") == 0) {
            sgm = 1;
            all = 0;
        } else if (strcmp(argv[i], "capbias") == 0) {
            cb = 1;
            all = 0;
        } else if (strcmp(argv[i], "compare") == 0) {
            cmp = 1;
            all = 0;
        } else {
            fprintf(stderr, "sfit_mc: unknown argument %s\n", argv[i]);
            return 2;
        }
    }
    tu_frame(k_axis, g_n, g_e1, g_e2);
    if (all || cmp) {
        run_compare(dir);
    }
    if (all || cb) {
        run_capbias(dir);
    }
    if (all || sgm) {
        run_sigma(dir);
    }
    if (all || sc) {
        run_scenarios(dir);
        write_table_and_claims(dir);
    }
    return 0;
}
