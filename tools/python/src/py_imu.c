/* SPDX-License-Identifier: MIT */
/**
 * @file py_imu.c
 * @brief _sfit._imu_joint(acc1, gyr1, acc2, gyr2, rate) -> (code, dict or
 * None, index of the refused sample or -1): the joint between two IMUs
 * (sfit_imu.h), every sample through sfit_imu_add, then sfit_imu_solve.
 * The dict holds the result's fields (numpy arrays; the flags as a mask,
 * named in sfit/_imu.py).
 */
#include "py_sfit.h"

#include <string.h>

#include "sfit/sfit_imu.h"

/* A float32 C-contiguous copy of a real (N, 3) array. */
static PyArrayObject *imu_f32(PyObject *o, const char *what)
{
    PyArrayObject *a;
    const sfit_py_why_t why = sfit_py_f32_get(o, 2, 0, what, &a, NULL);
    if (why == SFIT_PY_NOT_REAL || why == SFIT_PY_SHAPE) {
        PyErr_Format(PyExc_ValueError, "imu_joint: %s must be a real array of shape (N, 3)",
                     what);
    }
    return a;
}

/* The reasons in words of an untrusted result (lab/names), None when trusted. */
static PyObject *imu_reason(uint32_t flags)
{
    char why[512];
    if ((flags & SFIT_FLAG_UNTRUSTED) == 0u) {
        Py_RETURN_NONE;
    }
    return PyUnicode_FromString(names_imu_reasons(flags, why, sizeof why));
}

static PyObject *imu_dict(const sfit_imu_result_t *r)
{
    PyObject *d = PyDict_New();
    if (d == NULL) {
        return NULL;
    }
    if (sfit_py_put(d, "n", PyLong_FromUnsignedLong(r->n)) < 0
        || sfit_py_put(d, "used", PyLong_FromUnsignedLong(r->used)) < 0
        || sfit_py_put(d, "joint", PyUnicode_FromString(r->hinge ? "hinge" : "ball")) < 0
        || sfit_py_put(d, "r1", sfit_py_vec3_out(r->r1.v)) < 0
        || sfit_py_put(d, "r2", sfit_py_vec3_out(r->r2.v)) < 0
        || sfit_py_put(d, "r1_cov", sfit_py_mat3_out(&r->r1_cov)) < 0
        || sfit_py_put(d, "r2_cov", sfit_py_mat3_out(&r->r2_cov)) < 0
        || sfit_py_put(d, "axis1", sfit_py_vec3_out(r->axis1.v)) < 0
        || sfit_py_put(d, "axis2", sfit_py_vec3_out(r->axis2.v)) < 0
        || sfit_py_put(d, "axis1_cov", sfit_py_mat3_out(&r->axis1_cov)) < 0
        || sfit_py_put(d, "axis2_cov", sfit_py_mat3_out(&r->axis2_cov)) < 0
        || sfit_py_put(d, "acc_bias1", sfit_py_vec3_out(r->acc_bias1.v)) < 0
        || sfit_py_put(d, "acc_bias2", sfit_py_vec3_out(r->acc_bias2.v)) < 0
        || sfit_py_put(d, "resid_rms", PyFloat_FromDouble((double)r->resid_rms)) < 0
        || sfit_py_put(d, "noise_rms", PyFloat_FromDouble((double)r->noise_rms)) < 0
        || sfit_py_put(d, "hinge_ratio", PyFloat_FromDouble((double)r->hinge_ratio)) < 0
        || sfit_py_put(d, "wobble_deg", PyFloat_FromDouble((double)r->wobble_deg)) < 0
        || sfit_py_put(d, "line_sd", PyFloat_FromDouble((double)r->line_sd)) < 0
        || sfit_py_put(d, "line_ratio", PyFloat_FromDouble((double)r->line_ratio)) < 0
        || sfit_py_put(d, "line_off", PyFloat_FromDouble((double)r->line_off)) < 0
        || sfit_py_put(d, "force_ratio", PyFloat_FromDouble((double)r->force_ratio)) < 0
        || sfit_py_put(d, "rate_rms1", PyFloat_FromDouble((double)r->rate_rms1)) < 0
        || sfit_py_put(d, "rate_rms2", PyFloat_FromDouble((double)r->rate_rms2)) < 0
        || sfit_py_put(d, "flags_mask", PyLong_FromUnsignedLong(r->flags)) < 0
        || sfit_py_put(d, "flags", sfit_py_family_names(r->flags, NAMES_IMU)) < 0
        || sfit_py_put(d, "reason", imu_reason(r->flags)) < 0) {
        Py_DECREF(d);
        return NULL;
    }
    return d;
}

PyObject *sfit_py_imu_joint(PyObject *self, PyObject *args)
{
    PyObject *o[4], *out = NULL;
    PyArrayObject *a[4] = {NULL, NULL, NULL, NULL};
    static const char *const what[4] = {"acc1", "gyr1", "acc2", "gyr2"};
    double rate;
    sfit_imu_t *s = NULL;
    sfit_imu_result_t r;
    sfit_status_t st;
    npy_intp n, k;
    int i;
    (void)self;
    if (!PyArg_ParseTuple(args, "OOOOd", &o[0], &o[1], &o[2], &o[3], &rate)) {
        return NULL;
    }
    for (i = 0; i < 4; i++) {
        a[i] = imu_f32(o[i], what[i]);
        if (a[i] == NULL) {
            goto done;
        }
    }
    n = PyArray_DIM(a[0], 0);
    for (i = 1; i < 4; i++) {
        if (PyArray_DIM(a[i], 0) != n) {
            PyErr_SetString(PyExc_ValueError,
                            "imu_joint: acc1, gyr1, acc2, gyr2 must have the same length");
            goto done;
        }
    }
    s = PyMem_Malloc(sizeof *s);
    if (s == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    st = sfit_imu_init(s, (float)rate, NULL);
    for (k = 0; k < n && st == SFIT_OK; k++) {
        sfit_imu_sample_t x;
        memcpy(x.acc1.v, (const float *)PyArray_DATA(a[0]) + 3 * k, sizeof x.acc1.v);
        memcpy(x.gyr1.v, (const float *)PyArray_DATA(a[1]) + 3 * k, sizeof x.gyr1.v);
        memcpy(x.acc2.v, (const float *)PyArray_DATA(a[2]) + 3 * k, sizeof x.acc2.v);
        memcpy(x.gyr2.v, (const float *)PyArray_DATA(a[3]) + 3 * k, sizeof x.gyr2.v);
        st = sfit_imu_add(s, &x);
        if (st != SFIT_OK) {
            out = Py_BuildValue("(iOn)", (int)st, Py_None, (Py_ssize_t)k);
            goto done;
        }
    }
    if (st == SFIT_OK) {
        st = sfit_imu_solve(s, &r);
    }
    if (st != SFIT_OK) {
        out = Py_BuildValue("(iOn)", (int)st, Py_None, (Py_ssize_t)-1);
    } else {
        PyObject *d = imu_dict(&r);
        if (d != NULL) {
            out = Py_BuildValue("(iNn)", 0, d, (Py_ssize_t)-1);
        }
    }
done:
    PyMem_Free(s);
    for (i = 0; i < 4; i++) {
        Py_XDECREF(a[i]);
    }
    return out;
}
