/* SPDX-License-Identifier: MIT */
/**
 * @file imu_py.c
 * @brief _sfit._imu_joint(acc1, gyr1, acc2, gyr2, rate) -> (code, dict or
 * None, index of the refused sample or -1): the joint between two IMUs
 * (sfit_imu.h), every sample through sfit_imu_add, then sfit_imu_solve.
 * The dict holds the result's fields (numpy arrays; the flags as a mask,
 * named in sfit/__init__.py).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <string.h>

#include "imu_py.h"
#include "sfit/sfit_imu.h"

int sfit_py_imu_import(void)
{
    import_array1(-1);
    return 0;
}

/* A float32 C-contiguous copy of a real (N, 3) array. */
static PyArrayObject *imu_f32(PyObject *o, const char *what)
{
    PyArrayObject *a;
    PyObject *probe = PyArray_FROMANY(o, NPY_NOTYPE, 0, 0, 0);
    if (probe == NULL) {
        return NULL;
    }
    if (!(PyTypeNum_ISINTEGER(PyArray_DESCR((PyArrayObject *)probe)->type_num)
          || PyTypeNum_ISFLOAT(PyArray_DESCR((PyArrayObject *)probe)->type_num))
        || PyArray_NDIM((PyArrayObject *)probe) != 2
        || PyArray_DIM((PyArrayObject *)probe, 1) != 3) {
        Py_DECREF(probe);
        PyErr_Format(PyExc_ValueError, "imu_joint: %s must be a real array of shape (N, 3)",
                     what);
        return NULL;
    }
    a = (PyArrayObject *)PyArray_FROMANY(probe, NPY_FLOAT32, 2, 2,
                                         NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED
                                             | NPY_ARRAY_FORCECAST);
    Py_DECREF(probe);
    return a;
}

static PyObject *imu_vec(const sfit_vec3_t *v)
{
    npy_intp d = 3;
    PyObject *a = PyArray_SimpleNew(1, &d, NPY_FLOAT64);
    int i;
    if (a != NULL) {
        for (i = 0; i < 3; i++) {
            ((double *)PyArray_DATA((PyArrayObject *)a))[i] = (double)v->v[i];
        }
    }
    return a;
}

static PyObject *imu_mat(const sfit_mat3_t *m)
{
    npy_intp d[2] = {3, 3};
    PyObject *a = PyArray_SimpleNew(2, d, NPY_FLOAT64);
    int i;
    if (a != NULL) {
        for (i = 0; i < 9; i++) {
            ((double *)PyArray_DATA((PyArrayObject *)a))[i] = (double)m->m[i];
        }
    }
    return a;
}

static int imu_set(PyObject *d, const char *k, PyObject *v)
{
    int rc;
    if (v == NULL) {
        return -1;
    }
    rc = PyDict_SetItemString(d, k, v);
    Py_DECREF(v);
    return rc;
}

static PyObject *imu_dict(const sfit_imu_result_t *r)
{
    PyObject *d = PyDict_New();
    if (d == NULL) {
        return NULL;
    }
    if (imu_set(d, "n", PyLong_FromUnsignedLong(r->n)) < 0
        || imu_set(d, "used", PyLong_FromUnsignedLong(r->used)) < 0
        || imu_set(d, "joint", PyUnicode_FromString(r->hinge ? "hinge" : "ball")) < 0
        || imu_set(d, "r1", imu_vec(&r->r1)) < 0 || imu_set(d, "r2", imu_vec(&r->r2)) < 0
        || imu_set(d, "r1_cov", imu_mat(&r->r1_cov)) < 0
        || imu_set(d, "r2_cov", imu_mat(&r->r2_cov)) < 0
        || imu_set(d, "axis1", imu_vec(&r->axis1)) < 0
        || imu_set(d, "axis2", imu_vec(&r->axis2)) < 0
        || imu_set(d, "axis1_cov", imu_mat(&r->axis1_cov)) < 0
        || imu_set(d, "axis2_cov", imu_mat(&r->axis2_cov)) < 0
        || imu_set(d, "acc_bias1", imu_vec(&r->acc_bias1)) < 0
        || imu_set(d, "acc_bias2", imu_vec(&r->acc_bias2)) < 0
        || imu_set(d, "resid_rms", PyFloat_FromDouble((double)r->resid_rms)) < 0
        || imu_set(d, "noise_rms", PyFloat_FromDouble((double)r->noise_rms)) < 0
        || imu_set(d, "hinge_ratio", PyFloat_FromDouble((double)r->hinge_ratio)) < 0
        || imu_set(d, "line_sd", PyFloat_FromDouble((double)r->line_sd)) < 0
        || imu_set(d, "line_ratio", PyFloat_FromDouble((double)r->line_ratio)) < 0
        || imu_set(d, "rate_rms1", PyFloat_FromDouble((double)r->rate_rms1)) < 0
        || imu_set(d, "rate_rms2", PyFloat_FromDouble((double)r->rate_rms2)) < 0
        || imu_set(d, "flags_mask", PyLong_FromUnsignedLong(r->flags)) < 0) {
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
