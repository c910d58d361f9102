/* SPDX-License-Identifier: MIT */
/**
 * @file py_option.c
 * @brief Options in: the fit options that fit(), fit_multi(),
 * Moments.fit(), Incremental() and Joint() share (noise model, mode,
 * planar ratio, weight) and checked counts.
 */
#include "py_sfit.h"

#include <math.h>
#include <string.h>

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
        sfit_py_raise_arg("mode must be 'auto', 'sphere' or 'planar', got %R",
                          o != NULL ? o : Py_None);
        return -1;
    }
    return 0;
}

/* A finite float >= 0 from a Python number. */
int sfit_py_nonneg_get(PyObject *o, float *x, const char *what)
{
    double d;
    if (o == NULL || !PyNumber_Check(o) || PyBool_Check(o) || PyUnicode_Check(o)) {
        sfit_py_raise_arg("%s must be a number", what);
        return -1;
    }
    d = PyFloat_AsDouble(o);
    if (d == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        sfit_py_raise_arg("%s must be a number", what);
        return -1;
    }
    if (!(d >= 0.0) || !isfinite(d) || d > 3.4e38) {
        sfit_py_raise_arg("%s must be finite and >= 0, got %R", what, o);
        return -1;
    }
    *x = (float)d;
    return 0;
}

/* noise_cov: a (3, 3) symmetric array or 6 packed XX,YY,ZZ,XY,XZ,YZ. */
static int cov_get(PyObject *o, sfit_mat3_t *m)
{
    PyArrayObject *a = sfit_py_real_f64(o, 1, 2);
    const double *d;
    int i;
    if (a == NULL) {
        sfit_py_raise_arg("noise_cov must be a (3, 3) array or 6 numbers XX,YY,ZZ,XY,XZ,YZ");
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
            sfit_py_raise_arg("noise_cov must be symmetric");
            return -1;
        }
    } else {
        Py_DECREF(a);
        sfit_py_raise_arg("noise_cov must be a (3, 3) array or 6 numbers XX,YY,ZZ,XY,XZ,YZ");
        return -1;
    }
    Py_DECREF(a);
    for (i = 0; i < 9; i++) {
        if (!isfinite(m->m[i])) {
            sfit_py_raise_arg("noise_cov must be finite");
            return -1;
        }
    }
    return 0;
}

/* The fit options shared by fit(), fit_multi(), Moments.fit() and
 * Incremental(): noise_var (None, a number; "auto" is handled by the
 * caller), noise_cov, mode, planar_ratio. */
int sfit_py_cfg_get(PyObject *noise_var, PyObject *noise_cov, PyObject *mode, double planar_ratio,
                   sfit_fit_cfg_t *cfg)
{
    *cfg = sfit_fit_cfg_default;
    cfg->eigen = true; /* fit() reports eigenvalues, axis and the exact trust ratio */
    if (mode != NULL && mode_get(mode, &cfg->mode) < 0) {
        return -1;
    }
    if (noise_var != NULL && noise_var != Py_None && noise_cov != NULL && noise_cov != Py_None) {
        sfit_py_raise_arg("give noise_var or noise_cov, not both");
        return -1;
    }
    if (noise_var != NULL && noise_var != Py_None) {
        if (sfit_py_nonneg_get(noise_var, &cfg->noise_var, "noise_var") < 0) {
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
        sfit_py_raise_arg("planar_ratio must be in [0, 0.5) (0 = the library default)");
        return -1;
    }
    cfg->planar_ratio = (float)planar_ratio;
    return 0;
}

int sfit_py_weight_get(const char *w, sfit_multi_weight_t *out)
{
    if (strcmp(w, "equal") == 0) {
        *out = SFIT_MULTI_WEIGHT_EQUAL;
    } else if (strcmp(w, "samples") == 0) {
        *out = SFIT_MULTI_WEIGHT_SAMPLES;
    } else {
        sfit_py_raise_arg("weight must be 'equal' or 'samples', got '%s'", w);
        return -1;
    }
    return 0;
}

/* A Python int argument >= 0, values above max taken as max: TypeError
 * for a non-int (as the "k" format would), ArgError for a negative value
 * (the "k" format silently wraps -1 to 2**64 - 1 and 2**64 + 1 to 1). */
int sfit_py_count_get(PyObject *o, unsigned long long max, unsigned long long *out,
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
        sfit_py_raise_arg("%s must be >= 0, got %R", what, o);
        return -1;
    }
    *out = (overflow > 0 || (unsigned long long)v > max) ? max : (unsigned long long)v;
    return 0;
}

int sfit_py_is_auto(PyObject *o)
{
    return o != NULL && PyUnicode_Check(o) && PyUnicode_CompareWithASCIIString(o, "auto") == 0;
}

