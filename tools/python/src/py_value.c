/* SPDX-License-Identifier: MIT */
/**
 * @file py_value.c
 * @brief Values out: the library's float32 values as float64 numpy arrays
 * and Python floats holding them exactly (the Python layer wraps them),
 * flag names, and the result dicts that several families share.
 */
#include "py_sfit.h"

PyObject *sfit_py_vec3_out(const float *v)
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

PyObject *sfit_py_mat3_out(const sfit_mat3_t *m)
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
int sfit_py_put(PyObject *dict, const char *key, PyObject *value)
{
    int rc;
    if (value == NULL) {
        return -1;
    }
    rc = PyDict_SetItemString(dict, key, value);
    Py_DECREF(value);
    return rc;
}

PyObject *sfit_py_flt(float x)
{
    return PyFloat_FromDouble((double)x);
}

PyObject *sfit_py_flag_names(uint32_t flags, const json_out_flag_t *tab, size_t n)
{
    PyObject *l = PyList_New(0);
    size_t i;
    if (l == NULL) {
        return NULL;
    }
    for (i = 0; tab != NULL && i < n; i++) {
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

PyObject *sfit_py_family_names(uint32_t flags, names_family_t fam)
{
    size_t n = 0;
    const json_out_flag_t *tab = names_flags(fam, &n);
    return sfit_py_flag_names(flags, tab, n);
}

PyObject *sfit_py_noise_flag_names(uint32_t flags)
{
    return sfit_py_family_names(flags, NAMES_NOISE);
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
    if (sfit_py_put(d, "eigenvalues", sfit_py_vec3_out(eig->v)) < 0
        || sfit_py_put(d, "axis", sfit_py_vec3_out(axis->v)) < 0
        || sfit_py_put(d, "trust_ratio", sfit_py_flt(trust)) < 0
        || sfit_py_put(d, "leontief_ratio", sfit_py_flt(leontief)) < 0
        || sfit_py_put(d, "flags", sfit_py_family_names(flags, NAMES_FIT)) < 0
        || sfit_py_put(d, "flags_mask", PyLong_FromUnsignedLong((unsigned long)flags)) < 0
        || sfit_py_put(d, "method",
                       PyUnicode_FromString(method == SFIT_METHOD_UGDK ? "ugdk" : "gdke"))
               < 0
        || sfit_py_put(d, "mode", PyUnicode_FromString(mode_name(mode))) < 0) {
        return -1;
    }
    return 0;
}

/* The fields of a sfit_result_t into d. */
int sfit_py_result_into(PyObject *d, const sfit_result_t *r)
{
    if (sfit_py_put(d, "center", sfit_py_vec3_out(r->center.v)) < 0
        || sfit_py_put(d, "radius", sfit_py_flt(r->radius)) < 0
        || sfit_py_put(d, "n", PyLong_FromUnsignedLong((unsigned long)r->n)) < 0) {
        return -1;
    }
    return summary_into(d, &r->eigenvalues, &r->axis, r->trust_ratio, r->leontief_ratio,
                        r->flags, r->method, r->mode);
}

/* The fields of a sfit_multi_result_t into d. */
int sfit_py_multi_into(PyObject *d, const sfit_multi_result_t *r)
{
    if (sfit_py_put(d, "center", sfit_py_vec3_out(r->center.v)) < 0
        || sfit_py_put(d, "n", PyLong_FromUnsignedLong((unsigned long)r->n_total)) < 0
        || sfit_py_put(d, "markers", PyLong_FromUnsignedLong((unsigned long)r->markers)) < 0
        || sfit_py_put(d, "skipped", PyLong_FromUnsignedLong((unsigned long)r->skipped)) < 0) {
        return -1;
    }
    return summary_into(d, &r->eigenvalues, &r->axis, r->trust_ratio, r->leontief_ratio,
                        r->flags, r->method, r->mode);
}

int sfit_py_uncert_into(PyObject *d, const sfit_uncert_t *u)
{
    if (sfit_py_put(d, "center_cov", sfit_py_mat3_out(&u->center_cov)) < 0
        || sfit_py_put(d, "radius_var", sfit_py_flt(u->radius_var)) < 0
        || sfit_py_put(d, "center_radius_cov", sfit_py_vec3_out(u->center_radius_cov)) < 0
        || sfit_py_put(d, "uncert_noise_var", sfit_py_flt(u->noise_var)) < 0) {
        return -1;
    }
    return 0;
}

