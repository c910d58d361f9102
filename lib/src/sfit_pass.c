/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_pass.c
 * @brief The per-sample distance pass shared by refine, uncert and selfcal.
 */
#include "sfit_pass.h"

/* Row and column of the packed entries (XX, YY, ZZ, XY, XZ, YZ). */
static const uint8_t k_row[6] = {0u, 1u, 2u, 0u, 0u, 1u};
static const uint8_t k_col[6] = {0u, 1u, 2u, 1u, 2u, 2u};

/* The self-calibrated sandwich's row: packed eta eta^T, then f u. */
static void prv_row_sandwich(const sfit_i_rows_t *q, const float x[3], float d, const float u[3],
                             float *b)
{
    const float f = d - q->dbar;
    const float gt = f * (d + q->dbar) - q->mf2; /* |z|^2 - mean |z|^2, no cancellation */
    const float xi = f * f - q->sv + q->alpha_n * gt;
    float eta[3];
    int j;
    for (j = 0; j < 3; j++) {
        const float y = x[j] - q->m[j];
        eta[j] = 0.5f * gt * y - q->kv * (y + q->a[j]) + q->p[j] * xi;
        b[6 + j] += f * u[j];
    }
    for (j = 0; j < 6; j++) {
        b[j] += eta[k_row[j]] * eta[k_col[j]];
    }
}

/* Add the row (k floats) of sample x at distance d > 0, direction u to the
 * inner level b of the sum. */
static void prv_row(sfit_i_rows_t *q, int k, const float x[3], float d, const float u[3],
                    float *b)
{
    float v[3], e;
    int j;
    switch (q->kind) {
    case SFIT_I_ROWS_RESID:
        e = d - q->ref;
        b[0] += e;
        b[1] += e * e;
        break;
    case SFIT_I_ROWS_DIRS:
        if (q->first) {
            q->ref = d;
            q->first = 0;
        }
        e = d - q->ref;
        for (j = 0; j < 3; j++) {
            b[j] += u[j];
        }
        b[3] += e;
        if (k == 5) {
            b[4] += e * e;
        }
        break;
    case SFIT_I_ROWS_LM:
    case SFIT_I_ROWS_CENTRED:
        e = d - q->dbar;
        for (j = 0; j < 3; j++) {
            v[j] = u[j] - q->ub[j];
        }
        for (j = 0; j < 6; j++) {
            b[j] += v[k_row[j]] * v[k_col[j]];
        }
        if (q->kind == SFIT_I_ROWS_LM) {
            for (j = 0; j < 3; j++) {
                b[6 + j] += v[j] * e;
            }
        } else if (k == 13) {
            const float g = e / d;
            for (j = 0; j < 6; j++) {
                b[6 + j] += g * (((j < 3) ? 1.0f : 0.0f) - u[k_row[j]] * u[k_col[j]]);
            }
            b[12] += e * e;
        } else {
            /* k == 6: the packed (u - ub)(u - ub)^T alone */
        }
        break;
    case SFIT_I_ROWS_SANDWICH:
    default:
        prv_row_sandwich(q, x, d, u, b);
        break;
    }
}

void sfit_i_rows_init(sfit_i_rows_t *q, sfit_i_rows_kind_t kind, float ref, const float *ub,
                      float dbar)
{
    int j;
    memset(q, 0, sizeof *q);
    q->kind = kind;
    q->ref = ref;
    for (j = 0; j < 3 && ub != NULL; j++) {
        q->ub[j] = ub[j];
    }
    q->dbar = dbar;
}

int sfit_i_pass(const sfit_vec3_t *pts, size_t n, const float c[3], const float *p,
                sfit_i_rows_t *q, int k, sfit_i_sum_t *s)
{
    size_t i;
    int j;
    memset(s, 0, sizeof *s);
    for (i = 0; i < n; i++) {
        float u[3], d;
        int ok;
        if (p != NULL) {
            for (j = 0; j < 3; j++) {
                u[j] = (pts[i].v[j] - c[j]) - p[j];
            }
            ok = sfit_i_unit3(u, &d);
        } else {
            ok = sfit_i_dist_dir(pts[i].v, c, &d, u);
        }
        if (!ok) {
            return 0;
        }
        prv_row(q, k, pts[i].v, d, u, s->blk);
        sfit_i_sum_next(s, k);
    }
    sfit_i_sum_end(s, k);
    return 1;
}
