/* SPDX-License-Identifier: MIT */
/**
 * @file py_c3d.c
 * @brief C3D files for the Python package: the host library's reader and
 * writer (tools/formats/c3d.c, c3d_write.c, compiled into the extension by
 * setup.py)
 * behind three functions of sfit._sfit, wrapped by sfit.read_c3d,
 * sfit.write_c3d and sfit.write_trc (sfit/_c3d.py).
 *
 * Arrays cross as bytes of float32 (no numpy C API here): the Python layer
 * makes them with numpy. A file that cannot be read raises OSError; a
 * malformed file or a refused write raises ValueError with the reader's or
 * writer's message.
 */
#include "py_sfit.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "c3d.h"
#include "c3d_write.h"

/* Load and parse; on failure a Python exception is set and -1 returned. */
static int load(const char *path, unsigned char **buf, size_t *len, c3d_t *c)
{
    char err[C3D_ERR_MAX];
    int e;
    errno = 0;
    if (c3d_load_bytes(path, buf, len, err) != 0) {
        e = errno;
        if (e != 0) {
            errno = e;
            PyErr_SetFromErrnoWithFilename(PyExc_OSError, path);
        } else {
            PyErr_SetString(PyExc_ValueError, err);
        }
        return -1;
    }
    if (c3d_parse(*buf, *len, c, err) != 0) {
        free(*buf);
        *buf = NULL;
        PyErr_Format(PyExc_ValueError, "%s: %s", path, err);
        return -1;
    }
    return 0;
}

static PyObject *str_or_empty(const char *s)
{
    return PyUnicode_DecodeLatin1(s != NULL ? s : "", (Py_ssize_t)(s != NULL ? strlen(s) : 0u),
                                  "replace");
}

PyObject *sfit_py_c3d_read(PyObject *self, PyObject *args)
{
    PyObject *path_b = NULL, *d = NULL, *labels = NULL, *warns = NULL, *src = NULL;
    unsigned char *buf = NULL;
    size_t len = 0;
    c3d_t c;
    int k, bad = 0;
    (void)self;
    memset(&c, 0, sizeof c);
    if (!PyArg_ParseTuple(args, "O&:read_c3d", PyUnicode_FSConverter, &path_b)) {
        return NULL;
    }
    if (load(PyBytes_AS_STRING(path_b), &buf, &len, &c) != 0) {
        Py_DECREF(path_b);
        return NULL;
    }
    free(buf);
    Py_DECREF(path_b);
    d = PyDict_New();
    labels = PyList_New(c.npoints);
    warns = PyList_New(c.nwarn);
    src = PyDict_New();
    if (d == NULL || labels == NULL || warns == NULL || src == NULL) {
        goto fail;
    }
    for (k = 0; k < c.npoints; k++) {
        PyObject *s = str_or_empty(c.labels[k]);
        if (s == NULL) {
            goto fail;
        }
        PyList_SET_ITEM(labels, k, s);
    }
    for (k = 0; k < c.nwarn; k++) {
        PyObject *s = str_or_empty(c.warnings[k]);
        if (s == NULL) {
            goto fail;
        }
        PyList_SET_ITEM(warns, k, s);
    }
    bad |= sfit_py_put(src, "processor", str_or_empty(c.src_processor));
    bad |= sfit_py_put(src, "points", str_or_empty(c.src_points));
    bad |= sfit_py_put(src, "frames", str_or_empty(c.src_frames));
    bad |= sfit_py_put(src, "scale", str_or_empty(c.src_scale));
    bad |= sfit_py_put(src, "rate", str_or_empty(c.src_rate));
    bad |= sfit_py_put(src, "analog", str_or_empty(c.src_analog));
    bad |= sfit_py_put(d, "labels", labels);
    labels = NULL;
    bad |= sfit_py_put(d, "warnings", warns);
    warns = NULL;
    bad |= sfit_py_put(d, "sources", src);
    src = NULL;
    bad |= sfit_py_put(d, "rate", PyFloat_FromDouble((double)c.rate));
    bad |= sfit_py_put(d, "scale", PyFloat_FromDouble((double)c.scale));
    bad |= sfit_py_put(d, "units", str_or_empty(c.units));
    bad |= sfit_py_put(d, "processor", PyLong_FromLong(c.processor));
    bad |= sfit_py_put(d, "processor_name", str_or_empty(c3d_processor_name(c.processor)));
    bad |= sfit_py_put(d, "first_frame", PyLong_FromLong(c.first_frame));
    bad |= sfit_py_put(d, "frames", PyLong_FromLong(c.nframes));
    bad |= sfit_py_put(d, "npoints", PyLong_FromLong(c.npoints));
    bad |= sfit_py_put(d, "analog_channels", PyLong_FromLong(c.analog_channels));
    bad |= sfit_py_put(d, "analog_per_frame", PyLong_FromLong(c.analog_per_frame));
    bad |= sfit_py_put(d, "analog_rate", PyFloat_FromDouble((double)c.analog_rate));
    bad |= sfit_py_put(d, "zero_samples", PyLong_FromLong(c.zero_samples));
    bad |= sfit_py_put(d, "storage", str_or_empty(c.word == 4 ? "float" : "integer"));
    bad |= sfit_py_put(d, "xyz",
                    PyBytes_FromStringAndSize((const char *)c.xyz,
                                              (Py_ssize_t)((size_t)c.nframes * (size_t)c.npoints
                                                           * 3u * sizeof(float))));
    if (bad) {
        goto fail;
    }
    c3d_free(&c);
    return d;
fail:
    Py_XDECREF(d);
    Py_XDECREF(labels);
    Py_XDECREF(warns);
    Py_XDECREF(src);
    c3d_free(&c);
    return NULL;
}

/* names (list of str) and xyz (bytes of F * n * 3 float32) into an add set. */
static int make_add(PyObject *names, Py_buffer *xyz, const char *prefix, long nframes,
                    c3d_add_t *add, const char ***out_names)
{
    Py_ssize_t n, i;
    const char **nm;
    memset(add, 0, sizeof *add);
    *out_names = NULL;
    if (!PyList_Check(names)) {
        PyErr_SetString(PyExc_TypeError, "names must be a list of str");
        return -1;
    }
    n = PyList_GET_SIZE(names);
    if (n < 1 || n > 65535) {
        PyErr_SetString(PyExc_ValueError, "1 to 65535 new points");
        return -1;
    }
    if ((size_t)xyz->len != (size_t)nframes * (size_t)n * 3u * sizeof(float)) {
        PyErr_Format(PyExc_ValueError, "the new points must have %ld frames", nframes);
        return -1;
    }
    nm = malloc((size_t)n * sizeof *nm);
    if (nm == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    for (i = 0; i < n; i++) {
        PyObject *s = PyList_GET_ITEM(names, i);
        const char *u;
        if (!PyUnicode_Check(s) || (u = PyUnicode_AsUTF8(s)) == NULL) {
            free(nm);
            if (!PyErr_Occurred()) {
                PyErr_SetString(PyExc_TypeError, "names must be a list of str");
            }
            return -1;
        }
        if (u[0] == '\0' || strlen(u) > 200u || strchr(u, '\t') != NULL
            || strchr(u, '\n') != NULL) {
            free(nm);
            PyErr_Format(PyExc_ValueError, "point name %R: 1 to 200 characters, no tab or newline",
                         s);
            return -1;
        }
        nm[i] = u;
    }
    add->n = (int)n;
    add->names = nm;
    add->xyz = (const float *)xyz->buf;
    add->prefix = prefix;
    *out_names = nm;
    return 0;
}

/* The descriptions (list of str, one per name, or None) into add->descs. */
static int make_descs(PyObject *descs, c3d_add_t *add, const char ***out)
{
    Py_ssize_t i;
    const char **d;
    *out = NULL;
    if (descs == Py_None) {
        return 0;
    }
    if (!PyList_Check(descs) || PyList_GET_SIZE(descs) != (Py_ssize_t)add->n) {
        PyErr_SetString(PyExc_ValueError, "descriptions: a list of str, one per new point");
        return -1;
    }
    d = malloc((size_t)add->n * sizeof *d);
    if (d == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    for (i = 0; i < (Py_ssize_t)add->n; i++) {
        PyObject *s = PyList_GET_ITEM(descs, i);
        const char *u;
        if (!PyUnicode_Check(s) || (u = PyUnicode_AsUTF8(s)) == NULL || strlen(u) > 200u
            || strchr(u, '\n') != NULL) {
            free(d);
            if (!PyErr_Occurred() || PyErr_ExceptionMatches(PyExc_UnicodeError)) {
                PyErr_Clear();
                PyErr_SetString(PyExc_ValueError,
                                "descriptions: str of at most 200 characters, no newline");
            }
            return -1;
        }
        d[i] = u;
    }
    add->descs = d;
    *out = d;
    return 0;
}

/* _c3d_write(src, dst, names, xyz_bytes, prefix, trc[, descs]) -> bool (float
 * storage). trc = 0: write the C3D file dst; trc = 1: the TRC file dst (names
 * may be empty). descs: None or a list of str, one per name. */
PyObject *sfit_py_c3d_write(PyObject *self, PyObject *args)
{
    PyObject *src_b = NULL, *dst_b = NULL, *names, *res = NULL, *descs = Py_None;
    Py_buffer xyz;
    const char *prefix;
    const char **nm = NULL, **ds = NULL;
    int trc, to_float = 0;
    unsigned char *buf = NULL;
    size_t len = 0;
    c3d_t c;
    c3d_add_t add;
    char err[C3D_ERR_MAX];
    (void)self;
    memset(&c, 0, sizeof c);
    if (!PyArg_ParseTuple(args, "O&O&Oy*sp|O:write_c3d", PyUnicode_FSConverter, &src_b,
                          PyUnicode_FSConverter, &dst_b, &names, &xyz, &prefix, &trc, &descs)) {
        Py_XDECREF(src_b);
        Py_XDECREF(dst_b);
        return NULL;
    }
    if (strlen(prefix) > 60u) {
        PyErr_SetString(PyExc_ValueError, "prefix: at most 60 characters");
        goto out;
    }
    if (load(PyBytes_AS_STRING(src_b), &buf, &len, &c) != 0) {
        goto out;
    }
    if (trc && PyList_Check(names) && PyList_GET_SIZE(names) == 0) {
        if (c3d_write_trc(PyBytes_AS_STRING(dst_b), &c, NULL, err) != 0) {
            PyErr_SetString(PyExc_OSError, err);
            goto out;
        }
        Py_INCREF(Py_False);
        res = Py_False;
        goto out;
    }
    if (make_add(names, &xyz, prefix, c.nframes, &add, &nm) != 0
        || make_descs(descs, &add, &ds) != 0) {
        goto out;
    }
    if (trc) {
        if (c3d_write_trc(PyBytes_AS_STRING(dst_b), &c, &add, err) != 0) {
            PyErr_SetString(c.rate > 0.0f ? PyExc_OSError : PyExc_ValueError, err);
            goto out;
        }
    } else if (c3d_write_added(buf, len, &c, &add, PyBytes_AS_STRING(dst_b), &to_float, err) != 0) {
        PyErr_SetString(strncmp(err, "cannot write", 12) == 0 ? PyExc_OSError : PyExc_ValueError,
                        err);
        goto out;
    }
    res = PyBool_FromLong(to_float);
out:
    free(ds);
    free(nm);
    free(buf);
    c3d_free(&c);
    PyBuffer_Release(&xyz);
    Py_DECREF(src_b);
    Py_DECREF(dst_b);
    return res;
}
