/* SPDX-License-Identifier: MIT */
/**
 * @file py_moments.c
 * @brief sfit._sfit.Moments: the streaming moments accumulator
 * (sfit_moments.h) and what reads it: fit, stats, noise calibration
 * (sfit_noise.h) and uncertainty. Methods that change the state keep the
 * GIL (no two threads ever update one state at once).
 */
#include "py_sfit.h"

#include <math.h>
#include <string.h>

typedef struct {
    PyObject_HEAD
    sfit_moments_t m;
    long rejected;
} MomentsObject;


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
        sfit_py_pts_t p;
        const sfit_vec3_t *v;
        sfit_vec3_t *own;
        size_t nv;
        if (sfit_py_pts_get(points, &p, "Moments(points)", 1) < 0) {
            return -1;
        }
        rej = sfit_py_pts_filter(&p, &m, &v, &own, &nv);
        PyMem_RawFree(own);
        sfit_py_pts_release(&p);
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
    sfit_py_pts_t p;
    size_t i;
    long added = 0, rej = 0;
    int full = 0;
    if (sfit_py_pts_get(x, &p, "Moments.add", 1) < 0) {
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
    sfit_py_pts_release(&p);
    if (full) {
        return sfit_py_raise_status(SFIT_E_RANGE, "Moments.add (sample count full)", -1, -1);
    }
    self->rejected += rej;
    return PyLong_FromLong(added);
}

static PyObject *Moments_merge(MomentsObject *self, PyObject *other)
{
    sfit_status_t st;
    if (!PyObject_TypeCheck(other, &sfit_py_moments_type)) {
        return sfit_py_raise_arg("Moments.merge: expected a Moments, got %s",
                                 Py_TYPE(other)->tp_name);
    }
    st = sfit_moments_merge(&self->m, &((MomentsObject *)other)->m);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "Moments.merge", -1, -1);
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
    if (c != NULL && !PyObject_TypeCheck((PyObject *)c, &sfit_py_moments_type)) {
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
    if (sfit_py_is_auto(noise_var)) {
        return sfit_py_raise_arg("Moments.fit: noise_var='auto' needs the samples (use sfit.fit)");
    }
    if (sfit_py_cfg_get(noise_var, noise_cov, mode, planar_ratio, &cfg) < 0) {
        return NULL;
    }
    st = sfit_fit_moments(&self->m, &cfg, &r);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "Moments.fit", (long)sfit_moments_count(&self->m),
                            self->rejected);
    }
    if (cfg.noise == SFIT_NOISE_ISO && r.mode == SFIT_MODE_SPHERE) {
        has_u = (sfit_uncert_moments(&self->m, &r.center, r.radius, cfg.noise_var,
                                     SFIT_UNCERT_NOISE_KNOWN, &u) == SFIT_OK);
    }
    d = PyDict_New();
    if (d == NULL || sfit_py_result_into(d, &r) < 0
        || sfit_py_put(d, "rejected", PyLong_FromLong(self->rejected)) < 0
        || sfit_py_put(d, "outliers", PyLong_FromLong(0)) < 0
        || sfit_py_put(d, "noise_var",
                       cfg.noise == SFIT_NOISE_ISO ? sfit_py_flt(cfg.noise_var)
                                                   : Py_NewRef(Py_None))
               < 0
        || sfit_py_put(d, "noise_estimated", PyBool_FromLong(0)) < 0
        || sfit_py_put(d, "noise_capped", PyBool_FromLong(0)) < 0
        || sfit_py_put(d, "iterations", PyLong_FromLong(0)) < 0
        || sfit_py_put(d, "rms", Py_NewRef(Py_None)) < 0
        || (has_u && sfit_py_uncert_into(d, &u) < 0)) {
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
        return sfit_py_raise_status(st, "Moments.stats", (long)sfit_moments_count(&self->m),
                            self->rejected);
    }
    return Py_BuildValue("(NNN)", sfit_py_vec3_out(mean.v), sfit_py_mat3_out(&c),
                         sfit_py_vec3_out(s.v));
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
    if (sfit_py_vec3_get(center, &c0, "center") < 0) {
        return NULL;
    }
    st = sfit_noise_calibrate(&self->m, &c0, (float)radius, &e);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "calibrate_noise", (long)sfit_moments_count(&self->m),
                            self->rejected);
    }
    flags = sfit_py_noise_flag_names(e.flags);
    if (flags == NULL) {
        return NULL;
    }
    return Py_BuildValue("{s:k,s:N,s:N,s:N,s:N,s:l}", "n", (unsigned long)e.n, "noise_trace",
                         sfit_py_flt(e.noise_trace), "noise_var", sfit_py_flt(e.noise_var),
                         "noise_var_std", sfit_py_flt(e.noise_var_std), "flags", flags, "rejected",
                         self->rejected);
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
    if (sfit_py_vec3_get(center, &c, "center") < 0
        || sfit_py_nonneg_get(nvo, &nvar, "noise_var") < 0) {
        return NULL;
    }
    st = sfit_uncert_moments(&self->m, &c, (float)radius, nvar,
                             estimated ? SFIT_UNCERT_NOISE_ESTIMATED : SFIT_UNCERT_NOISE_KNOWN, &u);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "Moments.uncertainty", -1, -1);
    }
    d = PyDict_New();
    if (d == NULL || sfit_py_uncert_into(d, &u) < 0) {
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

PyTypeObject sfit_py_moments_type = {
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

