/* SPDX-License-Identifier: MIT */
/**
 * @file pair_py.c
 * @brief sfit._sfit._pair_solve: the pair of segments (sfit_pair.h) over
 * trajectories, for sfit.joint_center(method="default" | "score" | "sara").
 *
 * _pair_solve(parent, child, parent_template, child_template, method, mode,
 *             noise, marker_var) -> (code, result or None, frames rejected)
 *   parent (F, Mp, 3), child (F, Mc, 3): markers (global), NaN = occluded;
 *   the templates (Mp, 3), (Mc, 3) in each segment frame; method 0 default,
 *   1 plain SCoRE / SARA; mode 0 auto, 1 ball, 2 hinge; noise 0 the
 *   registration residuals, 1 marker_var given. Frames that either cluster
 *   cannot register are skipped and counted. code is the library's status
 *   (0 ok); the Python layer raises the matching sfit.Error. Every value of
 *   the result dict is the library's float32 value, exactly.
 * _joint_center_cov (Joint._center_cov): the multi-marker fit's centre
 *   covariance with the CLI's noise figure (cli_joint_mgdk_cov).
 * Kept apart from sfitmodule.c (issue 26: new bindings in new files); the
 * module's init calls sfit_py_pair_import() for numpy's C API here.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <string.h>

#include "cli_joint.h" /* cli_joint_pair_reason: the CLI's names */
#include "pair_py.h"
#include "sfit/sfit_cluster.h"
#include "sfit/sfit_pair.h"

int sfit_py_pair_import(void)
{
    import_array1(-1);
    return 0;
}

/* A float32 C-contiguous copy of a real array of ndim dims, last dim 3. */
static PyArrayObject *as_f32(PyObject *o, int ndim, const char *what)
{
    PyArray_Descr *d;
    PyArrayObject *a;
    PyObject *probe = PyArray_FROMANY(o, NPY_NOTYPE, 0, 0, 0);
    if (probe == NULL) {
        return NULL;
    }
    d = PyArray_DESCR((PyArrayObject *)probe);
    if (!(PyTypeNum_ISINTEGER(d->type_num) || PyTypeNum_ISFLOAT(d->type_num))
        || PyArray_NDIM((PyArrayObject *)probe) != ndim
        || PyArray_DIM((PyArrayObject *)probe, ndim - 1) != 3) {
        Py_DECREF(probe);
        PyErr_Format(PyExc_ValueError, "%s: a real array of shape %s expected", what,
                     ndim == 3 ? "(frames, markers, 3)" : "(markers, 3)");
        return NULL;
    }
    a = (PyArrayObject *)PyArray_FROMANY(probe, NPY_FLOAT32, ndim, ndim,
                                         NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED
                                             | NPY_ARRAY_FORCECAST);
    Py_DECREF(probe);
    return a;
}

static PyObject *vec(const float *v, npy_intp n)
{
    PyObject *a = PyArray_SimpleNew(1, &n, NPY_FLOAT64);
    npy_intp k;
    if (a == NULL) {
        return NULL;
    }
    for (k = 0; k < n; k++) {
        ((double *)PyArray_DATA((PyArrayObject *)a))[k] = (double)v[k];
    }
    return a;
}

static PyObject *mat(const sfit_mat3_t *m)
{
    npy_intp dims[2] = {3, 3};
    PyObject *a = PyArray_SimpleNew(2, dims, NPY_FLOAT64);
    int k;
    if (a == NULL) {
        return NULL;
    }
    for (k = 0; k < 9; k++) {
        ((double *)PyArray_DATA((PyArrayObject *)a))[k] = (double)m->m[k];
    }
    return a;
}

/* d[key] = value (stolen); -1 on failure. */
static int put(PyObject *d, const char *key, PyObject *value)
{
    int rc;
    if (value == NULL) {
        return -1;
    }
    rc = PyDict_SetItemString(d, key, value);
    Py_DECREF(value);
    return rc;
}

static PyObject *flags_list(uint32_t flags)
{
    static const struct {
        uint32_t bit;
        const char *name;
    } names[] = {
        {SFIT_FLAG_UNTRUSTED, "untrusted"},         {SFIT_FLAG_FEW_SAMPLES, "few_frames"},
        {SFIT_PAIR_FLAG_SMALL_MOTION, "small_motion"}, {SFIT_PAIR_FLAG_AXIS_FREE, "axis_free"},
        {SFIT_PAIR_FLAG_AMBIGUOUS, "ambiguous"},    {SFIT_PAIR_FLAG_MISFIT, "misfit"},
        {SFIT_PAIR_FLAG_NO_NOISE, "no_noise"},
    };
    PyObject *l = PyList_New(0);
    size_t k;
    for (k = 0; l != NULL && k < sizeof names / sizeof names[0]; k++) {
        if ((flags & names[k].bit) != 0u) {
            PyObject *s = PyUnicode_FromString(names[k].name);
            if (s == NULL || PyList_Append(l, s) != 0) {
                Py_XDECREF(s);
                Py_DECREF(l);
                return NULL;
            }
            Py_DECREF(s);
        }
    }
    return l;
}

/* The information bits (facts about the data, not faults). */
static PyObject *info_list(uint32_t info)
{
    PyObject *l = PyList_New(0);
    const char *names[2] = {"axis_free", "skin_motion"};
    const uint32_t bits[2] = {SFIT_PAIR_INFO_AXIS_FREE, SFIT_PAIR_INFO_SKIN};
    size_t k;
    for (k = 0; l != NULL && k < 2; k++) {
        if ((info & bits[k]) != 0u) {
            PyObject *s = PyUnicode_FromString(names[k]);
            if (s == NULL || PyList_Append(l, s) != 0) {
                Py_XDECREF(s);
                Py_DECREF(l);
                return NULL;
            }
            Py_DECREF(s);
        }
    }
    return l;
}

static PyObject *result_dict(const sfit_pair_result_t *r)
{
    PyObject *d = PyDict_New();
    if (d == NULL) {
        return NULL;
    }
    if (put(d, "center", vec(r->center_p.v, 3)) || put(d, "center_child", vec(r->center_c.v, 3))
        || put(d, "axis", vec(r->axis_p.v, 3)) || put(d, "axis_child", vec(r->axis_c.v, 3))
        || put(d, "center_cov", mat(&r->center_cov))
        || put(d, "axis_cov", r->mode == SFIT_PAIR_MODE_HINGE ? mat(&r->axis_cov)
                                                              : (Py_INCREF(Py_None), Py_None))
        || put(d, "center_cov_model", mat(&r->center_cov_model))
        || put(d, "axis_cov_model", r->mode == SFIT_PAIR_MODE_HINGE
                                        ? mat(&r->axis_cov_model)
                                        : (Py_INCREF(Py_None), Py_None))
        || put(d, "skin_rms", PyFloat_FromDouble((double)r->sta_rms))
        || put(d, "skin_ratio", PyFloat_FromDouble((double)r->sta_ratio))
        || put(d, "wobble_rms", PyFloat_FromDouble((double)r->wobble_rms))
        || put(d, "info", info_list(r->info))
        || put(d, "eigenvalues", vec(r->eigenvalues.v, 3))
        || put(d, "trust_ratio", PyFloat_FromDouble((double)r->trust_ratio))
        || put(d, "misfit", PyFloat_FromDouble((double)r->misfit))
        || put(d, "model_rms", PyFloat_FromDouble((double)r->rms))
        || put(d, "marker_noise_var", PyFloat_FromDouble((double)r->marker_var))
        || put(d, "marker_noise_var_parent", PyFloat_FromDouble((double)r->marker_var_p))
        || put(d, "marker_noise_var_child", PyFloat_FromDouble((double)r->marker_var_c))
        || put(d, "noise_source", PyUnicode_FromString(r->noise == SFIT_PAIR_NOISE_GIVEN
                                                            ? "given"
                                                            : "registration_residuals"))
        || put(d, "frames", PyLong_FromUnsignedLong((unsigned long)r->frames))
        || put(d, "flags", flags_list(r->flags))
        || put(d, "flags_mask", PyLong_FromUnsignedLong((unsigned long)r->flags))
        || put(d, "untrusted", PyBool_FromLong((r->flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u))
        || put(d, "reason", PyUnicode_FromString(cli_joint_pair_reason(r->reason)))
        || put(d, "mode", PyUnicode_FromString(r->mode == SFIT_PAIR_MODE_HINGE ? "planar"
                                                                               : "sphere"))) {
        Py_DECREF(d);
        return NULL;
    }
    return d;
}

/* A template from (M, 3) positions; status. */
static sfit_status_t template_of(PyArrayObject *a, sfit_cluster_t *cl)
{
    const npy_intp m = PyArray_DIM(a, 0);
    if (m < 3 || m > SFIT_CLUSTER_MAX_MARKERS) {
        return SFIT_E_ARG;
    }
    return sfit_cluster_init(cl, (const sfit_vec3_t *)PyArray_DATA(a), (size_t)m);
}

PyObject *sfit_py_pair_solve(PyObject *self, PyObject *args)
{
    PyObject *po, *co, *pto, *cto, *out = NULL;
    PyArrayObject *p = NULL, *c = NULL, *pt = NULL, *ct = NULL;
    int method, mode, noise;
    double var;
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    sfit_cluster_t pcl, ccl;
    sfit_pair_t *s = NULL;
    sfit_pair_result_t r;
    sfit_status_t st = SFIT_OK;
    long rejected = 0;
    (void)self;
    if (!PyArg_ParseTuple(args, "OOOOiiid", &po, &co, &pto, &cto, &method, &mode, &noise, &var)) {
        return NULL;
    }
    if (method < 0 || method > 1 || mode < 0 || mode > 2 || noise < 0 || noise > 1
        || !(var >= 0.0) || !(var < 3.0e38)) {
        return Py_BuildValue("(iOl)", (int)SFIT_E_ARG, Py_None, 0L);
    }
    p = as_f32(po, 3, "parent");
    c = (p != NULL) ? as_f32(co, 3, "child") : NULL;
    pt = (c != NULL) ? as_f32(pto, 2, "parent template") : NULL;
    ct = (pt != NULL) ? as_f32(cto, 2, "child template") : NULL;
    if (ct == NULL) {
        goto done;
    }
    if (PyArray_DIM(p, 0) != PyArray_DIM(c, 0) || PyArray_DIM(p, 1) != PyArray_DIM(pt, 0)
        || PyArray_DIM(c, 1) != PyArray_DIM(ct, 0) || PyArray_DIM(p, 0) > (npy_intp)UINT32_MAX) {
        out = Py_BuildValue("(iOl)", (int)SFIT_E_ARG, Py_None, 0L);
        goto done;
    }
    cfg.method = (sfit_pair_method_t)method;
    cfg.mode = (sfit_pair_mode_t)mode;
    cfg.noise = (sfit_pair_noise_t)noise;
    cfg.marker_var = (float)var;
    st = template_of(pt, &pcl);
    if (st == SFIT_OK) {
        st = template_of(ct, &ccl);
    }
    s = (st == SFIT_OK) ? PyMem_Malloc(sizeof *s) : NULL;
    if (st == SFIT_OK && s == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    if (st == SFIT_OK) {
        st = sfit_pair_init(s, &pcl, &ccl, &cfg);
    }
    if (st == SFIT_OK) {
        const npy_intp nf = PyArray_DIM(p, 0), mp = PyArray_DIM(p, 1), mc = PyArray_DIM(c, 1);
        const sfit_vec3_t *pv = (const sfit_vec3_t *)PyArray_DATA(p);
        const sfit_vec3_t *cv = (const sfit_vec3_t *)PyArray_DATA(c);
        npy_intp f;
        Py_BEGIN_ALLOW_THREADS
        for (f = 0; f < nf; f++) {
            if (sfit_pair_add_markers(s, &pcl, pv + f * mp, (size_t)mp, &ccl, cv + f * mc,
                                      (size_t)mc) != SFIT_OK) {
                rejected++;
            }
        }
        Py_END_ALLOW_THREADS
        st = sfit_pair_solve(s, &r);
    }
    if (st != SFIT_OK) {
        out = Py_BuildValue("(iOl)", (int)st, Py_None, rejected);
    } else {
        PyObject *d = result_dict(&r);
        if (d != NULL) {
            out = Py_BuildValue("(iNl)", 0, d, rejected);
        }
    }
done:
    PyMem_Free(s);
    Py_XDECREF(p);
    Py_XDECREF(c);
    Py_XDECREF(pt);
    Py_XDECREF(ct);
    return out;
}

PyObject *sfit_py_joint_center_cov(const sfit_joint_t *j, PyObject *args)
{
    const char *raw;
    Py_ssize_t rawlen;
    PyObject *po, *co, *out = NULL;
    PyArrayObject *p = NULL, *c = NULL;
    double var_given;
    sfit_joint_result_t r;
    sfit_mat3_t cov;
    float var = 0.0f;
    sfit_status_t st;
    if (!PyArg_ParseTuple(args, "y#OOd", &raw, &rawlen, &po, &co, &var_given)) {
        return NULL;
    }
    if (rawlen != (Py_ssize_t)sizeof r || !(var_given < 3.0e38)) {
        return Py_BuildValue("(iOd)", (int)SFIT_E_ARG, Py_None, 0.0);
    }
    memcpy(&r, raw, sizeof r);
    p = as_f32(po, 3, "parent");
    c = (p != NULL) ? as_f32(co, 3, "child") : NULL;
    if (c == NULL) {
        goto done;
    }
    if (PyArray_DIM(p, 0) != PyArray_DIM(c, 0) || PyArray_DIM(p, 0) < 1
        || PyArray_DIM(p, 1) != (npy_intp)j->parent.count
        || PyArray_DIM(c, 1) != (npy_intp)j->cfg.n_child) {
        out = Py_BuildValue("(iOd)", (int)SFIT_E_ARG, Py_None, 0.0);
        goto done;
    }
    Py_BEGIN_ALLOW_THREADS
    st = cli_joint_mgdk_cov(j, &r, (const sfit_vec3_t *)PyArray_DATA(p),
                            (const sfit_vec3_t *)PyArray_DATA(c), (size_t)PyArray_DIM(p, 0),
                            (var_given >= 0.0) ? (float)var_given : -1.0f, &cov, &var);
    Py_END_ALLOW_THREADS
    if (st != SFIT_OK) {
        out = Py_BuildValue("(iOd)", (int)st, Py_None, (double)var);
    } else {
        out = Py_BuildValue("(iNd)", 0, mat(&cov), (double)var);
    }
done:
    Py_XDECREF(p);
    Py_XDECREF(c);
    return out;
}
