/* SPDX-License-Identifier: MIT */
/**
 * @file main.c
 * @brief Known-answer fit in a plain firmware project that links sfit
 * (tests/scripts/test_plain_toolchain.sh): 30 samples exactly on a sphere
 * of radius 7 about (1200, -350, 80), integer offsets (7,0,0) and (2,3,6)
 * with every sign and order, so the data carry no rounding at all.
 * Exit 0 when the centre and radius are within 1e-3 of the truth.
 */
#include <stdio.h>

#include "sfit/sfit.h"

static float prv_abs(float v)
{
    return (v < 0.0f) ? -v : v;
}

int main(void)
{
    static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    static const float c_true[3] = {1200.0f, -350.0f, 80.0f};
    const float base[3] = {2.0f, 3.0f, 6.0f};
    sfit_moments_t acc;
    sfit_result_t fit;
    sfit_fit_cfg_t cfg = sfit_fit_cfg_default;
    float err = 0.0f;
    int i, k, s;

    if (sfit_moments_init(&acc) != SFIT_OK) {
        return 2;
    }
    for (k = 0; k < 3; k++) { /* (+-7, 0, 0) and its permutations */
        for (s = -1; s <= 1; s += 2) {
            sfit_vec3_t x = {{c_true[0], c_true[1], c_true[2]}};
            x.v[k] += 7.0f * (float)s;
            if (sfit_moments_add(&acc, &x) != SFIT_OK) {
                return 3;
            }
        }
    }
    for (i = 0; i < 6; i++) { /* (+-2, +-3, +-6), 4 of the 8 sign patterns */
        for (s = 0; s < 4; s++) {
            sfit_vec3_t x = {{c_true[0], c_true[1], c_true[2]}};
            for (k = 0; k < 3; k++) {
                const float sign = (((s + i) >> (k % 2)) & 1) != 0 ? -1.0f : 1.0f;
                x.v[perm[i][k]] += sign * base[k];
            }
            if (sfit_moments_add(&acc, &x) != SFIT_OK) {
                return 3;
            }
        }
    }
    if (sfit_fit_moments(&acc, &cfg, &fit) != SFIT_OK) {
        return 4;
    }
    for (k = 0; k < 3; k++) {
        const float d = prv_abs(fit.center.v[k] - c_true[k]);
        err = (d > err) ? d : err;
    }
    /* nano printf has no %f: micro-units as integers */
    printf("plain consumer: n %lu, centre error %ld um, radius %ld um (7000000 expected)\n",
           (unsigned long)fit.n, (long)(err * 1e6f), (long)(fit.radius * 1e6f));
    if (fit.n != 30u || err > 1e-3f || prv_abs(fit.radius - 7.0f) > 1e-3f) {
        printf("plain consumer: FAIL\n");
        return 1;
    }
    printf("plain consumer: PASS\n");
    return 0;
}
