/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_c3d.c
 * @brief `sfit c3d`: what a C3D file holds, and its markers as a wide table.
 *
 *   sfit c3d FILE [--json] [--export OUT.csv [--markers A,B,...] [--frames F:L]]
 *
 * Prints the processor type, point count, frame count, first frame number,
 * rate, units, scale and labels. --export writes frame,A_X,A_Y,A_Z,... (the
 * wide table `sfit joint` reads; frame = 0-based index; an invalid sample
 * is a blank cell), every marker unless --markers.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "c3d.h"
#include "c3d_write.h"
#include "cli.h"
#include "frames.h"
#include "table.h"

typedef struct c3d_opts {
    const char *file;
    char *out, *markers;
    char *add, *write, *trc, *prefix;
    long first, last;
    int json;
} c3d_opts_t;

static void c3d_usage(FILE *f)
{
    fputs("usage: sfit c3d FILE [--json] [--export OUT.csv [--markers A,B,...] [--frames F:L]]\n"
          "                [--add TABLE.csv --write OUT.c3d] [--trc OUT.trc] [--prefix P]\n"
          "  Describe a C3D file: processor type, points, frames, rate, units, labels.\n"
          "  --export OUT.csv  write frame,A_X,A_Y,A_Z,... (the wide table `sfit joint`\n"
          "                    reads; frame = 0-based index; invalid sample = blank cells)\n"
          "  --markers LIST    markers to export (default: all)\n"
          "  --frames F:L      frames to export, 0-based, both included (default: all)\n"
          "  --add TABLE.csv   points to add: a wide table frame,NAME_X,NAME_Y,NAME_Z,...\n"
          "                    (frame = 0-based index; a frame not listed or a blank\n"
          "                    cell: the point is missing there, residual -1)\n"
          "  --write OUT.c3d   the recording with the added points (nothing else changed)\n"
          "  --trc OUT.trc     an OpenSim marker file: every marker (and the added points)\n"
          "  --prefix P        put P before the added names (default: the subject prefix\n"
          "                    such as 'P01:' when every label has the same one)\n"
          "  --json            one JSON object on stdout\n",
          f);
}

/* --frames F:L (CLI_OPT_FN). */
static const char *c3d_frames(void *dst, const char *v)
{
    c3d_opts_t *o = (c3d_opts_t *)dst;
    const int rc = frames_parse_range(v, &o->first, &o->last);
    if (rc != 0) {
        return (rc == 1) ? "--frames needs F:L" : "--frames needs F:L, 0 <= F <= L";
    }
    return NULL;
}

/* -1 to go on, or the exit status (cli_parse). */
static int c3d_parse_args(int argc, char **argv, c3d_opts_t *o)
{
    const cli_opt_t opts[] = {
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &o->json},
        {.name = "--export", .kind = CLI_OPT_STRING, .dst = &o->out},
        {.name = "--markers", .kind = CLI_OPT_STRING, .dst = &o->markers},
        {.name = "--frames", .kind = CLI_OPT_FN, .dst = o, .fn = c3d_frames},
        {.name = "--add", .kind = CLI_OPT_STRING, .dst = &o->add},
        {.name = "--write", .kind = CLI_OPT_STRING, .dst = &o->write},
        {.name = "--trc", .kind = CLI_OPT_STRING, .dst = &o->trc},
        {.name = "--prefix", .kind = CLI_OPT_STRING, .dst = &o->prefix},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0],
                             CLI_ONE_FILE(o->file),
                             .usage = c3d_usage};
    memset(o, 0, sizeof *o);
    o->last = -1;
    return cli_parse(argc, argv, &args);
}

static void put_cell(FILE *f, float v)
{
    if (isfinite(v)) {
        fprintf(f, ",%.9g", (double)v);
    } else {
        fputc(',', f);
    }
}

static int export_table(const c3d_opts_t *o, const c3d_t *c, char *why)
{
    int *idx;
    char **names;
    int n = 0, k;
    long fr, last = (o->last < 0 || o->last >= c->nframes) ? c->nframes - 1 : o->last;
    FILE *f;
    const size_t room = (size_t)c->npoints + (o->markers != NULL ? strlen(o->markers) : 0u) + 1u;
    idx = malloc(room * sizeof *idx);
    names = malloc(room * sizeof *names);
    if (idx == NULL || names == NULL) {
        free(idx);
        free(names);
        (void)snprintf(why, C3D_ERR_MAX, "out of memory");
        return -2;
    }
    if (o->markers != NULL) {
        n = frames_split_list(o->markers, names, (int)room);
        if (n < 1) {
            (void)snprintf(why, C3D_ERR_MAX, "--markers: a comma-separated list of names");
            free(idx);
            free(names);
            return -2;
        }
        for (k = 0; k < n; k++) {
            idx[k] = c3d_find(c, names[k]);
            if (idx[k] < 0) {
                (void)snprintf(why, C3D_ERR_MAX, "no marker labelled '%.200s'", names[k]);
                free(idx);
                free(names);
                return -2;
            }
        }
    } else {
        n = c->npoints; /* every marker, however many */
        for (k = 0; k < n; k++) {
            idx[k] = k;
        }
    }
    free(names);
    f = fopen(o->out, "w");
    if (f == NULL) {
        (void)snprintf(why, C3D_ERR_MAX, "cannot write %s: %s", o->out, strerror(errno));
        free(idx);
        return -2;
    }
    fputs("frame", f);
    for (k = 0; k < n; k++) {
        const char *l = c->labels[idx[k]];
        fprintf(f, ",%s_X,%s_Y,%s_Z", l, l, l);
    }
    fputc('\n', f);
    for (fr = o->first; fr <= last; fr++) {
        fprintf(f, "%ld", fr);
        for (k = 0; k < n; k++) {
            const float *p = c->xyz + ((size_t)fr * (size_t)c->npoints + (size_t)idx[k]) * 3u;
            put_cell(f, p[0]);
            put_cell(f, p[1]);
            put_cell(f, p[2]);
        }
        fputc('\n', f);
    }
    free(idx);
    if (fclose(f) != 0) {
        (void)snprintf(why, C3D_ERR_MAX, "cannot write %s", o->out);
        return -2;
    }
    return 0;
}

static void json_src(const char *key, const char *src)
{
    printf(",\"%s\":", key);
    json_out_str(stdout, src != NULL ? src : "", 0);
}

static void print_c3d_json(const c3d_t *c)
{
    int k;
    printf("{\"status\":\"ok\",\"processor\":%d,\"processor_name\":\"%s\",\"points\":%d,"
           "\"frames\":%ld,\"first_frame\":%ld,\"rate\":%.9g,\"scale\":%.9g,"
           "\"storage\":\"%s\",\"analog_channels\":%d,\"analog_per_frame\":%d,"
           "\"analog_words\":%ld,\"analog_rate\":%.9g,\"frames_in_file\":%ld,"
           "\"data_start_byte\":%lu,\"parameter_section\":%s,\"zero_samples\":%ld,\"units\":",
           c->processor, c3d_processor_name(c->processor), c->npoints, c->nframes,
           c->first_frame, (double)c->rate, (double)c->scale, c->word == 4 ? "float" : "integer",
           c->analog_channels, c->analog_per_frame, c->analog_words, (double)c->analog_rate,
           c->frames_in_file, (unsigned long)c->data_start, c->nentries > 0 ? "true" : "false",
           c->zero_samples);
    json_out_str(stdout, c->units, 0);
    printf(",\"sources\":{\"processor\":");
    json_out_str(stdout, c->src_processor, 0);
    json_src("points", c->src_points);
    json_src("frames", c->src_frames);
    json_src("scale", c->src_scale);
    json_src("rate", c->src_rate);
    json_src("analog", c->src_analog);
    printf("},\"warnings\":[");
    for (k = 0; k < c->nwarn; k++) {
        if (k > 0) {
            putchar(',');
        }
        json_out_str(stdout, c->warnings[k], 0);
    }
    printf("],\"warnings_dropped\":%d,\"labels\":[", c->nwarn_dropped);
    for (k = 0; k < c->npoints; k++) {
        if (k > 0) {
            putchar(',');
        }
        json_out_str(stdout, c->labels[k], 0);
    }
    printf("]}\n");
}

/* The subject prefix every label shares ("P01:"), or "". */
static void common_prefix(const c3d_t *c, char *out, size_t size)
{
    char p[C3D_LABEL_MAX], q[C3D_LABEL_MAX];
    int k;
    out[0] = '\0';
    if (c->npoints < 1) {
        return;
    }
    c3d_label_prefix(c, 0, p, sizeof p);
    for (k = 1; k < c->npoints; k++) {
        c3d_label_prefix(c, k, q, sizeof q);
        if (strcmp(p, q) != 0) {
            return;
        }
    }
    (void)snprintf(out, size, "%s", p);
}

/* --add TABLE: frame,NAME_X,NAME_Y,NAME_Z,... into nframes x n x 3 (NaN where absent). */
static int read_added(const char *path, const c3d_t *c, char ***names, int *n, float **xyz,
                      char *why)
{
    table_t t;
    int *cols = NULL, k, m = 0, rc;
    float *vals = NULL;
    *names = NULL;
    *xyz = NULL;
    *n = 0;
    if (table_open_file(&t, path) != 0) {
        (void)snprintf(why, C3D_ERR_MAX, "cannot open %s: %s", path, strerror(errno));
        return -1;
    }
    if (table_start(&t) != 0 || !t.header || t.ncols < 4) {
        (void)snprintf(why, C3D_ERR_MAX,
                       "%s: a table with a header frame,NAME_X,NAME_Y,NAME_Z,... is needed", path);
        table_close(&t);
        return -1;
    }
    cols = malloc((size_t)t.ncols * sizeof *cols);
    *names = calloc((size_t)t.ncols, sizeof **names);
    if (cols == NULL || *names == NULL) {
        goto oom;
    }
    cols[0] = 0;
    for (k = 1; k + 2 < t.ncols; k += 3) {
        const char *h = t.names[k];
        const size_t l = strlen(h);
        char *nm;
        if (l < 3u || strcmp(h + l - 2u, "_X") != 0 || strncmp(t.names[k + 1], h, l - 2u) != 0
            || strcmp(t.names[k + 1] + l - 2u, "_Y") != 0
            || strncmp(t.names[k + 2], h, l - 2u) != 0
            || strcmp(t.names[k + 2] + l - 2u, "_Z") != 0) {
            (void)snprintf(why, C3D_ERR_MAX, "%s: columns %d-%d are not NAME_X,NAME_Y,NAME_Z",
                           path, k + 1, k + 3);
            goto bad;
        }
        nm = malloc(l - 1u);
        if (nm == NULL) {
            goto oom;
        }
        memcpy(nm, h, l - 2u);
        nm[l - 2u] = '\0';
        (*names)[m++] = nm;
        cols[k] = k;
        cols[k + 1] = k + 1;
        cols[k + 2] = k + 2;
    }
    if (m < 1 || 1 + 3 * m != t.ncols) {
        (void)snprintf(why, C3D_ERR_MAX, "%s: frame, then x,y,z column triples", path);
        goto bad;
    }
    *n = m;
    vals = malloc((size_t)t.ncols * sizeof *vals);
    *xyz = malloc(((size_t)c->nframes * (size_t)m * 3u + 1u) * sizeof **xyz);
    if (vals == NULL || *xyz == NULL || table_select_idx(&t, cols, t.ncols) != 0) {
        goto oom;
    }
    for (k = 0; (size_t)k < (size_t)c->nframes * (size_t)m * 3u; k++) {
        (*xyz)[k] = NAN;
    }
    while ((rc = table_next(&t, vals)) != TABLE_EOF) {
        const float fr = vals[0];
        if (rc != TABLE_ROW_OK || !(fr >= 0.0f) || fr != floorf(fr) || fr >= (float)c->nframes) {
            (void)snprintf(why, C3D_ERR_MAX, "%s line %lu: a frame 0 to %ld and numbers expected",
                           path, t.lineno, c->nframes - 1);
            goto bad;
        }
        memcpy(*xyz + (size_t)fr * (size_t)m * 3u, vals + 1, (size_t)m * 3u * sizeof *vals);
    }
    table_close(&t);
    free(cols);
    free(vals);
    return 0;
oom:
    (void)snprintf(why, C3D_ERR_MAX, "out of memory");
bad:
    table_close(&t);
    free(cols);
    free(vals);
    free(*xyz);
    *xyz = NULL;
    if (*names != NULL) {
        for (k = 0; k < m; k++) {
            free((*names)[k]);
        }
        free(*names);
        *names = NULL;
    }
    *n = 0;
    return -1;
}

/* --add / --write / --trc. 0, or -1 with why. */
static int write_outputs(const c3d_opts_t *o, const c3d_t *c, char *why)
{
    char **names = NULL, prefix[C3D_LABEL_MAX];
    float *xyz = NULL;
    int n = 0, k, rc = 0, to_float = 0;
    c3d_add_t add;
    if (o->prefix != NULL) {
        (void)snprintf(prefix, sizeof prefix, "%s", o->prefix);
    } else {
        common_prefix(c, prefix, sizeof prefix);
    }
    if (o->add != NULL && read_added(o->add, c, &names, &n, &xyz, why) != 0) {
        return -1;
    }
    memset(&add, 0, sizeof add);
    add.n = n;
    add.names = (const char *const *)names;
    add.xyz = xyz;
    add.prefix = prefix;
    if (o->write != NULL) {
        rc = c3d_write_added_file(o->file, o->write, &add, &to_float, why);
        if (rc == 0 && to_float) {
            fprintf(stderr, "sfit: note: %s: an added point does not fit 16-bit integers times "
                            "POINT:SCALE; written with float storage\n", o->write);
        }
    }
    if (rc == 0 && o->trc != NULL) {
        rc = c3d_write_trc(o->trc, c, n > 0 ? &add : NULL, why);
    }
    for (k = 0; k < n; k++) {
        free(names[k]);
    }
    free(names);
    free(xyz);
    return rc;
}

int cli_cmd_c3d(int argc, char **argv)
{
    c3d_opts_t o;
    c3d_t c;
    char err[C3D_ERR_MAX];
    int k;
    {
        const int prc = c3d_parse_args(argc, argv, &o);
        if (prc >= 0) {
            return prc;
        }
    }
    if (c3d_read_file(o.file, &c, err) != 0) {
        return cli_input_failed(-2, o.file, err, o.json);
    }
    if ((o.add != NULL) != (o.write != NULL) || (o.prefix != NULL && o.add == NULL)) {
        c3d_free(&c);
        fprintf(stderr, "sfit: --add and --write go together (--prefix with them)\n");
        c3d_usage(stderr);
        return CLI_USAGE;
    }
    if ((o.write != NULL || o.trc != NULL) && write_outputs(&o, &c, err) != 0) {
        c3d_free(&c);
        return cli_input_failed(-2, o.file, err, o.json);
    }
    if (o.out != NULL) {
        if (o.first >= c.nframes && c.nframes > 0) {
            (void)snprintf(err, sizeof err, "--frames starts at %ld; the file has %ld frames",
                           o.first, c.nframes);
            c3d_free(&c);
            return cli_input_failed(-2, o.file, err, o.json);
        }
        if (export_table(&o, &c, err) != 0) {
            c3d_free(&c);
            return cli_input_failed(-2, o.file, err, o.json);
        }
    }
    if (o.json) {
        print_c3d_json(&c);
    } else {
        printf("file         %s\n", o.file);
        printf("processor    %d (%s; from the %s)\n", c.processor,
               c3d_processor_name(c.processor), c.src_processor);
        printf("points       %d (%s), %s storage (scale %g, %s)\n", c.npoints, c.src_points,
               c.word == 4 ? "float" : "16-bit integer", (double)c.scale, c.src_scale);
        printf("frames       %ld (%s; first frame number %ld), %g Hz (%s), units '%s'\n",
               c.nframes, c.src_frames, c.first_frame, (double)c.rate, c.src_rate, c.units);
        printf("analog       %d channels x %d samples per frame = %ld words (%s)\n",
               c.analog_channels, c.analog_per_frame, c.analog_words, c.src_analog);
        for (k = 0; k < c.nwarn; k++) {
            printf("warning      %s\n", c.warnings[k]);
        }
        printf("labels      ");
        for (k = 0; k < c.npoints; k++) {
            printf(" %s", c.labels[k]);
        }
        printf("\n");
    }
    c3d_free(&c);
    return CLI_OK;
}
