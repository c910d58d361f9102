/* SPDX-License-Identifier: MIT */
/**
 * @file minimal_app.c
 * @brief The smallest useful firmware: one accumulator, samples added, one
 * fit with the defaults (sfit_fit_moments_default: the full solver alone).
 * tools/flopcount/footprint.sh links it with --gc-sections against the
 * library objects and reports the bytes of sfit code and constant data it
 * pulls in (record "code minimal_app"). With -DSFIT_MINAPP_SCREENED the
 * fit is sfit_fit_moments(m, NULL, out) (the screen and its fallback:
 * records minimal_app_screened, minimal_app_lean).
 */
#include "sfit/sfit.h"

volatile float g_minapp_out[4];

int main(void)
{
    static sfit_moments_t m;
    sfit_result_t r;
    sfit_vec3_t x = {{1.0f, 2.0f, 3.0f}};
    unsigned i;
    (void)sfit_moments_init(&m);
    for (i = 0; i < 100u; i++) {
        x.v[i % 3u] += 0.5f;
        (void)sfit_moments_add(&m, &x);
    }
#ifdef SFIT_MINAPP_SCREENED
    if (sfit_fit_moments(&m, NULL, &r) == SFIT_OK) {
#else
    if (sfit_fit_moments_default(&m, &r) == SFIT_OK) {
#endif
        g_minapp_out[0] = r.center.v[0];
        g_minapp_out[1] = r.center.v[1];
        g_minapp_out[2] = r.center.v[2];
        g_minapp_out[3] = r.radius;
    }
    return 0;
}
