/* SPDX-License-Identifier: MIT */
/** @file session.c  The calibrated session as JSON: writer and reader (session.h). */
#include "session.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "json_out.h"

/* ------------------------------------------------------------------ writer */

/* A written point's C3D description: the joint and where its centre is
 * put (the session's convention, shortened to fit a description). */
void session_point_desc(const session_joint_t *j, int q, char *d, size_t cap)
{
    const char *conv = j->convention;
    const char *near = strstr(conv, "mid-point of ");
    if (q > 0) {
        (void)snprintf(d, cap, "%.40s hinge axis point %d", j->name, q);
    } else if (!j->hinge) {
        (void)snprintf(d, cap, "%.40s centre (functional)", j->name);
    } else if (near != NULL && strstr(conv, "landmarks") == NULL) {
        (void)snprintf(d, cap, "%.20s centre: axis nearest %.50s", j->name, near);
    } else {
        (void)snprintf(d, cap, "%.40s centre on the functional axis", j->name);
    }
}

void session_write_json(FILE *f, const session_t *s, const json_out_flag_t *flag_names,
                        size_t nflag_names)
{
    int i, k;
    fprintf(f, "{\"format\":\"sfit-session\",\"version\":1,\"units\":");
    json_out_str(f, s->units, 0);
    fprintf(f, ",\"root\":");
    json_out_str(f, s->seg[s->root].name, 0);
    fprintf(f, ",\n\"segments\":[");
    for (i = 0; i < s->nseg; i++) {
        fprintf(f, "%s{\"name\":", i > 0 ? ",\n  " : "\n  ");
        json_out_str(f, s->seg[i].name, 0);
        fprintf(f, ",\"markers\":[");
        for (k = 0; k < s->seg[i].nmarkers; k++) {
            if (k > 0) {
                fputc(',', f);
            }
            json_out_str(f, s->seg[i].markers[k], 0);
        }
        fprintf(f, "]}");
    }
    fprintf(f, "],\n\"joints\":[");
    for (i = 0; i < s->njoint; i++) {
        const session_joint_t *j = &s->joint[i];
        fprintf(f, "%s{\"name\":", i > 0 ? ",\n " : "\n ");
        json_out_str(f, j->name, 0);
        fprintf(f, ",\"parent\":");
        json_out_str(f, j->parent, 0);
        fprintf(f, ",\"child\":");
        json_out_str(f, j->child, 0);
        fprintf(f, ",\"type\":\"%s\",\"points\":[", j->hinge ? "hinge" : "ball");
        for (k = 0; k < j->npoints; k++) {
            if (k > 0) {
                fputc(',', f);
            }
            json_out_str(f, j->points[k], 0);
        }
        fprintf(f, "],\"trial\":");
        json_out_str(f, j->trial, 0);
        fprintf(f, ",\"frames_used\":%ld,\"frames\":%ld,\n  \"frame\":\"parent_template\","
                   "\"parent_markers\":[",
                j->frames_used, j->frames_total);
        for (k = 0; k < j->nmarkers; k++) {
            if (k > 0) {
                fputc(',', f);
            }
            json_out_str(f, j->markers[k], 0);
        }
        fprintf(f, "],\"template\":[");
        for (k = 0; k < j->nmarkers; k++) {
            if (k > 0) {
                fputc(',', f);
            }
            json_out_vec(f, j->tpl[k]);
        }
        fprintf(f, "],\n  \"center\":");
        json_out_vec(f, j->center);
        fprintf(f, ",\"axis\":");
        if (j->hinge) {
            json_out_vec(f, j->axis);
        } else {
            fprintf(f, "null");
        }
        fprintf(f, ",\n  \"center_convention\":");
        json_out_str(f, j->convention, 0);
        fprintf(f, ",\"template_reference_frame\":%ld,\"point_descriptions\":[", j->ref_frame);
        for (k = 0; k < j->npoints; k++) {
            char d[SESSION_DESC_MAX];
            session_point_desc(j, k, d, sizeof d);
            if (k > 0) {
                fputc(',', f);
            }
            json_out_str(f, d, 0);
        }
        fputc(']', f);
        fprintf(f, ",\n  \"center_cov\":[");
        for (k = 0; k < 3; k++) {
            if (k > 0) {
                fputc(',', f);
            }
            json_out_vecd(f, j->cov[k]);
        }
        fprintf(f, "],\"semi_axes_95\":");
        json_out_vecd(f, j->semi95);
        fprintf(f, ",\n  \"misfit\":%.9g,\"model_rms\":%.9g,\"jackknife_ratio\":%.9g,"
                   "\"model_scale\":%.9g,\"center_cov_jackknife\":",
                j->misfit, j->model_rms, j->jack_ratio, j->model_scale);
        json_out_matd(f, j->cov_jack);
        fprintf(f, ",\n  \"center_cov_model\":");
        json_out_matd(f, j->cov_model);
        fprintf(f, ",\"semi_axes_95_model\":");
        json_out_vecd(f, j->semi95_model);
        fprintf(f, ",\n  \"skin_rms\":%.9g,\"semi_axes_95_skin\":", j->skin_rms);
        json_out_vecd(f, j->semi95_skin);
        if (j->hinge) {
            fprintf(f, ",\"axis_cone_95_deg\":%.9g,\"axis_cone_95_model_deg\":%.9g,"
                       "\"wobble_rms_deg\":%.9g",
                    j->cone_deg, j->cone_model_deg, j->wobble_deg);
        }
        fprintf(f, ",\n  \"marker_sigma\":%.9g,\"rotation_range_deg\":", j->marker_sigma);
        json_out_vecd(f, j->range_deg);
        if (j->hinge) {
            fprintf(f, ",\"flexion_range_deg\":%.9g", j->flex_deg);
        }
        fprintf(f, ",\"flags\":");
        json_out_flags(f, j->flags, flag_names, nflag_names);
        fprintf(f, ",\"flag_bits\":%lu,\n  \"verdict\":", (unsigned long)j->flags);
        json_out_str(f, j->verdict, 0);
        fprintf(f, "}");
    }
    fprintf(f, "]}\n");
}

/* ------------------------------------------------------------------ reader */

enum { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ };

#define J_DEPTH_MAX 8
#define J_NODES_MAX 8192 /* a session of 32 joints of 8 markers needs about 3700 */
#define J_STR_MAX 600

typedef struct jnode {
    int type;
    double num;
    char str[J_STR_MAX];  /* string value, or the member's key */
    char key[SM_NAME_MAX + 32];
    int first, next;      /* first child, next sibling (-1 none) */
    int count;
} jnode_t;

typedef struct jparser {
    const char *p, *end;
    jnode_t *n;
    int used;
    char *err;
} jparser_t;

static int jfail(jparser_t *jp, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(jp->err, SM_ERR_MAX, fmt, ap);
    va_end(ap);
    return -1;
}

static void jws(jparser_t *jp)
{
    while (jp->p < jp->end && (*jp->p == ' ' || *jp->p == '\n' || *jp->p == '\r'
                               || *jp->p == '\t')) {
        jp->p++;
    }
}

static int jstring(jparser_t *jp, char *dst, size_t cap)
{
    size_t n = 0;
    if (jp->p >= jp->end || *jp->p != '"') {
        return jfail(jp, "a string expected at byte %ld", (long)(jp->end - jp->p));
    }
    jp->p++;
    while (jp->p < jp->end && *jp->p != '"') {
        char c = *jp->p++;
        if ((unsigned char)c < 0x20) {
            return jfail(jp, "a control character in a string");
        }
        if (c == '\\') {
            if (jp->p >= jp->end) {
                break;
            }
            c = *jp->p++;
            if (c == 'u') {
                unsigned v = 0;
                int k;
                for (k = 0; k < 4; k++) {
                    const char h = (jp->p < jp->end) ? *jp->p++ : 'x';
                    v <<= 4;
                    if (h >= '0' && h <= '9') {
                        v |= (unsigned)(h - '0');
                    } else if (h >= 'a' && h <= 'f') {
                        v |= (unsigned)(h - 'a' + 10);
                    } else if (h >= 'A' && h <= 'F') {
                        v |= (unsigned)(h - 'A' + 10);
                    } else {
                        return jfail(jp, "a bad \\u escape");
                    }
                }
                if (v == 0 || v > 0x7f) {
                    return jfail(jp, "a \\u escape outside ASCII");
                }
                c = (char)v;
            } else if (c == 'n') {
                c = '\n';
            } else if (c == 't') {
                c = '\t';
            } else if (c != '"' && c != '\\' && c != '/') {
                return jfail(jp, "a bad escape \\%c", c);
            }
        }
        if (n + 1 >= cap) {
            return jfail(jp, "a string longer than %lu characters", (unsigned long)cap - 1);
        }
        dst[n++] = c;
    }
    if (jp->p >= jp->end) {
        return jfail(jp, "an unterminated string");
    }
    jp->p++;
    dst[n] = '\0';
    return 0;
}

static int jvalue(jparser_t *jp, int depth)
{
    int me;
    jnode_t *n;
    jws(jp);
    if (jp->p >= jp->end) {
        return jfail(jp, "the JSON ends early");
    }
    if (depth > J_DEPTH_MAX) {
        return jfail(jp, "nested deeper than %d", J_DEPTH_MAX);
    }
    if (jp->used >= J_NODES_MAX) {
        return jfail(jp, "more than %d values", J_NODES_MAX);
    }
    me = jp->used++;
    n = &jp->n[me];
    memset(n, 0, sizeof *n);
    n->first = n->next = -1;
    if (*jp->p == '{' || *jp->p == '[') {
        const int obj = *jp->p == '{';
        int last = -1;
        n->type = obj ? J_OBJ : J_ARR;
        jp->p++;
        jws(jp);
        if (jp->p < jp->end && *jp->p == (obj ? '}' : ']')) {
            jp->p++;
            return me;
        }
        for (;;) {
            char key[SM_NAME_MAX + 32] = "";
            int c;
            jws(jp);
            if (obj) {
                if (jstring(jp, key, sizeof key) != 0) {
                    return -1;
                }
                jws(jp);
                if (jp->p >= jp->end || *jp->p != ':') {
                    return jfail(jp, "':' expected after \"%s\"", key);
                }
                jp->p++;
            }
            c = jvalue(jp, depth + 1);
            if (c < 0) {
                return -1;
            }
            memcpy(jp->n[c].key, key, sizeof key);
            if (last < 0) {
                jp->n[me].first = c;
            } else {
                jp->n[last].next = c;
            }
            last = c;
            jp->n[me].count++;
            jws(jp);
            if (jp->p < jp->end && *jp->p == ',') {
                jp->p++;
                continue;
            }
            if (jp->p < jp->end && *jp->p == (obj ? '}' : ']')) {
                jp->p++;
                return me;
            }
            return jfail(jp, "',' or '%c' expected", obj ? '}' : ']');
        }
    }
    if (*jp->p == '"') {
        n->type = J_STR;
        return jstring(jp, n->str, sizeof n->str) == 0 ? me : -1;
    }
    if ((size_t)(jp->end - jp->p) >= 4 && memcmp(jp->p, "null", 4) == 0) {
        jp->p += 4;
        n->type = J_NULL;
        return me;
    }
    if ((size_t)(jp->end - jp->p) >= 4 && memcmp(jp->p, "true", 4) == 0) {
        jp->p += 4;
        n->type = J_BOOL;
        n->num = 1.0;
        return me;
    }
    if ((size_t)(jp->end - jp->p) >= 5 && memcmp(jp->p, "false", 5) == 0) {
        jp->p += 5;
        n->type = J_BOOL;
        return me;
    }
    {
        char num[64];
        size_t k = 0;
        char *e;
        while (jp->p < jp->end && k + 1 < sizeof num && strchr("+-0123456789.eE", *jp->p)) {
            num[k++] = *jp->p++;
        }
        num[k] = '\0';
        if (k == 0) {
            return jfail(jp, "a value expected");
        }
        errno = 0;
        n->num = strtod(num, &e);
        if (*e != '\0' || errno != 0 || !isfinite(n->num)) {
            return jfail(jp, "a bad number '%s'", num);
        }
        n->type = J_NUM;
        return me;
    }
}

static const jnode_t *jget(const jparser_t *jp, int obj, const char *key)
{
    int c;
    if (obj < 0 || jp->n[obj].type != J_OBJ) {
        return NULL;
    }
    for (c = jp->n[obj].first; c >= 0; c = jp->n[c].next) {
        if (strcmp(jp->n[c].key, key) == 0) {
            return &jp->n[c];
        }
    }
    return NULL;
}

/* A string member into dst (cap bytes). */
static int jget_str(jparser_t *jp, int obj, const char *key, char *dst, size_t cap)
{
    const jnode_t *n = jget(jp, obj, key);
    if (n == NULL || n->type != J_STR) {
        return jfail(jp, "\"%s\" missing or not a string", key);
    }
    if (strlen(n->str) >= cap) {
        return jfail(jp, "\"%s\" is too long", key);
    }
    strcpy(dst, n->str);
    return 0;
}

/* An array of n numbers (n < 0: any count up to -n; *count gets it). */
static int jnums(jparser_t *jp, const jnode_t *a, double *v, int n, const char *what)
{
    int c, k = 0;
    if (a == NULL || a->type != J_ARR || a->count != n) {
        return jfail(jp, "\"%s\" must be an array of %d numbers", what, n);
    }
    for (c = a->first; c >= 0; c = jp->n[c].next) {
        if (jp->n[c].type != J_NUM || !(fabs(jp->n[c].num) < 1e30)) {
            return jfail(jp, "\"%s\" must hold finite numbers", what);
        }
        v[k++] = jp->n[c].num;
    }
    return 0;
}

/* An array of strings (1..max names) into names; returns the count or -1. */
static int jnames(jparser_t *jp, const jnode_t *a, char (*names)[SM_NAME_MAX], int max,
                  const char *what)
{
    int c, k = 0;
    if (a == NULL || a->type != J_ARR || a->count < 1 || a->count > max) {
        return jfail(jp, "\"%s\" must be an array of 1 to %d names", what, max);
    }
    for (c = a->first; c >= 0; c = jp->n[c].next) {
        const size_t len = strlen(jp->n[c].str);
        if (jp->n[c].type != J_STR || len == 0 || len >= SM_NAME_MAX) {
            return jfail(jp, "\"%s\" must hold names of 1 to %d characters", what,
                         SM_NAME_MAX - 1);
        }
        strcpy(names[k++], jp->n[c].str);
    }
    return k;
}

/* An optional 3x3 member (absent: m unchanged); 0 or -1. */
static int jread_mat(jparser_t *jp, const jnode_t *n, double m[3][3], const char *joint,
                     const char *what)
{
    int c, k;
    if (n == NULL) {
        return 0;
    }
    if (n->type != J_ARR || n->count != 3) {
        return jfail(jp, "joint %s: \"%s\" must be 3 rows", joint, what);
    }
    for (c = n->first, k = 0; c >= 0; c = jp->n[c].next, k++) {
        if (jnums(jp, &jp->n[c], m[k], 3, what) != 0) {
            return -1;
        }
    }
    return 0;
}

static int read_joint(jparser_t *jp, int o, session_joint_t *j)
{
    const jnode_t *n;
    char type[16];
    double v[3];
    int c, k;
    memset(j, 0, sizeof *j);
    if (jget_str(jp, o, "name", j->name, sizeof j->name) != 0
        || jget_str(jp, o, "parent", j->parent, sizeof j->parent) != 0
        || jget_str(jp, o, "child", j->child, sizeof j->child) != 0
        || jget_str(jp, o, "type", type, sizeof type) != 0
        || jget_str(jp, o, "trial", j->trial, sizeof j->trial) != 0
        || jget_str(jp, o, "verdict", j->verdict, sizeof j->verdict) != 0) {
        return -1;
    }
    j->ref_frame = -1;
    n = jget(jp, o, "template_reference_frame"); /* absent in older sessions */
    if (n != NULL) {
        if (n->type != J_NUM || !(n->num >= -1.0 && n->num < 2147483647.0)
            || n->num != floor(n->num)) {
            return jfail(jp, "joint %s: \"template_reference_frame\" must be a frame index",
                         j->name);
        }
        j->ref_frame = (long)n->num;
    }
    if (jget(jp, o, "center_convention") != NULL /* absent in older sessions */
        && jget_str(jp, o, "center_convention", j->convention, sizeof j->convention) != 0) {
        return -1;
    }
    if (strcmp(type, "ball") != 0 && strcmp(type, "hinge") != 0) {
        return jfail(jp, "joint %s: type must be ball or hinge", j->name);
    }
    j->hinge = strcmp(type, "hinge") == 0;
    j->npoints = jnames(jp, jget(jp, o, "points"), j->points, 3, "points");
    if (j->npoints != (j->hinge ? 3 : 1)) {
        return j->npoints < 0 ? -1 : jfail(jp, "joint %s: a %s has %d point(s)", j->name, type,
                                           j->hinge ? 3 : 1);
    }
    j->nmarkers = jnames(jp, jget(jp, o, "parent_markers"), j->markers, SM_MARKERS_MAX,
                         "parent_markers");
    if (j->nmarkers < 3) {
        return j->nmarkers < 0 ? -1 : jfail(jp, "joint %s: fewer than 3 parent markers", j->name);
    }
    n = jget(jp, o, "template");
    if (n == NULL || n->type != J_ARR || n->count != j->nmarkers) {
        return jfail(jp, "joint %s: \"template\" must hold one point per parent marker", j->name);
    }
    for (c = n->first, k = 0; c >= 0; c = jp->n[c].next, k++) {
        if (jnums(jp, &jp->n[c], v, 3, "template") != 0) {
            return -1;
        }
        j->tpl[k][0] = (float)v[0];
        j->tpl[k][1] = (float)v[1];
        j->tpl[k][2] = (float)v[2];
    }
    if (jnums(jp, jget(jp, o, "center"), v, 3, "center") != 0) {
        return -1;
    }
    for (k = 0; k < 3; k++) {
        j->center[k] = (float)v[k];
    }
    if (j->hinge) {
        double len;
        if (jnums(jp, jget(jp, o, "axis"), v, 3, "axis") != 0) {
            return -1;
        }
        len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(fabs(len - 1.0) < 1e-3)) {
            return jfail(jp, "joint %s: \"axis\" is not a unit vector", j->name);
        }
        for (k = 0; k < 3; k++) {
            j->axis[k] = (float)v[k];
        }
    }
    n = jget(jp, o, "center_cov");
    if (n == NULL || n->type != J_ARR || n->count != 3) {
        return jfail(jp, "joint %s: \"center_cov\" must be 3 rows", j->name);
    }
    for (c = n->first, k = 0; c >= 0; c = jp->n[c].next, k++) {
        if (jnums(jp, &jp->n[c], j->cov[k], 3, "center_cov") != 0) {
            return -1;
        }
    }
    if (jnums(jp, jget(jp, o, "semi_axes_95"), j->semi95, 3, "semi_axes_95") != 0
        || jnums(jp, jget(jp, o, "rotation_range_deg"), j->range_deg, 3, "rotation_range_deg")
               != 0) {
        return -1;
    }
    /* the model error (absent in sessions written before it: scale 1) */
    j->model_scale = 1.0;
    n = jget(jp, o, "model_scale");
    if (n != NULL) {
        if (n->type != J_NUM || !(n->num >= 1.0 && n->num < 1e12)) {
            return jfail(jp, "joint %s: \"model_scale\" must be a number >= 1", j->name);
        }
        j->model_scale = n->num;
    }
    for (k = 0; k < 9; k++) { /* cov_model = model_scale cov, unless given */
        j->cov_model[k / 3][k % 3] = j->model_scale * j->cov[k / 3][k % 3];
    }
    for (k = 0; k < 3; k++) {
        j->semi95_model[k] = j->semi95[k] * sqrt(j->model_scale);
    }
    if (jread_mat(jp, jget(jp, o, "center_cov_model"), j->cov_model, j->name, "center_cov_model")
            != 0
        || jread_mat(jp, jget(jp, o, "center_cov_jackknife"), j->cov_jack, j->name,
                     "center_cov_jackknife") != 0
        || (jget(jp, o, "semi_axes_95_model") != NULL
            && jnums(jp, jget(jp, o, "semi_axes_95_model"), j->semi95_model, 3,
                     "semi_axes_95_model") != 0)) {
        return -1;
    }
    n = jget(jp, o, "flexion_range_deg");
    j->flex_deg = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    n = jget(jp, o, "misfit");
    j->misfit = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    n = jget(jp, o, "model_rms");
    j->model_rms = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    n = jget(jp, o, "jackknife_ratio");
    j->jack_ratio = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    n = jget(jp, o, "skin_rms");
    j->skin_rms = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    if (jget(jp, o, "semi_axes_95_skin") != NULL
        && jnums(jp, jget(jp, o, "semi_axes_95_skin"), j->semi95_skin, 3, "semi_axes_95_skin")
               != 0) {
        return -1;
    }
    n = jget(jp, o, "axis_cone_95_deg");
    j->cone_deg = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    n = jget(jp, o, "axis_cone_95_model_deg");
    j->cone_model_deg = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    n = jget(jp, o, "wobble_rms_deg");
    j->wobble_deg = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    n = jget(jp, o, "flag_bits");
    if (n == NULL || n->type != J_NUM || !(n->num >= 0.0 && n->num < 4294967296.0)) {
        return jfail(jp, "joint %s: \"flag_bits\" missing or out of range", j->name);
    }
    j->flags = (uint32_t)n->num;
    n = jget(jp, o, "marker_sigma");
    j->marker_sigma = (n != NULL && n->type == J_NUM) ? n->num : 0.0;
    n = jget(jp, o, "frames_used");
    j->frames_used = (n != NULL && n->type == J_NUM && fabs(n->num) < 1e15) ? (long)n->num : 0;
    n = jget(jp, o, "frames");
    j->frames_total = (n != NULL && n->type == J_NUM && fabs(n->num) < 1e15) ? (long)n->num : 0;
    return 0;
}

int session_parse(const char *text, size_t len, session_t *s, char *err)
{
    jparser_t jp;
    const jnode_t *n;
    char root[SM_NAME_MAX];
    int top, c, i, k;
    memset(s, 0, sizeof *s);
    jp.p = text;
    jp.end = text + len;
    jp.used = 0;
    jp.err = err;
    err[0] = '\0';
    jp.n = malloc(sizeof(jnode_t) * J_NODES_MAX);
    if (jp.n == NULL) {
        return jfail(&jp, "out of memory");
    }
    top = jvalue(&jp, 0);
    if (top < 0) {
        goto bad;
    }
    jws(&jp);
    if (jp.p != jp.end) {
        jfail(&jp, "text after the JSON object");
        goto bad;
    }
    n = jget(&jp, top, "format");
    if (n == NULL || n->type != J_STR || strcmp(n->str, "sfit-session") != 0) {
        jfail(&jp, "not an sfit session (\"format\":\"sfit-session\" missing)");
        goto bad;
    }
    if (jget_str(&jp, top, "units", s->units, sizeof s->units) != 0
        || jget_str(&jp, top, "root", root, sizeof root) != 0) {
        goto bad;
    }
    n = jget(&jp, top, "segments");
    if (n == NULL || n->type != J_ARR || n->count < 1 || n->count > SM_SEGMENTS_MAX) {
        jfail(&jp, "\"segments\" must be an array of 1 to %d segments", SM_SEGMENTS_MAX);
        goto bad;
    }
    for (c = n->first; c >= 0; c = jp.n[c].next) {
        sm_segment_t *g = &s->seg[s->nseg];
        if (jget_str(&jp, c, "name", g->name, sizeof g->name) != 0) {
            goto bad;
        }
        g->nmarkers = jnames(&jp, jget(&jp, c, "markers"), g->markers, SM_MARKERS_MAX, "markers");
        if (g->nmarkers < 0) {
            goto bad;
        }
        s->nseg++;
    }
    s->root = -1;
    for (i = 0; i < s->nseg; i++) {
        if (strcmp(s->seg[i].name, root) == 0) {
            s->root = i;
        }
    }
    if (s->root < 0) {
        jfail(&jp, "the root segment '%s' is not among the segments", root);
        goto bad;
    }
    n = jget(&jp, top, "joints");
    if (n == NULL || n->type != J_ARR || n->count > SM_JOINTS_MAX) {
        jfail(&jp, "\"joints\" must be an array of 0 to %d joints", SM_JOINTS_MAX);
        goto bad;
    }
    for (c = n->first; c >= 0; c = jp.n[c].next) {
        session_joint_t *j = &s->joint[s->njoint];
        if (read_joint(&jp, c, j) != 0) {
            goto bad;
        }
        for (k = 0; k < s->njoint; k++) {
            if (strcmp(s->joint[k].name, j->name) == 0) {
                jfail(&jp, "joint '%s' given twice", j->name);
                goto bad;
            }
        }
        s->njoint++;
    }
    free(jp.n);
    return 0;
bad:
    free(jp.n);
    memset(s, 0, sizeof *s);
    return -1;
}

int session_read(const char *path, session_t *s, char *err)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    size_t n;
    int rc;
    const size_t cap = (size_t)4 << 20;
    memset(s, 0, sizeof *s);
    if (f == NULL) {
        (void)snprintf(err, SM_ERR_MAX, "cannot open %s: %s", path, strerror(errno));
        return -1;
    }
    buf = malloc(cap + 1u);
    if (buf == NULL) {
        fclose(f);
        (void)snprintf(err, SM_ERR_MAX, "out of memory");
        return -1;
    }
    n = fread(buf, 1, cap + 1u, f);
    if (ferror(f) || n > cap) {
        (void)snprintf(err, SM_ERR_MAX, "%s: %s", path,
                       ferror(f) ? "read error" : "larger than 4 MiB (not a session)");
        rc = -1;
    } else {
        char e2[SM_ERR_MAX];
        rc = session_parse(buf, n, s, e2);
        if (rc != 0) {
            (void)snprintf(err, SM_ERR_MAX, "%s: %.200s", path, e2);
        }
    }
    free(buf);
    fclose(f);
    return rc;
}
