/* SPDX-License-Identifier: MIT */
/**
 * @file py_array.c
 * @brief Arrays in: the one converter of a caller's array of 3-vectors
 * (any real numeric array-like becomes a C-contiguous float32 copy made by
 * numpy: float64 is rounded to nearest float32, values beyond float32's
 * range become inf and are rejected as the library rejects them), its
 * wrappers for samples (N, 3) and frames (F, M, 3), the library's row
 * filter, 3-vector arguments, and the one loop that places a point and a
 * direction in every frame (Cluster._place, Joint._center_at).
 */
#include "py_sfit.h"

#include <math.h>
#include <string.h>

sfit_py_why_t sfit_py_f32_get(PyObject *obj, int ndim, int opts, const char *what,
                              PyArrayObject **out, PyObject **probe)
{
    PyArrayObject *any;
    char kind;
    int nd;
    *out = NULL;
    if (probe != NULL) {
        *probe = NULL;
    }
    any = (PyArrayObject *)PyArray_FROMANY(obj, NPY_NOTYPE, 0, 0, 0);
    if (any == NULL) {
        return SFIT_PY_NOT_ARRAY;
    }
    kind = PyArray_DESCR(any)->kind;
    nd = PyArray_NDIM(any);
    if (kind != 'f' && kind != 'i' && kind != 'u') {
        goto refused;
    }
    if ((opts & SFIT_PY_EMPTY) != 0 && nd == 1 && PyArray_DIM(any, 0) == 0) { /* [] : no rows */
        npy_intp dims[2] = {0, 3};
        Py_DECREF(any);
        *out = (PyArrayObject *)PyArray_ZEROS(2, dims, NPY_FLOAT32, 0);
        return (*out != NULL) ? SFIT_PY_OK : SFIT_PY_RAISED;
    }
    if (!((nd == ndim || ((opts & SFIT_PY_ONE) != 0 && nd == ndim - 1)) && nd >= 1
          && PyArray_DIM(any, nd - 1) == 3)) {
        goto refused;
    }
    /* more rows or frames than the library counts (uint32): refused before
     * the float32 copy (a broadcast view of 2**32 rows costs nothing, its
     * copy 48 GiB) */
    if ((opts & SFIT_PY_LIMIT) != 0 && nd == ndim
        && (uint64_t)PyArray_DIM(any, 0) > (uint64_t)UINT32_MAX) {
        Py_DECREF(any);
        sfit_py_raise_status(SFIT_E_RANGE, what, -1, -1);
        return SFIT_PY_RAISED;
    }
    *out = (PyArrayObject *)PyArray_FROM_OTF((PyObject *)any, NPY_FLOAT32,
                                             NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
    Py_DECREF(any);
    return (*out != NULL) ? SFIT_PY_OK : SFIT_PY_RAISED;
refused:
    if (probe != NULL) {
        *probe = (PyObject *)any;
    } else {
        Py_DECREF(any);
    }
    return (kind != 'f' && kind != 'i' && kind != 'u') ? SFIT_PY_NOT_REAL : SFIT_PY_SHAPE;
}

/* The ArgError of a refused argument; consumes probe. shapes: the shapes
 * accepted, for the message; named: the message names the dtype. */
static int refused(sfit_py_why_t why, PyObject *probe, const char *what, const char *shapes,
                   int named)
{
    PyObject *s = NULL;
    if (why == SFIT_PY_NOT_ARRAY) {
        PyErr_Clear();
        sfit_py_raise_arg("%s: not an array of numbers", what);
    } else if (why == SFIT_PY_NOT_REAL && !named) {
        sfit_py_raise_arg("%s: not a real number type (use float32 or float64)", what);
    } else if (why == SFIT_PY_NOT_REAL) {
        s = PyObject_Str((PyObject *)PyArray_DESCR((PyArrayObject *)probe));
        if (s != NULL) {
            sfit_py_raise_arg("%s: dtype %U is not a real number type (use float32 or float64)",
                              what, s);
        }
    } else if (why == SFIT_PY_SHAPE) {
        s = PyObject_GetAttrString(probe, "shape");
        if (s != NULL) {
            sfit_py_raise_arg("%s: expected shape %s, got %R", what, shapes, s);
        }
    }
    Py_XDECREF(s);
    Py_XDECREF(probe);
    return -1;
}

PyArrayObject *sfit_py_f32_value(PyObject *obj, int ndim, const char *what)
{
    PyArrayObject *a;
    const sfit_py_why_t why = sfit_py_f32_get(obj, ndim, 0, what, &a, NULL);
    if (why == SFIT_PY_NOT_REAL || why == SFIT_PY_SHAPE) {
        PyErr_Format(PyExc_ValueError, "%s: a real array of shape %s expected", what,
                     ndim == 3 ? "(frames, markers, 3)" : "(markers, 3)");
    }
    return a;
}

void sfit_py_pts_release(sfit_py_pts_t *p)
{
    Py_CLEAR(p->arr);
    p->v = NULL;
    p->n = 0;
}

int sfit_py_pts_get(PyObject *obj, sfit_py_pts_t *p, const char *what, int allow_one)
{
    PyObject *probe;
    const sfit_py_why_t why = sfit_py_f32_get(
        obj, 2, (allow_one ? SFIT_PY_ONE : 0) | SFIT_PY_EMPTY | SFIT_PY_LIMIT, what, &p->arr,
        &probe);
    p->v = NULL;
    p->n = 0;
    if (why != SFIT_PY_OK) {
        return refused(why, probe, what, allow_one ? "(N, 3) or (3,)" : "(N, 3)", 1);
    }
    p->v = (const sfit_vec3_t *)PyArray_DATA(p->arr);
    p->n = (PyArray_NDIM(p->arr) == 1) ? 1u : (size_t)PyArray_DIM(p->arr, 0);
    return 0;
}

int sfit_py_frames_get(PyObject *obj, sfit_py_frames_t *f, const char *what, int allow_one)
{
    PyObject *probe;
    const sfit_py_why_t why = sfit_py_f32_get(
        obj, 3, (allow_one ? SFIT_PY_ONE : 0) | SFIT_PY_LIMIT, what, &f->arr, &probe);
    int nd;
    if (why != SFIT_PY_OK) {
        return refused(why, probe, what,
                       allow_one ? "(markers, 3) or (frames, markers, 3)" : "(frames, markers, 3)",
                       0);
    }
    nd = PyArray_NDIM(f->arr);
    f->v = (const sfit_vec3_t *)PyArray_DATA(f->arr);
    f->nframes = (nd == 3) ? (size_t)PyArray_DIM(f->arr, 0) : 1u;
    f->count = (size_t)PyArray_DIM(f->arr, nd - 2);
    return 0;
}

/* The valid rows of p (NaN, Inf and out-of-range rows removed), as a
 * contiguous array: p itself when every row is valid, else a PyMem copy
 * in *own (free with PyMem_Free). The validity test is the library's own:
 * a row is valid when sfit_moments_add accepts it, so the rows kept are
 * exactly those the CLI keeps. Also accumulates the kept rows into acc
 * (if not NULL). Returns the rejected count, or -1 (memory). */
long sfit_py_pts_filter(const sfit_py_pts_t *p, sfit_moments_t *acc, const sfit_vec3_t **out,
                       sfit_vec3_t **own, size_t *nout)
{
    size_t i, k = 0;
    long rejected = 0;
    sfit_moments_t scratch;
    sfit_vec3_t *buf = NULL;
    if (acc == NULL) {
        acc = &scratch;
        (void)sfit_moments_init(acc);
    }
    *own = NULL;
    Py_BEGIN_ALLOW_THREADS
    for (i = 0; i < p->n; i++) {
        const sfit_status_t st = sfit_moments_add(acc, &p->v[i]);
        if (st != SFIT_OK) {
            if (buf == NULL) { /* first rejected row: copy what came before */
                buf = (sfit_vec3_t *)PyMem_RawMalloc((p->n > 0u ? p->n : 1u) * sizeof *buf);
                if (buf == NULL) {
                    break;
                }
                if (i > 0u) {
                    memcpy(buf, p->v, i * sizeof *buf);
                }
                k = i;
            }
            rejected++;
        } else if (buf != NULL) {
            buf[k++] = p->v[i];
        }
    }
    Py_END_ALLOW_THREADS
    if (rejected > 0 && buf == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    if (buf != NULL) {
        *own = buf;
        *out = buf;
        *nout = k;
    } else {
        *out = p->v;
        *nout = p->n;
    }
    return rejected;
}

/* obj as a C-contiguous float64 array of minnd..maxnd dimensions, when
 * its values are real numbers (float, int, uint: not complex, bool, object
 * or str, which a forced cast would silently truncate); else NULL, with
 * any exception cleared (the caller raises its ArgError). */
PyArrayObject *sfit_py_real_f64(PyObject *obj, int minnd, int maxnd)
{
    PyArrayObject *a, *any = (PyArrayObject *)PyArray_FROMANY(obj, NPY_NOTYPE, minnd, maxnd, 0);
    char kind;
    if (any == NULL) {
        PyErr_Clear();
        return NULL;
    }
    kind = PyArray_DESCR(any)->kind;
    if (kind != 'f' && kind != 'i' && kind != 'u') {
        Py_DECREF(any);
        return NULL;
    }
    a = (PyArrayObject *)PyArray_FROM_OTF((PyObject *)any, NPY_FLOAT64,
                                          NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
    Py_DECREF(any);
    if (a == NULL) {
        PyErr_Clear();
    }
    return a;
}

/* Read a 3-vector argument (any sequence of 3 real numbers, finite or
 * not: the library judges the values). */
int sfit_py_vec3_get(PyObject *obj, sfit_vec3_t *v, const char *what)
{
    PyArrayObject *a = sfit_py_real_f64(obj, 1, 1);
    const double *d;
    if (a == NULL || PyArray_DIM(a, 0) != 3) {
        Py_XDECREF(a);
        PyErr_Clear();
        sfit_py_raise_arg("%s: expected 3 numbers", what);
        return -1;
    }
    d = (const double *)PyArray_DATA(a);
    v->v[0] = (float)d[0];
    v->v[1] = (float)d[1];
    v->v[2] = (float)d[2];
    Py_DECREF(a);
    return 0;
}

PyObject *sfit_py_frames_place(const sfit_py_frames_t *f, sfit_py_place_fn fn, void *ctx)
{
    npy_intp dim[2];
    PyObject *ca, *aa, *va;
    dim[0] = (npy_intp)f->nframes;
    dim[1] = 3;
    ca = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    aa = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    va = PyArray_SimpleNew(1, dim, NPY_BOOL);
    if (ca == NULL || aa == NULL || va == NULL) {
        Py_XDECREF(ca);
        Py_XDECREF(aa);
        Py_XDECREF(va);
        return NULL;
    }
    {
        double *cd = (double *)PyArray_DATA((PyArrayObject *)ca);
        double *ad = (double *)PyArray_DATA((PyArrayObject *)aa);
        npy_bool *vd = (npy_bool *)PyArray_DATA((PyArrayObject *)va);
        size_t i;
        Py_BEGIN_ALLOW_THREADS
        for (i = 0; i < f->nframes; i++) {
            double c[3], a[3];
            const int ok = fn(ctx, f->v + i * f->count, f->count, c, a) == 0;
            int k;
            vd[i] = (npy_bool)ok;
            for (k = 0; k < 3; k++) {
                cd[3 * i + (size_t)k] = ok ? c[k] : NAN;
                ad[3 * i + (size_t)k] = ok ? a[k] : NAN;
            }
        }
        Py_END_ALLOW_THREADS
    }
    return Py_BuildValue("(NNN)", ca, aa, va);
}
