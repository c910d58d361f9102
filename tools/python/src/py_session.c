/* SPDX-License-Identifier: MIT */
/**
 * @file py_session.c
 * @brief A lab session for the Python package: the host library's session
 * model parser, calibration and placement (tools/formats/session_model.c,
 * session.c, tools/lab/session_calib.c and what they use, compiled into
 * the extension by setup.py) behind three functions of sfit._sfit, wrapped by
 * sfit.session_model, sfit.calibrate and sfit.apply_session
 * (sfit/_session.py). Registered in py_module.c.
 *
 *   _session_model(text) -> str            the model as JSON
 *   _session_calibrate(model_text, joint, buf, frames, units, trial) -> str
 *       buf: writable float32 frames x (parent + child markers) x 3 in the
 *       model's order (label swaps repaired in place); a session JSON with
 *       that one joint
 *   _session_place(session_text, joint, buf, frames, d) -> (bytes, str)
 *       buf: writable float32 frames x parent markers x 3; float32 frames x
 *       points x 3, NaN where the parent does not register, and the
 *       placement's covariance as JSON (the "placement" of `sfit apply
 *       --json`)
 *
 * A bad model or session raises ValueError with the parser's message; a
 * joint that cannot be calibrated raises ValueError with the reason.
 */
#include "py_sfit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frames.h"
#include "json_out.h"
#include "names.h"
#include "session.h"
#include "session_calib.h"
#include "session_model.h"

/* The text written to a temporary file, as a Python str. */
static PyObject *file_text(FILE *f)
{
    long n;
    char *buf;
    PyObject *s;
    if (fflush(f) != 0 || (n = ftell(f)) < 0 || fseek(f, 0L, SEEK_SET) != 0) {
        fclose(f);
        return PyErr_Format(PyExc_OSError, "temporary file failed");
    }
    buf = malloc((size_t)n + 1u);
    if (buf == NULL) {
        fclose(f);
        return PyErr_NoMemory();
    }
    if (fread(buf, 1, (size_t)n, f) != (size_t)n) {
        free(buf);
        fclose(f);
        return PyErr_Format(PyExc_OSError, "temporary file failed");
    }
    fclose(f);
    s = PyUnicode_DecodeLatin1(buf, (Py_ssize_t)n, "replace");
    free(buf);
    return s;
}

static int parse_model(const char *text, Py_ssize_t len, session_model_t *m)
{
    char err[SM_ERR_MAX];
    if (session_model_parse(text, (size_t)len, m, err) != 0) {
        PyErr_Format(PyExc_ValueError, "session model: %s", err);
        return -1;
    }
    return 0;
}

PyObject *sfit_py_session_model(PyObject *self, PyObject *args)
{
    const char *text;
    Py_ssize_t len;
    session_model_t *m;
    FILE *f;
    int i, k;
    (void)self;
    if (!PyArg_ParseTuple(args, "s#:_session_model", &text, &len)) {
        return NULL;
    }
    m = malloc(sizeof *m);
    if (m == NULL) {
        return PyErr_NoMemory();
    }
    if (parse_model(text, len, m) != 0) {
        free(m);
        return NULL;
    }
    f = tmpfile();
    if (f == NULL) {
        free(m);
        return PyErr_SetFromErrno(PyExc_OSError);
    }
    fprintf(f, "{\"root\":");
    json_out_str(f, m->seg[m->root].name, 0u);
    fprintf(f, ",\"segments\":[");
    for (i = 0; i < m->nseg; i++) {
        fprintf(f, "%s{\"name\":", i > 0 ? "," : "");
        json_out_str(f, m->seg[i].name, 0u);
        fprintf(f, ",\"markers\":[");
        for (k = 0; k < m->seg[i].nmarkers; k++) {
            if (k > 0) {
                fputc(',', f);
            }
            json_out_str(f, m->seg[i].markers[k], 0u);
        }
        fprintf(f, "]}");
    }
    fprintf(f, "],\"joints\":[");
    for (i = 0; i < m->njoint; i++) {
        const sm_joint_t *j = &m->joint[i];
        fprintf(f, "%s{\"name\":", i > 0 ? "," : "");
        json_out_str(f, j->name, 0u);
        fprintf(f, ",\"parent\":");
        json_out_str(f, m->seg[j->parent].name, 0u);
        fprintf(f, ",\"child\":");
        json_out_str(f, m->seg[j->child].name, 0u);
        fprintf(f, ",\"type\":\"%s\",\"points\":[", session_model_type_name(j->type));
        for (k = 0; k < (j->type == SM_AUTO ? 3 : j->npoints); k++) {
            if (k > 0) {
                fputc(',', f);
            }
            json_out_str(f, j->points[k], 0u);
        }
        fprintf(f, "],\"pattern\":");
        json_out_str(f, j->pattern, 0u);
        fprintf(f, "}");
    }
    fprintf(f, "]}");
    free(m);
    return file_text(f);
}

/* A writable C-contiguous buffer of exactly n float32 values. */
static int float_buffer(PyObject *o, Py_buffer *b, Py_ssize_t n)
{
    if (PyObject_GetBuffer(o, b, PyBUF_WRITABLE | PyBUF_C_CONTIGUOUS) != 0) {
        return -1;
    }
    if (b->len != n * (Py_ssize_t)sizeof(float)) {
        PyBuffer_Release(b);
        PyErr_Format(PyExc_ValueError, "buffer of %zd bytes, %zd float32 values expected",
                     b->len, n);
        return -1;
    }
    return 0;
}

PyObject *sfit_py_session_calibrate(PyObject *self, PyObject *args)
{
    const char *text, *units, *trial;
    Py_ssize_t len, frames;
    int k, nm;
    PyObject *bo;
    Py_buffer b;
    session_model_t *m;
    session_t *s;
    frames_data_t fr;
    char err[SM_ERR_MAX];
    FILE *f;
    const json_out_flag_t *flags;
    size_t nflags = 0;
    (void)self;
    if (!PyArg_ParseTuple(args, "s#iOnss:_session_calibrate", &text, &len, &k, &bo, &frames,
                          &units, &trial)) {
        return NULL;
    }
    m = malloc(sizeof *m);
    s = malloc(sizeof *s);
    if (m == NULL || s == NULL) {
        free(m);
        free(s);
        return PyErr_NoMemory();
    }
    if (parse_model(text, len, m) != 0) {
        goto fail;
    }
    if (k < 0 || k >= m->njoint) {
        PyErr_Format(PyExc_ValueError, "joint %d: the model has %d joints", k, m->njoint);
        goto fail;
    }
    if (frames < 1 || frames > 100000000) {
        PyErr_Format(PyExc_ValueError, "frames must be 1 to 1e8, not %zd", frames);
        goto fail;
    }
    if (strlen(trial) >= SESSION_PATH_MAX || strlen(units) >= 16) {
        PyErr_Format(PyExc_ValueError, "trial name or units too long");
        goto fail;
    }
    nm = m->seg[m->joint[k].parent].nmarkers + m->seg[m->joint[k].child].nmarkers;
    if (float_buffer(bo, &b, frames * nm * 3) != 0) {
        goto fail;
    }
    memset(&fr, 0, sizeof fr);
    fr.nmarkers = nm;
    fr.nframes = (long)frames;
    fr.xyz = (sfit_vec3_t *)b.buf;
    fr.is_c3d = 1;
    (void)snprintf(fr.units, sizeof fr.units, "%s", units);
    memset(s, 0, sizeof *s);
    if (session_calibrate_frames(&fr, m, k, trial, &s->joint[0], err) != 0) {
        PyBuffer_Release(&b);
        PyErr_Format(PyExc_ValueError, "%s: %s", m->joint[k].name, err);
        goto fail;
    }
    PyBuffer_Release(&b);
    s->njoint = 1;
    s->nseg = m->nseg;
    memcpy(s->seg, m->seg, sizeof s->seg);
    s->root = m->root;
    (void)snprintf(s->units, sizeof s->units, "%s", units);
    f = tmpfile();
    if (f == NULL) {
        PyErr_SetFromErrno(PyExc_OSError);
        goto fail;
    }
    flags = names_flags(NAMES_SESSION, &nflags);
    session_write_json(f, s, flags, nflags);
    free(m);
    free(s);
    return file_text(f);
fail:
    free(m);
    free(s);
    return NULL;
}

PyObject *sfit_py_session_place(PyObject *self, PyObject *args)
{
    const char *text;
    Py_ssize_t len, frames;
    int k;
    float d;
    PyObject *bo, *out;
    Py_buffer b;
    session_t *s;
    frames_data_t fr;
    char err[SM_ERR_MAX];
    float *pts;
    size_t i, n;
    long placed;
    session_place_cov_t pc;
    PyObject *js;
    FILE *f;
    int nm;
    (void)self;
    if (!PyArg_ParseTuple(args, "s#iOnf:_session_place", &text, &len, &k, &bo, &frames, &d)) {
        return NULL;
    }
    if (!(d > 0.0f && d < 1e6f)) {
        return PyErr_Format(PyExc_ValueError, "axis point distance must be in (0, 1e6)");
    }
    s = malloc(sizeof *s);
    if (s == NULL) {
        return PyErr_NoMemory();
    }
    if (session_parse(text, (size_t)len, s, err) != 0) {
        free(s);
        return PyErr_Format(PyExc_ValueError, "session: %s", err);
    }
    if (k < 0 || k >= s->njoint || frames < 0 || frames > 100000000) {
        free(s);
        return PyErr_Format(PyExc_ValueError, "joint %d or frames %zd out of range", k, frames);
    }
    if (float_buffer(bo, &b, frames * s->joint[k].nmarkers * 3) != 0) {
        free(s);
        return NULL;
    }
    n = (size_t)frames * (size_t)s->joint[k].npoints * 3u;
    pts = malloc((n + 1u) * sizeof *pts);
    if (pts == NULL) {
        PyBuffer_Release(&b);
        free(s);
        return PyErr_NoMemory();
    }
    for (i = 0; i < n; i++) {
        pts[i] = NAN;
    }
    memset(&fr, 0, sizeof fr);
    fr.nmarkers = s->joint[k].nmarkers;
    fr.nframes = (long)frames;
    fr.xyz = (sfit_vec3_t *)b.buf;
    placed = session_place_frames(&s->joint[k], &fr, d, pts, s->joint[k].npoints, NULL, &pc);
    PyBuffer_Release(&b);
    nm = s->joint[k].nmarkers;
    free(s);
    if (placed < 0) {
        free(pts);
        return PyErr_Format(PyExc_ValueError, "the session's template of joint %d is degenerate",
                            k);
    }
    f = tmpfile();
    if (f == NULL) {
        free(pts);
        return PyErr_SetFromErrno(PyExc_OSError);
    }
    session_place_json(f, &pc, nm);
    js = file_text(f);
    if (js == NULL) {
        free(pts);
        return NULL;
    }
    out = Py_BuildValue("(y#N)", (const char *)pts, (Py_ssize_t)(n * sizeof *pts), js);
    free(pts);
    return out;
}
