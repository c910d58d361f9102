/* SPDX-License-Identifier: MIT */
/**
 * @file test_ref_selfcheck.c
 * @brief Plain-C self-check of the double-precision reference (no cmocka).
 *
 * Checks the reference against exact synthetic truths, against independent
 * formulations of the same estimators, against the chapter's closed forms
 * and by fixed-seed Monte Carlo. With a data directory argument
 * (tests/data) it also checks the published reference-fit table of
 * tests/data/README.md and prints the fits of every file.
 *
 * Build: gcc -std=c99 <warnings> -Werror -I tests tests/ref/sfit_ref.c
 *        tests/ref/test_ref_selfcheck.c -lm -o ref_selfcheck
 * Run:   ./ref_selfcheck [tests/data]      exit status 0 = all passed.
 */
#include "ref/sfit_ref.h"
#include "test_util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static int g_fail, g_checks;

#define CHECK(cond, ...)                                                      \
    do {                                                                      \
        ++g_checks;                                                           \
        if (!(cond)) {                                                        \
            ++g_fail;                                                         \
            printf("FAIL %s:%d: ", __FILE__, __LINE__);                       \
            printf(__VA_ARGS__);                                              \
            printf("\n");                                                     \
        }                                                                     \
    } while (0)

#define NMAX 20000
static double g_x[NMAX][3];
static double g_y[NMAX][3];

static const double C_FAR[3] = {2700.0, -1500.0, 900.0};
static const double R_FAR = 100.0;

/* Gaussian elimination with partial pivoting, double, n <= 8 (local copy:
 * the reference's solver is private and this one cross-checks it). */
static int sc_solve(int n, double *a, double *b)
{
    int i, j, k;
    for (k = 0; k < n; ++k) {
        int piv = k;
        for (i = k + 1; i < n; ++i) {
            if (fabs(a[i * n + k]) > fabs(a[piv * n + k])) {
                piv = i;
            }
        }
        if (a[piv * n + k] == 0.0) {
            return -1;
        }
        for (j = 0; j < n; ++j) {
            double t = a[k * n + j];
            a[k * n + j] = a[piv * n + j];
            a[piv * n + j] = t;
        }
        {
            double t = b[k];
            b[k] = b[piv];
            b[piv] = t;
        }
        for (i = k + 1; i < n; ++i) {
            double f = a[i * n + k] / a[k * n + k];
            for (j = k; j < n; ++j) {
                a[i * n + j] -= f * a[k * n + j];
            }
            b[i] -= f * b[k];
        }
    }
    for (k = n - 1; k >= 0; --k) {
        double s = b[k];
        for (j = k + 1; j < n; ++j) {
            s -= a[k * n + j] * b[j];
        }
        b[k] = s / a[k * n + k];
    }
    return 0;
}

/* ---------------------------------------------------------------------- */
static void test_rng(void)
{
    tu_rng_t g;
    double s = 0.0, s2 = 0.0;
    int i, n = 1000000, inrange = 1;
    tu_rng_seed(&g, 0);
    CHECK(tu_rng_u64(&g) == UINT64_C(0xE220A8397B1DCDAF),
          "splitmix64 first output for seed 0");
    tu_rng_seed(&g, 12345);
    for (i = 0; i < n; ++i) {
        double u = tu_rng_uniform(&g), z = tu_rng_gauss(&g);
        inrange &= (u >= 0.0 && u < 1.0);
        s += z;
        s2 += z * z;
    }
    CHECK(inrange, "uniform outside [0,1)");
    CHECK(fabs(s / n) < 5e-3 && fabs(s2 / n - 1.0) < 5e-3,
          "gauss mean %g var %g", s / n, s2 / n);
}

/* ---------------------------------------------------------------------- */
static void check_eig(const double a[3][3], const char *what)
{
    double w[3], v[3][3], nrm = 0.0, rec = 0.0, orth = 0.0;
    int i, j, k;
    ref_sym3_eig(a, w, v);
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            double s = 0.0, o = 0.0;
            for (k = 0; k < 3; ++k) {
                s += v[i][k] * w[k] * v[j][k];
                o += v[k][i] * v[k][j];
            }
            nrm += a[i][j] * a[i][j];
            rec = fmax(rec, fabs(s - a[i][j]));
            orth = fmax(orth, fabs(o - (i == j ? 1.0 : 0.0)));
        }
    }
    nrm = sqrt(nrm);
    CHECK(rec <= 1e-14 * nrm + 1e-300, "%s: |VDV^T - A| = %g (|A| = %g)", what,
          rec, nrm);
    CHECK(orth <= 1e-14, "%s: |V^T V - I| = %g", what, orth);
    CHECK(w[0] <= w[1] && w[1] <= w[2], "%s: not ascending", what);
}

static void test_eig(void)
{
    tu_rng_t g;
    double a[3][3], q[3][3], d[3] = {1e-10, 1.0, 1e10};
    int t, i, j, k;
    tu_rng_seed(&g, 1);
    for (t = 0; t < 2000; ++t) {
        for (i = 0; i < 3; ++i) {
            for (j = i; j < 3; ++j) {
                a[i][j] = a[j][i] = tu_rng_gauss(&g) * pow(10.0, t % 7 - 3);
            }
        }
        check_eig(REF_C3(a), "random");
    }
    memset(a, 0, sizeof a);
    check_eig(REF_C3(a), "zero");
    for (i = 0; i < 3; ++i) {
        a[i][i] = 2.0;
    }
    check_eig(REF_C3(a), "2I");
    {
        double u[3] = {1.0, -2.0, 0.5};
        for (i = 0; i < 3; ++i) {
            for (j = 0; j < 3; ++j) {
                a[i][j] = u[i] * u[j];
            }
        }
        check_eig(REF_C3(a), "rank1");
    }
    /* graded, rotated: Q diag(d) Q^T with Q from a frame */
    {
        double ax[3] = {0.3, -0.5, 0.8}, n[3], e1[3], e2[3], w[3], v[3][3];
        tu_frame(ax, n, e1, e2);
        for (i = 0; i < 3; ++i) {
            q[i][0] = e1[i];
            q[i][1] = e2[i];
            q[i][2] = n[i];
        }
        for (i = 0; i < 3; ++i) {
            for (j = 0; j < 3; ++j) {
                a[i][j] = 0.0;
                for (k = 0; k < 3; ++k) {
                    a[i][j] += q[i][k] * d[k] * q[j][k];
                }
            }
        }
        check_eig(REF_C3(a), "graded");
        ref_sym3_eig(REF_C3(a), w, v);
        CHECK(fabs(w[2] - 1e10) < 1e-5 && fabs(w[1] - 1.0) < 1e-5,
              "graded eigenvalues %g %g %g", w[0], w[1], w[2]);
    }
}

/* ---------------------------------------------------------------------- */
static void test_moments(void)
{
    tu_rng_t g;
    double ax[3] = {0.2, 0.9, -0.3}, z[3] = {0.0, 0.0, 0.0};
    double m1[3], C1[3][3], S1[3], m2[3], C2[3][3], S2[3];
    double dc = 0.0, ds = 0.0, cn = 0.0, sn = 0.0, dm = 0.0;
    size_t i, n = 10000;
    int j, k;
    tu_rng_seed(&g, 2);
    for (i = 0; i < n; ++i) {
        tu_sample_cap(&g, z, R_FAR, ax, 0.5, 1.0, g_y[i]);
        for (j = 0; j < 3; ++j) {
            g_x[i][j] = g_y[i][j] + C_FAR[j];
        }
    }
    CHECK(ref_moments(REF_C3(g_x), n, m1, C1, S1) == 0, "mom");
    CHECK(ref_moments(REF_C3(g_y), n, m2, C2, S2) == 0, "mom");
    for (j = 0; j < 3; ++j) {
        dm = fmax(dm, fabs(m1[j] - C_FAR[j] - m2[j]));
        ds = fmax(ds, fabs(S1[j] - S2[j]));
        sn = fmax(sn, fabs(S2[j]));
        for (k = 0; k < 3; ++k) {
            dc = fmax(dc, fabs(C1[j][k] - C2[j][k]));
            cn = fmax(cn, fabs(C2[j][k]));
        }
    }
    /* The data differ by the rounding of y + C_FAR (~2e-13 each). */
    CHECK(dm < 1e-12 && dc < 1e-12 * cn && ds < 1e-11 * sn,
          "translation invariance: dm %g dC %g dS %g", dm, dc / cn, ds / sn);
    CHECK(ref_moments(REF_C3(g_x), 1, m1, C1, S1) != 0, "n=1");
}

/* ---------------------------------------------------------------------- */
static void test_exact_sphere(void)
{
    static const double th[] = {TU_PI, 2.0, 1.0, 0.5, 0.2};
    tu_rng_t g;
    double ax[3] = {-0.4, 0.3, 0.85};
    size_t n = 500, i;
    int t;
    tu_rng_seed(&g, 3);
    for (t = 0; t < 5; ++t) {
        ref_fit_t f, fu;
        double cd[3], rd, cg[3], rg, ci[3], cov0[6] = {0, 0, 0, 0, 0, 0};
        int it = 0, j;
        for (i = 0; i < n; ++i) {
            tu_sample_cap(&g, C_FAR, R_FAR, ax, th[t], 0.0, g_x[i]);
        }
        CHECK(ref_fit_sphere(REF_C3(g_x), n, NULL, &f) == 0,
              "fit");
        CHECK(tu_dist3(f.center, C_FAR) <= 1e-9 * R_FAR &&
                  fabs(f.radius - R_FAR) <= 1e-9 * R_FAR,
              "exact sphere theta %g: centre err %g r err %g", th[t],
              tu_dist3(f.center, C_FAR), f.radius - R_FAR);
        CHECK(f.planar == 0 && f.trust_ratio == 0.0, "flags");
        if (th[t] < 3.0) {
            double an = tu_norm3(ax);
            CHECK(fabs(tu_dot3(f.axis, ax)) > 0.99 * an,
                  "cap axis theta %g: %g", th[t], tu_dot3(f.axis, ax) / an);
        }
        CHECK(ref_fit_sphere(REF_C3(g_x), n, cov0, &fu) == 0 &&
                  memcmp(fu.center, f.center, sizeof f.center) == 0,
              "UGDK with Sigma = 0 is GDKE");
        CHECK(ref_kasa_sphere_direct(REF_C3(g_x), n, cd, &rd) ==
                      0 &&
                  tu_dist3(cd, C_FAR) <= 1e-9 * R_FAR &&
                  fabs(rd - R_FAR) <= 1e-9 * R_FAR,
              "exact direct Kasa theta %g: %g", th[t], tu_dist3(cd, C_FAR));
        for (j = 0; j < 3; ++j) {
            ci[j] = C_FAR[j] + (j == 1 ? -6.0 : 4.0);
        }
        CHECK(ref_fit_geometric(REF_C3(g_x), n, ci, R_FAR + 7.0,
                                cg, &rg, &it) == 0 &&
                  tu_dist3(cg, C_FAR) <= 1e-9 * R_FAR &&
                  fabs(rg - R_FAR) <= 1e-9 * R_FAR,
              "exact geometric theta %g: %g (%d iters)", th[t],
              tu_dist3(cg, C_FAR), it);
    }
    CHECK(ref_fit_sphere(REF_C3(g_x), 3, NULL, NULL) != 0, "n<4");
}

/* ---------------------------------------------------------------------- */
static void test_exact_circle(void)
{
    static const double th[] = {TU_PI, 1.0, 0.3};
    tu_rng_t g;
    double ax[3] = {0.5, -0.2, 0.7}, rd[3] = {1.0, 1.0, 0.0};
    size_t n = 300, i;
    int t;
    tu_rng_seed(&g, 4);
    for (t = 0; t < 3; ++t) {
        ref_fit_t f, fs;
        double an = tu_norm3(ax), big = 0.0;
        int j;
        for (i = 0; i < n; ++i) {
            tu_sample_arc(&g, C_FAR, R_FAR, ax, rd, th[t], 0.0, g_x[i]);
        }
        CHECK(ref_fit_circle(REF_C3(g_x), n, NULL, &f) == 0,
              "circle fit");
        CHECK(tu_dist3(f.center, C_FAR) <= 1e-9 * R_FAR &&
                  fabs(f.radius - R_FAR) <= 1e-9 * R_FAR,
              "exact circle theta %g: centre err %g r err %g", th[t],
              tu_dist3(f.center, C_FAR), f.radius - R_FAR);
        CHECK(fabs(fabs(tu_dot3(f.axis, ax)) - an) < 1e-12 * an,
              "circle axis");
        for (j = 0; j < 3; ++j) {
            if (fabs(f.axis[j]) > fabs(big)) {
                big = f.axis[j];
            }
        }
        CHECK(big > 0.0 && fabs(tu_norm3(f.axis) - 1.0) < 1e-15 &&
                  f.planar == 1,
              "axis sign/norm");
        CHECK(ref_fit_sphere(REF_C3(g_x), n, NULL, &fs) != 0,
              "sphere fit must refuse planar data");
    }
}

/* ---------------------------------------------------------------------- */
/* Gander, Golub & Strebel (1994), BIT 34, example points. The Kasa fit
 * (normalisation: coefficient of x^2+y^2 equal to 1) is, in exact rational
 * arithmetic, c = (773/163, 5001/1304), r^2 = 28706289/1700416, i.e.
 * (4.742331, 3.835123), r = 4.108762. NOTE: the "algebraic fit" printed by
 * GGS, (5.3794, 7.2532), r = 3.0370, is NOT Kasa: it minimises the same
 * algebraic residual under the constraint |(a, b1, b2, c)| = 1 (smallest
 * singular vector); do not use it as the oracle for GDKE/Kasa. Their
 * geometric fit, (4.7398, 2.9835), r = 4.7142, is checked below. */
static void test_ggs(void)
{
    static const double p[6][2] = {{1, 7}, {2, 6}, {5, 8},
                                   {7, 7}, {9, 5}, {3, 7}};
    double c2[2], r2, n[3], e1[3], e2[3], ax[3] = {1.0, 2.0, -0.5};
    double cexp[3], cg[3], rg;
    ref_fit_t f;
    int i, j;
    CHECK(ref_kasa_circle_2d(p, 6, c2, &r2) == 0, "kasa 2d");
    CHECK(fabs(c2[0] - 773.0 / 163.0) < 1e-14 &&
              fabs(c2[1] - 5001.0 / 1304.0) < 1e-14 &&
              fabs(r2 - sqrt(28706289.0 / 1700416.0)) < 1e-14,
          "GGS Kasa: (%.16g, %.16g) r %.16g", c2[0], c2[1], r2);
    for (i = 0; i < 6; ++i) {
        g_x[i][0] = p[i][0];
        g_x[i][1] = p[i][1];
        g_x[i][2] = 0.0;
    }
    CHECK(ref_fit_circle(REF_C3(g_x), 6, NULL, &f) == 0, "c");
    CHECK(fabs(f.center[0] - c2[0]) < 1e-12 && fabs(f.center[1] - c2[1]) <
              1e-12 && fabs(f.center[2]) < 1e-12 && fabs(f.radius - r2) <
              1e-12,
          "GGS: fit_circle (%.15g %.15g %.3g) %.15g vs 2-D %.15g %.15g %.15g",
          f.center[0], f.center[1], f.center[2], f.radius, c2[0], c2[1], r2);
    CHECK(fabs(f.axis[2] - 1.0) < 1e-15, "GGS axis");
    /* The same points in a tilted plane far from the origin. */
    tu_frame(ax, n, e1, e2);
    for (i = 0; i < 6; ++i) {
        for (j = 0; j < 3; ++j) {
            g_x[i][j] = C_FAR[j] + p[i][0] * e1[j] + p[i][1] * e2[j];
        }
    }
    for (j = 0; j < 3; ++j) {
        cexp[j] = C_FAR[j] + c2[0] * e1[j] + c2[1] * e2[j];
    }
    CHECK(ref_fit_circle(REF_C3(g_x), 6, NULL, &f) == 0 &&
              tu_dist3(f.center, cexp) < 1e-9 && fabs(f.radius - r2) < 1e-9,
          "GGS tilted: %g", tu_dist3(f.center, cexp));
    /* GGS geometric circle: (4.7398, 2.9835), r = 4.7142; as a sphere of
     * the planar points embedded in 3-D, the geometric fit (started in the
     * plane) stays in the plane by symmetry. */
    for (i = 0; i < 6; ++i) {
        g_x[i][0] = p[i][0];
        g_x[i][1] = p[i][1];
        g_x[i][2] = 0.0;
    }
    {
        double ci[3];
        ci[0] = c2[0];
        ci[1] = c2[1];
        ci[2] = 0.0;
        CHECK(ref_fit_geometric(REF_C3(g_x), 6, ci, r2, cg,
                                &rg, NULL) == 0 &&
                  fabs(cg[0] - 4.7398) < 6e-5 && fabs(cg[1] - 2.9835) < 6e-5 &&
                  fabs(rg - 4.7142) < 6e-5,
              "GGS geometric: (%.5f %.5f %.2g) r %.5f", cg[0], cg[1], cg[2],
              rg);
    }
}

/* ---------------------------------------------------------------------- */
static void test_kasa_equiv(void)
{
    static const double th[] = {TU_PI, 0.7, 0.3};
    tu_rng_t g;
    double ax[3] = {0.1, 0.2, 1.0};
    size_t n = 1000, i;
    int t;
    tu_rng_seed(&g, 5);
    for (t = 0; t < 3; ++t) {
        ref_fit_t f;
        double cd[3], rd;
        for (i = 0; i < n; ++i) {
            tu_sample_cap(&g, C_FAR, R_FAR, ax, th[t], 1.0, g_x[i]);
        }
        CHECK(ref_fit_sphere(REF_C3(g_x), n, NULL, &f) == 0 &&
                  ref_kasa_sphere_direct(REF_C3(g_x), n, cd,
                                         &rd) == 0,
              "fits");
        CHECK(tu_dist3(cd, f.center) <= 1e-9 * R_FAR &&
                  fabs(rd - f.radius) <= 1e-9 * R_FAR,
              "GDKE vs direct Kasa theta %g: %g / %g", th[t],
              tu_dist3(cd, f.center), rd - f.radius);
    }
}

/* ---------------------------------------------------------------------- */
static void test_ugdk(void)
{
    tu_rng_t g;
    double ax[3] = {0.0, 0.6, 0.8}, z3[3] = {0, 0, 0};
    double cov[6] = {0.9, 0.4, 1.6, 0.2, -0.3, 0.1};
    double ci[6] = {1.0, 1.0, 1.0, 0.0, 0.0, 0.0};
    size_t n = 2000, i;
    ref_fit_t f, fi, fc;
    tu_rng_seed(&g, 6);
    for (i = 0; i < n; ++i) {
        tu_sample_cap(&g, C_FAR, R_FAR, ax, 0.6, 1.0, g_x[i]);
    }
    /* isotropic: rho = sigma^2 / lambda_min(C - sigma^2 I) */
    CHECK(ref_fit_sphere(REF_C3(g_x), n, ci, &fi) == 0, "ugdk");
    CHECK(fabs(fi.trust_ratio - 1.0 / (fi.eig[0] - 1.0)) <
              1e-12 * fi.trust_ratio,
          "isotropic trust %g vs %g", fi.trust_ratio, 1.0 / (fi.eig[0] - 1.0));
    /* anisotropic: power iteration on C'^-1 Sigma */
    CHECK(ref_fit_sphere(REF_C3(g_x), n, cov, &f) == 0, "ugdk");
    {
        double m[3], C[3][3], S[3], a[9], M[3][3], sig[3][3], v[3] = {1, 1, 1};
        double lam = 0.0;
        int j, k, it;
        sig[0][0] = cov[0];
        sig[1][1] = cov[1];
        sig[2][2] = cov[2];
        sig[0][1] = sig[1][0] = cov[3];
        sig[0][2] = sig[2][0] = cov[4];
        sig[1][2] = sig[2][1] = cov[5];
        (void)ref_moments(REF_C3(g_x), n, m, C, S);
        for (k = 0; k < 3; ++k) {
            double b[3];
            for (j = 0; j < 9; ++j) {
                a[j] = C[j / 3][j % 3] - sig[j / 3][j % 3];
            }
            for (j = 0; j < 3; ++j) {
                b[j] = sig[j][k];
            }
            (void)sc_solve(3, a, b);
            for (j = 0; j < 3; ++j) {
                M[j][k] = b[j];
            }
        }
        for (it = 0; it < 3000; ++it) {
            double u[3], nu;
            for (j = 0; j < 3; ++j) {
                u[j] = M[j][0] * v[0] + M[j][1] * v[1] + M[j][2] * v[2];
            }
            nu = tu_norm3(u);
            lam = nu / tu_norm3(v);
            for (j = 0; j < 3; ++j) {
                v[j] = u[j] / nu;
            }
        }
        CHECK(fabs(f.trust_ratio - lam) < 1e-9 * lam,
              "anisotropic trust %.12g vs power iteration %.12g",
              f.trust_ratio, lam);
        CHECK(ref_fit_circle(REF_C3(g_x), n, ci, &fc) == 0, "c");
    }
    /* Not positive definite: Sigma larger than the spread. */
    {
        double huge[6] = {1e4, 1e4, 1e4, 0, 0, 0};
        CHECK(ref_fit_sphere(REF_C3(g_x), n, huge, &f) != 0,
              "C' not PD must fail");
    }
    /* Bias: GDKE on a cap is biased along the axis, UGDK removes it. */
    {
        double bg = 0.0, bu = 0.0, su = 0.0, an = tu_norm3(ax);
        int trial, T = 200;
        for (trial = 0; trial < T; ++trial) {
            ref_fit_t a1, a2;
            for (i = 0; i < n; ++i) {
                tu_sample_cap(&g, z3, R_FAR, ax, 0.6, 1.0, g_x[i]);
            }
            (void)ref_fit_sphere(REF_C3(g_x), n, NULL, &a1);
            (void)ref_fit_sphere(REF_C3(g_x), n, ci, &a2);
            bg += tu_dot3(a1.center, ax) / an;
            bu += tu_dot3(a2.center, ax) / an;
            su += pow(tu_dot3(a2.center, ax) / an, 2);
        }
        bg /= T;
        bu /= T;
        su = sqrt((su / T - bu * bu) / T);
        printf("  cap 0.6 rad, sigma 1, r 100, N 2000: axial bias GDKE %.3f, "
               "UGDK %.3f (SE %.3f); rho(C0^-1 Sigma) ~ %.3f\n",
               bg, bu, su, fi.trust_ratio);
        CHECK(fabs(bu) < 4.0 * su + 0.02 && fabs(bg) > 20.0 * su,
              "UGDK bias %g (SE %g) GDKE %g", bu, su, bg);
    }
}

/* ---------------------------------------------------------------------- */
/* Multi-marker: exact data, and the weighted form against a direct joint
 * linear least squares in (c, k_1..k_M). */
static void joint_ls(const double *const *xs, const size_t *ns, int m,
                     double c[3], double *radii)
{
    double a[64], b[8], o[3];
    int p, i, j, k, nu = 3 + m;
    size_t q;
    memset(a, 0, sizeof a);
    memset(b, 0, sizeof b);
    memcpy(o, xs[0], sizeof o);
    for (p = 0; p < m; ++p) {
        for (q = 0; q < ns[p]; ++q) {
            double row[8], y[3], z;
            for (i = 0; i < 3; ++i) {
                y[i] = xs[p][3 * q + (size_t)i] - o[i];
            }
            z = tu_dot3(y, y);
            memset(row, 0, sizeof row);
            for (i = 0; i < 3; ++i) {
                row[i] = 2.0 * y[i];
            }
            row[3 + p] = 1.0;
            for (j = 0; j < nu; ++j) {
                b[j] += row[j] * z;
                for (k = 0; k < nu; ++k) {
                    a[j * nu + k] += row[j] * row[k];
                }
            }
        }
    }
    (void)sc_solve(nu, a, b);
    for (p = 0; p < m; ++p) {
        radii[p] = sqrt(b[3 + p] + tu_dot3(b, b));
    }
    for (i = 0; i < 3; ++i) {
        c[i] = o[i] + b[i];
    }
}

static void test_multi(void)
{
    static double xa[1500][3], xb[900][3], xc[600][3];
    const double *xs[3];
    size_t ns[3] = {1500, 900, 600};
    double r0[3] = {80.0, 120.0, 200.0}, ax[3][3] = {{0, 0, 1},
                                                     {0.3, 0, 1},
                                                     {-0.2, 0.4, 1}};
    double c[3], cw[3], cj[3], rr[3], rw[3], rj[3];
    double cov0[6] = {0, 0, 0, 0, 0, 0}, covi[6] = {0.25, 0.25, 0.25, 0, 0,
                                                    0};
    tu_rng_t g;
    size_t i;
    int p, round;
    double (*arr[3])[3];
    arr[0] = xa;
    arr[1] = xb;
    arr[2] = xc;
    tu_rng_seed(&g, 7);
    for (p = 0; p < 3; ++p) {
        xs[p] = &arr[p][0][0];
    }
    for (round = 0; round < 2; ++round) {
        double sg = round ? 0.5 : 0.0;
        for (p = 0; p < 3; ++p) {
            for (i = 0; i < ns[p]; ++i) {
                tu_sample_cap(&g, C_FAR, r0[p], ax[p], 0.5, sg, arr[p][i]);
            }
        }
        CHECK(ref_fit_multi(xs, ns, 3, NULL, c, rr) == 0 &&
                  ref_fit_multi_weighted(xs, ns, 3, NULL, cw, rw) == 0,
              "multi");
        if (round == 0) {
            CHECK(tu_dist3(c, C_FAR) < 1e-9 * R_FAR &&
                      tu_dist3(cw, C_FAR) < 1e-9 * R_FAR,
                  "multi exact: %g %g", tu_dist3(c, C_FAR),
                  tu_dist3(cw, C_FAR));
            for (p = 0; p < 3; ++p) {
                CHECK(fabs(rr[p] - r0[p]) < 1e-9 * r0[p] &&
                          fabs(rw[p] - r0[p]) < 1e-9 * r0[p],
                      "multi exact radius %d", p);
            }
        } else {
            joint_ls(xs, ns, 3, cj, rj);
            CHECK(tu_dist3(cw, cj) < 1e-8 * R_FAR,
                  "weighted multi vs joint LS: %g", tu_dist3(cw, cj));
            for (p = 0; p < 3; ++p) {
                CHECK(fabs(rw[p] - rj[p]) < 1e-8 * r0[p], "joint LS r %d", p);
            }
            printf("  unequal n_p, sigma 0.5: eq.220 (unweighted) vs joint LS "
                   "centre differ by %.4f mm\n",
                   tu_dist3(c, cj));
            CHECK(ref_fit_multi(xs, ns, 3, cov0, cj, rj) == 0 &&
                      memcmp(cj, c, sizeof c) == 0,
                  "multi Sigma=0");
            CHECK(ref_fit_multi(xs, ns, 3, covi, cj, rj) == 0 &&
                      ref_fit_multi_weighted(xs, ns, 3, covi, cw, rw) == 0,
                  "unbiased multi");
            /* Equal counts: both forms coincide. */
            {
                size_t ne[3] = {600, 600, 600};
                CHECK(ref_fit_multi(xs, ne, 3, NULL, c, rr) == 0 &&
                          ref_fit_multi_weighted(xs, ne, 3, NULL, cw, rw) ==
                              0 &&
                          tu_dist3(c, cw) < 1e-10 * R_FAR,
                      "equal n_p: %g", tu_dist3(c, cw));
            }
        }
    }
    /* Bias: concentric caps around one axis (markers on one segment),
     * sigma 1: MGDK biased along the axis, unbiased MGDK (eq. 222) not. */
    {
        double bg = 0.0, bu = 0.0, bw = 0.0, su = 0.0, z3[3] = {0, 0, 0};
        double cov1[6] = {1, 1, 1, 0, 0, 0};
        int t, T = 200;
        for (t = 0; t < T; ++t) {
            for (p = 0; p < 3; ++p) {
                for (i = 0; i < ns[p]; ++i) {
                    tu_sample_cap(&g, z3, r0[p], ax[0], 0.5, 1.0, arr[p][i]);
                }
            }
            (void)ref_fit_multi(xs, ns, 3, NULL, c, rr);
            (void)ref_fit_multi(xs, ns, 3, cov1, cj, rj);
            (void)ref_fit_multi_weighted(xs, ns, 3, cov1, cw, rw);
            bg += c[2] / T;
            bu += cj[2] / T;
            bw += cw[2] / T;
            su += cj[2] * cj[2] / T;
        }
        su = sqrt((su - bu * bu) / T);
        printf("  3 concentric caps 0.5 rad, sigma 1: axial bias MGDK %.3f, "
               "unbiased MGDK %.3f (SE %.3f), unbiased weighted %.3f\n",
               bg, bu, su, bw);
        CHECK(fabs(bu) < 4.0 * su + 0.02 && fabs(bw) < 4.0 * su + 0.02 &&
                  fabs(bg) > 20.0 * su,
              "unbiased multi bias %g %g (SE %g), MGDK %g", bu, bw, su, bg);
    }
    /* Single marker: MGDK == GDKE. */
    {
        ref_fit_t f;
        (void)ref_fit_sphere(REF_C3(xa), ns[0], NULL, &f);
        CHECK(ref_fit_multi(xs, ns, 1, NULL, c, rr) == 0 &&
                  tu_dist3(c, f.center) < 1e-10 * R_FAR &&
                  fabs(rr[0] - f.radius) < 1e-10 * R_FAR,
              "M=1");
    }
}

/* ---------------------------------------------------------------------- */
/* eq. 177 / 190 Monte Carlo. */
static void mc_noise(int dim, double r0, double sigma, size_t n, int T,
                     double theta)
{
    tu_rng_t g;
    double ax[3] = {0, 0, 1}, rd[3] = {1, 0, 0}, c0[3] = {10.0, -20.0, 30.0};
    double s = 0.0, s2 = 0.0, mean, var, pv, s2t = sigma * sigma;
    size_t i;
    int t;
    tu_rng_seed(&g, 8);
    for (t = 0; t < T; ++t) {
        double est;
        for (i = 0; i < n; ++i) {
            if (dim == 3) {
                tu_sample_cap(&g, c0, r0, ax, theta, sigma, g_x[i]);
            } else {
                tu_sample_arc(&g, c0, r0, ax, rd, theta, 0.0, g_x[i]);
                g_x[i][0] += sigma * tu_rng_gauss(&g);
                g_x[i][1] += sigma * tu_rng_gauss(&g);
            }
        }
        est = ref_noise_trace(REF_C3(g_x), n, c0, r0) / dim;
        s += est;
        s2 += est * est;
    }
    mean = s / T;
    var = (s2 - s * mean) / (T - 1);
    pv = ref_noise_trace_var(s2t, r0, n, dim);
    printf("  eq.190 D=%d r0=%g sigma=%g N=%zu: mean %.5g (true %.5g), "
           "var %.4g predicted %.4g (ratio %.3f)\n",
           dim, r0, sigma, n, mean, s2t, var, pv, var / pv);
    CHECK(fabs(mean - s2t) < 4.0 * sqrt(pv / T), "noise mean D=%d", dim);
    CHECK(fabs(var / pv - 1.0) < 4.0 * sqrt(2.0 / (T - 1)) + 0.02,
          "noise var D=%d: %g vs %g", dim, var, pv);
}

static void test_noise(void)
{
    mc_noise(3, 100.0, 0.5, 100, 20000, TU_PI);
    mc_noise(3, 1.0, 0.7, 20, 20000, 0.8);
    mc_noise(2, 1.0, 0.7, 20, 20000, 1.5);
    mc_noise(2, 50.0, 2.0, 50, 20000, TU_PI);
}

/* ---------------------------------------------------------------------- */
static void test_geometric_crlb(void)
{
    tu_rng_t g;
    double ax[3] = {1, 1, 1}, crlb[4][4], cg[3], rg, c0[3] = {0, 0, 0};
    size_t n = 20000, i;
    int j, k;
    /* Fibonacci lattice on the full sphere: CRLB ~ s2/N diag(3,3,3,1). */
    for (i = 0; i < n; ++i) {
        double zz = 1.0 - (2.0 * (double)i + 1.0) / (double)n;
        double ph = (double)i * TU_PI * (3.0 - sqrt(5.0));
        double rho = sqrt(1.0 - zz * zz);
        g_x[i][0] = C_FAR[0] + R_FAR * rho * cos(ph);
        g_x[i][1] = C_FAR[1] + R_FAR * rho * sin(ph);
        g_x[i][2] = C_FAR[2] + R_FAR * zz;
    }
    ref_crlb_sphere(REF_C3(g_x), n, C_FAR, R_FAR, 2.0, crlb);
    for (j = 0; j < 4; ++j) {
        for (k = 0; k < 4; ++k) {
            double e = (j != k) ? 0.0 : (j < 3 ? 3.0 : 1.0);
            CHECK(fabs(crlb[j][k] * (double)n / 2.0 - e) < 1e-3,
                  "CRLB full sphere [%d][%d] = %g", j, k,
                  crlb[j][k] * (double)n / 2.0);
        }
    }
    /* MLE (geometric fit) attains the CRLB: Monte Carlo on a cap. */
    {
        static double xt[200][3];
        double sg = 0.5, mean[4] = {0, 0, 0, 0}, m2[4][4], tr_e = 0, tr_b = 0;
        int t, T = 400, fails = 0;
        size_t nn = 200;
        memset(m2, 0, sizeof m2);
        tu_rng_seed(&g, 9);
        for (i = 0; i < nn; ++i) {
            tu_sample_cap(&g, c0, R_FAR, ax, 1.0, 0.0, xt[i]);
        }
        ref_crlb_sphere(REF_C3(xt), nn, c0, R_FAR, sg * sg,
                        crlb);
        for (t = 0; t < T; ++t) {
            ref_fit_t f;
            double e[4];
            for (i = 0; i < nn; ++i) {
                for (j = 0; j < 3; ++j) {
                    g_x[i][j] = xt[i][j] + sg * tu_rng_gauss(&g);
                }
            }
            (void)ref_fit_sphere(REF_C3(g_x), nn, NULL, &f);
            fails += ref_fit_geometric(REF_C3(g_x), nn,
                                       f.center, f.radius, cg, &rg, NULL) != 0;
            e[0] = cg[0];
            e[1] = cg[1];
            e[2] = cg[2];
            e[3] = rg - R_FAR;
            for (j = 0; j < 4; ++j) {
                mean[j] += e[j] / T;
                for (k = 0; k < 4; ++k) {
                    m2[j][k] += e[j] * e[k] / T;
                }
            }
        }
        for (j = 0; j < 4; ++j) {
            tr_e += m2[j][j] - mean[j] * mean[j];
            tr_b += crlb[j][j];
        }
        printf("  geometric MLE on cap 1 rad, N 200, sigma 0.5: trace cov "
               "%.4g vs CRLB %.4g (ratio %.3f)\n",
               tr_e, tr_b, tr_e / tr_b);
        CHECK(fails == 0, "geometric fit failures %d", fails);
        CHECK(tr_e / tr_b > 0.8 && tr_e / tr_b < 1.25, "MLE vs CRLB");
        /* Stationarity of the last fit: J^T e ~ 0. */
        {
            double gr[4] = {0, 0, 0, 0}, en = 0.0;
            for (i = 0; i < nn; ++i) {
                double d[3], dist, res;
                for (j = 0; j < 3; ++j) {
                    d[j] = g_x[i][j] - cg[j];
                }
                dist = tu_norm3(d);
                res = dist - rg;
                en += res * res;
                for (j = 0; j < 3; ++j) {
                    gr[j] -= res * d[j] / dist;
                }
                gr[3] -= res;
            }
            CHECK(fabs(gr[0]) + fabs(gr[1]) + fabs(gr[2]) + fabs(gr[3]) <
                      1e-10 * sqrt(en * (double)nn),
                  "geometric gradient not zero");
        }
    }
}

/* ---------------------------------------------------------------------- */
/* Chapter closed forms (theta = half-angle) vs numerical quadrature. */
static void test_cap_arc(void)
{
    static const double th[] = {0.05, 0.1, 0.3, 0.6, 1.0, 1.5, 2.0, 2.5,
                                3.0,  TU_PI};
    double worst_arc = 0.0, worst_cap = 0.0;
    int t;
    for (t = 0; t < 10; ++t) {
        double a = th[t], r = 2.5, lmin, lmax, emin, emax, s2;
        ref_arc_eigs_numeric(a, r, &lmin, &lmax);
        emin = r * r * (a * (2.0 * a + sin(2.0 * a)) - 4.0 * sin(a) * sin(a)) /
               (4.0 * a * a);                                   /* eq. 203 */
        emax = r * r * (a - cos(a) * sin(a)) / (2.0 * a);       /* eq. 204 */
        worst_arc = fmax(worst_arc, fmax(fabs(lmin / emin - 1.0),
                                         fabs(lmax / emax - 1.0)));
        /* eq. 203 loses digits to cancellation for small theta. */
        CHECK(fabs(lmin / emin - 1.0) < (a < 0.2 ? 1e-7 : 1e-10) &&
                  fabs(lmax / emax - 1.0) < 1e-10,
              "arc theta %g: numeric %.15g %.15g, eq.203/204 %.15g %.15g", a,
              lmin, lmax, emin, emax);
        ref_cap_eigs_numeric(a, r, &lmin, &lmax);
        s2 = sin(0.5 * a) * sin(0.5 * a);
        emin = r * r * s2 * s2 / 3.0;                           /* eq. 210 */
        emax = r * r * (2.0 + cos(a)) * s2 / 3.0;               /* eq. 211 */
        worst_cap = fmax(worst_cap, fmax(fabs(lmin / emin - 1.0),
                                         fabs(lmax / emax - 1.0)));
        CHECK(fabs(lmin / emin - 1.0) < 1e-10 &&
                  fabs(lmax / emax - 1.0) < 1e-10,
              "cap theta %g: numeric %.15g %.15g, eq.210/211 %.15g %.15g", a,
              lmin, lmax, emin, emax);
    }
    printf("  eq.203/204 (arc) worst rel. diff %.2e; eq.210/211 (cap) %.2e\n",
           worst_arc, worst_cap);
}

/* Samplers of test_util.h against the quadrature and their definition. */
static void test_samplers(void)
{
    tu_rng_t g;
    double ax[3] = {0.3, -0.4, 0.5}, rd[3] = {0, 0, 1}, z[3] = {0, 0, 0};
    double m[3], C[3][3], S[3], w[3], v[3][3], lmin, lmax, an = tu_norm3(ax);
    double th = 0.8, worst = 0.0, wr = 0.0;
    size_t n = NMAX, i;
    tu_rng_seed(&g, 10);
    for (i = 0; i < n; ++i) {
        tu_sample_cap(&g, z, 1.0, ax, th, 0.0, g_x[i]);
        wr = fmax(wr, fabs(tu_norm3(g_x[i]) - 1.0));
        worst = fmax(worst, acos(fmin(1.0, tu_dot3(g_x[i], ax) / an)));
    }
    CHECK(wr < 1e-15 && worst <= th + 1e-12, "cap sampler support");
    (void)ref_moments(REF_C3(g_x), n, m, C, S);
    ref_sym3_eig(REF_C3(C), w, v);
    ref_cap_eigs_numeric(th, 1.0, &lmin, &lmax);
    CHECK(fabs(w[0] / lmin - 1.0) < 0.04 && fabs(w[2] / lmax - 1.0) < 0.04 &&
              fabs(tu_dot3(m, ax) / an - cos(th / 2) * cos(th / 2)) < 2e-3,
          "cap sampler moments %g/%g %g/%g", w[0], lmin, w[2], lmax);
    worst = 0.0;
    wr = 0.0;
    for (i = 0; i < n; ++i) {
        tu_sample_arc(&g, z, 1.0, ax, rd, th, 0.0, g_x[i]);
        wr = fmax(wr, fabs(tu_norm3(g_x[i]) - 1.0) +
                          fabs(tu_dot3(g_x[i], ax)) / an);
    }
    (void)ref_moments(REF_C3(g_x), n, m, C, S);
    ref_sym3_eig(REF_C3(C), w, v);
    ref_arc_eigs_numeric(th, 1.0, &lmin, &lmax);
    CHECK(wr < 1e-15 && fabs(w[1] / lmin - 1.0) < 0.04 &&
              fabs(w[2] / lmax - 1.0) < 0.04 && w[0] < 1e-14 * w[2],
          "arc sampler %g %g/%g %g/%g", wr, w[1], lmin, w[2], lmax);
}

/* ---------------------------------------------------------------------- */
/* Real data: README table check and fits of every file. */
typedef struct {
    const char *file;
    double kc[3], kr, gc[3], gr, rms, tol;
} sc_table_t;

static const sc_table_t k_table[] = {
    {"mocap/hip_right/RTHI1.csv", {-66.129, -93.950, 76.081}, 254.519,
     {-67.033, -88.814, 72.238}, 260.495, 1.75, 1e-3},
    {"mocap/hip_right/RLFE.csv", {-67.523, -85.245, 82.423}, 415.261,
     {-70.844, -78.911, 78.887}, 422.521, 2.27, 1e-3},
    {"mocap/hip_right/RGT.csv", {-94.794, -82.267, 147.767}, 44.362,
     {-87.155, -76.349, 126.351}, 65.952, 1.74, 1e-3},
    {"mocap/elbow_right/ForearmR1.csv", {-0.615184, 0.988093, 0.144978},
     0.167362, {-0.614066, 0.989055, 0.144687}, 0.168437, 0.00184, 1e-6},
    {"mag/fusion_example/mag.csv", {4.692, 0.110, -1.806}, 40.351,
     {4.703, 0.205, -0.351}, 41.608, 1.51, 1e-3},
};

static const char *const k_files[] = {
    "mocap/hip_right/RTHI1.csv",       "mocap/hip_right/RTHI2.csv",
    "mocap/hip_right/RTHI3.csv",       "mocap/hip_right/RLFE.csv",
    "mocap/hip_right/RMFE.csv",        "mocap/hip_right/RGT.csv",
    "mocap/knee_right/RATT.csv",       "mocap/knee_right/RLM.csv",
    "mocap/knee_right/RSPH.csv",       "mocap/knee_right/RLEG1.csv",
    "mocap/knee_right/RLEG2.csv",      "mocap/knee_right/RLEG3.csv",
    "mocap/elbow_right/ForearmR1.csv", "mocap/elbow_right/ForearmR2.csv",
    "mocap/elbow_right/ForearmR3.csv", "mag/fusion_example/mag.csv",
};

static double g_d[6][4096][3];

static int load(const char *dir, const char *file, double (*x)[3], size_t *n)
{
    char path[1024];
    int rc;
    snprintf(path, sizeof path, "%s/%s", dir, file);
    rc = tu_load_csv(path, x, 4096, n);
    CHECK(rc == 0 && *n > 10, "load %s rc %d n %zu", path, rc, *n);
    return rc;
}

static void test_data(const char *dir)
{
    size_t t, n, ns[6];
    const double *xs[6];
    double c[3], rr[6];
    int j;

    for (t = 0; t < sizeof k_table / sizeof k_table[0]; ++t) {
        const sc_table_t *e = &k_table[t];
        ref_fit_t f;
        double cg[3], rg, rms = 0.0, tol = e->tol;
        size_t i;
        if (load(dir, e->file, g_d[0], &n)) {
            continue;
        }
        CHECK(ref_fit_sphere(REF_C3(g_d[0]), n, NULL, &f) == 0 &&
                  ref_fit_geometric(REF_C3(g_d[0]), n, f.center,
                                    f.radius, cg, &rg, NULL) == 0,
              "fit %s", e->file);
        for (i = 0; i < n; ++i) {
            double d = tu_dist3(g_d[0][i], cg) - rg;
            rms += d * d;
        }
        rms = sqrt(rms / (double)n);
        for (j = 0; j < 3; ++j) {
            CHECK(fabs(f.center[j] - e->kc[j]) < tol &&
                      fabs(cg[j] - e->gc[j]) < tol,
                  "%s centre[%d] Kasa %.6f (table %.6f) Geo %.6f (table %.6f)",
                  e->file, j, f.center[j], e->kc[j], cg[j], e->gc[j]);
        }
        CHECK(fabs(f.radius - e->kr) < tol && fabs(rg - e->gr) < tol &&
                  fabs(rms - e->rms) < 0.006 * e->rms,
              "%s radius Kasa %.6f (%.6f) Geo %.6f (%.6f) RMS %.5f (%.5f)",
              e->file, f.radius, e->kr, rg, e->gr, rms, e->rms);
    }

    printf("  Kasa (GDKE) sphere fits of every file, double precision:\n");
    for (t = 0; t < sizeof k_files / sizeof k_files[0]; ++t) {
        ref_fit_t f, fc;
        double cd[3], rd;
        if (load(dir, k_files[t], g_d[0], &n)) {
            continue;
        }
        CHECK(ref_fit_sphere(REF_C3(g_d[0]), n, NULL, &f) == 0 &&
                  ref_kasa_sphere_direct(REF_C3(g_d[0]), n, cd,
                                         &rd) == 0 &&
                  tu_dist3(cd, f.center) < 1e-9 * f.radius,
              "%s", k_files[t]);
        (void)ref_fit_circle(REF_C3(g_d[0]), n, NULL, &fc);
        printf("    %-32s n=%4zu  c=(%.6g, %.6g, %.6g) r=%.6g  "
               "eig=(%.4g, %.4g, %.4g)\n"
               "    %-32s circle c=(%.6g, %.6g, %.6g) r=%.6g "
               "axis=(%.4f, %.4f, %.4f)\n",
               k_files[t], n, f.center[0], f.center[1], f.center[2],
               f.radius, f.eig[0], f.eig[1], f.eig[2], "", fc.center[0],
               fc.center[1], fc.center[2], fc.radius, fc.axis[0], fc.axis[1],
               fc.axis[2]);
    }

    /* Multi-marker centres per joint (eq. 220 and joint LS). */
    {
        static const size_t first[3] = {0, 6, 12}, cnt[3] = {6, 6, 3};
        int jn;
        for (jn = 0; jn < 3; ++jn) {
            double cw[3], rw[6];
            size_t p;
            for (p = 0; p < cnt[jn]; ++p) {
                (void)load(dir, k_files[first[jn] + p], g_d[p], &ns[p]);
                xs[p] = &g_d[p][0][0];
            }
            CHECK(ref_fit_multi(xs, ns, cnt[jn], NULL, c, rr) == 0 &&
                      ref_fit_multi_weighted(xs, ns, cnt[jn], NULL, cw, rw) ==
                          0,
                  "multi joint %d", jn);
            printf("  MGDK %-12s c=(%.6g, %.6g, %.6g) radii:", jn == 0 ? "hip" :
                   jn == 1 ? "knee" : "elbow", c[0], c[1], c[2]);
            for (p = 0; p < cnt[jn]; ++p) {
                printf(" %.5g", rr[p]);
            }
            printf("  (weighted differs by %.2g)\n", tu_dist3(c, cw));
        }
    }
}

/* ---------------------------------------------------------------------- */
int main(int argc, char **argv)
{
    test_rng();
    test_eig();
    test_moments();
    test_exact_sphere();
    test_exact_circle();
    test_ggs();
    test_kasa_equiv();
    test_ugdk();
    test_multi();
    test_noise();
    test_geometric_crlb();
    test_cap_arc();
    test_samplers();
    if (argc > 1) {
        test_data(argv[1]);
    }
    printf("ref selfcheck: %d checks, %d failures\n", g_checks, g_fail);
    return g_fail ? 1 : 0;
}
