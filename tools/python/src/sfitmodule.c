/* SPDX-License-Identifier: MIT */
/**
 * @file sfitmodule.c
 * @brief sfit._sfit: the CPython extension over lib/src (compiled from the
 * same sources, see setup.py).
 *
 * This file is the only place that calls the C library: every sfit_*
 * function and type the Python package uses appears here, and nowhere in
 * the Python layer (sfit/__init__.py), so that an API rename touches this
 * file only. What it does:
 *  - arrays in: any real numeric array-like of shape (N, 3) (or (3,) for one
 *    sample) is converted to a C-contiguous float32 copy by numpy (float64
 *    is rounded to nearest float32; values beyond float32's range become
 *    inf and are rejected as the library rejects them);
 *  - rows the library rejects (NaN, Inf, |x| >= 2^SFIT_COORD_MAX_EXP) are
 *    skipped and counted, as the CLI does with such lines;
 *  - results out: dicts of float64 numpy arrays and Python floats holding
 *    the library's float32 values exactly (the Python layer wraps them);
 *  - a status other than SFIT_OK raises the sfit.Error subclass of that
 *    status, carrying the status name, the code and a message.
 * The GIL is released around the loops over samples of the functions on
 * arrays; methods that change an object's state keep it (no two threads
 * ever update one state at once).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <math.h>
#include <string.h>

#include "sfit/sfit.h"
#include "swaps.h" /* _label_swaps: tools/sfit/cli_swaps.c, for joint_center */
#include "pair_py.h" /* the pair of segments: pair_py.c */
#include "imu_py.h"  /* the joint between two IMUs: imu_py.c */
#include "cli_refine.h" /* the recipe's flat result as the CLI prints it: tools/sfit */
#include "sfit/sfit_cluster.h"
#include "sfit/sfit_joint.h"

/* ------------------------------------------------------------------------ */
/* Exceptions                                                               */
/* ------------------------------------------------------------------------ */

#define N_STATUS 8 /* SFIT_OK .. SFIT_E_RANGE (0 .. -7) */

/* C3D files (c3dmodule.c): sfit.read_c3d / write_c3d / write_trc. */
PyMethodDef *sfit_py_c3d_methods(void);
/* A lab session (session_py.c): sfit.session_model / calibrate / apply_session. */
PyMethodDef *sfit_py_session_methods(void);

static PyObject *g_error;            /* sfit.Error */
static PyObject *g_exc[N_STATUS];    /* per status code (index -code), [0] unused */

static const char *const g_exc_names[N_STATUS] = {
    NULL,               "ArgError",       "TooFewError",     "NotPosDefError",
    "NoConvergenceError", "DegenerateError", "NonFiniteError", "RangeError"};

static const char *status_message(sfit_status_t st)
{
    switch (st) {
    case SFIT_E_ARG: return "invalid argument or option";
    case SFIT_E_TOO_FEW: return "fewer valid samples than the solution needs";
    case SFIT_E_NOT_POSDEF:
        return "not positive definite: the noise model is larger than the spread "
               "of the samples (or the geometry is ill-posed)";
    case SFIT_E_NO_CONVERGENCE: return "the iteration did not converge within its bound";
    case SFIT_E_DEGENERATE:
        return "degenerate geometry: samples coincident, collinear, or planar "
               "(try mode='planar')";
    case SFIT_E_NONFINITE: return "non-finite value (NaN or Inf)";
    case SFIT_E_RANGE: return "value out of the supported float range";
    case SFIT_E_UNSUPPORTED: return "not in this build of the library (SFIT_FULL_SOLVER 0)";
    case SFIT_OK: return "ok";
    default: return "unknown status";
    }
}

/* Raise the exception of status st; `what` names the operation. n and
 * rejected (>= 0) are attached as attributes when given. Returns NULL. */
static PyObject *raise_status(sfit_status_t st, const char *what, long n, long rejected)
{
    const int idx = (st < 0 && st > -N_STATUS) ? -(int)st : 0;
    PyObject *cls = (idx > 0) ? g_exc[idx] : g_error;
    PyObject *msg, *exc;
    if (n >= 0) {
        msg = PyUnicode_FromFormat("%s failed (%s): %s [n=%ld, rejected=%ld]", what,
                                   sfit_status_str(st), status_message(st), n, rejected);
    } else {
        msg = PyUnicode_FromFormat("%s failed (%s): %s", what, sfit_status_str(st),
                                   status_message(st));
    }
    if (msg == NULL) {
        return NULL;
    }
    exc = PyObject_CallOneArg(cls, msg);
    Py_DECREF(msg);
    if (exc == NULL) {
        return NULL;
    }
    {
        PyObject *s = PyUnicode_FromString(sfit_status_str(st));
        PyObject *c = PyLong_FromLong((long)st);
        PyObject *m = PyUnicode_FromString(status_message(st));
        PyObject *nn = (n >= 0) ? PyLong_FromLong(n) : Py_NewRef(Py_None);
        PyObject *rr = (n >= 0) ? PyLong_FromLong(rejected) : Py_NewRef(Py_None);
        int bad = (s == NULL || c == NULL || m == NULL || nn == NULL || rr == NULL)
                  || PyObject_SetAttrString(exc, "status", s) < 0
                  || PyObject_SetAttrString(exc, "code", c) < 0
                  || PyObject_SetAttrString(exc, "message", m) < 0
                  || PyObject_SetAttrString(exc, "n", nn) < 0
                  || PyObject_SetAttrString(exc, "rejected", rr) < 0;
        Py_XDECREF(s);
        Py_XDECREF(c);
        Py_XDECREF(m);
        Py_XDECREF(nn);
        Py_XDECREF(rr);
        if (bad) {
            Py_DECREF(exc);
            return NULL;
        }
    }
    PyErr_SetObject(cls, exc);
    Py_DECREF(exc);
    return NULL;
}

/* An argument error of the binding itself (shape, dtype, option value). */
static PyObject *raise_arg(const char *fmt, ...)
{
    va_list ap;
    PyObject *msg, *exc;
    va_start(ap, fmt);
    msg = PyUnicode_FromFormatV(fmt, ap);
    va_end(ap);
    if (msg == NULL) {
        return NULL;
    }
    exc = PyObject_CallOneArg(g_exc[1], msg);
    if (exc != NULL) {
        PyObject *s = PyUnicode_FromString(sfit_status_str(SFIT_E_ARG));
        PyObject *c = PyLong_FromLong((long)SFIT_E_ARG);
        if (s != NULL && c != NULL && PyObject_SetAttrString(exc, "status", s) == 0
            && PyObject_SetAttrString(exc, "code", c) == 0
            && PyObject_SetAttrString(exc, "message", msg) == 0
            && PyObject_SetAttrString(exc, "n", Py_None) == 0
            && PyObject_SetAttrString(exc, "rejected", Py_None) == 0) {
            PyErr_SetObject(g_exc[1], exc);
        }
        Py_XDECREF(s);
        Py_XDECREF(c);
        Py_DECREF(exc);
    }
    Py_DECREF(msg);
    return NULL;
}

/* ------------------------------------------------------------------------ */
/* Arrays in                                                                */
/* ------------------------------------------------------------------------ */

/* A float32 (n, 3) view of the caller's samples. */
typedef struct pts {
    PyArrayObject *arr; /* owned reference (C-contiguous float32) */
    const sfit_vec3_t *v;
    size_t n;
} pts_t;

static void pts_release(pts_t *p)
{
    Py_CLEAR(p->arr);
    p->v = NULL;
    p->n = 0;
}

/* Convert obj to float32 C-contiguous. ndim_ok: 2 = (N, 3) only;
 * 1 = (3,) or (N, 3). Returns 0, or -1 with an exception set. */
static int pts_get(PyObject *obj, pts_t *p, const char *what, int allow_one)
{
    PyArrayObject *any, *f;
    char kind;
    int nd;
    p->arr = NULL;
    p->v = NULL;
    p->n = 0;
    any = (PyArrayObject *)PyArray_FROMANY(obj, NPY_NOTYPE, 0, 0, 0);
    if (any == NULL) {
        PyErr_Clear();
        raise_arg("%s: not an array of numbers", what);
        return -1;
    }
    kind = PyArray_DESCR(any)->kind;
    if (kind != 'f' && kind != 'i' && kind != 'u') {
        PyObject *dt = PyObject_Str((PyObject *)PyArray_DESCR(any));
        Py_DECREF(any);
        if (dt == NULL) {
            return -1;
        }
        raise_arg("%s: dtype %U is not a real number type (use float32 or float64)", what, dt);
        Py_DECREF(dt);
        return -1;
    }
    nd = PyArray_NDIM(any);
    if (nd == 1 && PyArray_DIM(any, 0) == 0) { /* [] : no samples */
        npy_intp dims[2] = {0, 3};
        Py_DECREF(any);
        p->arr = (PyArrayObject *)PyArray_ZEROS(2, dims, NPY_FLOAT32, 0);
        if (p->arr == NULL) {
            return -1;
        }
        p->v = (const sfit_vec3_t *)PyArray_DATA(p->arr);
        return 0;
    }
    if (!((nd == 2 && PyArray_DIM(any, 1) == 3) || (allow_one && nd == 1 && PyArray_DIM(any, 0) == 3))) {
        PyObject *shape = PyObject_GetAttrString((PyObject *)any, "shape");
        Py_DECREF(any);
        if (shape == NULL) {
            return -1;
        }
        raise_arg("%s: expected shape %s, got %R", what, allow_one ? "(N, 3) or (3,)" : "(N, 3)",
                  shape);
        Py_DECREF(shape);
        return -1;
    }
    /* more rows than the library counts (uint32): refused before the
     * float32 copy (a broadcast view of 2**32 rows costs nothing, its copy
     * 48 GiB) */
    if (nd == 2 && (uint64_t)PyArray_DIM(any, 0) > (uint64_t)UINT32_MAX) {
        Py_DECREF(any);
        raise_status(SFIT_E_RANGE, what, -1, -1);
        return -1;
    }
    f = (PyArrayObject *)PyArray_FROM_OTF((PyObject *)any, NPY_FLOAT32,
                                          NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
    Py_DECREF(any);
    if (f == NULL) {
        return -1;
    }
    p->arr = f;
    p->v = (const sfit_vec3_t *)PyArray_DATA(f);
    p->n = (nd == 1) ? 1u : (size_t)PyArray_DIM(f, 0);
    return 0;
}

/* The valid rows of p (NaN, Inf and out-of-range rows removed), as a
 * contiguous array: p itself when every row is valid, else a PyMem copy
 * in *own (free with PyMem_Free). The validity test is the library's own:
 * a row is valid when sfit_moments_add accepts it, so the rows kept are
 * exactly those the CLI keeps. Also accumulates the kept rows into acc
 * (if not NULL). Returns the rejected count, or -1 (memory). */
static long pts_filter(const pts_t *p, sfit_moments_t *acc, const sfit_vec3_t **out,
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
static PyArrayObject *real_f64(PyObject *obj, int minnd, int maxnd)
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
static int vec3_get(PyObject *obj, sfit_vec3_t *v, const char *what)
{
    PyArrayObject *a = real_f64(obj, 1, 1);
    const double *d;
    if (a == NULL || PyArray_DIM(a, 0) != 3) {
        Py_XDECREF(a);
        PyErr_Clear();
        raise_arg("%s: expected 3 numbers", what);
        return -1;
    }
    d = (const double *)PyArray_DATA(a);
    v->v[0] = (float)d[0];
    v->v[1] = (float)d[1];
    v->v[2] = (float)d[2];
    Py_DECREF(a);
    return 0;
}

/* ------------------------------------------------------------------------ */
/* Values out                                                               */
/* ------------------------------------------------------------------------ */

static PyObject *vec3_out(const float *v)
{
    npy_intp dim = 3;
    PyObject *a = PyArray_SimpleNew(1, &dim, NPY_FLOAT64);
    if (a != NULL) {
        double *d = (double *)PyArray_DATA((PyArrayObject *)a);
        d[0] = (double)v[0];
        d[1] = (double)v[1];
        d[2] = (double)v[2];
    }
    return a;
}

static PyObject *mat3_out(const sfit_mat3_t *m)
{
    npy_intp dim[2] = {3, 3};
    PyObject *a = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    int i;
    if (a != NULL) {
        double *d = (double *)PyArray_DATA((PyArrayObject *)a);
        for (i = 0; i < 9; i++) {
            d[i] = (double)m->m[i];
        }
    }
    return a;
}

/* dict[key] = value, stealing value; returns -1 on failure (value freed). */
static int put(PyObject *dict, const char *key, PyObject *value)
{
    int rc;
    if (value == NULL) {
        return -1;
    }
    rc = PyDict_SetItemString(dict, key, value);
    Py_DECREF(value);
    return rc;
}

static PyObject *flt(float x)
{
    return PyFloat_FromDouble((double)x);
}

typedef struct flag_name {
    uint32_t bit;
    const char *name;
} flag_name_t;

static const flag_name_t g_fit_flags[] = {{SFIT_FLAG_UNTRUSTED, "untrusted"},
                                          {SFIT_FLAG_FEW_SAMPLES, "few_samples"},
                                          {SFIT_FLAG_NEAR_PLANAR, "near_planar"},
                                          {SFIT_FLAG_ROUNDING, "rounding"},
                                          {SFIT_SELFCAL_FLAG_CAPPED, "noise_capped"},
                                          {SFIT_FLAG_COV_LIMIT, "cov_limit"},
                                          {SFIT_MULTI_FLAG_SKIPPED, "skipped_markers"},
                                          {0u, NULL}};
static const flag_name_t g_noise_flags[] = {{SFIT_NOISE_FLAG_NEGATIVE, "negative"},
                                            {SFIT_NOISE_FLAG_IMPRECISE, "imprecise"},
                                            {0u, NULL}};

/* The names of the bits set in flags, as a list of str. */
static PyObject *flag_names(uint32_t flags, const flag_name_t *tab)
{
    PyObject *l = PyList_New(0);
    size_t i;
    if (l == NULL) {
        return NULL;
    }
    for (i = 0; tab[i].name != NULL; i++) {
        if (flags & tab[i].bit) {
            PyObject *s = PyUnicode_FromString(tab[i].name);
            if (s == NULL || PyList_Append(l, s) < 0) {
                Py_XDECREF(s);
                Py_DECREF(l);
                return NULL;
            }
            Py_DECREF(s);
        }
    }
    return l;
}

static const char *mode_name(sfit_mode_t m)
{
    return (m == SFIT_MODE_PLANAR) ? "planar" : "sphere";
}

/* The solve summary that sfit_result_t and sfit_multi_result_t share. */
static int summary_into(PyObject *d, const sfit_vec3_t *eig, const sfit_vec3_t *axis,
                        float trust, float leontief, uint32_t flags, sfit_method_t method,
                        sfit_mode_t mode)
{
    if (put(d, "eigenvalues", vec3_out(eig->v)) < 0 || put(d, "axis", vec3_out(axis->v)) < 0
        || put(d, "trust_ratio", flt(trust)) < 0 || put(d, "leontief_ratio", flt(leontief)) < 0
        || put(d, "flags", flag_names(flags, g_fit_flags)) < 0
        || put(d, "flags_mask", PyLong_FromUnsignedLong((unsigned long)flags)) < 0
        || put(d, "method", PyUnicode_FromString(method == SFIT_METHOD_UGDK ? "ugdk" : "gdke")) < 0
        || put(d, "mode", PyUnicode_FromString(mode_name(mode))) < 0) {
        return -1;
    }
    return 0;
}

/* The fields of a sfit_result_t into d. */
static int result_into(PyObject *d, const sfit_result_t *r)
{
    if (put(d, "center", vec3_out(r->center.v)) < 0 || put(d, "radius", flt(r->radius)) < 0
        || put(d, "n", PyLong_FromUnsignedLong((unsigned long)r->n)) < 0) {
        return -1;
    }
    return summary_into(d, &r->eigenvalues, &r->axis, r->trust_ratio, r->leontief_ratio,
                        r->flags, r->method, r->mode);
}

/* The fields of a sfit_multi_result_t into d. */
static int multi_into(PyObject *d, const sfit_multi_result_t *r)
{
    if (put(d, "center", vec3_out(r->center.v)) < 0
        || put(d, "n", PyLong_FromUnsignedLong((unsigned long)r->n_total)) < 0
        || put(d, "markers", PyLong_FromUnsignedLong((unsigned long)r->markers)) < 0
        || put(d, "skipped", PyLong_FromUnsignedLong((unsigned long)r->skipped)) < 0) {
        return -1;
    }
    return summary_into(d, &r->eigenvalues, &r->axis, r->trust_ratio, r->leontief_ratio,
                        r->flags, r->method, r->mode);
}

static int uncert_into(PyObject *d, const sfit_uncert_t *u)
{
    if (put(d, "center_cov", mat3_out(&u->center_cov)) < 0
        || put(d, "radius_var", flt(u->radius_var)) < 0
        || put(d, "center_radius_cov", vec3_out(u->center_radius_cov)) < 0
        || put(d, "uncert_noise_var", flt(u->noise_var)) < 0) {
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------------------ */
/* Options                                                                  */
/* ------------------------------------------------------------------------ */

/* mode: "auto" / "sphere" / "planar". */
static int mode_get(PyObject *o, sfit_mode_t *m)
{
    /* PyUnicode_CompareWithASCIIString compares the whole string: "auto\0x"
     * is not "auto" (strcmp on its UTF-8 would stop at the NUL) */
    const int str = (o != NULL && PyUnicode_Check(o));
    if (str && PyUnicode_CompareWithASCIIString(o, "auto") == 0) {
        *m = SFIT_MODE_AUTO;
    } else if (str && PyUnicode_CompareWithASCIIString(o, "sphere") == 0) {
        *m = SFIT_MODE_SPHERE;
    } else if (str && PyUnicode_CompareWithASCIIString(o, "planar") == 0) {
        *m = SFIT_MODE_PLANAR;
    } else {
        PyErr_Clear();
        raise_arg("mode must be 'auto', 'sphere' or 'planar', got %R", o != NULL ? o : Py_None);
        return -1;
    }
    return 0;
}

/* A finite float >= 0 from a Python number. */
static int nonneg_get(PyObject *o, float *x, const char *what)
{
    double d;
    if (o == NULL || !PyNumber_Check(o) || PyBool_Check(o) || PyUnicode_Check(o)) {
        raise_arg("%s must be a number", what);
        return -1;
    }
    d = PyFloat_AsDouble(o);
    if (d == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        raise_arg("%s must be a number", what);
        return -1;
    }
    if (!(d >= 0.0) || !isfinite(d) || d > 3.4e38) {
        raise_arg("%s must be finite and >= 0, got %R", what, o);
        return -1;
    }
    *x = (float)d;
    return 0;
}

/* noise_cov: a (3, 3) symmetric array or 6 packed XX,YY,ZZ,XY,XZ,YZ. */
static int cov_get(PyObject *o, sfit_mat3_t *m)
{
    PyArrayObject *a = real_f64(o, 1, 2);
    const double *d;
    int i;
    if (a == NULL) {
        raise_arg("noise_cov must be a (3, 3) array or 6 numbers XX,YY,ZZ,XY,XZ,YZ");
        return -1;
    }
    d = (const double *)PyArray_DATA(a);
    if (PyArray_NDIM(a) == 1 && PyArray_DIM(a, 0) == 6) {
        const float c[6] = {(float)d[0], (float)d[1], (float)d[2],
                            (float)d[3], (float)d[4], (float)d[5]};
        m->m[0] = c[0]; m->m[4] = c[1]; m->m[8] = c[2];
        m->m[1] = m->m[3] = c[3];
        m->m[2] = m->m[6] = c[4];
        m->m[5] = m->m[7] = c[5];
    } else if (PyArray_NDIM(a) == 2 && PyArray_DIM(a, 0) == 3 && PyArray_DIM(a, 1) == 3) {
        for (i = 0; i < 9; i++) {
            m->m[i] = (float)d[i];
        }
        if (d[1] != d[3] || d[2] != d[6] || d[5] != d[7]) {
            Py_DECREF(a);
            raise_arg("noise_cov must be symmetric");
            return -1;
        }
    } else {
        Py_DECREF(a);
        raise_arg("noise_cov must be a (3, 3) array or 6 numbers XX,YY,ZZ,XY,XZ,YZ");
        return -1;
    }
    Py_DECREF(a);
    for (i = 0; i < 9; i++) {
        if (!isfinite(m->m[i])) {
            raise_arg("noise_cov must be finite");
            return -1;
        }
    }
    return 0;
}

/* The fit options shared by fit(), fit_multi(), Moments.fit() and
 * Incremental(): noise_var (None, a number; "auto" is handled by the
 * caller), noise_cov, mode, planar_ratio. */
static int cfg_get(PyObject *noise_var, PyObject *noise_cov, PyObject *mode, double planar_ratio,
                   sfit_fit_cfg_t *cfg)
{
    *cfg = sfit_fit_cfg_default;
    cfg->eigen = true; /* fit() reports eigenvalues, axis and the exact trust ratio */
    if (mode != NULL && mode_get(mode, &cfg->mode) < 0) {
        return -1;
    }
    if (noise_var != NULL && noise_var != Py_None && noise_cov != NULL && noise_cov != Py_None) {
        raise_arg("give noise_var or noise_cov, not both");
        return -1;
    }
    if (noise_var != NULL && noise_var != Py_None) {
        if (nonneg_get(noise_var, &cfg->noise_var, "noise_var") < 0) {
            return -1;
        }
        cfg->noise = SFIT_NOISE_ISO;
    } else if (noise_cov != NULL && noise_cov != Py_None) {
        if (cov_get(noise_cov, &cfg->noise_cov) < 0) {
            return -1;
        }
        cfg->noise = SFIT_NOISE_COV;
    }
    if (!(planar_ratio >= 0.0 && planar_ratio < 0.5)) {
        raise_arg("planar_ratio must be in [0, 0.5) (0 = the library default)");
        return -1;
    }
    cfg->planar_ratio = (float)planar_ratio;
    return 0;
}

static int weight_get(const char *w, sfit_multi_weight_t *out)
{
    if (strcmp(w, "equal") == 0) {
        *out = SFIT_MULTI_WEIGHT_EQUAL;
    } else if (strcmp(w, "samples") == 0) {
        *out = SFIT_MULTI_WEIGHT_SAMPLES;
    } else {
        raise_arg("weight must be 'equal' or 'samples', got '%s'", w);
        return -1;
    }
    return 0;
}

/* A Python int argument >= 0, values above max taken as max: TypeError
 * for a non-int (as the "k" format would), ArgError for a negative value
 * (the "k" format silently wraps -1 to 2**64 - 1 and 2**64 + 1 to 1). */
static int count_get(PyObject *o, unsigned long long max, unsigned long long *out,
                     const char *what)
{
    int overflow = 0;
    long long v;
    if (!PyLong_Check(o)) {
        PyErr_Format(PyExc_TypeError, "%s must be an int, not %.100s", what, Py_TYPE(o)->tp_name);
        return -1;
    }
    v = PyLong_AsLongLongAndOverflow(o, &overflow);
    if (v == -1 && PyErr_Occurred()) {
        return -1;
    }
    if (overflow < 0 || (overflow == 0 && v < 0)) {
        raise_arg("%s must be >= 0, got %R", what, o);
        return -1;
    }
    *out = (overflow > 0 || (unsigned long long)v > max) ? max : (unsigned long long)v;
    return 0;
}

static int is_auto(PyObject *o)
{
    return o != NULL && PyUnicode_Check(o) && PyUnicode_CompareWithASCIIString(o, "auto") == 0;
}

/* ------------------------------------------------------------------------ */
/* fit()                                                                    */
/* ------------------------------------------------------------------------ */

PyDoc_STRVAR(fit_doc, "_fit(points, noise_var, noise_cov, mode, refine, planar_ratio, gate) -> dict\n"
                      "Internal: see sfit.fit.");

static PyObject *py_fit(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "noise_var", "noise_cov", "mode", "refine",
                             "planar_ratio", "gate", NULL};
    PyObject *points, *noise_var = Py_None, *noise_cov = Py_None, *mode = NULL, *gate = Py_None;
    int refine = 0, auto_noise;
    double planar_ratio = 0.0;
    sfit_fit_cfg_t cfg;
    pts_t p;
    sfit_moments_t acc;
    const sfit_vec3_t *v = NULL;
    sfit_vec3_t *own = NULL;
    size_t nv = 0;
    long rejected = 0, outliers = 0;
    sfit_status_t st;
    sfit_result_t r;
    sfit_uncert_t u;
    int has_u = 0, has_noise = 0, noise_est = 0, capped = 0, refined = 0;
    float nvar = 0.0f, rms = 0.0f;
    unsigned long iters = 0;
    float gate_k = 0.0f;
    PyObject *d;
    (void)self;

    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|OOOpdO", kwlist, &points, &noise_var,
                                     &noise_cov, &mode, &refine, &planar_ratio, &gate)) {
        return NULL;
    }
    auto_noise = is_auto(noise_var);
    if (cfg_get(auto_noise ? Py_None : noise_var, noise_cov, mode, planar_ratio, &cfg) < 0) {
        return NULL;
    }
    if (auto_noise && cfg.noise != SFIT_NOISE_NONE) {
        return raise_arg("give noise_var or noise_cov, not both");
    }
    if (gate != Py_None) {
        double k = PyFloat_AsDouble(gate);
        if ((k == -1.0 && PyErr_Occurred()) || !(k > 1.0) || !isfinite(k)) {
            PyErr_Clear();
            return raise_arg("gate must be a number K > 1 (sigmas)");
        }
        if (auto_noise || refine) {
            return raise_arg("gate does not combine with noise_var='auto' or refine=True");
        }
        gate_k = (float)k;
    }
    if (refine && cfg.noise != SFIT_NOISE_NONE) {
        return raise_arg("refine=True estimates the noise itself (self-calibrated start): "
                         "no noise_var / noise_cov");
    }
    if ((auto_noise || refine) && cfg.mode == SFIT_MODE_PLANAR) {
        return raise_arg("noise_var='auto' and refine=True fit spheres (not mode='planar')");
    }
    if (pts_get(points, &p, "points", 0) < 0) {
        return NULL;
    }
    memset(&u, 0, sizeof u);
    if (gate_k > 0.0f) {
        /* the gate judges every sample: a rejected row is counted, an
         * outlier is counted separately */
        sfit_gate_cfg_t gc = sfit_gate_cfg_default;
        sfit_gate_t *g = (sfit_gate_t *)PyMem_Malloc(sizeof *g);
        sfit_gate_stats_t gs;
        size_t i;
        if (g == NULL) {
            pts_release(&p);
            return PyErr_NoMemory();
        }
        gc.fit = cfg;
        gc.k = gate_k;
        if (cfg.noise == SFIT_NOISE_ISO) {
            gc.noise_var = cfg.noise_var;
        }
        st = sfit_gate_init(g, &gc);
        if (st == SFIT_OK) {
            Py_BEGIN_ALLOW_THREADS
            for (i = 0; i < p.n; i++) {
                if (sfit_gate_add(g, &p.v[i], NULL) != SFIT_OK) {
                    rejected++;
                }
            }
            st = sfit_gate_fit(g, &r);
            Py_END_ALLOW_THREADS
            (void)sfit_gate_stats(g, &gs);
            outliers = (long)gs.outliers;
            if (st == SFIT_OK && cfg.noise == SFIT_NOISE_ISO && r.mode == SFIT_MODE_SPHERE
                && sfit_gate_moments(g) != NULL) {
                has_noise = 1;
                nvar = cfg.noise_var;
                has_u = (sfit_uncert_moments(sfit_gate_moments(g), &r.center, r.radius, nvar,
                                             SFIT_UNCERT_NOISE_KNOWN, &u) == SFIT_OK);
            }
        }
        PyMem_Free(g);
        nv = p.n - (size_t)rejected;
        pts_release(&p);
        if (st != SFIT_OK) {
            return raise_status(st, "fit", (long)nv - outliers, rejected);
        }
        nv = (size_t)r.n;
    } else {
        (void)sfit_moments_init(&acc);
        rejected = pts_filter(&p, &acc, &v, &own, &nv);
        if (rejected < 0) {
            pts_release(&p);
            return NULL;
        }
        Py_BEGIN_ALLOW_THREADS
        if (refine) {
            st = SFIT_OK; /* the recipe below makes its own start */
        } else if (auto_noise) {
            sfit_selfcal_result_t sc;
            sfit_selfcal_cfg_t scc = sfit_selfcal_cfg_default;
            scc.planar_ratio = cfg.planar_ratio;
            st = sfit_selfcal_points(v, nv, &scc, &sc);
            if (st == SFIT_OK) {
                r = sc.fit;
                has_noise = 1;
                nvar = sc.noise_var;
                noise_est = 1;
                iters = sc.iterations;
                capped = (sc.flags & SFIT_SELFCAL_FLAG_CAPPED) != 0u;
            }
        } else {
            st = sfit_fit_moments(&acc, &cfg, &r);
            if (st == SFIT_OK && cfg.noise == SFIT_NOISE_ISO) {
                has_noise = 1;
                nvar = cfg.noise_var;
            }
        }
        if (st == SFIT_OK && refine) {
            /* the library's recipe (sfit_refine_fit), one call and one flat
             * result, printed as the CLI prints it (cli_refine.h) */
            sfit_refine_result_t rf;
            sfit_refined_cfg_t rc = sfit_refined_cfg_default;
            rc.selfcal.planar_ratio = cfg.planar_ratio;
            st = sfit_refine_fit(v, nv, &rc, &rf);
            if (st == SFIT_OK) {
                cli_refine_parts(&rf, &r, &u);
                refined = 1;
                has_noise = 1;
                nvar = rf.noise_var;
                noise_est = 1;
                iters = rf.iterations;
                rms = rf.rms;
                capped = (rf.flags & SFIT_SELFCAL_FLAG_CAPPED) != 0u;
                has_u = 1;
            }
        } else if (st == SFIT_OK && has_noise && r.mode == SFIT_MODE_SPHERE) {
            /* self-calibrated: its own sandwich (as sfit fit --noise-var auto) */
            has_u = noise_est ? (sfit_uncert_selfcal(v, nv, &r.center, r.radius, nvar,
                                                     &u) == SFIT_OK)
                              : (sfit_uncert_moments(&acc, &r.center, r.radius, nvar,
                                                     SFIT_UNCERT_NOISE_KNOWN, &u) == SFIT_OK);
        }
        Py_END_ALLOW_THREADS
        PyMem_RawFree(own);
        pts_release(&p);
        if (st != SFIT_OK) {
            return raise_status(st, "fit", (long)nv, rejected);
        }
    }
    d = PyDict_New();
    if (d == NULL || result_into(d, &r) < 0
        || put(d, "rejected", PyLong_FromLong(rejected)) < 0
        || put(d, "outliers", PyLong_FromLong(outliers)) < 0
        || put(d, "noise_var", has_noise ? flt(nvar) : Py_NewRef(Py_None)) < 0
        || put(d, "noise_estimated", PyBool_FromLong(noise_est)) < 0
        || put(d, "noise_capped", PyBool_FromLong(capped)) < 0
        || put(d, "iterations", PyLong_FromUnsignedLong(iters)) < 0
        || put(d, "rms", refined ? flt(rms) : Py_NewRef(Py_None)) < 0
        || (refined && put(d, "method", PyUnicode_FromString("geometric")) < 0)
        || (has_u && uncert_into(d, &u) < 0)) {
        Py_XDECREF(d);
        return NULL;
    }
    return d;
}

/* ------------------------------------------------------------------------ */
/* fit_multi()                                                              */
/* ------------------------------------------------------------------------ */

/* The most items fit_multi reads from a sequence: far more markers than
 * any cluster has, few enough that their states stay small (about 50 MB). */
#define PY_MULTI_MAX_ITEMS 262144

/* A tuple of the items of obj, read one by one from its iterator: the
 * tuple grows with the items actually read, never with what __len__ (or
 * __length_hint__) claims, and stops with an ArgError past max items. A
 * non-iterable obj or an error while iterating is an ArgError too. */
static PyObject *items_read(PyObject *obj, Py_ssize_t max, const char *what)
{
    PyObject *it, *list, *item, *tup;
    if (PyTuple_Check(obj) || PyList_Check(obj)) {
        if (PySequence_Fast_GET_SIZE(obj) > max) {
            return raise_arg("%s: more than %zd items", what, max);
        }
        return PySequence_Tuple(obj); /* the size is the items held */
    }
    it = PyObject_GetIter(obj);
    if (it == NULL) {
        PyErr_Clear();
        return raise_arg("%s must be a sequence of (N, 3) arrays", what);
    }
    list = PyList_New(0);
    if (list == NULL) {
        Py_DECREF(it);
        return NULL;
    }
    while ((item = PyIter_Next(it)) != NULL) {
        const int rc = (PyList_GET_SIZE(list) >= max) ? -2 : PyList_Append(list, item);
        Py_DECREF(item);
        if (rc != 0) {
            Py_DECREF(it);
            Py_DECREF(list);
            if (rc == -2) {
                return raise_arg("%s: more than %zd items", what, max);
            }
            return NULL;
        }
    }
    Py_DECREF(it);
    if (PyErr_Occurred()) {
        Py_DECREF(list);
        PyErr_Clear();
        return raise_arg("%s must be a sequence of (N, 3) arrays", what);
    }
    tup = PyList_AsTuple(list);
    Py_DECREF(list);
    return tup;
}

static PyObject *py_fit_multi(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"markers", "noise_var", "noise_cov", "mode", "weight",
                             "planar_ratio", NULL};
    PyObject *markers, *noise_var = Py_None, *noise_cov = Py_None, *mode = NULL, *seq;
    const char *weight = "equal";
    double planar_ratio = 0.0;
    sfit_multi_cfg_t mc = sfit_multi_cfg_default;
    sfit_moments_t *acc = NULL;
    float *radii = NULL;
    long *rej = NULL;
    Py_ssize_t count, k;
    long rejected = 0;
    sfit_multi_result_t r;
    sfit_status_t st;
    PyObject *d = NULL, *ra = NULL, *na = NULL, *rja = NULL;
    (void)self;

    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|OOOsd", kwlist, &markers, &noise_var,
                                     &noise_cov, &mode, &weight, &planar_ratio)) {
        return NULL;
    }
    if (is_auto(noise_var)) {
        return raise_arg("fit_multi: noise_var='auto' is not supported (give a number)");
    }
    if (cfg_get(noise_var, noise_cov, mode, planar_ratio, &mc.fit) < 0) {
        return NULL;
    }
    if (weight_get(weight, &mc.weight) < 0) {
        return NULL;
    }
    if (PyArray_Check(markers) && PyArray_NDIM((PyArrayObject *)markers) != 3) {
        return raise_arg("fit_multi: markers must be a list of (N, 3) arrays or one (M, N, 3) array");
    }
    /* a tuple of our own: PySequence_Fast would hand back the caller's list
     * itself, whose items an item's __array__ may remove while we use them */
    seq = items_read(markers, PY_MULTI_MAX_ITEMS, "fit_multi: markers");
    if (seq == NULL) {
        return NULL;
    }
    count = PyTuple_GET_SIZE(seq);
    if (count == 0) {
        Py_DECREF(seq);
        return raise_status(SFIT_E_TOO_FEW, "fit_multi", 0, 0);
    }
    acc = (sfit_moments_t *)PyMem_Calloc((size_t)count, sizeof *acc);
    radii = (float *)PyMem_Calloc((size_t)count, sizeof *radii);
    rej = (long *)PyMem_Calloc((size_t)count, sizeof *rej);
    if (acc == NULL || radii == NULL || rej == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    for (k = 0; k < count; k++) {
        pts_t p;
        const sfit_vec3_t *v;
        sfit_vec3_t *own;
        size_t nv;
        (void)sfit_moments_init(&acc[k]);
        if (pts_get(PyTuple_GET_ITEM(seq, k), &p, "fit_multi: markers[i]", 0) < 0) {
            goto done;
        }
        rej[k] = pts_filter(&p, &acc[k], &v, &own, &nv);
        PyMem_RawFree(own);
        pts_release(&p);
        if (rej[k] < 0) {
            goto done;
        }
        rejected += rej[k];
    }
    Py_BEGIN_ALLOW_THREADS
    st = sfit_multi_fit(acc, (size_t)count, &mc, &r, radii);
    Py_END_ALLOW_THREADS
    if (st != SFIT_OK) {
        long n = 0;
        for (k = 0; k < count; k++) {
            n += (long)sfit_moments_count(&acc[k]);
        }
        raise_status(st, "fit_multi", n, rejected);
        goto done;
    }
    {
        npy_intp dim = count;
        ra = PyArray_SimpleNew(1, &dim, NPY_FLOAT64);
        na = PyArray_SimpleNew(1, &dim, NPY_INT64);
        rja = PyArray_SimpleNew(1, &dim, NPY_INT64);
        if (ra == NULL || na == NULL || rja == NULL) {
            goto done;
        }
        for (k = 0; k < count; k++) {
            ((double *)PyArray_DATA((PyArrayObject *)ra))[k] = (double)radii[k];
            ((npy_int64 *)PyArray_DATA((PyArrayObject *)na))[k] =
                (npy_int64)sfit_moments_count(&acc[k]);
            ((npy_int64 *)PyArray_DATA((PyArrayObject *)rja))[k] = (npy_int64)rej[k];
        }
    }
    d = PyDict_New();
    if (d == NULL || multi_into(d, &r) < 0 || put(d, "weight", PyUnicode_FromString(weight)) < 0
        || put(d, "rejected", PyLong_FromLong(rejected)) < 0
        || PyDict_SetItemString(d, "radii", ra) < 0
        || PyDict_SetItemString(d, "marker_n", na) < 0
        || PyDict_SetItemString(d, "marker_rejected", rja) < 0) {
        Py_CLEAR(d);
    }
done:
    Py_XDECREF(ra);
    Py_XDECREF(na);
    Py_XDECREF(rja);
    Py_DECREF(seq);
    PyMem_Free(acc);
    PyMem_Free(radii);
    PyMem_Free(rej);
    return d;
}

/* ------------------------------------------------------------------------ */
/* Moments                                                                  */
/* ------------------------------------------------------------------------ */

typedef struct {
    PyObject_HEAD
    sfit_moments_t m;
    long rejected;
} MomentsObject;

static PyTypeObject MomentsType;

static int Moments_init(MomentsObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", NULL};
    PyObject *points = Py_None;
    sfit_moments_t m; /* the new state, stored only on success */
    long rej = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|O", kwlist, &points)) {
        return -1;
    }
    (void)sfit_moments_init(&m);
    if (points != Py_None) {
        pts_t p;
        const sfit_vec3_t *v;
        sfit_vec3_t *own;
        size_t nv;
        if (pts_get(points, &p, "Moments(points)", 1) < 0) {
            return -1;
        }
        rej = pts_filter(&p, &m, &v, &own, &nv);
        PyMem_RawFree(own);
        pts_release(&p);
        if (rej < 0) {
            return -1;
        }
    }
    self->m = m;
    self->rejected = rej;
    return 0;
}

static PyObject *Moments_add(MomentsObject *self, PyObject *x)
{
    pts_t p;
    size_t i;
    long added = 0, rej = 0;
    int full = 0;
    if (pts_get(x, &p, "Moments.add", 1) < 0) {
        return NULL;
    }
    if ((uint64_t)sfit_moments_count(&self->m) + (uint64_t)p.n > (uint64_t)UINT32_MAX) {
        full = 1;
    } else {
        for (i = 0; i < p.n; i++) {
            if (sfit_moments_add(&self->m, &p.v[i]) == SFIT_OK) {
                added++;
            } else {
                rej++;
            }
        }
    }
    pts_release(&p);
    if (full) {
        return raise_status(SFIT_E_RANGE, "Moments.add (sample count full)", -1, -1);
    }
    self->rejected += rej;
    return PyLong_FromLong(added);
}

static PyObject *Moments_merge(MomentsObject *self, PyObject *other)
{
    sfit_status_t st;
    if (!PyObject_TypeCheck(other, &MomentsType)) {
        return raise_arg("Moments.merge: expected a Moments, got %s", Py_TYPE(other)->tp_name);
    }
    st = sfit_moments_merge(&self->m, &((MomentsObject *)other)->m);
    if (st != SFIT_OK) {
        return raise_status(st, "Moments.merge", -1, -1);
    }
    self->rejected += ((MomentsObject *)other)->rejected;
    Py_RETURN_NONE;
}

static PyObject *Moments_reset(MomentsObject *self, PyObject *unused)
{
    (void)unused;
    (void)sfit_moments_reset(&self->m);
    self->rejected = 0;
    Py_RETURN_NONE;
}

static PyObject *Moments_copy(MomentsObject *self, PyObject *unused)
{
    /* same (sub)type as self */
    MomentsObject *c = (MomentsObject *)PyObject_CallNoArgs((PyObject *)Py_TYPE(self));
    (void)unused;
    if (c != NULL && !PyObject_TypeCheck((PyObject *)c, &MomentsType)) {
        /* a subclass whose __new__ returns something else: never write a
         * Moments state into it */
        PyErr_Format(PyExc_TypeError, "Moments.copy: %.100s() returned %.100s, not a Moments",
                     Py_TYPE(self)->tp_name, Py_TYPE(c)->tp_name);
        Py_DECREF(c);
        return NULL;
    }
    if (c != NULL) {
        c->m = self->m;
        c->rejected = self->rejected;
    }
    return (PyObject *)c;
}

static PyObject *Moments_fit(MomentsObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"noise_var", "noise_cov", "mode", "planar_ratio", NULL};
    PyObject *noise_var = Py_None, *noise_cov = Py_None, *mode = NULL, *d;
    double planar_ratio = 0.0;
    sfit_fit_cfg_t cfg;
    sfit_result_t r;
    sfit_uncert_t u;
    sfit_status_t st;
    int has_u = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|OOOd", kwlist, &noise_var, &noise_cov, &mode,
                                     &planar_ratio)) {
        return NULL;
    }
    if (is_auto(noise_var)) {
        return raise_arg("Moments.fit: noise_var='auto' needs the samples (use sfit.fit)");
    }
    if (cfg_get(noise_var, noise_cov, mode, planar_ratio, &cfg) < 0) {
        return NULL;
    }
    st = sfit_fit_moments(&self->m, &cfg, &r);
    if (st != SFIT_OK) {
        return raise_status(st, "Moments.fit", (long)sfit_moments_count(&self->m),
                            self->rejected);
    }
    if (cfg.noise == SFIT_NOISE_ISO && r.mode == SFIT_MODE_SPHERE) {
        has_u = (sfit_uncert_moments(&self->m, &r.center, r.radius, cfg.noise_var,
                                     SFIT_UNCERT_NOISE_KNOWN, &u) == SFIT_OK);
    }
    d = PyDict_New();
    if (d == NULL || result_into(d, &r) < 0
        || put(d, "rejected", PyLong_FromLong(self->rejected)) < 0
        || put(d, "outliers", PyLong_FromLong(0)) < 0
        || put(d, "noise_var", cfg.noise == SFIT_NOISE_ISO ? flt(cfg.noise_var) : Py_NewRef(Py_None)) < 0
        || put(d, "noise_estimated", PyBool_FromLong(0)) < 0
        || put(d, "noise_capped", PyBool_FromLong(0)) < 0
        || put(d, "iterations", PyLong_FromLong(0)) < 0
        || put(d, "rms", Py_NewRef(Py_None)) < 0
        || (has_u && uncert_into(d, &u) < 0)) {
        Py_XDECREF(d);
        return NULL;
    }
    return d;
}

static PyObject *Moments_stats(MomentsObject *self, PyObject *unused)
{
    sfit_vec3_t mean, s;
    sfit_mat3_t c;
    sfit_status_t st = sfit_moments_stats(&self->m, &mean, &c, &s);
    (void)unused;
    if (st != SFIT_OK) {
        return raise_status(st, "Moments.stats", (long)sfit_moments_count(&self->m),
                            self->rejected);
    }
    return Py_BuildValue("(NNN)", vec3_out(mean.v), mat3_out(&c), vec3_out(s.v));
}

static PyObject *Moments_calibrate_noise(MomentsObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"center", "radius", NULL};
    PyObject *center;
    double radius;
    sfit_vec3_t c0;
    sfit_noise_est_t e;
    sfit_status_t st;
    PyObject *flags;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "Od", kwlist, &center, &radius)) {
        return NULL;
    }
    if (vec3_get(center, &c0, "center") < 0) {
        return NULL;
    }
    st = sfit_noise_calibrate(&self->m, &c0, (float)radius, &e);
    if (st != SFIT_OK) {
        return raise_status(st, "calibrate_noise", (long)sfit_moments_count(&self->m),
                            self->rejected);
    }
    flags = flag_names(e.flags, g_noise_flags);
    if (flags == NULL) {
        return NULL;
    }
    return Py_BuildValue("{s:k,s:N,s:N,s:N,s:N,s:l}", "n", (unsigned long)e.n, "noise_trace",
                         flt(e.noise_trace), "noise_var", flt(e.noise_var), "noise_var_std",
                         flt(e.noise_var_std), "flags", flags, "rejected", self->rejected);
}

static PyObject *Moments_uncertainty(MomentsObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"center", "radius", "noise_var", "estimated", NULL};
    PyObject *center, *nvo, *d;
    double radius;
    int estimated = 0;
    float nvar;
    sfit_vec3_t c;
    sfit_uncert_t u;
    sfit_status_t st;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OdO|p", kwlist, &center, &radius, &nvo,
                                     &estimated)) {
        return NULL;
    }
    if (vec3_get(center, &c, "center") < 0 || nonneg_get(nvo, &nvar, "noise_var") < 0) {
        return NULL;
    }
    st = sfit_uncert_moments(&self->m, &c, (float)radius, nvar,
                             estimated ? SFIT_UNCERT_NOISE_ESTIMATED : SFIT_UNCERT_NOISE_KNOWN, &u);
    if (st != SFIT_OK) {
        return raise_status(st, "Moments.uncertainty", -1, -1);
    }
    d = PyDict_New();
    if (d == NULL || uncert_into(d, &u) < 0) {
        Py_XDECREF(d);
        return NULL;
    }
    return d;
}

static PyObject *Moments_get_count(MomentsObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromUnsignedLong((unsigned long)sfit_moments_count(&self->m));
}

static PyObject *Moments_get_rejected(MomentsObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromLong(self->rejected);
}

static Py_ssize_t Moments_len(MomentsObject *self)
{
    return (Py_ssize_t)sfit_moments_count(&self->m);
}

static PyObject *Moments_repr(MomentsObject *self)
{
    return PyUnicode_FromFormat("sfit.Moments(count=%lu, rejected=%ld)",
                                (unsigned long)sfit_moments_count(&self->m), self->rejected);
}

static PyMethodDef Moments_methods[] = {
    {"add", (PyCFunction)Moments_add, METH_O,
     "add(points) -> int\n\nAdd one sample (shape (3,)) or an (N, 3) array; rows with NaN, Inf\n"
     "or |x| >= 2**27 are skipped and counted in `rejected`. Returns the number of\n"
     "samples added. float64 input is rounded to float32."},
    {"merge", (PyCFunction)Moments_merge, METH_O,
     "merge(other) -> None\n\nAdd another accumulator's samples (exact moment merge)."},
    {"reset", (PyCFunction)Moments_reset, METH_NOARGS, "reset() -> None\n\nForget every sample."},
    {"copy", (PyCFunction)Moments_copy, METH_NOARGS, "copy() -> Moments\n\nAn independent copy."},
    {"_fit", (PyCFunction)(void (*)(void))Moments_fit, METH_VARARGS | METH_KEYWORDS,
     "Internal: see Moments.fit."},
    {"stats", (PyCFunction)Moments_stats, METH_NOARGS,
     "stats() -> (mean, C, S)\n\nSample mean, covariance C = sum y y^T/(N-1) and third-moment\n"
     "vector S = sum |y|^2 y/(N-1), y = x - mean (the chapter's notation)."},
    {"_calibrate_noise", (PyCFunction)(void (*)(void))Moments_calibrate_noise,
     METH_VARARGS | METH_KEYWORDS, "Internal: see Moments.calibrate_noise."},
    {"_uncertainty", (PyCFunction)(void (*)(void))Moments_uncertainty,
     METH_VARARGS | METH_KEYWORDS, "Internal: see Moments.uncertainty."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef Moments_getset[] = {
    {"count", (getter)Moments_get_count, NULL, "Samples accumulated.", NULL},
    {"rejected", (getter)Moments_get_rejected, NULL,
     "Rows skipped since creation or reset (NaN, Inf, out of range).", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PySequenceMethods Moments_as_seq = {.sq_length = (lenfunc)Moments_len};

static PyTypeObject MomentsType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sfit._sfit.Moments",
    .tp_basicsize = sizeof(MomentsObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Streaming moments accumulator (the library's sfit_moments_t).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Moments_init,
    .tp_methods = Moments_methods,
    .tp_getset = Moments_getset,
    .tp_as_sequence = &Moments_as_seq,
    .tp_repr = (reprfunc)Moments_repr,
};

/* ------------------------------------------------------------------------ */
/* Incremental                                                              */
/* ------------------------------------------------------------------------ */

typedef struct {
    PyObject_HEAD
    sfit_incr_t s;
    long rejected;
} IncrObject;

static PyTypeObject IncrType;

static int Incr_init(IncrObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"noise_var", "noise_cov", NULL};
    PyObject *noise_var = Py_None, *noise_cov = Py_None;
    sfit_fit_cfg_t cfg;
    sfit_status_t st;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|OO", kwlist, &noise_var, &noise_cov)) {
        return -1;
    }
    sfit_incr_cfg_t icfg = sfit_incr_cfg_default;
    if (cfg_get(noise_var, noise_cov, NULL, 0.0, &cfg) < 0) {
        return -1;
    }
    icfg.noise = cfg.noise;
    icfg.noise_var = cfg.noise_var;
    icfg.noise_cov = cfg.noise_cov;
    st = sfit_incr_init(&self->s, &icfg);
    if (st != SFIT_OK) {
        raise_status(st, "Incremental", -1, -1);
        return -1;
    }
    self->rejected = 0;
    return 0;
}

static PyObject *est_out(const sfit_sphere_t *e)
{
    return Py_BuildValue("(NNk)", vec3_out(e->center.v), flt(e->radius), (unsigned long)e->n);
}

static PyObject *Incr_start(IncrObject *self, PyObject *points)
{
    pts_t p;
    const sfit_vec3_t *v;
    sfit_vec3_t *own;
    size_t nv;
    long rej;
    sfit_sphere_t e;
    sfit_status_t st;
    if (pts_get(points, &p, "Incremental.start", 0) < 0) {
        return NULL;
    }
    rej = pts_filter(&p, NULL, &v, &own, &nv);
    if (rej < 0) {
        pts_release(&p);
        return NULL;
    }
    st = sfit_incr_start(&self->s, v, nv, &e);
    PyMem_RawFree(own);
    pts_release(&p);
    if (st != SFIT_OK) {
        return raise_status(st, "Incremental.start", (long)nv, rej);
    }
    self->rejected = rej;
    return est_out(&e);
}

static PyObject *Incr_add(IncrObject *self, PyObject *x)
{
    pts_t p;
    size_t i;
    long added = 0, rej = 0;
    if (pts_get(x, &p, "Incremental.add", 1) < 0) {
        return NULL;
    }
    for (i = 0; i < p.n; i++) {
        if (sfit_incr_add(&self->s, &p.v[i]) == SFIT_OK) {
            added++;
        } else {
            rej++;
        }
    }
    pts_release(&p);
    self->rejected += rej;
    return PyLong_FromLong(added);
}

static PyObject *Incr_estimate(IncrObject *self, PyObject *unused)
{
    sfit_sphere_t e;
    sfit_status_t st = sfit_incr_fit(&self->s, &e);
    (void)unused;
    if (st != SFIT_OK) {
        return raise_status(st, "Incremental.estimate", (long)sfit_incr_count(&self->s),
                            self->rejected);
    }
    return est_out(&e);
}

/* track(points): update with every row; the estimate after each accepted
 * row where one exists -> (n, centers, radii) arrays of the rows that have
 * an estimate. */
static PyObject *Incr_track(IncrObject *self, PyObject *points)
{
    pts_t p;
    size_t i, k = 0;
    long rej = 0;
    PyObject *na = NULL, *ca = NULL, *ra = NULL;
    npy_intp dim[2];
    if (pts_get(points, &p, "Incremental.track", 0) < 0) {
        return NULL;
    }
    dim[0] = (npy_intp)p.n;
    dim[1] = 3;
    na = PyArray_SimpleNew(1, dim, NPY_INT64);
    ca = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    ra = PyArray_SimpleNew(1, dim, NPY_FLOAT64);
    if (na == NULL || ca == NULL || ra == NULL) {
        goto fail;
    }
    {
        npy_int64 *nd = (npy_int64 *)PyArray_DATA((PyArrayObject *)na);
        double *cd = (double *)PyArray_DATA((PyArrayObject *)ca);
        double *rd = (double *)PyArray_DATA((PyArrayObject *)ra);
        for (i = 0; i < p.n; i++) {
            sfit_sphere_t e;
            const uint32_t before = sfit_incr_count(&self->s);
            const sfit_status_t st = sfit_incr_update(&self->s, &p.v[i], &e);
            if (st == SFIT_OK) {
                nd[k] = (npy_int64)e.n;
                cd[3 * k] = (double)e.center.v[0];
                cd[3 * k + 1] = (double)e.center.v[1];
                cd[3 * k + 2] = (double)e.center.v[2];
                rd[k] = (double)e.radius;
                k++;
            } else if (sfit_incr_count(&self->s) == before) {
                rej++; /* rejected by the add: state unchanged */
            }
        }
    }
    pts_release(&p);
    self->rejected += rej;
    /* full-length arrays and the number of rows filled (the Python layer slices) */
    return Py_BuildValue("(NNNn)", na, ca, ra, (Py_ssize_t)k);
fail:
    Py_XDECREF(na);
    Py_XDECREF(ca);
    Py_XDECREF(ra);
    pts_release(&p);
    return NULL;
}

static PyObject *Incr_reset(IncrObject *self, PyObject *unused)
{
    (void)unused;
    (void)sfit_incr_reset(&self->s);
    self->rejected = 0;
    Py_RETURN_NONE;
}

static PyObject *Incr_get_count(IncrObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromUnsignedLong((unsigned long)sfit_incr_count(&self->s));
}

static PyObject *Incr_get_rejected(IncrObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromLong(self->rejected);
}

static PyMethodDef Incr_methods[] = {
    {"_start", (PyCFunction)Incr_start, METH_O, "Internal: see Incremental.start."},
    {"add", (PyCFunction)Incr_add, METH_O,
     "add(points) -> int\n\nAdd one sample (3,) or an (N, 3) array without solving; rows\n"
     "with NaN, Inf or |x| >= 2**27 are skipped and counted. Returns the number added."},
    {"_estimate", (PyCFunction)Incr_estimate, METH_NOARGS, "Internal: see Incremental.estimate."},
    {"_track", (PyCFunction)Incr_track, METH_O, "Internal: see Incremental.track."},
    {"reset", (PyCFunction)Incr_reset, METH_NOARGS,
     "reset() -> None\n\nForget every sample, keep the noise model."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef Incr_getset[] = {
    {"count", (getter)Incr_get_count, NULL, "Samples added.", NULL},
    {"rejected", (getter)Incr_get_rejected, NULL, "Rows skipped (NaN, Inf, out of range).", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject IncrType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sfit._sfit.Incremental",
    .tp_basicsize = sizeof(IncrObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Incremental estimator (the library's sfit_incr_t).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Incr_init,
    .tp_methods = Incr_methods,
    .tp_getset = Incr_getset,
};

/* ------------------------------------------------------------------------ */
/* Functions over a caller's array                                          */
/* ------------------------------------------------------------------------ */

/* Shared prologue: points -> valid rows. */
typedef struct valid {
    pts_t p;
    const sfit_vec3_t *v;
    sfit_vec3_t *own;
    size_t n;
    long rejected;
} valid_t;

static int valid_get(PyObject *points, valid_t *w, const char *what)
{
    if (pts_get(points, &w->p, what, 0) < 0) {
        return -1;
    }
    w->rejected = pts_filter(&w->p, NULL, &w->v, &w->own, &w->n);
    if (w->rejected < 0) {
        pts_release(&w->p);
        return -1;
    }
    return 0;
}

static void valid_release(valid_t *w)
{
    PyMem_RawFree(w->own);
    w->own = NULL;
    pts_release(&w->p);
}

static PyObject *py_refine(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "center", "max_iters", "tol", NULL};
    PyObject *points, *center, *iters_o = NULL;
    unsigned long long max_iters = 0;
    double tol = 0.0;
    sfit_refine_cfg_t cfg = sfit_refine_cfg_default;
    sfit_vec3_t c0;
    sfit_refine_result_t r;
    sfit_status_t st;
    valid_t w;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|Od", kwlist, &points, &center, &iters_o,
                                     &tol)) {
        return NULL;
    }
    /* 0 = the library default; more than 1000 iterations are 1000 */
    if ((iters_o != NULL && count_get(iters_o, 1000u, &max_iters, "max_iters") < 0)
        || vec3_get(center, &c0, "center") < 0) {
        return NULL;
    }
    cfg.max_iters = (uint32_t)max_iters;
    cfg.tol = (float)tol;
    if (valid_get(points, &w, "points") < 0) {
        return NULL;
    }
    Py_BEGIN_ALLOW_THREADS
    st = sfit_refine_points(w.v, w.n, &c0, &cfg, &r);
    Py_END_ALLOW_THREADS
    valid_release(&w);
    if (st != SFIT_OK) {
        return raise_status(st, "refine", (long)w.n, w.rejected);
    }
    return Py_BuildValue("{s:N,s:N,s:N,s:N,s:k,s:k,s:l}", "center", vec3_out(r.center.v), "radius",
                         flt(r.radius), "rms", flt(r.rms), "noise_var", flt(r.noise_var), "n",
                         (unsigned long)r.n, "iterations", (unsigned long)r.iterations,
                         "rejected", w.rejected);
}

static PyObject *py_residual_noise_var(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "center", "radius", NULL};
    PyObject *points, *center;
    double radius;
    sfit_vec3_t c;
    float nv;
    sfit_status_t st;
    valid_t w;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOd", kwlist, &points, &center, &radius)) {
        return NULL;
    }
    if (vec3_get(center, &c, "center") < 0 || valid_get(points, &w, "points") < 0) {
        return NULL;
    }
    Py_BEGIN_ALLOW_THREADS
    st = sfit_selfcal_noise_var(w.v, w.n, &c, (float)radius, &nv);
    Py_END_ALLOW_THREADS
    valid_release(&w);
    if (st != SFIT_OK) {
        return raise_status(st, "residual_noise_var", (long)w.n, w.rejected);
    }
    return flt(nv);
}

static PyObject *py_uncertainty(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "center", "radius", "noise_var", NULL};
    PyObject *points, *center, *nvo = Py_None, *d;
    double radius = 0.0;
    float nvar = 0.0f;
    sfit_vec3_t c;
    sfit_uncert_t u;
    sfit_status_t st;
    valid_t w;
    int geometric;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|dO", kwlist, &points, &center, &radius,
                                     &nvo)) {
        return NULL;
    }
    geometric = (nvo == Py_None);
    if (vec3_get(center, &c, "center") < 0
        || (!geometric && nonneg_get(nvo, &nvar, "noise_var") < 0)
        || valid_get(points, &w, "points") < 0) {
        return NULL;
    }
    Py_BEGIN_ALLOW_THREADS
    if (geometric) {
        st = sfit_uncert_geometric(w.v, w.n, &c, &u);
    } else {
        st = sfit_uncert_points(w.v, w.n, &c, (float)radius, nvar, &u);
    }
    Py_END_ALLOW_THREADS
    valid_release(&w);
    if (st != SFIT_OK) {
        return raise_status(st, "uncertainty", (long)w.n, w.rejected);
    }
    d = PyDict_New();
    if (d == NULL || uncert_into(d, &u) < 0) {
        Py_XDECREF(d);
        return NULL;
    }
    return d;
}

/* ------------------------------------------------------------------------ */
/* Noise calibration and coverage (scalars)                                 */
/* ------------------------------------------------------------------------ */

static PyObject *py_calibration_std(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"noise_var", "radius", "n", NULL};
    double nv, r0;
    PyObject *no;
    unsigned long long n = 0;
    int overflow = 0;
    long long v;
    float sd;
    sfit_status_t st;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "ddO", kwlist, &nv, &r0, &no)) {
        return NULL;
    }
    if (!PyLong_Check(no)) {
        PyErr_Format(PyExc_TypeError, "calibration_std: n must be an int, not %.100s",
                     Py_TYPE(no)->tp_name);
        return NULL;
    }
    /* no wrap-around: n < 0 or beyond uint32 is out of range */
    v = PyLong_AsLongLongAndOverflow(no, &overflow);
    if (v == -1 && PyErr_Occurred()) {
        return NULL;
    }
    if (overflow != 0 || v < 0 || (unsigned long long)v > (unsigned long long)UINT32_MAX) {
        return raise_status(SFIT_E_RANGE, "calibration_std", -1, -1);
    }
    n = (unsigned long long)v;
    st = sfit_noise_calib_std((float)nv, (float)r0, (uint32_t)n, &sd);
    if (st != SFIT_OK) {
        return raise_status(st, "calibration_std", -1, -1);
    }
    return flt(sd);
}

static int kind_get(const char *s, sfit_coverage_kind_t *k)
{
    if (strcmp(s, "cap") == 0) {
        *k = SFIT_COVERAGE_CAP;
    } else if (strcmp(s, "arc") == 0) {
        *k = SFIT_COVERAGE_ARC;
    } else {
        raise_arg("kind must be 'cap' or 'arc', got '%s'", s);
        return -1;
    }
    return 0;
}

static PyObject *py_coverage_eigs(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"kind", "theta", "radius", NULL};
    const char *ks;
    double th, r;
    sfit_coverage_kind_t k;
    float lmin, lmax;
    sfit_status_t st;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "sdd", kwlist, &ks, &th, &r) || kind_get(ks, &k) < 0) {
        return NULL;
    }
    st = sfit_coverage_eigs(k, (float)th, (float)r, &lmin, &lmax);
    if (st != SFIT_OK) {
        return raise_status(st, "coverage_eigs", -1, -1);
    }
    return Py_BuildValue("(NN)", flt(lmin), flt(lmax));
}

static PyObject *py_coverage_max_sigma(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"kind", "theta", "radius", NULL};
    const char *ks;
    double th, r;
    sfit_coverage_kind_t k;
    float s;
    sfit_status_t st;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "sdd", kwlist, &ks, &th, &r) || kind_get(ks, &k) < 0) {
        return NULL;
    }
    st = sfit_coverage_max_sigma(k, (float)th, (float)r, &s);
    if (st != SFIT_OK) {
        return raise_status(st, "coverage_max_sigma", -1, -1);
    }
    return flt(s);
}

static PyObject *py_coverage_min_theta(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"kind", "sigma_over_r", NULL};
    const char *ks;
    double q;
    sfit_coverage_kind_t k;
    float th;
    sfit_status_t st;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "sd", kwlist, &ks, &q) || kind_get(ks, &k) < 0) {
        return NULL;
    }
    st = sfit_coverage_min_theta(k, (float)q, &th);
    if (st != SFIT_OK) {
        return raise_status(st, "coverage_min_theta", -1, -1);
    }
    return flt(th);
}

static PyObject *py_coverage_estimate_theta(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"kind", "eigenvalues", NULL};
    const char *ks;
    PyObject *eo;
    sfit_coverage_kind_t k;
    sfit_vec3_t e;
    float th;
    sfit_status_t st;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "sO", kwlist, &ks, &eo) || kind_get(ks, &k) < 0
        || vec3_get(eo, &e, "eigenvalues") < 0) {
        return NULL;
    }
    st = sfit_coverage_estimate_theta(k, &e, &th);
    if (st != SFIT_OK) {
        return raise_status(st, "coverage_estimate_theta", -1, -1);
    }
    return flt(th);
}

static PyObject *py_status_name(PyObject *self, PyObject *arg)
{
    long c = PyLong_AsLong(arg);
    (void)self;
    if (c == -1 && PyErr_Occurred()) {
        return NULL;
    }
    if (c < -1000 || c > 1000) { /* no status: not truncated into one */
        c = -1000;
    }
    return PyUnicode_FromString(sfit_status_str((sfit_status_t)c));
}

/* ------------------------------------------------------------------------ */
/* Joint centre: Cluster and Joint                                          */
/* ------------------------------------------------------------------------ */

/* A frame-major (F, M, 3) float32 view (or (M, 3) as one frame). */
typedef struct frames {
    PyArrayObject *arr;
    const sfit_vec3_t *v;
    size_t nframes, count;
} frames_t;

static int frames_get(PyObject *obj, frames_t *f, const char *what, int allow_one)
{
    PyArrayObject *any, *a;
    char kind;
    int nd;
    f->arr = NULL;
    any = (PyArrayObject *)PyArray_FROMANY(obj, NPY_NOTYPE, 0, 0, 0);
    if (any == NULL) {
        PyErr_Clear();
        raise_arg("%s: not an array of numbers", what);
        return -1;
    }
    kind = PyArray_DESCR(any)->kind;
    nd = PyArray_NDIM(any);
    if (kind != 'f' && kind != 'i' && kind != 'u') {
        Py_DECREF(any);
        raise_arg("%s: not a real number type (use float32 or float64)", what);
        return -1;
    }
    if (!((nd == 3 && PyArray_DIM(any, 2) == 3) || (allow_one && nd == 2 && PyArray_DIM(any, 1) == 3))) {
        PyObject *shape = PyObject_GetAttrString((PyObject *)any, "shape");
        Py_DECREF(any);
        if (shape != NULL) {
            raise_arg("%s: expected shape %s, got %R", what,
                      allow_one ? "(markers, 3) or (frames, markers, 3)" : "(frames, markers, 3)",
                      shape);
            Py_DECREF(shape);
        }
        return -1;
    }
    /* more frames than the library counts (uint32): refused before the
     * float32 copy of what may be a free broadcast view */
    if (nd == 3 && (uint64_t)PyArray_DIM(any, 0) > (uint64_t)UINT32_MAX) {
        Py_DECREF(any);
        raise_status(SFIT_E_RANGE, what, -1, -1);
        return -1;
    }
    a = (PyArrayObject *)PyArray_FROM_OTF((PyObject *)any, NPY_FLOAT32,
                                          NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
    Py_DECREF(any);
    if (a == NULL) {
        return -1;
    }
    f->arr = a;
    f->v = (const sfit_vec3_t *)PyArray_DATA(a);
    f->nframes = (nd == 3) ? (size_t)PyArray_DIM(a, 0) : 1u;
    f->count = (size_t)PyArray_DIM(a, nd - 2);
    return 0;
}

typedef struct {
    PyObject_HEAD
    sfit_cluster_t cl;
    long frames_used;
} ClusterObject;

static PyTypeObject ClusterType;

/* The private argument of Cluster.from_frames' cls(g_cluster_shell): an
 * empty shell that the classmethod fills in (Cluster(None) is an error). */
static PyObject *g_cluster_shell;

static int Cluster_init(ClusterObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"template", NULL};
    PyObject *tpl;
    frames_t f;
    sfit_status_t st;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O", kwlist, &tpl)
        || frames_get(tpl, &f, "Cluster(template)", 1) < 0) {
        return -1;
    }
    if (f.nframes != 1u) {
        Py_DECREF(f.arr);
        raise_arg("Cluster(template): expected one (markers, 3) array");
        return -1;
    }
    st = sfit_cluster_init(&self->cl, f.v, f.count);
    Py_DECREF(f.arr);
    if (st != SFIT_OK) {
        raise_status(st, "Cluster", -1, -1);
        return -1;
    }
    self->frames_used = 1;
    return 0;
}

/* Cluster._from_frames(frames): a template from one (M, 3) or several
 * (F, M, 3) measured frames (NaN = occluded). */
static PyObject *Cluster_from_frames(PyObject *cls, PyObject *arg)
{
    frames_t f;
    sfit_cluster_t cl;
    size_t used = 1;
    sfit_status_t st;
    ClusterObject *o;
    if (frames_get(arg, &f, "Cluster.from_frames", 1) < 0) {
        return NULL;
    }
    Py_BEGIN_ALLOW_THREADS
    if (PyArray_NDIM(f.arr) == 2) {
        st = sfit_cluster_from_frame(&cl, f.v, f.count);
    } else if (f.nframes == 0u) {
        st = SFIT_E_TOO_FEW;
    } else {
        st = sfit_cluster_from_frames(&cl, f.v, f.nframes, f.count, &used);
    }
    Py_END_ALLOW_THREADS
    Py_DECREF(f.arr);
    if (st != SFIT_OK) {
        return raise_status(st, "Cluster.from_frames", -1, -1);
    }
    o = (ClusterObject *)PyObject_CallOneArg(cls, g_cluster_shell);
    if (o == NULL) {
        return NULL;
    }
    if (!PyObject_TypeCheck((PyObject *)o, &ClusterType)) {
        /* a subclass whose __new__ returns something else: never write a
         * template into it */
        PyErr_Format(PyExc_TypeError,
                     "Cluster.from_frames: %.100s() returned %.100s, not a Cluster",
                     ((PyTypeObject *)cls)->tp_name, Py_TYPE(o)->tp_name);
        Py_DECREF(o);
        return NULL;
    }
    o->cl = cl;
    o->frames_used = (long)used;
    return (PyObject *)o;
}

static PyObject *pose_out(const sfit_pose_t *p, const sfit_cluster_fit_t *fit)
{
    return Py_BuildValue("{s:N,s:N,s:N,s:k}", "rotation", mat3_out(&p->r), "translation",
                         vec3_out(p->t.v), "rms", flt(fit->rms), "used", (unsigned long)fit->used);
}

static PyObject *Cluster_register(ClusterObject *self, PyObject *arg)
{
    frames_t f;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    sfit_status_t st;
    if (frames_get(arg, &f, "Cluster.register", 1) < 0) {
        return NULL;
    }
    if (PyArray_NDIM(f.arr) != 2) {
        Py_DECREF(f.arr);
        return raise_arg("Cluster.register: expected one frame (markers, 3)");
    }
    if (f.count != (size_t)self->cl.count) {
        Py_DECREF(f.arr);
        return raise_arg("Cluster.register: %zu markers, the template has %lu", f.count,
                         (unsigned long)self->cl.count);
    }
    st = sfit_cluster_register(&self->cl, f.v, f.count, &pose, &fit);
    Py_DECREF(f.arr);
    if (st != SFIT_OK) {
        return raise_status(st, "Cluster.register", -1, -1);
    }
    return pose_out(&pose, &fit);
}

/* Cluster._place(frames, center, axis) -> (centers (F, 3), axes (F, 3),
 * valid (F,)): a point and a direction of the segment frame in the global
 * frame of every (M, 3) frame of frames, R center + t and R axis (double,
 * as numpy's R @ c + t of the pose); NaN rows and valid False where the
 * frame cannot be registered. One C loop instead of F register() calls. */
static PyObject *Cluster_place(ClusterObject *self, PyObject *args)
{
    PyObject *fo, *ca, *aa, *va;
    double c[3], ax[3];
    frames_t f;
    npy_intp dim[2];
    size_t i;
    if (!PyArg_ParseTuple(args, "O(ddd)(ddd)", &fo, &c[0], &c[1], &c[2], &ax[0], &ax[1],
                          &ax[2])
        || frames_get(fo, &f, "Cluster._place", 1) < 0) {
        return NULL;
    }
    if (f.count != (size_t)self->cl.count) {
        Py_DECREF(f.arr);
        return raise_arg("Cluster._place: %zu markers, the template has %lu", f.count,
                         (unsigned long)self->cl.count);
    }
    dim[0] = (npy_intp)f.nframes;
    dim[1] = 3;
    ca = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    aa = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    va = PyArray_SimpleNew(1, dim, NPY_BOOL);
    if (ca == NULL || aa == NULL || va == NULL) {
        Py_XDECREF(ca);
        Py_XDECREF(aa);
        Py_XDECREF(va);
        Py_DECREF(f.arr);
        return NULL;
    }
    {
        double *cd = (double *)PyArray_DATA((PyArrayObject *)ca);
        double *ad = (double *)PyArray_DATA((PyArrayObject *)aa);
        npy_bool *vd = (npy_bool *)PyArray_DATA((PyArrayObject *)va);
        Py_BEGIN_ALLOW_THREADS
        for (i = 0; i < f.nframes; i++) {
            sfit_pose_t pose;
            sfit_cluster_fit_t fit;
            const sfit_status_t st =
                sfit_cluster_register(&self->cl, f.v + i * f.count, f.count, &pose, &fit);
            int r;
            vd[i] = (npy_bool)(st == SFIT_OK);
            for (r = 0; r < 3; r++) {
                double pc = NAN, pa = NAN;
                if (st == SFIT_OK) {
                    const float *row = &pose.r.m[3 * r];
                    pc = (double)row[0] * c[0] + (double)row[1] * c[1] + (double)row[2] * c[2];
                    pa = (double)row[0] * ax[0] + (double)row[1] * ax[1] + (double)row[2] * ax[2];
                    pc += (double)pose.t.v[r];
                }
                cd[3 * i + (size_t)r] = pc;
                ad[3 * i + (size_t)r] = pa;
            }
        }
        Py_END_ALLOW_THREADS
    }
    Py_DECREF(f.arr);
    return Py_BuildValue("(NNN)", ca, aa, va);
}

static PyObject *Cluster_get_positions(ClusterObject *self, void *closure)
{
    npy_intp dim[2];
    PyObject *a;
    uint32_t i;
    (void)closure;
    dim[0] = (npy_intp)self->cl.count;
    dim[1] = 3;
    a = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    if (a != NULL) {
        double *d = (double *)PyArray_DATA((PyArrayObject *)a);
        for (i = 0; i < self->cl.count; i++) {
            d[3 * i] = (double)self->cl.pos[i].v[0];
            d[3 * i + 1] = (double)self->cl.pos[i].v[1];
            d[3 * i + 2] = (double)self->cl.pos[i].v[2];
        }
    }
    return a;
}

static PyObject *Cluster_get_count(ClusterObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromUnsignedLong((unsigned long)self->cl.count);
}

static PyObject *Cluster_get_frames_used(ClusterObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromLong(self->frames_used);
}

/* tp_init; from_frames' cls(g_cluster_shell) makes an empty shell */
static int Cluster_init_any(ClusterObject *self, PyObject *args, PyObject *kw)
{
    if (kw == NULL && PyTuple_GET_SIZE(args) == 1 && PyTuple_GET_ITEM(args, 0) == g_cluster_shell) {
        memset(&self->cl, 0, sizeof self->cl);
        self->frames_used = 0;
        return 0;
    }
    return Cluster_init(self, args, kw);
}

static PyMethodDef Cluster_methods[] = {
    {"_from_frames", (PyCFunction)Cluster_from_frames, METH_O | METH_CLASS,
     "Internal: see Cluster.from_frames."},
    {"_register", (PyCFunction)Cluster_register, METH_O, "Internal: see Cluster.register."},
    {"_place", (PyCFunction)Cluster_place, METH_VARARGS,
     "Internal: a segment-frame point and direction in every frame (joint_center)."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef Cluster_getset[] = {
    {"positions", (getter)Cluster_get_positions, NULL,
     "(markers, 3) template positions in the segment frame.", NULL},
    {"count", (getter)Cluster_get_count, NULL, "Markers of the template.", NULL},
    {"frames_used", (getter)Cluster_get_frames_used, NULL,
     "Frames averaged into the template (from_frames).", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject ClusterType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sfit._sfit.Cluster",
    .tp_basicsize = sizeof(ClusterObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Rigid marker cluster template (the library's sfit_cluster_t).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Cluster_init_any,
    .tp_methods = Cluster_methods,
    .tp_getset = Cluster_getset,
};

typedef struct {
    PyObject_HEAD
    sfit_joint_t j;
    long rejected_frames;
    int ready;
} JointObject;

static PyTypeObject JointType;

static int Joint_init(JointObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"parent", "n_child", "noise_var", "noise_cov", "mode", "weight",
                             "planar_ratio", "marker_noise_var", NULL};
    PyObject *parent, *noise_var = Py_None, *noise_cov = Py_None, *mode = NULL;
    PyObject *marker_var = Py_None, *n_child_o;
    unsigned long long n_child = 0;
    const char *weight = "equal";
    double planar_ratio = 0.0;
    sfit_joint_cfg_t cfg = sfit_joint_cfg_default;
    sfit_joint_t *j;
    sfit_status_t st;
    /* a rejected (re-)__init__ leaves the object as it was */
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OOOsdO", kwlist, &parent, &n_child_o, &noise_var,
                                     &noise_cov, &mode, &weight, &planar_ratio, &marker_var)) {
        return -1;
    }
    if (marker_var != Py_None) {
        if (noise_var != Py_None || noise_cov != Py_None) {
            raise_arg("Joint: marker_noise_var replaces noise_var / noise_cov (give one)");
            return -1;
        }
        /* the marker noise, propagated through the parent pose by the library */
        noise_var = marker_var;
        cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
    }
    if (!PyObject_TypeCheck(parent, &ClusterType) || ((ClusterObject *)parent)->cl.count == 0u) {
        raise_arg("Joint: parent must be a sfit.Cluster");
        return -1;
    }
    if (!PyLong_Check(n_child_o)) {
        PyErr_Format(PyExc_TypeError, "Joint: n_child must be an int, not %.100s",
                     Py_TYPE(n_child_o)->tp_name);
        return -1;
    }
    {
        int overflow = 0;
        const long long v = PyLong_AsLongLongAndOverflow(n_child_o, &overflow);
        if (v == -1 && PyErr_Occurred()) {
            return -1;
        }
        if (overflow != 0 || v < 1 || v > (long long)SFIT_JOINT_MAX_CHILD) {
            raise_arg("Joint: n_child must be in 1..%d", (int)SFIT_JOINT_MAX_CHILD);
            return -1;
        }
        n_child = (unsigned long long)v;
    }
    if (is_auto(noise_var)) {
        raise_arg("Joint: noise_var='auto' is not supported (give a number)");
        return -1;
    }
    if (cfg_get(noise_var, noise_cov, mode, planar_ratio, &cfg.solve.fit) < 0
        || weight_get(weight, &cfg.solve.weight) < 0) {
        return -1;
    }
    cfg.n_child = (uint32_t)n_child;
    j = (sfit_joint_t *)PyMem_Malloc(sizeof *j);
    if (j == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    st = sfit_joint_init(j, &((ClusterObject *)parent)->cl, &cfg);
    if (st != SFIT_OK) {
        PyMem_Free(j);
        raise_status(st, "Joint", -1, -1);
        return -1;
    }
    self->j = *j;
    PyMem_Free(j);
    self->rejected_frames = 0;
    self->ready = 1;
    return 0;
}

/* Joint._add(parent_frames, child_frames) -> accepted frame count. One frame
 * ((M, 3) each) or F frames ((F, M, 3) each). A frame the library rejects
 * (parent not registrable, Inf, out of range) is skipped and counted. */
static PyObject *Joint_add(JointObject *self, PyObject *args)
{
    PyObject *po, *co;
    frames_t pf, cf;
    size_t i;
    long accepted = 0, rejected = 0;
    int arg_error = 0;
    if (!self->ready) {
        return raise_arg("Joint: not initialised");
    }
    if (!PyArg_ParseTuple(args, "OO", &po, &co)) {
        return NULL;
    }
    if (frames_get(po, &pf, "Joint.add(parent)", 1) < 0) {
        return NULL;
    }
    if (frames_get(co, &cf, "Joint.add(child)", 1) < 0) {
        Py_DECREF(pf.arr);
        return NULL;
    }
    if (PyArray_NDIM(pf.arr) != PyArray_NDIM(cf.arr) || pf.nframes != cf.nframes) {
        Py_DECREF(pf.arr);
        Py_DECREF(cf.arr);
        return raise_arg("Joint.add: parent and child must have the same number of frames");
    }
    if (pf.count != (size_t)self->j.parent.count || cf.count != (size_t)self->j.cfg.n_child) {
        PyObject *e = raise_arg("Joint.add: %zu parent / %zu child markers, expected %lu / %lu",
                                pf.count, cf.count, (unsigned long)self->j.parent.count,
                                (unsigned long)self->j.cfg.n_child);
        Py_DECREF(pf.arr);
        Py_DECREF(cf.arr);
        return e;
    }
    for (i = 0; i < pf.nframes; i++) {
        const sfit_status_t st = sfit_joint_add(&self->j, pf.v + i * pf.count, pf.count,
                                                cf.v + i * cf.count, cf.count, NULL);
        if (st == SFIT_OK) {
            accepted++;
        } else if (st == SFIT_E_ARG) {
            arg_error = 1;
            break;
        } else {
            rejected++;
        }
    }
    Py_DECREF(pf.arr);
    Py_DECREF(cf.arr);
    self->rejected_frames += rejected;
    if (arg_error) {
        return raise_status(SFIT_E_ARG, "Joint.add", -1, -1);
    }
    return PyLong_FromLong(accepted);
}

static PyObject *Joint_solve(JointObject *self, PyObject *unused)
{
    sfit_joint_result_t r;
    float radii[SFIT_JOINT_MAX_CHILD];
    sfit_status_t st;
    PyObject *d, *ra, *na;
    npy_intp dim;
    uint32_t k;
    (void)unused;
    if (!self->ready) {
        return raise_arg("Joint: not initialised");
    }
    st = sfit_joint_fit(&self->j, &r, radii);
    if (st != SFIT_OK) {
        return raise_status(st, "Joint.fit", (long)self->j.frames, self->rejected_frames);
    }
    dim = (npy_intp)self->j.cfg.n_child;
    ra = PyArray_SimpleNew(1, &dim, NPY_FLOAT64);
    na = PyArray_SimpleNew(1, &dim, NPY_INT64);
    if (ra == NULL || na == NULL) {
        Py_XDECREF(ra);
        Py_XDECREF(na);
        return NULL;
    }
    for (k = 0; k < self->j.cfg.n_child; k++) {
        ((double *)PyArray_DATA((PyArrayObject *)ra))[k] = (double)radii[k];
        ((npy_int64 *)PyArray_DATA((PyArrayObject *)na))[k] =
            (npy_int64)sfit_moments_count(&self->j.child[k]);
    }
    d = PyDict_New();
    if (d == NULL || multi_into(d, &r.fit) < 0
        || put(d, "frames", PyLong_FromUnsignedLong((unsigned long)r.frames)) < 0
        || put(d, "rejected_frames", PyLong_FromLong(self->rejected_frames)) < 0
        || put(d, "residual_mean", flt(r.residual_mean)) < 0
        || put(d, "residual_max", flt(r.residual_max)) < 0
        || put(d, "radii", ra) < 0 || put(d, "marker_n", na) < 0) {
        Py_XDECREF(d);
        return NULL;
    }
    /* keep the raw result for center_at */
    if (put(d, "_raw", PyBytes_FromStringAndSize((const char *)&r, (Py_ssize_t)sizeof r)) < 0) {
        Py_DECREF(d);
        return NULL;
    }
    return d;
}

/* Joint._center_at(raw, parent_frames) -> (centers (F, 3), axes (F, 3),
 * valid (F,)): the centre in the global frame of every frame; rows of the
 * frames whose parent cannot be registered are NaN and valid is False. */
static PyObject *Joint_center_at(JointObject *self, PyObject *args)
{
    const char *raw;
    Py_ssize_t rawlen;
    PyObject *po, *ca, *aa, *va;
    frames_t pf;
    sfit_joint_result_t r;
    npy_intp dim[2];
    size_t i;
    if (!self->ready) {
        return raise_arg("Joint: not initialised");
    }
    if (!PyArg_ParseTuple(args, "y#O", &raw, &rawlen, &po)) {
        return NULL;
    }
    if (rawlen != (Py_ssize_t)sizeof r) {
        return raise_arg("Joint.center_at: not a result of this joint's solve()");
    }
    memcpy(&r, raw, sizeof r);
    if (frames_get(po, &pf, "Joint.center_at(parent)", 1) < 0) {
        return NULL;
    }
    if (pf.count != (size_t)self->j.parent.count) {
        Py_DECREF(pf.arr);
        return raise_arg("Joint.center_at: %zu parent markers, expected %lu", pf.count,
                         (unsigned long)self->j.parent.count);
    }
    dim[0] = (npy_intp)pf.nframes;
    dim[1] = 3;
    ca = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    aa = PyArray_SimpleNew(2, dim, NPY_FLOAT64);
    va = PyArray_SimpleNew(1, dim, NPY_BOOL);
    if (ca == NULL || aa == NULL || va == NULL) {
        Py_XDECREF(ca);
        Py_XDECREF(aa);
        Py_XDECREF(va);
        Py_DECREF(pf.arr);
        return NULL;
    }
    {
        double *cd = (double *)PyArray_DATA((PyArrayObject *)ca);
        double *ad = (double *)PyArray_DATA((PyArrayObject *)aa);
        npy_bool *vd = (npy_bool *)PyArray_DATA((PyArrayObject *)va);
        Py_BEGIN_ALLOW_THREADS
        for (i = 0; i < pf.nframes; i++) {
            sfit_vec3_t c, a;
            const sfit_status_t st =
                sfit_joint_center_at(&self->j, &r, pf.v + i * pf.count, pf.count, &c, &a);
            int k;
            vd[i] = (npy_bool)(st == SFIT_OK);
            for (k = 0; k < 3; k++) {
                cd[3 * i + (size_t)k] = (st == SFIT_OK) ? (double)c.v[k] : NAN;
                ad[3 * i + (size_t)k] = (st == SFIT_OK) ? (double)a.v[k] : NAN;
            }
        }
        Py_END_ALLOW_THREADS
    }
    Py_DECREF(pf.arr);
    return Py_BuildValue("(NNN)", ca, aa, va);
}

/* Joint._center_cov: see pair_py.c (sfit_py_joint_center_cov). */
static PyObject *Joint_center_cov(JointObject *self, PyObject *args)
{
    if (!self->ready) {
        return raise_arg("Joint: not initialised");
    }
    return sfit_py_joint_center_cov(&self->j, args);
}

/* Joint.noise_cov(marker_var) -> (3, 3): first-order noise covariance of a
 * child marker in the parent frame for isotropic marker noise. */
static PyObject *Joint_noise_cov(JointObject *self, PyObject *arg)
{
    float var;
    sfit_mat3_t cov;
    sfit_status_t st;
    if (!self->ready) {
        return raise_arg("Joint: not initialised");
    }
    if (nonneg_get(arg, &var, "marker_var") < 0) {
        return NULL;
    }
    st = sfit_joint_noise_cov(&self->j, var, &cov);
    if (st != SFIT_OK) {
        return raise_status(st, "Joint.noise_cov", (long)self->j.frames, self->rejected_frames);
    }
    return mat3_out(&cov);
}

static PyObject *Joint_reset(JointObject *self, PyObject *unused)
{
    (void)unused;
    if (self->ready) {
        (void)sfit_joint_reset(&self->j);
    }
    self->rejected_frames = 0;
    Py_RETURN_NONE;
}

static PyObject *Joint_get_frames(JointObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromUnsignedLong(self->ready ? (unsigned long)self->j.frames : 0ul);
}

static PyObject *Joint_get_rejected(JointObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromLong(self->rejected_frames);
}

static PyMethodDef Joint_methods[] = {
    {"_add", (PyCFunction)Joint_add, METH_VARARGS, "Internal: see Joint.add."},
    {"_solve", (PyCFunction)Joint_solve, METH_NOARGS, "Internal: see Joint.solve."},
    {"_center_at", (PyCFunction)Joint_center_at, METH_VARARGS, "Internal: see Joint.center_at."},
    {"_center_cov", (PyCFunction)Joint_center_cov, METH_VARARGS, "Internal: see pair_py.c."},
    {"noise_cov", (PyCFunction)Joint_noise_cov, METH_O,
     "noise_cov(marker_var) -> ndarray (3, 3)\n\nFirst-order noise covariance of a child marker in\n"
     "the parent frame, for isotropic noise of variance marker_var on every coordinate of\n"
     "every measured marker (the parent pose error included, lever arm and all)."},
    {"reset", (PyCFunction)Joint_reset, METH_NOARGS,
     "reset() -> None\n\nForget every frame; keep the template and the options."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef Joint_getset[] = {
    {"frames", (getter)Joint_get_frames, NULL, "Frames accepted.", NULL},
    {"rejected_frames", (getter)Joint_get_rejected, NULL,
     "Frames rejected (parent not registrable, Inf or out-of-range values).", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject JointType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sfit._sfit.Joint",
    .tp_basicsize = sizeof(JointObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Streaming functional joint centre (the library's sfit_joint_t).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Joint_init,
    .tp_methods = Joint_methods,
    .tp_getset = Joint_getset,
};

/* ------------------------------------------------------------------------ */
/* Module                                                                   */
/* ------------------------------------------------------------------------ */

static PyMethodDef module_methods[] = {
    {"fit", (PyCFunction)(void (*)(void))py_fit, METH_VARARGS | METH_KEYWORDS, fit_doc},
    {"fit_multi", (PyCFunction)(void (*)(void))py_fit_multi, METH_VARARGS | METH_KEYWORDS,
     "Internal: see sfit.fit_multi."},
    {"refine", (PyCFunction)(void (*)(void))py_refine, METH_VARARGS | METH_KEYWORDS,
     "Internal: see sfit.refine."},
    {"residual_noise_var", (PyCFunction)(void (*)(void))py_residual_noise_var,
     METH_VARARGS | METH_KEYWORDS, "Internal: see sfit.residual_noise_var."},
    {"uncertainty", (PyCFunction)(void (*)(void))py_uncertainty, METH_VARARGS | METH_KEYWORDS,
     "Internal: see sfit.uncertainty."},
    {"calibration_std", (PyCFunction)(void (*)(void))py_calibration_std,
     METH_VARARGS | METH_KEYWORDS, "Internal: see sfit.calibration_std."},
    {"coverage_eigs", (PyCFunction)(void (*)(void))py_coverage_eigs, METH_VARARGS | METH_KEYWORDS,
     "Internal: see sfit.coverage_eigs."},
    {"coverage_max_sigma", (PyCFunction)(void (*)(void))py_coverage_max_sigma,
     METH_VARARGS | METH_KEYWORDS, "Internal: see sfit.coverage_max_sigma."},
    {"coverage_min_theta", (PyCFunction)(void (*)(void))py_coverage_min_theta,
     METH_VARARGS | METH_KEYWORDS, "Internal: see sfit.coverage_min_theta."},
    {"coverage_estimate_theta", (PyCFunction)(void (*)(void))py_coverage_estimate_theta,
     METH_VARARGS | METH_KEYWORDS, "Internal: see sfit.coverage_estimate_theta."},
    {"status_name", py_status_name, METH_O, "status_name(code) -> str (the library's name)."},
    {"_label_swaps", sfit_py_label_swaps, METH_VARARGS,
     "Internal: label swaps within one cluster (see sfit.joint_center)."},
    {"_pair_solve", sfit_py_pair_solve, METH_VARARGS, "Internal: see sfit.joint_center (pair_py.c)."},
    {"_imu_joint", sfit_py_imu_joint, METH_VARARGS, "Internal: see sfit.imu_joint (imu_py.c)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT, "sfit._sfit",
    "The compiled core of sfit (lib/src). Use the sfit package, not this module.", -1,
    module_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__sfit(void)
{
    PyObject *m;
    int i;
    import_array();
    if (sfit_py_pair_import() < 0 || sfit_py_imu_import() < 0) {
        return NULL;
    }
    if (PyType_Ready(&MomentsType) < 0 || PyType_Ready(&IncrType) < 0) {
        return NULL;
    }
    m = PyModule_Create(&module_def);
    if (m == NULL) {
        return NULL;
    }
    if (PyModule_AddFunctions(m, sfit_py_c3d_methods()) < 0
        || PyModule_AddFunctions(m, sfit_py_session_methods()) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    g_error = PyErr_NewExceptionWithDoc(
        "sfit.Error",
        "A status other than ok from the sfit library. Attributes: status (the library's "
        "status name), code (its negative value), message, n and rejected (samples used and "
        "rows skipped, when the call had samples; else None).",
        NULL, NULL);
    if (g_error == NULL || PyModule_AddObjectRef(m, "Error", g_error) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    for (i = 1; i < N_STATUS; i++) {
        char qual[64];
        PyObject *bases;
        if (i == 1) {
            bases = PyTuple_Pack(2, g_error, PyExc_ValueError);
        } else if (i == 7) {
            bases = PyTuple_Pack(2, g_error, PyExc_ValueError);
        } else {
            bases = PyTuple_Pack(1, g_error);
        }
        if (bases == NULL) {
            Py_DECREF(m);
            return NULL;
        }
        PyOS_snprintf(qual, sizeof qual, "sfit.%s", g_exc_names[i]);
        g_exc[i] = PyErr_NewExceptionWithDoc(qual, status_message((sfit_status_t)(-i)), bases,
                                             NULL);
        Py_DECREF(bases);
        if (g_exc[i] == NULL || PyModule_AddObjectRef(m, g_exc_names[i], g_exc[i]) < 0) {
            Py_DECREF(m);
            return NULL;
        }
    }
    if (g_cluster_shell == NULL) {
        g_cluster_shell = PyObject_CallNoArgs((PyObject *)&PyBaseObject_Type);
        if (g_cluster_shell == NULL) {
            Py_DECREF(m);
            return NULL;
        }
    }
    if (PyType_Ready(&ClusterType) < 0 || PyType_Ready(&JointType) < 0
        || PyModule_AddObjectRef(m, "Cluster", (PyObject *)&ClusterType) < 0
        || PyModule_AddObjectRef(m, "Joint", (PyObject *)&JointType) < 0
        || PyModule_AddIntConstant(m, "CLUSTER_MAX_MARKERS", SFIT_CLUSTER_MAX_MARKERS) < 0
        || PyModule_AddIntConstant(m, "JOINT_MAX_CHILD", SFIT_JOINT_MAX_CHILD) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    if (PyModule_AddObjectRef(m, "Moments", (PyObject *)&MomentsType) < 0
        || PyModule_AddObjectRef(m, "Incremental", (PyObject *)&IncrType) < 0
        || PyModule_AddIntConstant(m, "VERSION_MAJOR", SFIT_VERSION_MAJOR) < 0
        || PyModule_AddIntConstant(m, "VERSION_MINOR", SFIT_VERSION_MINOR) < 0
        || PyModule_AddIntConstant(m, "VERSION_PATCH", SFIT_VERSION_PATCH) < 0
        || PyModule_AddIntConstant(m, "MIN_SAMPLES", SFIT_MIN_SAMPLES) < 0
        || PyModule_AddIntConstant(m, "COORD_MAX_EXP", SFIT_COORD_MAX_EXP) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
