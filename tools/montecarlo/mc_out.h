/* SPDX-License-Identifier: MIT */
/**
 * @file mc_out.h
 * @brief Output files of the Monte Carlo programs: DIR/NAME opened for
 * writing, or NULL after a message naming the path.
 */
#ifndef SFIT_MC_OUT_H
#define SFIT_MC_OUT_H

#include <stdio.h>

static FILE *mc_out_open(const char *dir, const char *name)
{
    char path[1024];
    FILE *f;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    f = fopen(path, "w");
    if (f == NULL) {
        perror(path);
    }
    return f;
}

#endif /* SFIT_MC_OUT_H */
