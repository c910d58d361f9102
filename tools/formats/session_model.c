/* SPDX-License-Identifier: MIT */
/** @file session_model.c  The session model text file (session_model.h). */
#include "session_model.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SM_FIELDS_MAX 8
#define SM_LINE_MAX 1024
#define SM_FILE_MAX (1L << 20) /* a model file is small: 1 MiB at most */

static int fail(char *err, int line, const char *fmt, ...)
{
    va_list ap;
    int k;
    k = snprintf(err, SM_ERR_MAX, "line %d: ", line);
    if (k < 0 || k >= SM_ERR_MAX) {
        k = 0;
    }
    va_start(ap, fmt);
    (void)vsnprintf(err + k, (size_t)(SM_ERR_MAX - k), fmt, ap);
    va_end(ap);
    return -1;
}

int session_model_segment(const session_model_t *m, const char *name)
{
    int i;
    for (i = 0; i < m->nseg; i++) {
        if (strcmp(m->seg[i].name, name) == 0) {
            return i;
        }
    }
    return -1;
}

const char *session_model_type_name(int type)
{
    return type == SM_BALL ? "ball" : type == SM_HINGE ? "hinge" : "auto";
}

/* Copy a name: printable, no comma, shorter than SM_NAME_MAX. */
static int copy_name(char *dst, const char *src, const char *what, char *err, int line)
{
    const size_t n = strlen(src);
    size_t i;
    if (n == 0 || n >= SM_NAME_MAX) {
        return fail(err, line, "%s '%.40s%s' must have 1 to %d characters", what, src,
                    n > 40 ? "..." : "", SM_NAME_MAX - 1);
    }
    for (i = 0; i < n; i++) {
        const unsigned char c = (unsigned char)src[i];
        if (c < 33 || c > 126 || c == ',' || c == '"' || c == '\\') {
            return fail(err, line, "%s '%.40s' has a character that is not allowed "
                                   "(printable ASCII without , \" \\)", what, src);
        }
    }
    memcpy(dst, src, n + 1);
    return 0;
}

/* Split a comma list in place; -1 on an empty item or more than max. */
static int split_commas(char *s, char **items, int max)
{
    int n = 0;
    for (;;) {
        char *c = strchr(s, ',');
        if (c != NULL) {
            *c = '\0';
        }
        if (*s == '\0' || n >= max) {
            return -1;
        }
        items[n++] = s;
        if (c == NULL) {
            return n;
        }
        s = c + 1;
    }
}

static int parse_segment(session_model_t *m, char **f, int nf, char *err, int line)
{
    sm_segment_t *s;
    char *items[SM_MARKERS_MAX + 1];
    int n, i, k;
    if (nf != 3) {
        return fail(err, line, "segment needs NAME MARKER,MARKER,MARKER[,...] (%d fields)", nf);
    }
    if (m->nseg >= SM_SEGMENTS_MAX) {
        return fail(err, line, "more than %d segments", SM_SEGMENTS_MAX);
    }
    s = &m->seg[m->nseg];
    if (copy_name(s->name, f[1], "segment name", err, line) != 0) {
        return -1;
    }
    if (session_model_segment(m, s->name) >= 0) {
        return fail(err, line, "segment '%s' declared twice", s->name);
    }
    n = split_commas(f[2], items, SM_MARKERS_MAX + 1);
    if (n < 3 || n > SM_MARKERS_MAX) {
        return fail(err, line, "segment '%s' needs 3 to %d comma-separated markers", s->name,
                    SM_MARKERS_MAX);
    }
    for (i = 0; i < n; i++) {
        if (copy_name(s->markers[i], items[i], "marker name", err, line) != 0) {
            return -1;
        }
        for (k = 0; k < i; k++) {
            if (strcmp(s->markers[k], s->markers[i]) == 0) {
                return fail(err, line, "segment '%s' names marker '%s' twice", s->name,
                            s->markers[i]);
            }
        }
    }
    s->nmarkers = n;
    m->nseg++;
    return 0;
}

static int parse_joint(session_model_t *m, char **f, int nf, char *err, int line)
{
    sm_joint_t *j;
    char *items[4];
    int n, i;
    if (nf != 6 && nf != 7) {
        return fail(err, line, "joint needs NAME PARENT CHILD auto|ball|hinge POINTS "
                               "[TRIAL_PATTERN] (%d fields)", nf);
    }
    if (m->njoint >= SM_JOINTS_MAX) {
        return fail(err, line, "more than %d joints", SM_JOINTS_MAX);
    }
    j = &m->joint[m->njoint];
    memset(j, 0, sizeof *j);
    j->line = line;
    if (copy_name(j->name, f[1], "joint name", err, line) != 0) {
        return -1;
    }
    for (i = 0; i < m->njoint; i++) {
        if (strcmp(m->joint[i].name, j->name) == 0) {
            return fail(err, line, "joint '%s' declared twice", j->name);
        }
    }
    j->parent = session_model_segment(m, f[2]);
    j->child = session_model_segment(m, f[3]);
    if (j->parent < 0 || j->child < 0) {
        return fail(err, line, "joint '%s': segment '%.60s' is not declared above it", j->name,
                    j->parent < 0 ? f[2] : f[3]);
    }
    if (j->parent == j->child) {
        return fail(err, line, "joint '%s': parent and child are the same segment", j->name);
    }
    for (i = 0; i < m->njoint; i++) {
        if (m->joint[i].child == j->child) {
            return fail(err, line, "segment '%s' is the child of two joints ('%s' and '%s')",
                        m->seg[j->child].name, m->joint[i].name, j->name);
        }
    }
    if (strcmp(f[4], "auto") == 0) {
        j->type = SM_AUTO;
    } else if (strcmp(f[4], "ball") == 0) {
        j->type = SM_BALL;
    } else if (strcmp(f[4], "hinge") == 0) {
        j->type = SM_HINGE;
    } else {
        return fail(err, line, "joint '%s': type '%.40s' is not auto, ball or hinge", j->name,
                    f[4]);
    }
    n = split_commas(f[5], items, 4);
    if (n != (j->type == SM_HINGE ? 3 : 1)) {
        return fail(err, line, "joint '%s': a %s joint names %s", j->name,
                    session_model_type_name(j->type),
                    j->type == SM_HINGE ? "3 points (centre, two axis points)" : "1 point");
    }
    for (i = 0; i < n; i++) {
        if (copy_name(j->points[i], items[i], "point name", err, line) != 0) {
            return -1;
        }
    }
    if (j->type == SM_AUTO) {
        if (strlen(j->points[0]) + 4 >= SM_NAME_MAX) {
            return fail(err, line, "joint '%s': point name too long for its _AX1 suffix",
                        j->name);
        }
        const size_t k = strlen(j->points[0]);
        memcpy(j->points[1], j->points[0], k);
        memcpy(j->points[1] + k, "_AX1", 5);
        memcpy(j->points[2], j->points[0], k);
        memcpy(j->points[2] + k, "_AX2", 5);
    }
    j->npoints = n;
    if (nf == 7) {
        if (strlen(f[6]) >= SM_PATTERN_MAX) {
            return fail(err, line, "joint '%s': trial pattern longer than %d characters",
                        j->name, SM_PATTERN_MAX - 1);
        }
        strcpy(j->pattern, f[6]);
    }
    m->njoint++;
    return 0;
}

/* landmarks JOINT MARKER,MARKER: two markers of the joint's parent segment. */
static int parse_landmarks(session_model_t *m, char **f, int nf, char *err, int line)
{
    char *items[3];
    sm_joint_t *j = NULL;
    const sm_segment_t *ps;
    int i, k, n;
    if (nf != 3) {
        return fail(err, line, "landmarks needs JOINT MARKER,MARKER (%d fields)", nf);
    }
    for (i = 0; i < m->njoint; i++) {
        if (strcmp(m->joint[i].name, f[1]) == 0) {
            j = &m->joint[i];
        }
    }
    if (j == NULL) {
        return fail(err, line, "landmarks: joint '%.60s' is not declared above it", f[1]);
    }
    if (j->nlandmarks != 0) {
        return fail(err, line, "landmarks of joint '%s' given twice", j->name);
    }
    n = split_commas(f[2], items, 3);
    if (n != 2 || strcmp(items[0], items[1]) == 0) {
        return fail(err, line, "landmarks of joint '%s': two different comma-separated markers",
                    j->name);
    }
    ps = &m->seg[j->parent];
    for (i = 0; i < 2; i++) {
        for (k = 0; k < ps->nmarkers && strcmp(ps->markers[k], items[i]) != 0; k++) {
        }
        if (k == ps->nmarkers) {
            return fail(err, line,
                        "landmarks of joint '%s': '%.60s' is not a marker of its parent "
                        "segment '%s'",
                        j->name, items[i], ps->name);
        }
        memcpy(j->landmarks[i], items[i], strlen(items[i]) + 1);
    }
    j->nlandmarks = 2;
    return 0;
}

int session_model_parse(const char *text, size_t len, session_model_t *m, char *err)
{
    char buf[SM_LINE_MAX];
    char root[SM_NAME_MAX] = "";
    size_t pos = 0;
    int line = 0, i, root_line = 0;
    memset(m, 0, sizeof *m);
    m->root = -1;
    err[0] = '\0';
    if (text == NULL) {
        return fail(err, 0, "no text");
    }
    while (pos < len) {
        char *f[SM_FIELDS_MAX + 1];
        int nf = 0;
        size_t n = 0;
        char *p, *hash;
        line++;
        while (pos < len && text[pos] != '\n') {
            if (text[pos] == '\0') {
                return fail(err, line, "a NUL byte (not a text file)");
            }
            if (n + 1 >= sizeof buf) {
                return fail(err, line, "longer than %d characters", SM_LINE_MAX - 1);
            }
            buf[n++] = text[pos++];
        }
        pos++; /* the newline */
        buf[n] = '\0';
        hash = strchr(buf, '#');
        if (hash != NULL) {
            *hash = '\0';
        }
        for (p = buf; *p != '\0';) {
            while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\v' || *p == '\f') {
                *p++ = '\0';
            }
            if (*p == '\0') {
                break;
            }
            if (nf > SM_FIELDS_MAX - 1) {
                return fail(err, line, "too many fields");
            }
            f[nf++] = p;
            while (*p != '\0' && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\v'
                   && *p != '\f') {
                p++;
            }
        }
        if (nf == 0) {
            continue;
        }
        if (strcmp(f[0], "segment") == 0) {
            if (parse_segment(m, f, nf, err, line) != 0) {
                return -1;
            }
        } else if (strcmp(f[0], "joint") == 0) {
            if (parse_joint(m, f, nf, err, line) != 0) {
                return -1;
            }
        } else if (strcmp(f[0], "landmarks") == 0) {
            if (parse_landmarks(m, f, nf, err, line) != 0) {
                return -1;
            }
        } else if (strcmp(f[0], "root") == 0) {
            if (nf != 2 || root[0] != '\0') {
                return fail(err, line, nf != 2 ? "root needs one SEGMENT" : "root given twice");
            }
            if (copy_name(root, f[1], "root segment", err, line) != 0) {
                return -1;
            }
            root_line = line;
        } else {
            return fail(err, line, "unknown keyword '%.40s' (segment, joint, landmarks or root)", f[0]);
        }
    }
    if (m->nseg == 0) {
        return fail(err, line, "no segment declared");
    }
    if (root[0] != '\0') {
        m->root = session_model_segment(m, root);
        if (m->root < 0) {
            return fail(err, root_line, "root segment '%s' is not declared", root);
        }
        for (i = 0; i < m->njoint; i++) {
            if (m->joint[i].child == m->root) {
                return fail(err, root_line, "root segment '%s' is the child of joint '%s'", root,
                            m->joint[i].name);
            }
        }
    } else {
        int s, k;
        for (s = 0; s < m->nseg && m->root < 0; s++) {
            for (k = 0; k < m->njoint && m->joint[k].child != s; k++) {
            }
            if (k == m->njoint) {
                m->root = s;
            }
        }
        if (m->root < 0) {
            return fail(err, line, "every segment is a child: the joints form a cycle");
        }
    }
    /* no cycle: from every segment, the parents lead to a segment without one */
    for (i = 0; i < m->nseg; i++) {
        int s = i, steps = 0;
        for (;;) {
            int k;
            for (k = 0; k < m->njoint && m->joint[k].child != s; k++) {
            }
            if (k == m->njoint) {
                break;
            }
            s = m->joint[k].parent;
            if (++steps > m->njoint) {
                return fail(err, m->joint[k].line, "the joints form a cycle through segment '%s'",
                            m->seg[i].name);
            }
        }
    }
    return 0;
}

int session_model_load(const char *path, session_model_t *m, char *err)
{
    FILE *f = fopen(path, "rb");
    char *buf;
    size_t n;
    int rc;
    if (f == NULL) {
        (void)snprintf(err, SM_ERR_MAX, "cannot open %s: %s", path, strerror(errno));
        memset(m, 0, sizeof *m);
        return -1;
    }
    buf = malloc((size_t)SM_FILE_MAX + 1u);
    if (buf == NULL) {
        fclose(f);
        (void)snprintf(err, SM_ERR_MAX, "out of memory");
        memset(m, 0, sizeof *m);
        return -1;
    }
    n = fread(buf, 1, (size_t)SM_FILE_MAX + 1u, f);
    if (ferror(f) || n > (size_t)SM_FILE_MAX) {
        (void)snprintf(err, SM_ERR_MAX, "%s: %s", path,
                       ferror(f) ? "read error" : "larger than 1 MiB (not a model file)");
        rc = -1;
        memset(m, 0, sizeof *m);
    } else {
        rc = session_model_parse(buf, n, m, err);
        if (rc != 0) {
            char tmp[SM_ERR_MAX];
            (void)snprintf(tmp, sizeof tmp, "%s: %s", path, err);
            memcpy(err, tmp, sizeof tmp);
        }
    }
    free(buf);
    fclose(f);
    return rc;
}
