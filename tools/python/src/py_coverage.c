/* SPDX-License-Identifier: MIT */
/**
 * @file py_coverage.c
 * @brief Noise calibration and coverage, functions of scalars
 * (sfit_noise.h, sfit_coverage.h): calibration_std, coverage_eigs,
 * coverage_max_sigma, coverage_min_theta, coverage_estimate_theta.
 */
#include "py_sfit.h"

#include <string.h>

PyObject *sfit_py_calibration_std(PyObject *self, PyObject *args, PyObject *kw)
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
        return sfit_py_raise_status(SFIT_E_RANGE, "calibration_std", -1, -1);
    }
    n = (unsigned long long)v;
    st = sfit_noise_calib_std((float)nv, (float)r0, (uint32_t)n, &sd);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "calibration_std", -1, -1);
    }
    return sfit_py_flt(sd);
}

static int kind_get(const char *s, sfit_coverage_kind_t *k)
{
    if (strcmp(s, "cap") == 0) {
        *k = SFIT_COVERAGE_CAP;
    } else if (strcmp(s, "arc") == 0) {
        *k = SFIT_COVERAGE_ARC;
    } else {
        sfit_py_raise_arg("kind must be 'cap' or 'arc', got '%s'", s);
        return -1;
    }
    return 0;
}

PyObject *sfit_py_coverage_eigs(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"kind", "theta", "radius", NULL};
    const char *ks;
    double th, r;
    sfit_coverage_kind_t k;
    float lmin, lmax;
    sfit_status_t st;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "sdd", kwlist, &ks, &th, &r)
        || kind_get(ks, &k) < 0) {
        return NULL;
    }
    st = sfit_coverage_eigs(k, (float)th, (float)r, &lmin, &lmax);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "coverage_eigs", -1, -1);
    }
    return Py_BuildValue("(NN)", sfit_py_flt(lmin), sfit_py_flt(lmax));
}

PyObject *sfit_py_coverage_max_sigma(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"kind", "theta", "radius", NULL};
    const char *ks;
    double th, r;
    sfit_coverage_kind_t k;
    float s;
    sfit_status_t st;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "sdd", kwlist, &ks, &th, &r)
        || kind_get(ks, &k) < 0) {
        return NULL;
    }
    st = sfit_coverage_max_sigma(k, (float)th, (float)r, &s);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "coverage_max_sigma", -1, -1);
    }
    return sfit_py_flt(s);
}

PyObject *sfit_py_coverage_min_theta(PyObject *self, PyObject *args, PyObject *kw)
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
        return sfit_py_raise_status(st, "coverage_min_theta", -1, -1);
    }
    return sfit_py_flt(th);
}

PyObject *sfit_py_coverage_estimate_theta(PyObject *self, PyObject *args, PyObject *kw)
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
        || sfit_py_vec3_get(eo, &e, "eigenvalues") < 0) {
        return NULL;
    }
    st = sfit_coverage_estimate_theta(k, &e, &th);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "coverage_estimate_theta", -1, -1);
    }
    return sfit_py_flt(th);
}

