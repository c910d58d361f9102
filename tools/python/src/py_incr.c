/* SPDX-License-Identifier: MIT */
/**
 * @file py_incr.c
 * @brief sfit._sfit.Incremental: the incremental estimator (sfit_incr.h).
 */
#include "py_sfit.h"

#include <math.h>
#include <string.h>

typedef struct {
    PyObject_HEAD
    sfit_incr_t s;
    long rejected;
} IncrObject;


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
    if (sfit_py_cfg_get(noise_var, noise_cov, NULL, 0.0, &cfg) < 0) {
        return -1;
    }
    icfg.noise = cfg.noise;
    icfg.noise_var = cfg.noise_var;
    icfg.noise_cov = cfg.noise_cov;
    st = sfit_incr_init(&self->s, &icfg);
    if (st != SFIT_OK) {
        sfit_py_raise_status(st, "Incremental", -1, -1);
        return -1;
    }
    self->rejected = 0;
    return 0;
}

static PyObject *est_out(const sfit_sphere_t *e)
{
    return Py_BuildValue("(NNk)", sfit_py_vec3_out(e->center.v), sfit_py_flt(e->radius),
                         (unsigned long)e->n);
}

static PyObject *Incr_start(IncrObject *self, PyObject *points)
{
    sfit_py_pts_t p;
    const sfit_vec3_t *v;
    sfit_vec3_t *own;
    size_t nv;
    long rej;
    sfit_sphere_t e;
    sfit_status_t st;
    if (sfit_py_pts_get(points, &p, "Incremental.start", 0) < 0) {
        return NULL;
    }
    rej = sfit_py_pts_filter(&p, NULL, &v, &own, &nv);
    if (rej < 0) {
        sfit_py_pts_release(&p);
        return NULL;
    }
    st = sfit_incr_start(&self->s, v, nv, &e);
    PyMem_RawFree(own);
    sfit_py_pts_release(&p);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "Incremental.start", (long)nv, rej);
    }
    self->rejected = rej;
    return est_out(&e);
}

static PyObject *Incr_add(IncrObject *self, PyObject *x)
{
    sfit_py_pts_t p;
    size_t i;
    long added = 0, rej = 0;
    if (sfit_py_pts_get(x, &p, "Incremental.add", 1) < 0) {
        return NULL;
    }
    for (i = 0; i < p.n; i++) {
        if (sfit_incr_add(&self->s, &p.v[i]) == SFIT_OK) {
            added++;
        } else {
            rej++;
        }
    }
    sfit_py_pts_release(&p);
    self->rejected += rej;
    return PyLong_FromLong(added);
}

static PyObject *Incr_estimate(IncrObject *self, PyObject *unused)
{
    sfit_sphere_t e;
    sfit_status_t st = sfit_incr_fit(&self->s, &e);
    (void)unused;
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "Incremental.estimate", (long)sfit_incr_count(&self->s),
                            self->rejected);
    }
    return est_out(&e);
}

/* track(points): update with every row; the estimate after each accepted
 * row where one exists -> (n, centers, radii) arrays of the rows that have
 * an estimate. */
static PyObject *Incr_track(IncrObject *self, PyObject *points)
{
    sfit_py_pts_t p;
    size_t i, k = 0;
    long rej = 0;
    PyObject *na = NULL, *ca = NULL, *ra = NULL;
    npy_intp dim[2];
    if (sfit_py_pts_get(points, &p, "Incremental.track", 0) < 0) {
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
    sfit_py_pts_release(&p);
    self->rejected += rej;
    /* full-length arrays and the number of rows filled (the Python layer slices) */
    return Py_BuildValue("(NNNn)", na, ca, ra, (Py_ssize_t)k);
fail:
    Py_XDECREF(na);
    Py_XDECREF(ca);
    Py_XDECREF(ra);
    sfit_py_pts_release(&p);
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

PyTypeObject sfit_py_incr_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sfit._sfit.Incremental",
    .tp_basicsize = sizeof(IncrObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Incremental estimator (the library's sfit_incr_t).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Incr_init,
    .tp_methods = Incr_methods,
    .tp_getset = Incr_getset,
};

