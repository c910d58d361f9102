/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_swaps.c
 * @brief libFuzzer harness of the host library's label-swap check
 * (tools/lab/swaps.c, compiled into the harness). Input: a header
 * (markers 1..8, repair flag, range), a template of signed bytes, then one
 * opcode per frame: the template moved and jittered, with two labels
 * exchanged, three rotated, a marker hostile (NaN, Inf, huge, raw bits) or
 * missing, or a frame of raw floats.
 * Contract: swaps_run returns 0; every status is in range and only
 * frames of the range are checked; the counts add up (per candidate, per
 * status, the runs); a checked cluster has a finite positive noise and
 * decision distance 2 z s; without repair no byte changes; with repair a
 * frame as given (or not checked) is unchanged, a swapped frame is its
 * relabelling of the original, a rejected frame is all NaN.
 */
#include "../../tools/lab/swaps.c"

#include "fuzz_common.h"

#define FZ_SW_FRAMES 160

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static sfit_vec3_t xyz[FZ_SW_FRAMES * SWAPS_MAX_MARKERS];
    static sfit_vec3_t orig[FZ_SW_FRAMES * SWAPS_MAX_MARKERS];
    static swaps_t s;
    fz_in_t in = {data, size, 0u};
    float tpl[SWAPS_MAX_MARKERS][3];
    const int m = 1 + fz_u8(&in) % SWAPS_MAX_MARKERS;
    const uint8_t flags = fz_u8(&in);
    const int repair = flags & 1u;
    long nf = 0, f, first, last, counted;
    long per_status[4] = {0, 0, 0, 0}; /* as given, swapped, no fit, ambiguous */
    int u, i, c, rc;
    for (u = 0; u < m; u++) {
        for (i = 0; i < 3; i++) {
            tpl[u][i] = (float)(int8_t)fz_u8(&in) * 2.0f;
        }
    }
    while (fz_more(&in) && nf < FZ_SW_FRAMES) {
        const uint8_t op = fz_u8(&in);
        const float ang = (float)(int8_t)fz_u8(&in) * 0.02f;
        const float tx = 2700.0f + (float)(int8_t)fz_u8(&in);
        sfit_vec3_t *row = xyz + (size_t)nf * (size_t)m;
        const float cs = cosf(ang), sn = sinf(ang);
        for (u = 0; u < m; u++) { /* rotate about z, translate, jitter */
            const float j = (float)((int)(op >> 4) - 8) * 0.01f * (float)(u + 1);
            row[u].v[0] = cs * tpl[u][0] - sn * tpl[u][1] + tx + j;
            row[u].v[1] = sn * tpl[u][0] + cs * tpl[u][1] - 1200.0f;
            row[u].v[2] = tpl[u][2] + 900.0f - j;
        }
        switch (op & 7u) {
        case 1: { /* exchange two labels */
            const int a = fz_u8(&in) % m, b = fz_u8(&in) % m;
            const sfit_vec3_t t = row[a];
            row[a] = row[b];
            row[b] = t;
            break;
        }
        case 2: { /* rotate three labels */
            const int a = fz_u8(&in) % m, b = fz_u8(&in) % m, d = fz_u8(&in) % m;
            const sfit_vec3_t t = row[a];
            row[a] = row[b];
            row[b] = row[d];
            row[d] = t;
            break;
        }
        case 3: /* one hostile coordinate */
            row[fz_u8(&in) % m].v[fz_u8(&in) % 3u] = fz_float(&in);
            break;
        case 4: /* one marker missing */
            u = fz_u8(&in) % m;
            row[u].v[0] = row[u].v[1] = row[u].v[2] = NAN;
            break;
        case 5: /* a frame of hostile floats */
            for (u = 0; u < m; u++) {
                for (i = 0; i < 3; i++) {
                    row[u].v[i] = fz_float(&in);
                }
            }
            break;
        default:
            break;
        }
        nf++;
    }
    first = (flags & 2u) ? (long)(fz_u8(&in) % (nf + 1)) : 0;
    last = (flags & 4u) ? first + (long)(fz_u8(&in) % (nf + 1)) - 1 : -1;
    memcpy(orig, xyz, (size_t)nf * (size_t)m * sizeof *xyz);
    rc = swaps_run(xyz, nf, m, 0, m, first, last, repair, &s);
    FZ_CHECK(rc == 0, "swaps_run returns 0");
    FZ_CHECK(s.m == m && s.ncand >= 1 && s.ncand <= SWAPS_MAX_CAND, "candidates");
    if (last < 0 || last >= nf) {
        last = nf - 1;
    }
    counted = 0;
    for (f = 0; f < nf; f++) {
        const int st = s.status[f];
        const sfit_vec3_t *a = xyz + (size_t)f * (size_t)m, *o = orig + (size_t)f * (size_t)m;
        FZ_CHECK(st >= SWAPS_AMBIGUOUS && st < s.ncand, "status in range");
        FZ_CHECK(st == SWAPS_UNCHECKED || (s.checked && f >= first && f <= last),
                 "only frames of the range of a checked cluster are checked");
        if (st != SWAPS_UNCHECKED) {
            counted++;
            per_status[st == 0 ? 0 : (st > 0 ? 1 : (st == SWAPS_NO_FIT ? 2 : 3))]++;
        }
        if (!repair || st == SWAPS_UNCHECKED || st == SWAPS_AS_GIVEN) {
            FZ_CHECK(memcmp(a, o, (size_t)m * sizeof *a) == 0, "frame unchanged");
        } else if (st > 0) {
            for (u = 0; u < m; u++) {
                FZ_CHECK(memcmp(&a[s.cand[st].lab[u]], &o[u], sizeof *a) == 0,
                         "a swapped frame is its relabelling");
            }
        } else {
            for (u = 0; u < m; u++) {
                FZ_CHECK(isnan(a[u].v[0]) && isnan(a[u].v[1]) && isnan(a[u].v[2]),
                         "a rejected frame is NaN");
            }
        }
    }
    FZ_CHECK(counted == s.frames_checked, "frames_checked counts the checked frames");
    FZ_CHECK(per_status[0] == s.cand[0].count && per_status[1] == s.frames_swapped
                 && per_status[2] == s.frames_no_fit && per_status[3] == s.frames_ambiguous,
             "counts per status");
    {
        long sum = 0, n, r;
        long (*runs)[2] = malloc((size_t)(nf + 1) * sizeof *runs);
        FZ_CHECK(runs != NULL, "memory");
        for (c = 1; c < s.ncand; c++) {
            sum += s.cand[c].count;
            FZ_CHECK(s.cand[c].count == 0 || s.cand[c].decidable,
                     "only decidable relabellings are applied");
            n = swaps_runs(&s, c, runs, nf + 1);
            for (r = 0; r < n; r++) {
                FZ_CHECK(runs[r][0] <= runs[r][1] && (r == 0 || runs[r][0] > runs[r - 1][1] + 1),
                         "runs ordered and maximal");
                sum -= runs[r][1] - runs[r][0] + 1;
            }
            sum += s.cand[c].count;
        }
        FZ_CHECK(sum == s.frames_swapped, "swap counts and runs add up");
        free(runs);
    }
    if (s.checked) {
        FZ_CHECK(isfinite(s.scale) && s.scale > 0.0 && s.decide == 2.0 * SWAPS_Z * s.scale,
                 "noise and decision distance");
    } else {
        FZ_CHECK(s.frames_checked == 0 && s.why != SWAPS_WHY_CHECKED, "not checked: why");
    }
    swaps_free(&s);
    return 0;
}
