/* SPDX-License-Identifier: MIT */
/**
 * @file cov_tally.h
 * @brief One scenario's coverage tally, shared by coverage.c and
 * coverage_joint.c: OK results, flagged (SFIT_FLAG_UNTRUSTED), failed
 * calls, and for the unflagged ones the centre errors, the reported traces
 * and how many true centres lie inside the reported 95 % ellipsoid
 * (e^T Cov^-1 e <= 7.815, chi-square with 3 degrees of freedom).
 */
#ifndef SFIT_MC_COV_TALLY_H
#define SFIT_MC_COV_TALLY_H

#include "sfit/sfit.h"
#include "test_util.h"

#define CHI2_3_95 7.8147279

typedef struct cov_tally {
    long ok, flagged, failed, covered;
    double trust;               /* sum of the reported trust ratio over OK results */
    double s[3], ss[3], rep;    /* unflagged: centre errors, reported traces */
} cov_tally_t;

/* One trial: status, flags, reported trust, centre, covariance and the
 * true centre. */
static void cov_tally_add(cov_tally_t *a, sfit_status_t st, uint32_t flags, float trust,
                          const sfit_vec3_t *c, const sfit_mat3_t *cov, const double truth[3])
{
    double e[3], d2;
    int k;
    if (st != SFIT_OK) {
        a->failed++;
        return;
    }
    a->ok++;
    a->trust += (double)trust;
    if ((flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u) {
        a->flagged++;
        return;
    }
    for (k = 0; k < 3; k++) {
        e[k] = (double)c->v[k] - truth[k];
        a->s[k] += e[k];
        a->ss[k] += e[k] * e[k];
    }
    a->rep += (double)cov->m[0] + (double)cov->m[4] + (double)cov->m[8];
    d2 = tu_mahal(cov->m, e);
    if (d2 >= 0.0 && d2 <= CHI2_3_95) {
        a->covered++;
    }
}

static long cov_tally_unflagged(const cov_tally_t *a)
{
    return a->ok - a->flagged;
}

/* reported / Monte Carlo covariance trace of the unflagged results (0 when
 * fewer than 2) */
static double cov_tally_ratio(const cov_tally_t *a)
{
    const long t = cov_tally_unflagged(a);
    double tr = 0.0;
    int k;
    if (t < 2) {
        return 0.0;
    }
    for (k = 0; k < 3; k++) {
        tr += (a->ss[k] - a->s[k] * a->s[k] / (double)t) / (double)(t - 1);
    }
    return (a->rep / (double)t) / tr;
}

/* reported trace / Monte Carlo mean squared error (about the true centre,
 * bias included) of the unflagged results (0 when none): the comparison
 * for a covariance that reports a mean squared error (the refined recipe,
 * docs/coverage.md rule 5) */
static inline double cov_tally_mse_ratio(const cov_tally_t *a)
{
    const long t = cov_tally_unflagged(a);
    const double mse = a->ss[0] + a->ss[1] + a->ss[2];
    if (t < 1 || !(mse > 0.0)) {
        return 0.0;
    }
    return a->rep / mse;
}

#endif /* SFIT_MC_COV_TALLY_H */
