/* SPDX-License-Identifier: MIT */
/**
 * @file c3d.c
 * @brief C3D reader of the `sfit` tool (see c3d.h and docs/c3d.md): header,
 * frames and data here, the parameter section and the labels in
 * c3d_param.c. Written from the format's description: every multi-byte
 * read goes through rd_*() (c3d_in.h), whose offsets are checked against
 * the buffer first, so a hostile file cannot make the reader look outside
 * it.
 *
 * Layout used here (block = 512 bytes, block numbers count from 1):
 *   header, block 1: byte 0 parameter block, byte 1 key 0x50; 16-bit words
 *     (counting from 1) 2 points, 3 analog words per frame, 4 first frame,
 *     5 last frame, 7-8 float scale, 9 data block, 10 analog samples per
 *     frame, 11-12 float rate;
 *   parameters: 4 bytes (byte 2 = the section's size in blocks, byte 3 =
 *     83 + processor type), then entries: int8 name length (0 ends; < 0 =
 *     locked), int8 id (< 0 group, > 0 the parameter's group), name, int16
 *     offset of the next entry counted from this word (0 = last); a
 *     parameter then has int8 type (-1 char, 1 byte, 2 int16, 4 float),
 *     uint8 dimension count, the dimensions, the data, then (as a group)
 *     a description length byte and the description;
 *   data: per frame, per point x, y, z, residual word (4-byte floats when
 *     POINT:SCALE < 0, else 16-bit integers times SCALE), then the frame's
 *     analog words.
 */
#include "c3d_in.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *c3d_processor_name(int proc)
{
    return proc == C3D_PROC_INTEL ? "Intel" : proc == C3D_PROC_DEC ? "DEC" : "MIPS";
}

int c3d_sniff(const unsigned char *buf, size_t len)
{
    return len >= 2u && buf[1] == 0x50u && buf[0] >= 2u;
}

/* Frames lo .. hi-1 of the data section are all zero bytes. */
static int zero_frames(const c3d_in_t *in, const c3d_t *c, long lo, long hi)
{
    const size_t a = c->data_start + (size_t)lo * c->frame_bytes;
    const size_t b = c->data_start + (size_t)hi * c->frame_bytes;
    size_t i;
    if (hi <= lo || b > in->n) {
        return 0;
    }
    for (i = a; i < b; i++) {
        if (in->b[i] != 0u) {
            return 0;
        }
    }
    return 1;
}

/* Whole frames held, without trailing frames of zero bytes that start in
 * the file's last 512 bytes (the last block's padding). */
static long held_frames(const c3d_in_t *in, const c3d_t *c)
{
    long n = c->frames_in_file;
    while (n > 1 && c->data_start + (size_t)(n - 1) * c->frame_bytes + C3D_BLOCK >= in->n
           && zero_frames(in, c, n - 1, n)) {
        n--;
    }
    return n;
}

/* Frames: the header's count, POINT:FRAMES, the long counts and the file's
 * size. 0 with c->nframes set, or -1. */
static int choose_frames(const c3d_in_t *in, c3d_t *c, long hdr_frames, int have_params,
                         char *err)
{
    const long cap = c->frames_in_file;
    const long pf = have_params ? c3d_param_count(in, c3d_param(c, "POINT", "FRAMES")) : -1;
    /* a data section that ends after whole frames (or a file of whole
     * 512-byte blocks) was written to its end: a count above what it
     * holds was never updated. One that ends inside a frame was cut. */
    const size_t rest = (c->frame_bytes > 0u && in->n >= c->data_start)
                            ? (in->n - c->data_start) - (size_t)cap * c->frame_bytes
                            : 1u;
    const int complete = cap >= 1 && (rest == 0u || in->n % C3D_BLOCK == 0u);
    long lf = -1, n;
    const char *lsrc = NULL;
    if (have_params) {
        const c3d_entry_t *lp = c3d_param(c, "POINT", "LONG_FRAMES");
        const long s = c3d_param_field(in, c3d_param(c, "TRIAL", "ACTUAL_START_FIELD"));
        const long e = c3d_param_field(in, c3d_param(c, "TRIAL", "ACTUAL_END_FIELD"));
        double v;
        if (lp != NULL && lp->type == 2 && lp->count >= 2u) {
            lf = c3d_param_field(in, lp);
        } else if (c3d_param_number_at(in, lp, 0u, &v) == 0 && v >= 1.0 && v < 1.0e9) {
            lf = (long)v;
        }
        if (lf > 65535) {
            lsrc = "POINT:LONG_FRAMES";
        } else if (s >= 0 && e >= s && e - s + 1 > 65535) {
            lf = e - s + 1;
            lsrc = "TRIAL:ACTUAL_START_FIELD/ACTUAL_END_FIELD";
            c->first_frame = s;
        } else {
            lf = -1;
        }
    }
    if (lsrc != NULL) {
        if (lf > cap) {
            if (!complete) {
                return fail(err,
                            "truncated: %s announces %ld frames of %lu bytes, the file holds %ld "
                            "and ends inside a frame",
                            lsrc, lf, (unsigned long)c->frame_bytes, cap);
            }
            warn(c, "frame count: %s announces %ld frames, the data section holds %ld whole "
                    "frames and ends there: read %ld", lsrc, lf, cap, held_frames(in, c));
            lf = held_frames(in, c);
        }
        c->nframes = lf;
        c->src_frames = lsrc;
        return 0;
    }
    if (pf < 0 || pf == hdr_frames) {
        n = hdr_frames;
        c->src_frames = (pf < 0) ? "header" : "header, POINT:FRAMES";
        if (n > cap) {
            if (!complete) {
                return fail(err,
                            "truncated: %ld frames of %lu bytes announced (%s), the file holds "
                            "%ld and ends inside a frame",
                            n, (unsigned long)c->frame_bytes, c->src_frames, cap);
            }
            warn(c, "frame count: %ld announced (%s), the data section holds %ld whole frames "
                    "and ends there: read %ld", n, c->src_frames, cap, held_frames(in, c));
            c->src_frames = (pf < 0) ? "data section size (the header says more)"
                                     : "data section size (header and POINT:FRAMES say more)";
            n = held_frames(in, c);
        }
    } else {
        const int h_ok = hdr_frames <= cap, p_ok = pf <= cap;
        if (!h_ok && !p_ok) {
            if (!complete) {
                return fail(err,
                            "truncated: the header announces %ld frames, POINT:FRAMES %ld; the "
                            "file holds %ld frames of %lu bytes and ends inside a frame",
                            hdr_frames, pf, cap, (unsigned long)c->frame_bytes);
            }
            n = held_frames(in, c);
            c->src_frames = "data section size (header and POINT:FRAMES say more)";
            warn(c,
                 "frame count: the header says %ld, POINT:FRAMES %ld; the data section holds %ld "
                 "whole frames and ends there: read %ld",
                 hdr_frames, pf, cap, n);
        } else {
            const long lo = (hdr_frames < pf) ? hdr_frames : pf;
            const long hi = (hdr_frames < pf) ? pf : hdr_frames;
            if (h_ok && p_ok && zero_frames(in, c, lo, hi)) {
                /* the larger count's extra frames are zero bytes: padding */
                n = lo;
            } else {
                n = (h_ok && p_ok) ? hi : (h_ok ? hdr_frames : pf);
            }
            c->src_frames = (n == hdr_frames) ? "header (file size)" : "POINT:FRAMES (file size)";
            if (h_ok && p_ok && n == lo) {
                warn(c,
                     "frame count: the header says %ld, POINT:FRAMES %ld; frames %ld to %ld of "
                     "the data section are zero bytes (padding): read %ld (%s)",
                     hdr_frames, pf, lo, hi - 1, n, n == pf ? "POINT:FRAMES" : "the header");
            } else {
                warn(c,
                     "frame count: the header says %ld, POINT:FRAMES %ld; the file holds %ld: "
                     "read %ld (%s)",
                     hdr_frames, pf, cap, n, n == pf ? "POINT:FRAMES" : "the header");
            }
        }
    }
    c->nframes = n;
    if (cap > n && c->frame_bytes > 0u && (size_t)(cap - n) * c->frame_bytes >= C3D_BLOCK) {
        warn(c, "the data section holds %ld frames, %ld announced (%s): read %ld", cap, n,
             c->src_frames, n);
    }
    return 0;
}

/* A frame count n fits a frame size fb in a data section of `bytes` when
 * the n frames end at its end or in its last 512-byte block (padding). */
static int count_fits(size_t fb, size_t bytes, long n)
{
    if (n < 1 || fb == 0u || (size_t)n > bytes / fb) {
        return 0;
    }
    return bytes - (size_t)n * fb < C3D_BLOCK;
}

/* The announced count (the header's, else POINT:FRAMES) that frames of fb
 * bytes fit in the data section; 0 when neither does. */
static long fitting_count(size_t fb, size_t bytes, long hdr_frames, long pframes)
{
    return count_fits(fb, bytes, hdr_frames) ? hdr_frames
           : count_fits(fb, bytes, pframes)  ? pframes
                                             : 0;
}

/* Frames of fb bytes fit one announced count. */
static int layout_fits(size_t fb, size_t bytes, long hdr_frames, long pframes)
{
    return fitting_count(fb, bytes, hdr_frames, pframes) > 0;
}

/* Analog words per frame: the header against ANALOG:USED and the rates;
 * where they differ, the layout whose frames fill the data section. */
static int check_analog(const c3d_in_t *in, c3d_t *c, unsigned hdr_words, unsigned hdr_samples,
                        long hdr_frames, size_t data_bytes, char *err)
{
    const long pframes = c3d_param_count(in, c3d_param(c, "POINT", "FRAMES"));
    const long used = c3d_param_count(in, c3d_param(c, "ANALOG", "USED"));
    double ar = 0.0;
    c->analog_words = (long)hdr_words;
    c->src_analog = "header";
    if (c3d_param_number_at(in, c3d_param(c, "ANALOG", "RATE"), 0u, &ar) == 0 && isfinite(ar)
        && ar > 0.0) {
        c->analog_rate = (float)ar;
    }
    if (used < 0) {
        if (hdr_samples > 0u && hdr_words % hdr_samples == 0u) {
            c->analog_per_frame = (int)hdr_samples;
            c->analog_channels = (int)(hdr_words / hdr_samples);
        }
        return 0;
    }
    c->analog_channels = (int)used;
    if (used == 0) {
        if (hdr_words != 0u) {
            return fail(err,
                        "analog layout conflict: the header says %u analog words per frame, "
                        "ANALOG:USED 0",
                        hdr_words);
        }
        return 0;
    }
    if (c->analog_rate > 0.0f && c->rate > 0.0f) {
        const double ratio = (double)c->analog_rate / (double)c->rate;
        const double r = floor(ratio + 0.5);
        /* a ratio or a channel count past 16 bits cannot describe a frame
         * (the header's word is 16 bits): not used */
        if (r >= 1.0 && r <= 65535.0 && used <= 65535L && fabs(ratio - r) <= 1e-3 * r) {
            const long want = used * (long)r;
            if (want != (long)hdr_words) {
                const size_t pb = 4u * (size_t)c->npoints * (size_t)c->word;
                const size_t fh = pb + (size_t)hdr_words * (size_t)c->word;
                const size_t fp = pb + (size_t)want * (size_t)c->word;
                const int fits_h = layout_fits(fh, data_bytes, hdr_frames, pframes);
                const int fits_p = layout_fits(fp, data_bytes, hdr_frames, pframes);
                if (fits_h != fits_p) {
                    /* the data section's size decides: one layout ends the
                     * announced frames at its end (or in its last block) */
                    warn(c,
                         "analog layout: the header says %u analog words per frame, ANALOG:USED "
                         "%ld x ANALOG:RATE %g / POINT:RATE %g = %ld; the data section (%lu "
                         "bytes) holds the %ld frames announced in the %s layout only: read so",
                         hdr_words, used, ar, (double)c->rate, want, (unsigned long)data_bytes,
                         fits_h ? fitting_count(fh, data_bytes, hdr_frames, pframes)
                             : fitting_count(fp, data_bytes, hdr_frames, pframes),
                         fits_h ? "header's" : "parameters'");
                    c->analog_per_frame = fits_h ? (int)(hdr_words / (unsigned long)used) : (int)r;
                    if (fits_h && hdr_words % (unsigned long)used != 0u) {
                        c->analog_per_frame = 0;
                    }
                    c->analog_words = fits_h ? (long)hdr_words : want;
                    c->src_analog = fits_h ? "header (data section size)"
                                        : "ANALOG:USED x ANALOG:RATE / POINT:RATE (data section size)";
                    return 0;
                }
                return fail(err,
                            "analog layout conflict: the header says %u analog words per frame, "
                            "ANALOG:USED %ld x ANALOG:RATE %g / POINT:RATE %g = %ld; %ld frames "
                            "announced, the data section holds %lu frames of the header's layout, "
                            "%lu of the parameters'",
                            hdr_words, used, ar, (double)c->rate, want, hdr_frames,
                            (unsigned long)(fh > 0u ? data_bytes / fh : 0u),
                            (unsigned long)(fp > 0u ? data_bytes / fp : 0u));
            }
            c->analog_per_frame = (int)r;
            c->src_analog = "header, ANALOG:USED x ANALOG:RATE / POINT:RATE";
            return 0;
        }
        warn(c, "ANALOG:RATE / POINT:RATE = %g / %g is not a whole number", ar, (double)c->rate);
    }
    if (hdr_words % (unsigned long)used != 0u) {
        return fail(err,
                    "analog layout conflict: the header's %u analog words per frame are not a "
                    "multiple of ANALOG:USED %ld",
                    hdr_words, used);
    }
    c->analog_per_frame = (int)(hdr_words / (unsigned long)used);
    c->src_analog = "header, ANALOG:USED";
    return 0;
}

/* A walk ended at a link that leads nowhere: read on when the parameters
 * that fix the layout were read before it, else refuse naming the link and
 * the missing parameter. */
static int check_walk_end(c3d_t *c, const walk_end_t *w, unsigned hdr_points, unsigned hdr_analog,
                          char *err)
{
    static const char *const need[][2] = {{"POINT", "USED"},   {"POINT", "SCALE"},
                                          {"POINT", "RATE"},   {"POINT", "LABELS"},
                                          {"ANALOG", "USED"},  {"ANALOG", "RATE"}};
    size_t k;
    for (k = 0; k < sizeof need / sizeof need[0]; k++) {
        const int analog = need[k][0][0] == 'A';
        const int labels = need[k][1][0] == 'L';
        if ((analog && hdr_analog == 0u) || (labels && hdr_points == 0u)) {
            continue;
        }
        if (c3d_param(c, need[k][0], need[k][1]) == NULL) {
            return fail(err,
                        "parameter section: the link after %s (byte %lu) points to byte %lu, "
                        "where no entry starts (neither the other byte order nor the entry's "
                        "length gives one), and %s:%s was not read before it",
                        w->name, w->at, w->to, need[k][0], need[k][1]);
        }
    }
    warn(c,
         "parameter section: the link after %s (byte %lu) points to byte %lu, where no entry "
         "starts: the walk ends there, %d entries read (the layout's parameters among them)",
         w->name, w->at, w->to, c->nentries);
    return 0;
}

/* The processor type of a file without a parameter section: the byte order
 * that gives a data-start block inside the file, Intel or DEC by the rate. */
static int guess_processor(const unsigned char *buf, size_t len)
{
    c3d_in_t in;
    const unsigned nblocks = (unsigned)(len / C3D_BLOCK);
    unsigned w;
    float r;
    in.b = buf;
    in.n = len;
    in.proc = C3D_PROC_INTEL;
    w = rd_u16(&in, 16u);
    if (w < 2u || w > nblocks) {
        return C3D_PROC_MIPS;
    }
    r = rd_f32(&in, 20u);
    if (isfinite(r) && r > 0.0f && r < 1.0e6f) {
        return C3D_PROC_INTEL;
    }
    in.proc = C3D_PROC_DEC;
    r = rd_f32(&in, 20u);
    return (isfinite(r) && r > 0.0f && r < 1.0e6f) ? C3D_PROC_DEC : C3D_PROC_INTEL;
}

static int parse(const unsigned char *buf, size_t len, c3d_t *out, char *err)
{
    c3d_in_t in;
    size_t pstart, dstart, bound;
    unsigned hdr_points, hdr_analog, hdr_first, hdr_last, hdr_data, hdr_samples;
    int proc, have_params = 1;
    long f, cnt, hdr_frames;
    float hdr_scale, hdr_rate;
    double v;

    memset(out, 0, sizeof *out);
    err[0] = '\0';
    in.b = buf;
    in.n = len;
    in.proc = C3D_PROC_INTEL;
    if (len < C3D_BLOCK) {
        return fail(err, "not a C3D file: %lu bytes, shorter than the 512-byte header",
                    (unsigned long)len);
    }
    if (buf[1] != 0x50u || buf[0] < 2u) {
        return fail(err, "not a C3D file: no 0x50 key in the header");
    }
    pstart = ((size_t)buf[0] - 1u) * C3D_BLOCK;
    proc = has(&in, pstart, 4u) ? (int)buf[pstart + 3u] : 0;
    {
        /* No parameter section: the header's data block is the parameter
         * block (read in the processor's byte order, or either one). */
        const unsigned le = (unsigned)buf[16] | ((unsigned)buf[17] << 8);
        const unsigned be = ((unsigned)buf[16] << 8) | buf[17];
        const int valid = proc == C3D_PROC_INTEL || proc == C3D_PROC_DEC || proc == C3D_PROC_MIPS;
        const unsigned w9 = valid ? (proc == C3D_PROC_MIPS ? be : le) : 0u;
        if ((valid && w9 == buf[0]) || (!valid && (le == buf[0] || be == buf[0]))) {
            have_params = 0;
            proc = guess_processor(buf, len);
        } else if (!valid && !has(&in, pstart, 4u)) {
            return fail(err, "truncated: the parameter section (block %u) is missing", buf[0]);
        } else if (!valid) {
            return fail(err, "unknown processor type %d (84 Intel, 85 DEC, 86 MIPS)", proc);
        }
    }
    in.proc = proc;
    out->processor = proc;
    out->src_processor = have_params ? "parameter section" : "header (no parameter section)";
    hdr_points = rd_u16(&in, 2u);
    hdr_analog = rd_u16(&in, 4u);
    hdr_first = rd_u16(&in, 6u);
    hdr_last = rd_u16(&in, 8u);
    hdr_scale = rd_f32(&in, 12u);
    hdr_data = rd_u16(&in, 16u);
    hdr_samples = rd_u16(&in, 18u);
    hdr_rate = rd_f32(&in, 20u);
    hdr_frames = (hdr_last >= hdr_first) ? (long)hdr_last - (long)hdr_first + 1 : 0;
    out->first_frame = (long)hdr_first;

    if (have_params) {
        /* The walk is bounded by the section's declared size, or by the
         * data section's start when that is later (a declared size too
         * small: the entries run on to the data, as the field's readers
         * follow them). */
        const unsigned nb = buf[pstart + 2u];
        const size_t declared = (nb > 0u) ? pstart + (size_t)nb * C3D_BLOCK : pstart;
        const size_t dsb = (hdr_data >= 2u) ? ((size_t)hdr_data - 1u) * C3D_BLOCK : 0u;
        walk_end_t wend;
        int i, g = 0, ngroups = 0;
        memset(&wend, 0, sizeof wend);
        bound = (dsb > declared) ? dsb : (nb > 0u ? declared : len);
        if (bound > len) {
            bound = len;
        }
        out->param_start = pstart;
        out->param_blocks = nb;
        if (c3d_walk_params(&in, pstart, bound, out, &wend, err) != 0) {
            return -1;
        }
        if (nb > 0u && wend.reach > declared) {
            warn(out,
                 "parameter section: its first block declares %u blocks (%lu bytes), its entries "
                 "run to byte %lu, before the data section (block %u): read to there",
                 nb, (unsigned long)(declared - pstart), (unsigned long)wend.reach, hdr_data);
        }
        if (wend.ended) {
            if (check_walk_end(out, &wend, hdr_points, hdr_analog, err) != 0) {
                return -1;
            }
        }
        for (i = 0; i < out->nentries; i++) {
            g |= out->entries[i].is_group && name_eq(out->entries[i].name, "POINT");
            ngroups += out->entries[i].is_group;
        }
        if (!g && ngroups > 0) {
            return fail(err, "no POINT group in the parameter section (%d groups, %d entries)",
                        ngroups, out->nentries);
        }
        if (!g) {
            /* no group at all: the header alone describes the data */
            have_params = 0;
            warn(out,
                 "parameter section: no groups (%d entries): counts, scale and rate from the "
                 "header, points named POINT1, POINT2, ...",
                 out->nentries);
            out->src_processor = "parameter section (no groups)";
        }
    }

    out->npoints = (int)hdr_points;
    out->src_points = "header";
    cnt = c3d_param_count(&in, c3d_param(out, "POINT", "USED"));
    if (cnt >= 0) {
        if (cnt != (long)hdr_points) {
            /* refused: which labels go with which points cannot be told;
             * the message gives the frames each count makes of the data */
            double sv = (double)hdr_scale;
            unsigned long fa = 0, fb = 0;
            size_t ws, ds;
            (void)c3d_param_number_at(&in, c3d_param(out, "POINT", "SCALE"), 0u, &sv);
            ws = (sv < 0.0) ? 4u : 2u;
            ds = (hdr_data >= 2u && ((size_t)hdr_data - 1u) * C3D_BLOCK < len)
                     ? len - ((size_t)hdr_data - 1u) * C3D_BLOCK
                     : 0u;
            if (cnt <= 65535L) {
                const size_t ha = (4u * (size_t)hdr_points + hdr_analog) * ws;
                const size_t pa = (4u * (size_t)cnt + hdr_analog) * ws;
                fa = (ha > 0u) ? (unsigned long)(ds / ha) : 0ul;
                fb = (pa > 0u) ? (unsigned long)(ds / pa) : 0ul;
            }
            return fail(err,
                        "POINT:USED (%ld) differs from the header's point count (%u); %ld frames "
                        "announced, the data section holds %lu frames of %u points, %lu of %ld",
                        cnt, hdr_points, hdr_frames, fa, hdr_points, fb, cnt);
        }
        out->src_points = "header, POINT:USED";
    }
    out->scale = hdr_scale;
    out->src_scale = "header";
    if (c3d_param_number_at(&in, c3d_param(out, "POINT", "SCALE"), 0u, &v) == 0) {
        out->scale = (float)v;
        out->src_scale = "POINT:SCALE";
        if (!(fabsf(out->scale - hdr_scale) <= 1e-6f * fabsf(out->scale))) {
            warn(out, "the header's scale %g differs from POINT:SCALE %g: POINT:SCALE used",
                 (double)hdr_scale, (double)out->scale);
            out->src_scale = "POINT:SCALE (the header differs)";
        }
    }
    if (!isfinite(out->scale) || out->scale == 0.0f) {
        return fail(err, "POINT:SCALE is %g: neither float (< 0) nor integer (> 0) storage",
                    (double)out->scale);
    }
    out->rate = hdr_rate;
    out->src_rate = "header";
    if (c3d_param_number_at(&in, c3d_param(out, "POINT", "RATE"), 0u, &v) == 0) {
        out->rate = (float)v;
        out->src_rate = "POINT:RATE";
    }
    if (!isfinite(out->rate) || out->rate < 0.0f) {
        out->rate = 0.0f;
    }
    {
        const c3d_entry_t *u = c3d_param(out, "POINT", "UNITS");
        if (u != NULL && u->type == -1) {
            c3d_copy_label(buf + u->data, u->count, out->units, sizeof out->units);
        }
    }
    cnt = c3d_param_count(&in, c3d_param(out, "POINT", "DATA_START"));
    if (cnt >= 1 && cnt <= 65535) {
        if ((unsigned)cnt != hdr_data) {
            warn(out, "the header's data block %u differs from POINT:DATA_START %ld: "
                      "POINT:DATA_START used", hdr_data, cnt);
        }
        hdr_data = (unsigned)cnt;
    }
    if (hdr_data < 2u) {
        return fail(err, "invalid data start block %u", hdr_data);
    }
    out->word = (out->scale < 0.0f) ? 4 : 2;
    dstart = ((size_t)hdr_data - 1u) * C3D_BLOCK;
    if (dstart > len) {
        return fail(err, "truncated: the data section (block %u) starts past the end", hdr_data);
    }
    out->data_start = dstart;
    if (check_analog(&in, out, hdr_analog, hdr_samples, hdr_frames, len - dstart, err) != 0) {
        return -1;
    }
    out->frame_bytes = (4u * (size_t)hdr_points + (size_t)out->analog_words) * (size_t)out->word;
    out->frames_in_file = (out->frame_bytes > 0u) ? (long)((len - dstart) / out->frame_bytes)
                                                  : 2147483647L;
    if (choose_frames(&in, out, hdr_frames, have_params, err) != 0) {
        return -1;
    }
    if (!have_params && out->param_start == 0u) {
        warn(out, "no parameter section: counts, scale and rate from the header, processor type "
                  "%s guessed from its byte order, points named POINT1, POINT2, ...",
             c3d_processor_name(proc));
    }

    out->labels = calloc((size_t)out->npoints + 1u, sizeof *out->labels);
    out->xyz = malloc(((size_t)out->nframes * (size_t)out->npoints * 3u + 1u) * sizeof(float));
    if (out->labels == NULL || out->xyz == NULL) {
        return fail(err, "out of memory");
    }
    c3d_read_labels(&in, out);
    if (c3d_rename_duplicates(out) != 0) {
        return fail(err, "out of memory");
    }
    {
        long zero_markers = 0;
        int p;
        for (p = 0; p < out->npoints; p++) {
            long zeros = 0;
            for (f = 0; f < out->nframes; f++) {
                const size_t po = dstart + (size_t)f * out->frame_bytes
                                  + (size_t)p * 4u * (size_t)out->word;
                float *x = out->xyz + ((size_t)f * (size_t)out->npoints + (size_t)p) * 3u;
                int invalid, i;
                if (out->word == 4) {
                    for (i = 0; i < 3; i++) {
                        x[i] = rd_f32(&in, po + 4u * (size_t)i);
                    }
                    invalid = !(rd_f32(&in, po + 12u) >= 0.0f);
                } else {
                    for (i = 0; i < 3; i++) {
                        x[i] = (float)rd_i16(&in, po + 2u * (size_t)i) * out->scale;
                    }
                    invalid = rd_i16(&in, po + 6u) < 0;
                }
                if (invalid) {
                    x[0] = x[1] = x[2] = NAN;
                } else if (x[0] == 0.0f && x[1] == 0.0f && x[2] == 0.0f) {
                    zeros++;
                }
            }
            out->zero_samples += zeros;
            zero_markers += zeros > 0;
        }
        if (out->zero_samples > 0) {
            warn(out,
                 "%ld samples of %ld markers at exactly (0, 0, 0) with a valid residual (how some "
                 "systems write a missing marker): sfit joint and skeleton take them as missing",
                 out->zero_samples, zero_markers);
        }
    }
    return 0;
}

int c3d_parse(const unsigned char *buf, size_t len, c3d_t *out, char *err)
{
    const int rc = parse(buf, len, out, err);
    if (rc != 0) {
        c3d_free(out); /* nothing half-filled on failure */
    }
    return rc;
}

int c3d_load_bytes(const char *path, unsigned char **out, size_t *len, char *err)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    size_t n = 0, cap = 0;
    *out = NULL;
    *len = 0;
    if (f == NULL) {
        return fail(err, "cannot open %s: %s", path, strerror(errno));
    }
    for (;;) {
        size_t got;
        if (n == cap) {
            unsigned char *nb;
            if (cap >= C3D_FILE_MAX) {
                free(buf);
                fclose(f);
                return fail(err, "%s: larger than 1 GiB", path);
            }
            cap = (cap == 0u) ? 65536u : 2u * cap;
            nb = realloc(buf, cap);
            if (nb == NULL) {
                free(buf);
                fclose(f);
                return fail(err, "out of memory");
            }
            buf = nb;
        }
        got = fread(buf + n, 1u, cap - n, f);
        n += got;
        if (got == 0u) {
            break;
        }
    }
    if (ferror(f)) {
        free(buf);
        fclose(f);
        return fail(err, "cannot read %s", path);
    }
    fclose(f);
    *out = buf;
    *len = n;
    return 0;
}

int c3d_read_file(const char *path, c3d_t *out, char *err)
{
    unsigned char *buf;
    size_t n;
    int rc;
    memset(out, 0, sizeof *out);
    if (c3d_load_bytes(path, &buf, &n, err) != 0) {
        return -1;
    }
    rc = c3d_parse(buf, n, out, err);
    free(buf);
    return rc;
}

void c3d_free(c3d_t *c)
{
    free(c->labels);
    free(c->xyz);
    free(c->entries);
    memset(c, 0, sizeof *c);
}

int c3d_find(const c3d_t *c, const char *name)
{
    int i, hit = -1;
    for (i = 0; i < c->npoints; i++) {
        if (strcmp(c->labels[i], name) == 0) {
            return i;
        }
    }
    for (i = 0; i < c->npoints; i++) {
        if (name_eq(c->labels[i], name)) {
            return i;
        }
    }
    for (i = 0; i < c->npoints; i++) { /* "RASI" for "P01:RASI", when only one matches */
        const char *colon = strrchr(c->labels[i], ':');
        if (colon != NULL && strcmp(colon + 1, name) == 0) {
            if (hit >= 0) {
                return -1;
            }
            hit = i;
        }
    }
    return hit;
}

void c3d_label_prefix(const c3d_t *c, int k, char *out, size_t size)
{
    const char *colon;
    out[0] = '\0';
    if (k < 0 || k >= c->npoints || size == 0u) {
        return;
    }
    colon = strrchr(c->labels[k], ':');
    if (colon != NULL) {
        const size_t n = (size_t)(colon - c->labels[k]) + 1u;
        (void)snprintf(out, size, "%.*s", (int)n, c->labels[k]);
    }
}
