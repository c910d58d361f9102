/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_pass.c
 * @brief The per-sample distance pass shared by refine, uncert and selfcal.
 */
#include "sfit_pass.h"

void sfit_i_row_dirs(void *ctx, const float x[3], float d, const float u[3], float *t)
{
    sfit_i_dirs_t *q = (sfit_i_dirs_t *)ctx;
    (void)x;
    if (q->first) {
        q->ref = d;
        q->first = 0;
    }
    t[0] = u[0];
    t[1] = u[1];
    t[2] = u[2];
    t[3] = d - q->ref;
    if (q->k == 5) {
        t[4] = t[3] * t[3];
    }
}

int sfit_i_pass(const sfit_vec3_t *pts, size_t n, const float c[3], const float *p,
                sfit_i_row_fn row, void *ctx, int k, sfit_i_sum_t *s)
{
    size_t i;
    int j;
    memset(s, 0, sizeof *s);
    for (i = 0; i < n; i++) {
        float u[3], d, t[SFIT_I_SUM_MAX];
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
        row(ctx, pts[i].v, d, u, t);
        sfit_i_sum_add(s, t, k);
    }
    sfit_i_sum_end(s, k);
    return 1;
}
