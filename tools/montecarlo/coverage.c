/* SPDX-License-Identifier: MIT */
/**
 * @file coverage.c
 * @brief Monte Carlo coverage of the reported centre covariance: the
 * fraction of trials whose true centre lies inside the reported 95 %
 * ellipsoid (e^T Cov^-1 e <= 7.815, chi-square with 3 degrees of freedom),
 * for every estimator that reports a covariance:
 *   ugdk     sfit_fit_points with the true sigma^2 + sfit_uncert_moments (known)
 *   selfcal  sfit_selfcal_points + sfit_uncert_selfcal (sandwich)
 *   refined  sfit_refine_fit (geometric fit + its sandwich)
 * over caps of 20-180 degrees, sigma/r 0.005-0.4 and N 10-1e4
 * (docs/coverage.md). Results with SFIT_FLAG_UNTRUSTED are counted as
 * flagged and left out of the coverage; failed calls are counted apart.
 *
 * Usage: sfit_mc_coverage OUTDIR [quick]
 *        sfit_mc_coverage OUTDIR one CAP SIGMA/R N TRIALS [SEED]
 *        sfit_mc_coverage OUTDIR trust CAP TRUST N TRIALS [SEED]
 *        sfit_mc_coverage OUTFILE dump SCENFILE
 *   OUTDIR/coverage_table.md, OUTDIR/coverage.csv (quick: 1/10 of the trials)
 *   one: a single scenario printed to stdout.
 *   trust: the same, sigma chosen so that the true trust ratio
 *          sigma^2 / lambda_min(C) of the noisy population is TRUST.
 *   dump: the scenarios of SCENFILE (lines "CAP SIGMA/R N TRIALS SEED"),
 *          one line per trial and estimator into OUTFILE, for studying a
 *          flag or widening rule after the fact (tools/montecarlo/cut_study.py;
 *          build the library with -DSFIT_COV_MAX_TRUST=0.5f so that rule 3
 *          does not pre-empt the rule under study).
 * The ctest sfit.uncert (test_coverage_subset) checks a fixed-seed subset.
 * Fixed seeds; identical output from run to run on the same platform.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sfit/sfit.h"
#include "sfit_ref.h"
#include "test_util.h"
#include "cov_tally.h"
#include "mc_out.h"

#define NMAX 10000
#define K_R 100.0

static sfit_vec3_t g_pf[NMAX];
static const double k_c[3] = {1000.0, -2000.0, 1500.0};
static const double k_axis[3] = {0.3, -0.5, 0.8};

enum { EST_UGDK, EST_SELFCAL, EST_REFINED, EST_COUNT };
static const char *const k_est_name[EST_COUNT] = {"ugdk", "selfcal", "refined"};

typedef struct scen {
    double theta_deg, sr; /* cap half-angle, sigma / r */
    int n, trials;
} scen_t;

/* dump mode: per-trial records (NULL: none) and the scenario's index. */
static FILE *g_dump;
static int g_dump_idx;

/* One record of dump mode: scenario, estimator, status, flags, reported
 * trust ratio, e^T Cov^-1 e (-1 when flagged, failed or Cov not positive
 * definite), reported trace, centre error, noise variance the fit used. */
static void dump_trial(int est, sfit_status_t st, uint32_t flags, float trust,
                       const sfit_vec3_t *c, const sfit_mat3_t *cov, float noise_var)
{
    double e[3], d2 = -1.0;
    int k;
    if (g_dump == NULL) {
        return;
    }
    for (k = 0; k < 3; k++) {
        e[k] = (double)c->v[k] - k_c[k];
    }
    if (st == SFIT_OK && (flags & (uint32_t)SFIT_FLAG_UNTRUSTED) == 0u) {
        d2 = tu_mahal(cov->m, e);
    }
    fprintf(g_dump, "%d %d %d %u %.6g %.6g %.6g %.6g %.6g %.6g %.6g\n", g_dump_idx, est, (int)st,
            (unsigned)flags, (double)trust, d2, (double)cov->m[0] + (double)cov->m[4] + (double)cov->m[8],
            e[0], e[1], e[2], (double)noise_var);
}

/* One scenario: trials with fixed seed, one accumulator per estimator. */
static double run_scen(const scen_t *sc, uint64_t seed, cov_tally_t acc[EST_COUNT])
{
    const double theta = sc->theta_deg * TU_PI / 180.0, sig = sc->sr * K_R;
    double lmin, lmax;
    tu_rng_t g;
    int t, i, k;
    ref_cap_eigs_numeric(theta, K_R, &lmin, &lmax);
    memset(acc, 0, EST_COUNT * sizeof acc[0]);
    tu_rng_seed(&g, seed);
    for (t = 0; t < sc->trials; t++) {
        sfit_fit_cfg_t fc = sfit_fit_cfg_default;
        sfit_result_t r;
        sfit_selfcal_result_t s;
        sfit_refine_result_t rf;
        sfit_uncert_t u;
        sfit_status_t st;
        memset(&u, 0, sizeof u);
        memset(&r, 0, sizeof r);
        memset(&s, 0, sizeof s);
        memset(&rf, 0, sizeof rf);
        for (i = 0; i < sc->n; i++) {
            double x[3];
            tu_sample_cap(&g, k_c, K_R, k_axis, theta, sig, x);
            for (k = 0; k < 3; k++) {
                g_pf[i].v[k] = (float)x[k];
            }
        }
        fc.mode = SFIT_MODE_SPHERE;
        fc.noise = SFIT_NOISE_ISO;
        fc.noise_var = (float)(sig * sig);
        /* dump mode: the exact trust ratio (a screened result reports an
         * upper bound of it, enough for the library's own cut only) */
        fc.eigen = (g_dump != NULL);
        st = sfit_fit_points(g_pf, (size_t)sc->n, &fc, &r);
        if (st == SFIT_OK) {
            sfit_moments_t m;
            (void)sfit_moments_init(&m);
            (void)sfit_moments_add_block(&m, g_pf, (size_t)sc->n, NULL);
            st = sfit_uncert_moments(&m, &r.center, r.radius, fc.noise_var,
                                     SFIT_UNCERT_NOISE_KNOWN, &u);
        }
        cov_tally_add(&acc[EST_UGDK], st, r.flags, r.trust_ratio, &r.center, &u.center_cov, k_c);
        dump_trial(EST_UGDK, st, r.flags, r.trust_ratio, &r.center, &u.center_cov, fc.noise_var);
        memset(&u, 0, sizeof u);
        st = sfit_selfcal_points(g_pf, (size_t)sc->n, NULL, &s);
        if (st == SFIT_OK && (s.fit.flags & (uint32_t)SFIT_FLAG_UNTRUSTED) == 0u) {
            st = sfit_uncert_selfcal(g_pf, (size_t)sc->n, &s.fit.center, s.fit.radius,
                                     s.noise_var, &u);
        }
        cov_tally_add(&acc[EST_SELFCAL], st, s.fit.flags, s.fit.trust_ratio, &s.fit.center,
                      &u.center_cov, k_c);
        dump_trial(EST_SELFCAL, st, s.fit.flags, s.fit.trust_ratio, &s.fit.center, &u.center_cov,
                   s.noise_var);
        st = sfit_refine_fit(g_pf, (size_t)sc->n, NULL, &rf);
        cov_tally_add(&acc[EST_REFINED], st, rf.flags, rf.trust_ratio, &rf.center,
                      &rf.center_cov, k_c);
        dump_trial(EST_REFINED, st, rf.flags, rf.trust_ratio, &rf.center, &rf.center_cov,
                   rf.noise_var);
    }
    return sig * sig / (lmin + sig * sig); /* true trust ratio: sigma^2 / lambda_min(C) */
}

static const double k_caps[] = {20.0, 30.0, 45.0, 60.0, 90.0, 120.0, 180.0};
static const double k_srs[] = {0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.4};
static const int k_ns[] = {10, 30, 100, 1000, 10000};
/* Trials per scenario, by N: a row that keeps 25 % of 10^4 fits has a
 * binomial SE of 0.9 %; with 1000 trials 1.6 %, at the level of the 92-98 %
 * band's margins (docs/coverage.md, "How sharp the table's verdict is").
 * The N = 10^4 rows keep 1000 trials (their cost). */
static const int k_trials[] = {10000, 10000, 10000, 3000, 1000};

#define NCAPS (sizeof k_caps / sizeof k_caps[0])
#define NSRS (sizeof k_srs / sizeof k_srs[0])
#define NNS (sizeof k_ns / sizeof k_ns[0])

int main(int argc, char **argv)
{
    FILE *f, *csv;
    size_t ci, si, ni;
    int e, idx = 0, quick = (argc > 2 && strcmp(argv[2], "quick") == 0);
    long rows = 0, outside = 0, trials_total = 0, few_rows = 0, few_n = 0, few_cov = 0;
    double flmax = 0.0, qmin = 1e30, qmax = 0.0;
    double rmin[EST_COUNT], rmax[EST_COUNT], mmin[EST_COUNT], mmax[EST_COUNT];
    const long assess = quick ? 20 : 200; /* unflagged results for an assessed row */
    for (e = 0; e < EST_COUNT; e++) {
        rmin[e] = mmin[e] = 1e30;
        rmax[e] = mmax[e] = 0.0;
    }
    if (argc > 3 && strcmp(argv[2], "dump") == 0) {
        /* OUTFILE dump SCENFILE: per-trial records of the listed scenarios */
        FILE *in = fopen(argv[3], "r");
        scen_t sc;
        cov_tally_t acc[EST_COUNT];
        long seed;
        g_dump = (in != NULL) ? fopen(argv[1], "w") : NULL;
        if (g_dump == NULL) {
            perror((in == NULL) ? argv[3] : argv[1]);
            return 1;
        }
        fprintf(g_dump, "# scen est status flags trust d2 trace ex ey ez noise_var\n");
        while (fscanf(in, "%lf %lf %d %d %ld", &sc.theta_deg, &sc.sr, &sc.n, &sc.trials,
                      &seed) == 5) {
            double tt;
            if (sc.n < 1 || sc.n > NMAX || sc.trials < 1) {
                fprintf(stderr, "coverage: N in 1..%d, TRIALS >= 1\n", NMAX);
                return 2;
            }
            tt = run_scen(&sc, (uint64_t)seed, acc);
            fprintf(g_dump, "# scenario %d cap %.0f sigma_r %.6g n %d trials %d true_trust %.6g\n",
                    g_dump_idx, sc.theta_deg, sc.sr, sc.n, sc.trials, tt);
            g_dump_idx++;
        }
        fclose(in);
        return (fclose(g_dump) == 0) ? 0 : 1;
    }
    if (argc > 6 && (strcmp(argv[2], "one") == 0 || strcmp(argv[2], "trust") == 0)) {
        /* one scenario: OUTDIR one CAP SIGMA/R N TRIALS [SEED], or with
         * trust the true trust ratio instead of sigma / r */
        scen_t sc;
        cov_tally_t acc[EST_COUNT];
        double tt;
        sc.theta_deg = atof(argv[3]);
        sc.sr = atof(argv[4]);
        sc.n = atoi(argv[5]);
        sc.trials = atoi(argv[6]);
        if (sc.n < 1 || sc.n > NMAX || sc.trials < 1) {
            fprintf(stderr, "coverage: N in 1..%d, TRIALS >= 1\n", NMAX);
            return 2;
        }
        if (strcmp(argv[2], "trust") == 0) {
            /* sigma^2 / (lambda0 + sigma^2) = T: sigma^2 = lambda0 T / (1 - T) */
            double lmin, lmax;
            if (!(sc.sr > 0.0 && sc.sr < 1.0)) {
                fprintf(stderr, "coverage: TRUST in (0, 1)\n");
                return 2;
            }
            ref_cap_eigs_numeric(sc.theta_deg * TU_PI / 180.0, K_R, &lmin, &lmax);
            sc.sr = sqrt(lmin * sc.sr / (1.0 - sc.sr)) / K_R;
        }
        tt = run_scen(&sc, (argc > 7) ? (uint64_t)atol(argv[7]) : 1u, acc);
        for (e = 0; e < EST_COUNT; e++) {
            const long u = cov_tally_unflagged(&acc[e]);
            printf("cap %.0f sigma/r %.3f N %d trust %.3f %-8s unflagged %ld coverage %.4f "
                   "flagged %ld failed %ld cov/MC %.3f cov/MSE %.3f\n",
                   sc.theta_deg, sc.sr, sc.n, tt, k_est_name[e], u,
                   (u > 0) ? (double)acc[e].covered / (double)u : -1.0, acc[e].flagged,
                   acc[e].failed, cov_tally_ratio(&acc[e]), cov_tally_mse_ratio(&acc[e]));
        }
        return 0;
    }
    if (argc < 2) {
        fprintf(stderr, "usage: sfit_mc_coverage OUTDIR [quick | one CAP SIGMA/R N TRIALS [SEED]]\n");
        return 2;
    }
    f = mc_out_open(argv[1], "coverage_table.md");
    csv = (f != NULL) ? mc_out_open(argv[1], "coverage.csv") : NULL;
    if (f == NULL || csv == NULL) {
        return 1;
    }
    fprintf(csv, "cap,sigma_r,n,trials,true_trust,estimator,mean_trust,ok,flagged,failed,"
                 "unflagged,coverage,cov_ratio,mse_ratio\n");
    fprintf(f, "Coverage of the unflagged OK results (fraction whose true centre is inside "
               "the reported 95 %% ellipsoid), flagged fraction of the OK results, and for "
               "the self-calibrated fit the reported / Monte Carlo covariance trace. A "
               "coverage in parentheses comes from fewer than %ld unflagged results (binomial "
               "SE above 1.5 %%) and is not assessed; its count follows.\n\n"
               "| cap | sigma/r | N | true trust | ugdk cov | flag | selfcal cov | flag | "
               "cov/MC | refined cov | flag | fails |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|\n",
            assess);
    for (ci = 0; ci < NCAPS; ci++) {
        for (si = 0; si < NSRS; si++) {
            for (ni = 0; ni < NNS; ni++) {
                scen_t sc;
                cov_tally_t acc[EST_COUNT];
                double tt;
                long fails = 0;
                sc.theta_deg = k_caps[ci];
                sc.sr = k_srs[si];
                sc.n = k_ns[ni];
                sc.trials = quick ? k_trials[ni] / 10 : k_trials[ni];
                tt = run_scen(&sc, 1000u + (uint64_t)idx++, acc);
                fprintf(f, "| %.0f | %.3f | %d | %.3g |", sc.theta_deg, sc.sr, sc.n, tt);
                for (e = 0; e < EST_COUNT; e++) {
                    const long u = cov_tally_unflagged(&acc[e]);
                    const double cv = (u > 0) ? (double)acc[e].covered / (double)u : -1.0;
                    const double fl =
                        (acc[e].ok > 0) ? (double)acc[e].flagged / (double)acc[e].ok : 0.0;
                    fprintf(csv, "%.0f,%.3f,%d,%d,%.5g,%s,%.5g,%ld,%ld,%ld,%ld,%.4f,%.4f,%.4f\n",
                            sc.theta_deg, sc.sr, sc.n, sc.trials, tt, k_est_name[e],
                            (acc[e].ok > 0) ? acc[e].trust / (double)acc[e].ok : 0.0,
                            acc[e].ok, acc[e].flagged, acc[e].failed, u, cv,
                            cov_tally_ratio(&acc[e]), cov_tally_mse_ratio(&acc[e]));
                    if (u >= assess) {
                        fprintf(f, " %.3f |", cv);
                        rows++;
                        if (cv < 0.92 || cv > 0.98) {
                            outside++;
                            fprintf(stderr, "coverage: outside 92-98 %%: cap %.0f sigma/r %.3f "
                                            "N %d %s %.3f (%ld unflagged)\n",
                                    sc.theta_deg, sc.sr, sc.n, k_est_name[e], cv, u);
                        }
                        if (e == EST_SELFCAL) {
                            const double q = cov_tally_ratio(&acc[e]);
                            qmin = (q < qmin) ? q : qmin;
                            qmax = (q > qmax) ? q : qmax;
                        }
                        {
                            const double q = cov_tally_ratio(&acc[e]);
                            const double m = cov_tally_mse_ratio(&acc[e]);
                            rmin[e] = (q < rmin[e]) ? q : rmin[e];
                            rmax[e] = (q > rmax[e]) ? q : rmax[e];
                            mmin[e] = (m < mmin[e]) ? m : mmin[e];
                            mmax[e] = (m > mmax[e]) ? m : mmax[e];
                        }
                    } else if (u > 0) {
                        fprintf(f, " (%.2f, %ld) |", cv, u);
                        few_rows++;
                        few_n += u;
                        few_cov += acc[e].covered;
                    } else {
                        fprintf(f, " - |");
                    }
                    fprintf(f, " %.3f |", fl);
                    if (e == EST_SELFCAL) {
                        if (u >= assess) {
                            fprintf(f, " %.3f |", cov_tally_ratio(&acc[e]));
                        } else {
                            fprintf(f, " - |");
                        }
                    }
                    if (tt <= 0.1 && sc.n >= 100 && fl > flmax) {
                        flmax = fl;
                    }
                    fails += acc[e].failed;
                }
                fprintf(f, " %ld |\n", fails);
                trials_total += sc.trials;
                fflush(f);
                fflush(csv);
            }
        }
        fprintf(stderr, "coverage: cap %.0f done\n", k_caps[ci]);
    }
    fprintf(f, "\n%d scenarios x 3 estimators, %d trials each at N <= 100, %d at N = 1000, "
               "%d at N = 10000 (%ld fits in all).\n"
               "- Assessed (>= %ld unflagged results): %ld (scenario, estimator) rows, %ld of "
               "them outside 92-98 %%.\n"
               "- Not assessed (1-%ld unflagged results): %ld rows, %ld results, pooled "
               "coverage %.3f.\n"
               "- Largest flagged fraction where the true trust ratio <= 0.1 and N >= 100: "
               "%.3f.\n"
               "- Self-calibrated reported / MC covariance trace on the assessed rows: "
               "%.3f-%.3f.\n",
            idx, k_trials[2] / (quick ? 10 : 1), k_trials[3] / (quick ? 10 : 1),
            k_trials[4] / (quick ? 10 : 1), 3 * trials_total, assess, rows, outside, assess - 1,
            few_rows, few_n, (few_n > 0) ? (double)few_cov / (double)few_n : 0.0, flmax, qmin,
            qmax);
    fprintf(f, "- Reported trace / MC covariance trace (CSV cov_ratio) and / MC mean squared "
               "error about the true centre (mse_ratio), assessed rows:");
    for (e = 0; e < EST_COUNT; e++) {
        fprintf(f, "%s %s %.3f-%.3f and %.3f-%.3f", (e > 0) ? ";" : "", k_est_name[e],
                rmin[e], rmax[e], mmin[e], mmax[e]);
    }
    fprintf(f, ".\n");
    fclose(f);
    fclose(csv);
    return 0;
}
