/* SPDX-License-Identifier: MIT */
/** @file swaps_joint.c  Label swaps of a joint's two clusters (swaps.h). */
#include <stdio.h>
#include <string.h>

#include "frames.h"
#include "swaps.h"

int swaps_joint_run(struct frames_data *fr, int np, int nc, long first, long last, int repair,
                        swaps_joint_t *out)
{
    const int stride = np + nc;
    memset(out, 0, sizeof *out);
    out->repair = repair != 0;
    if (swaps_run(fr->xyz, fr->nframes, stride, 0, np, first, last, repair, &out->parent)
            != 0
        || swaps_run(fr->xyz, fr->nframes, stride, np, nc, first, last, repair, &out->child)
               != 0) {
        swaps_joint_free(out);
        memset(out, 0, sizeof *out);
        return -1;
    }
    return 0;
}

void swaps_joint_free(swaps_joint_t *s)
{
    swaps_free(&s->parent);
    swaps_free(&s->child);
}
