/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_joint.c
 * @brief `sfit joint`: the functional joint centre from a recording.
 *
 *   sfit joint FILE --parent A,B,C[,...] --child D,E[,...] [--frames F:L]
 *              [--noise-var V|auto] [--mode auto|sphere|planar]
 *              [--no-repair-swaps] [--trajectory OUT.csv] [--json]
 *
 * FILE is a C3D file or a wide table (frames.h). The parent cluster is
 * registered frame by frame on its template, every child marker is mapped
 * into the parent frame and accumulated, and the multi-marker solve gives
 * the centre (and the axis of a hinge) in the parent frame (joint_run.h).
 * Before that, label swaps within the parent and within the child markers
 * are found from their distances and repaired (swaps.h).
 * --trajectory writes frame,x,y,z: the centre in the lab frame at every
 * frame used (frame = 0-based index in the file).
 *
 * Exit status as `fit`: 0 ok, 1 the computation failed, 2 usage, 3 file
 * error (cannot open, malformed, marker missing).
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "c3d.h"
#include "c3d_write.h"
#include "cli.h"
#include "cli_joint.h"
#include "swaps.h"

typedef struct joint_opts {
    const char *file;
    char *trajectory;
    char *write, *trc, *name; /* --write OUT.c3d, --trc OUT.trc, --name JC */
    int json;
    char *names[FRAMES_MARKERS_MAX]; /* parent markers, then child markers */
    int np, nc;
    joint_run_opts_t j;
} joint_opts_t;

static void joint_usage(FILE *f)
{
    fputs("usage: sfit joint FILE --parent A,B,C[,...] --child D,E[,...] [--frames F:L]\n"
          "                  [--noise-var V|auto] [--mode auto|sphere|planar]\n"
          "                  [--method default|score|sara|mgdk] [--no-repair-swaps]\n"
          "                  [--trajectory OUT.csv] [--write OUT.c3d] [--trc OUT.trc]\n"
          "                  [--name JC] [--json]\n"
          "  FILE  a C3D file, or a table with a header and one x,y,z column triple per\n"
          "        marker: NAME_X NAME_Y NAME_Z (also NAME.x, NAME:X, NAME-X, 'NAME X';\n"
          "        any case); other columns (time, frame) are ignored; blank cell = missing\n"
          "  --parent LIST    3 or more markers of the parent segment (a rigid cluster)\n"
          "  --child LIST     markers of the child segment\n" CLI_JOINT_USAGE
          "  --trajectory OUT write frame,x,y,z: the centre in the lab frame at every frame\n"
          "                   used (frame: 0-based index in FILE)\n"
          "  --write OUT.c3d  FILE (a C3D file) with the centre added as a point NAME (in the\n"
          "                   frames used; residual -1 elsewhere), for a hinge also NAME_AX1\n"
          "                   and NAME_AX2 on the axis, 100 mm either side; the subject\n"
          "                   prefix of the first parent marker ('P01:') is put before them;\n"
          "                   nothing else in the file changes (docs/c3d.md)\n"
          "  --trc OUT.trc    an OpenSim marker file: every marker of FILE and the new points\n"
          "  --name NAME      the new point's label (default JC)\n"
          "  --json           one JSON object on stdout\n"
          "The centre is given in the parent frame: the template frame of the parent\n"
          "cluster (origin at the centroid of its markers' template, axes the lab axes\n"
          "at the reference frame, the first frame of the range with every parent marker).\n",
          f);
}

/* Split LIST into lo..room marker names; one message and -1 otherwise. */
static int marker_list(char *arg, char **dst, int lo, int room, const char *what)
{
    const int n = frames_split_list(arg, dst, room);
    if (n < lo) {
        fprintf(stderr, "sfit: %s needs %d to %d comma-separated marker names\n", what, lo,
                room);
        return -1;
    }
    return n;
}

/* -1 to go on, or the exit status (cli_parse). */
static int joint_parse(int argc, char **argv, joint_opts_t *o)
{
    char *parent = NULL, *child = NULL;
    const cli_opt_t opts[] = {
        CLI_JOINT_OPTS(&o->j),
        {.name = "--json", .kind = CLI_OPT_FLAG, .dst = &o->json},
        {.name = "--parent", .kind = CLI_OPT_STRING, .dst = &parent, .required = 1},
        {.name = "--child", .kind = CLI_OPT_STRING, .dst = &child, .required = 1},
        {.name = "--trajectory", .kind = CLI_OPT_STRING, .dst = &o->trajectory},
        {.name = "--write", .kind = CLI_OPT_STRING, .dst = &o->write},
        {.name = "--trc", .kind = CLI_OPT_STRING, .dst = &o->trc},
        {.name = "--name", .kind = CLI_OPT_STRING, .dst = &o->name},
    };
    const cli_args_t args = {.opts = opts, .nopts = sizeof opts / sizeof opts[0],
                             .pos = &o->file, .max_pos = 1, .min_pos = 1,
                             .extra = "one FILE expected",
                             .missing = "FILE, --parent and --child are required",
                             .required = "FILE, --parent and --child are required",
                             .usage = joint_usage};
    int rc;
    memset(o, 0, sizeof *o);
    joint_run_opts_default(&o->j);
    rc = cli_parse(argc, argv, &args);
    if (rc >= 0) {
        return rc;
    }
    o->np = marker_list(parent, o->names, 3, SFIT_CLUSTER_MAX_MARKERS, "--parent");
    o->nc = (o->np < 0) ? -1
                        : marker_list(child, o->names + o->np, 1, SFIT_JOINT_MAX_CHILD, "--child");
    return (o->nc < 0) ? cli_parse_outcome(-1, joint_usage) : -1;
}

static const char *method_name(const sfit_multi_result_t *r)
{
    return r->method == SFIT_METHOD_UGDK ? "ugdk" : "gdke";
}

static void print_json(const joint_opts_t *o, const frames_data_t *fr, const joint_run_out_t *jo,
                       long last, const sfit_vec3_t *lab_ref, const swaps_joint_t *sw)
{
    const sfit_multi_result_t *r = &jo->res.fit;
    int k;
    printf("{\"status\":\"ok\",\"method\":\"%s\",\"mode\":\"%s\",\"frame\":\"parent_template\","
           "\"reference_frame\":%ld,\"first\":%ld,\"last\":%ld,\"frames_used\":%ld,"
           "\"frames_rejected\":%ld,\"bad_rows\":%ld,\"zero_missing\":%ld,"
           "\"template_frames\":%lu,\"n\":%lu,\"center\":",
           jo->pair_used ? jo->method_name : method_name(r),
           r->mode == SFIT_MODE_PLANAR ? "planar" : "sphere", jo->ref_frame,
           o->j.first, last, jo->used, jo->rejected, fr->bad_rows, fr->zero_missing,
           jo->template_frames,
           (unsigned long)r->n_total);
    json_out_vec(stdout, r->center.v);
    printf(",\"center_lab_reference\":");
    if (lab_ref != NULL) {
        json_out_vec(stdout, lab_ref->v);
    } else {
        printf("null");
    }
    if (r->mode == SFIT_MODE_PLANAR) {
        printf(",\"axis\":");
        json_out_vec(stdout, r->axis.v);
    }
    printf(",\"eigenvalues\":");
    json_out_vec(stdout, r->eigenvalues.v);
    printf(",\"trust_ratio\":%.9g,\"leontief_ratio\":%.9g,\"flags\":", (double)r->trust_ratio,
           (double)r->leontief_ratio);
    cli_joint_print_flags_json(jo);
    cli_print_noise_json(jo->has_noise, jo->noise_var, jo->noise_estimated);
    cli_joint_print_pair_json(jo);
    printf(",\"residual_mean\":%.9g,\"residual_max\":%.9g,\"units\":",
           (double)jo->res.residual_mean, (double)jo->res.residual_max);
    json_out_str(stdout, fr->units, 0);
    printf(",\"rate\":%.9g,\"parent\":[", (double)fr->rate);
    for (k = 0; k < o->np; k++) {
        printf("%s{\"name\":", k > 0 ? "," : "");
        json_out_str(stdout, o->names[k], 0);
        printf(",\"template\":");
        json_out_vec(stdout, jo->j.parent.pos[k].v);
        printf("}");
    }
    printf("],\"markers\":[");
    for (k = 0; k < o->nc; k++) {
        printf("%s{\"name\":", k > 0 ? "," : "");
        json_out_str(stdout, o->names[o->np + k], 0);
        printf(",\"n\":%lu,\"radius\":", jo->child_n[k]);
        if (jo->radii[k] > 0.0f) {
            printf("%.9g}", (double)jo->radii[k]);
        } else {
            printf("null}");
        }
    }
    printf("]");
    cli_swaps_json(sw, (const char *const *)o->names, o->np);
    printf("}\n");
}

static void print_human(const joint_opts_t *o, const frames_data_t *fr, const joint_run_out_t *jo,
                        long last, const sfit_vec3_t *lab_ref, const swaps_joint_t *sw)
{
    const sfit_multi_result_t *r = &jo->res.fit;
    const char *u = fr->units[0] != '\0' ? fr->units : "units";
    int k;
    printf("file         %s (%s", o->file, fr->is_c3d ? "C3D" : "table");
    if (fr->rate > 0.0f) {
        printf(", %g Hz", (double)fr->rate);
    }
    printf(", %ld frames)\n", fr->nframes);
    printf("frames       %ld to %ld: %ld used, %ld rejected (parent not registrable)\n",
           o->j.first, last, jo->used, jo->rejected);
    if (fr->bad_rows > 0) {
        printf("warning      %ld table rows did not parse (read as missing markers)\n",
               fr->bad_rows);
    }
    if (fr->zero_missing > 0) {
        printf("missing      %ld marker samples at exactly (0, 0, 0) taken as missing\n",
               fr->zero_missing);
    }
    printf("parent       ");
    for (k = 0; k < o->np; k++) {
        printf("%s%s", k > 0 ? " " : "", o->names[k]);
    }
    printf("\nchild        ");
    for (k = 0; k < o->nc; k++) {
        printf("%s%s", k > 0 ? " " : "", o->names[o->np + k]);
    }
    printf("\n");
    cli_swaps_human(sw, (const char *const *)o->names, o->np, u, "label swaps  ",
                          "             ");
    printf("method       %s, %s\n",
           jo->pair_used ? (strcmp(jo->method_name, "default") == 0
                                ? "SCoRE/SARA from the two clusters' poses, bias removed"
                                : jo->method_name)
           : r->method == SFIT_METHOD_UGDK ? "unbiased MGDK" : "MGDK",
           r->mode == SFIT_MODE_PLANAR ? "hinge (planar solution: axis, centre on it)"
                                       : "ball joint (sphere solution)");
    printf("centre       %.4f %.4f %.4f %s (parent frame)\n", (double)r->center.v[0],
           (double)r->center.v[1], (double)r->center.v[2], u);
    if (r->mode == SFIT_MODE_PLANAR) {
        printf("axis         %.5f %.5f %.5f (parent frame)\n", (double)r->axis.v[0],
               (double)r->axis.v[1], (double)r->axis.v[2]);
    }
    printf("parent frame template frame of the parent cluster: origin at the centroid of\n"
           "             its %d markers (template averaged over %lu frames), axes the lab\n"
           "             axes at the reference frame %ld\n",
           o->np, jo->template_frames, jo->ref_frame);
    cli_joint_print_pair_text(jo, u, "");
    if (lab_ref != NULL) {
        printf("centre (lab) %.4f %.4f %.4f at frame %ld\n", (double)lab_ref->v[0],
               (double)lab_ref->v[1], (double)lab_ref->v[2], jo->ref_frame);
    }
    printf("registration RMS residual of the parent cluster: mean %.4g, max %.4g %s\n",
           (double)jo->res.residual_mean, (double)jo->res.residual_max, u);
    if (jo->has_noise) {
        printf("noise var    %.6g %s^2 (%s)\n", (double)jo->noise_var, u,
               jo->noise_estimated
                   ? "child markers in the parent frame, estimated: self-calibrated UGDK, pooled"
                   : "given, per marker coordinate; propagated through the parent pose");
    }
    printf("eigenvalues  %.6g %.6g %.6g (%s)\n", (double)r->eigenvalues.v[0],
           (double)r->eigenvalues.v[1], (double)r->eigenvalues.v[2],
           jo->pair_used ? "spread of the relative rotations, rad^2" : "of sum_p w_p C_p");
    printf("per marker   %s:\n",
           r->mode == SFIT_MODE_PLANAR ? "distance from the axis" : "radius about the centre");
    for (k = 0; k < o->nc; k++) {
        if (jo->radii[k] > 0.0f) {
            printf("  %-10s %10.4f (%lu samples)\n", o->names[o->np + k], (double)jo->radii[k],
                   jo->child_n[k]);
        } else {
            printf("  %-10s    skipped (%lu samples)\n", o->names[o->np + k], jo->child_n[k]);
        }
    }
    if (!jo->pair_used && (r->flags & SFIT_FLAG_UNTRUSTED)) {
        printf("warning      Leontief ratio %.3g >= 1: do not trust this fit\n",
               (double)r->leontief_ratio);
    }
    if (!jo->pair_used && (r->flags & SFIT_FLAG_NEAR_PLANAR) && r->mode == SFIT_MODE_SPHERE) {
        printf("warning      the markers' arcs are near-planar: the sphere is ill-conditioned "
               "(a hinge? try --mode planar)\n");
    }
}

/* --trajectory: frame,x,y,z in the lab frame for every frame used. */
static int write_trajectory(const joint_opts_t *o, const frames_data_t *fr,
                            const joint_run_out_t *jo, long last)
{
    FILE *f = fopen(o->trajectory, "w");
    long k;
    if (f == NULL) {
        fprintf(stderr, "sfit: cannot write %s: %s\n", o->trajectory, strerror(errno));
        return -1;
    }
    fprintf(f, "frame,x,y,z\n");
    for (k = o->j.first; k <= last; k++) {
        sfit_vec3_t c;
        if (jo->ok[k] && joint_run_lab(fr, o->np, jo, k, &c, NULL) == SFIT_OK) {
            fprintf(f, "%ld,%.9g,%.9g,%.9g\n", k, (double)c.v[0], (double)c.v[1], (double)c.v[2]);
        }
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "sfit: cannot write %s\n", o->trajectory);
        return -1;
    }
    return 0;
}

/* --write / --trc: the recording with the centre (and a hinge's axis points). */
static int write_c3d_points(const joint_opts_t *o, const frames_data_t *fr,
                            const joint_run_out_t *jo, long last)
{
    const int hinge = jo->res.fit.mode == SFIT_MODE_PLANAR;
    const int n = hinge ? 3 : 1;
    const char *base = (o->name != NULL) ? o->name : "JC";
    char n1[C3D_LABEL_MAX], n2[C3D_LABEL_MAX], prefix[C3D_LABEL_MAX], err[C3D_ERR_MAX];
    const char *names[3];
    unsigned char *buf = NULL;
    size_t len = 0;
    c3d_t c;
    c3d_add_t add;
    float *xyz;
    float d = 100.0f; /* the axis points: 100 mm either side of the centre */
    long k;
    int rc = -1, to_float = 0;
    if (!fr->is_c3d) {
        fprintf(stderr, "sfit: --write and --trc need a C3D file\n");
        return -1;
    }
    if (strcmp(fr->units, "m") == 0) {
        d = 0.1f;
    } else if (strcmp(fr->units, "cm") == 0) {
        d = 10.0f;
    }
    (void)snprintf(n1, sizeof n1, "%.50s_AX1", base);
    (void)snprintf(n2, sizeof n2, "%.50s_AX2", base);
    names[0] = base;
    names[1] = n1;
    names[2] = n2;
    if (c3d_load_bytes(o->file, &buf, &len, err) != 0 || c3d_parse(buf, len, &c, err) != 0) {
        fprintf(stderr, "sfit: %s\n", err);
        free(buf);
        return -1;
    }
    xyz = malloc(((size_t)c.nframes * (size_t)n * 3u + 1u) * sizeof *xyz);
    if (xyz == NULL || c.nframes != fr->nframes) {
        fprintf(stderr, "sfit: %s\n", xyz == NULL ? "out of memory" : "the file changed while read");
        goto out;
    }
    for (k = 0; k < c.nframes * n * 3; k++) {
        xyz[k] = NAN;
    }
    for (k = o->j.first; k <= last; k++) {
        sfit_vec3_t ctr, ax;
        float *p = xyz + (size_t)k * (size_t)n * 3u;
        int i;
        if (!jo->ok[k] || joint_run_lab(fr, o->np, jo, k, &ctr, hinge ? &ax : NULL) != SFIT_OK) {
            continue;
        }
        for (i = 0; i < 3; i++) {
            p[i] = ctr.v[i];
            if (hinge) {
                p[3 + i] = ctr.v[i] - d * ax.v[i];
                p[6 + i] = ctr.v[i] + d * ax.v[i];
            }
        }
    }
    c3d_label_prefix(&c, c3d_find(&c, o->names[0]), prefix, sizeof prefix);
    memset(&add, 0, sizeof add);
    add.n = n;
    add.names = names;
    add.xyz = xyz;
    add.prefix = prefix;
    if (o->write != NULL && c3d_write_added(buf, len, &c, &add, o->write, &to_float, err) != 0) {
        fprintf(stderr, "sfit: %s\n", err);
        goto out;
    }
    if (to_float) {
        fprintf(stderr, "sfit: note: %s written with float storage (the new points do not fit "
                        "16-bit integers times POINT:SCALE)\n", o->write);
    }
    if (o->trc != NULL && c3d_write_trc(o->trc, &c, &add, err) != 0) {
        fprintf(stderr, "sfit: %s\n", err);
        goto out;
    }
    rc = 0;
out:
    free(xyz);
    c3d_free(&c);
    free(buf);
    return rc;
}

int cli_cmd_joint(int argc, char **argv)
{
    joint_opts_t o;
    frames_data_t fr;
    joint_run_out_t jo;
    swaps_joint_t sw;
    char why[FRAMES_ERR_MAX];
    sfit_vec3_t lab;
    long last;
    int rc;

    {
        const int prc = joint_parse(argc, argv, &o);
        if (prc >= 0) {
            return prc;
        }
    }
    rc = frames_load(o.file, (const char *const *)o.names, o.np + o.nc, &fr, why);
    if (rc != 0) {
        return cli_input_failed(rc, o.file, why, o.json);
    }
    last = (o.j.last < 0 || o.j.last >= fr.nframes) ? fr.nframes - 1 : o.j.last;
    if (o.j.first >= fr.nframes) {
        char msg[96];
        (void)snprintf(msg, sizeof msg, "--frames starts at %ld; the file has %ld frames",
                       o.j.first, fr.nframes);
        frames_free(&fr);
        return cli_input_failed(-2, o.file, msg, o.json);
    }
    if (swaps_joint_run(&fr, o.np, o.nc, o.j.first, last, !o.j.no_repair_swaps, &sw) != 0) {
        frames_free(&fr);
        if (o.json) {
            return cli_json_error("out_of_memory", "label swap check: out of memory");
        }
        fprintf(stderr, "sfit: label swap check: out of memory\n");
        return CLI_FAIL;
    }
    if (joint_run(&fr, o.np, o.nc, &o.j, &jo) != SFIT_OK) {
        const sfit_status_t st = jo.st;
        if (o.json) {
            printf("{\"status\":\"%s\",\"message\":\"%s\",\"stage\":\"%s\",\"frames_used\":%ld,"
                   "\"frames_rejected\":%ld}\n",
                   sfit_status_str(st),
                   (st == SFIT_E_TOO_FEW && strcmp(jo.stage, "template") == 0)
                       ? "no frame sees every parent marker"
                       : names_status_message(st, NAMES_CLI),
                   jo.stage, jo.used, jo.rejected);
        } else {
            fprintf(stderr, "sfit: joint failed at the %s stage (%s): %s (%ld frames used, %ld "
                            "rejected)\n",
                    jo.stage, sfit_status_str(st),
                    (st == SFIT_E_TOO_FEW && strcmp(jo.stage, "template") == 0)
                        ? "no frame sees every parent marker"
                        : names_status_message(st, NAMES_CLI),
                    jo.used, jo.rejected);
        }
        joint_run_free(&jo);
        swaps_joint_free(&sw);
        frames_free(&fr);
        return CLI_FAIL;
    }
    rc = (jo.ref_frame >= 0 && joint_run_lab(&fr, o.np, &jo, jo.ref_frame, &lab, NULL) == SFIT_OK);
    if (o.json) {
        print_json(&o, &fr, &jo, last, rc ? &lab : NULL, &sw);
    } else {
        print_human(&o, &fr, &jo, last, rc ? &lab : NULL, &sw);
    }
    rc = CLI_OK;
    if (o.trajectory != NULL && write_trajectory(&o, &fr, &jo, last) != 0) {
        rc = CLI_IO;
    }
    if ((o.write != NULL || o.trc != NULL) && write_c3d_points(&o, &fr, &jo, last) != 0) {
        rc = CLI_IO;
    }
    joint_run_free(&jo);
    swaps_joint_free(&sw);
    frames_free(&fr);
    return rc;
}
