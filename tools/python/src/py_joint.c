/* SPDX-License-Identifier: MIT */
/**
 * @file py_joint.c
 * @brief sfit._sfit.Joint: the streaming functional joint centre
 * (sfit_joint.h) over a parent Cluster and child markers, its centre in
 * every frame and the multi-marker fit's centre covariance with the CLI's
 * noise figure.
 */
#include "py_sfit.h"

#include <math.h>
#include <string.h>

#include "joint_run.h" /* joint_run_mgdk_cov: the CLI's noise figure */

typedef struct {
    PyObject_HEAD
    sfit_joint_t j;
    long rejected_frames;
    int ready;
} JointObject;

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
            sfit_py_raise_arg("Joint: marker_noise_var replaces noise_var / noise_cov (give one)");
            return -1;
        }
        /* the marker noise, propagated through the parent pose by the library */
        noise_var = marker_var;
        cfg.noise_model = SFIT_JOINT_NOISE_MARKER;
    }
    if (!PyObject_TypeCheck(parent, &sfit_py_cluster_type)
        || ((sfit_py_cluster_t *)parent)->cl.count == 0u) {
        sfit_py_raise_arg("Joint: parent must be a sfit.Cluster");
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
            sfit_py_raise_arg("Joint: n_child must be in 1..%d", (int)SFIT_JOINT_MAX_CHILD);
            return -1;
        }
        n_child = (unsigned long long)v;
    }
    if (sfit_py_is_auto(noise_var)) {
        sfit_py_raise_arg("Joint: noise_var='auto' is not supported (give a number)");
        return -1;
    }
    if (sfit_py_cfg_get(noise_var, noise_cov, mode, planar_ratio, &cfg.solve.fit) < 0
        || sfit_py_weight_get(weight, &cfg.solve.weight) < 0) {
        return -1;
    }
    cfg.n_child = (uint32_t)n_child;
    j = (sfit_joint_t *)PyMem_Malloc(sizeof *j);
    if (j == NULL) {
        PyErr_NoMemory();
        return -1;
    }
    st = sfit_joint_init(j, &((sfit_py_cluster_t *)parent)->cl, &cfg);
    if (st != SFIT_OK) {
        PyMem_Free(j);
        sfit_py_raise_status(st, "Joint", -1, -1);
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
    sfit_py_frames_t pf, cf;
    size_t i;
    long accepted = 0, rejected = 0;
    int arg_error = 0;
    if (!self->ready) {
        return sfit_py_raise_arg("Joint: not initialised");
    }
    if (!PyArg_ParseTuple(args, "OO", &po, &co)) {
        return NULL;
    }
    if (sfit_py_frames_get(po, &pf, "Joint.add(parent)", 1) < 0) {
        return NULL;
    }
    if (sfit_py_frames_get(co, &cf, "Joint.add(child)", 1) < 0) {
        Py_DECREF(pf.arr);
        return NULL;
    }
    if (PyArray_NDIM(pf.arr) != PyArray_NDIM(cf.arr) || pf.nframes != cf.nframes) {
        Py_DECREF(pf.arr);
        Py_DECREF(cf.arr);
        return sfit_py_raise_arg("Joint.add: parent and child must have the same number of frames");
    }
    if (pf.count != (size_t)self->j.parent.count || cf.count != (size_t)self->j.cfg.n_child) {
        PyObject *e = sfit_py_raise_arg(
            "Joint.add: %zu parent / %zu child markers, expected %lu / %lu", pf.count, cf.count,
            (unsigned long)self->j.parent.count, (unsigned long)self->j.cfg.n_child);
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
        return sfit_py_raise_status(SFIT_E_ARG, "Joint.add", -1, -1);
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
        return sfit_py_raise_arg("Joint: not initialised");
    }
    st = sfit_joint_fit(&self->j, &r, radii);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "Joint.fit", (long)self->j.frames, self->rejected_frames);
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
    if (d == NULL || sfit_py_multi_into(d, &r.fit) < 0
        || sfit_py_put(d, "frames", PyLong_FromUnsignedLong((unsigned long)r.frames)) < 0
        || sfit_py_put(d, "rejected_frames", PyLong_FromLong(self->rejected_frames)) < 0
        || sfit_py_put(d, "residual_mean", sfit_py_flt(r.residual_mean)) < 0
        || sfit_py_put(d, "residual_max", sfit_py_flt(r.residual_max)) < 0
        || sfit_py_put(d, "radii", ra) < 0 || sfit_py_put(d, "marker_n", na) < 0) {
        Py_XDECREF(d);
        return NULL;
    }
    /* keep the raw result for center_at */
    if (sfit_py_put(d, "_raw", PyBytes_FromStringAndSize((const char *)&r, (Py_ssize_t)sizeof r))
        < 0) {
        Py_DECREF(d);
        return NULL;
    }
    return d;
}

/* Joint._center_at(raw, parent_frames) -> (centers (F, 3), axes (F, 3),
 * valid (F,)): the centre in the global frame of every frame; rows of the
 * frames whose parent cannot be registered are NaN and valid is False. */
typedef struct at {
    const sfit_joint_t *j;
    sfit_joint_result_t r;
} at_t;

static int at_one(void *ctx, const sfit_vec3_t *frame, size_t count, double c[3], double a[3])
{
    const at_t *p = (const at_t *)ctx;
    sfit_vec3_t cf, af;
    int k;
    if (sfit_joint_center_at(p->j, &p->r, frame, count, &cf, &af) != SFIT_OK) {
        return -1;
    }
    for (k = 0; k < 3; k++) {
        c[k] = (double)cf.v[k];
        a[k] = (double)af.v[k];
    }
    return 0;
}

static PyObject *Joint_center_at(JointObject *self, PyObject *args)
{
    const char *raw;
    Py_ssize_t rawlen;
    PyObject *po, *out;
    sfit_py_frames_t pf;
    at_t at;
    if (!self->ready) {
        return sfit_py_raise_arg("Joint: not initialised");
    }
    if (!PyArg_ParseTuple(args, "y#O", &raw, &rawlen, &po)) {
        return NULL;
    }
    if (rawlen != (Py_ssize_t)sizeof at.r) {
        return sfit_py_raise_arg("Joint.center_at: not a result of this joint's solve()");
    }
    memcpy(&at.r, raw, sizeof at.r);
    at.j = &self->j;
    if (sfit_py_frames_get(po, &pf, "Joint.center_at(parent)", 1) < 0) {
        return NULL;
    }
    if (pf.count != (size_t)self->j.parent.count) {
        Py_DECREF(pf.arr);
        return sfit_py_raise_arg("Joint.center_at: %zu parent markers, expected %lu", pf.count,
                                 (unsigned long)self->j.parent.count);
    }
    out = sfit_py_frames_place(&pf, at_one, &at);
    Py_DECREF(pf.arr);
    return out;
}

/* Joint._center_cov(raw result, parent (F, Mp, 3), child (F, K, 3), var_given)
 * -> (code, cov (3, 3) or None, marker variance used): the mgdk centre's
 * covariance as the CLI reports it (joint_run_mgdk_cov); var_given < 0 =
 * from the parent's registration residuals. */
static PyObject *Joint_center_cov(JointObject *self, PyObject *args)
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
    const sfit_joint_t *j = &self->j;
    if (!self->ready) {
        return sfit_py_raise_arg("Joint: not initialised");
    }
    if (!PyArg_ParseTuple(args, "y#OOd", &raw, &rawlen, &po, &co, &var_given)) {
        return NULL;
    }
    if (rawlen != (Py_ssize_t)sizeof r || !(var_given < 3.0e38)) {
        return Py_BuildValue("(iOd)", (int)SFIT_E_ARG, Py_None, 0.0);
    }
    memcpy(&r, raw, sizeof r);
    p = sfit_py_f32_value(po, 3, "parent");
    c = (p != NULL) ? sfit_py_f32_value(co, 3, "child") : NULL;
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
    st = joint_run_mgdk_cov(j, &r, (const sfit_vec3_t *)PyArray_DATA(p),
                            (const sfit_vec3_t *)PyArray_DATA(c), (size_t)PyArray_DIM(p, 0),
                            (var_given >= 0.0) ? (float)var_given : -1.0f, &cov, &var);
    Py_END_ALLOW_THREADS
    if (st != SFIT_OK) {
        out = Py_BuildValue("(iOd)", (int)st, Py_None, (double)var);
    } else {
        out = Py_BuildValue("(iNd)", 0, sfit_py_mat3_out(&cov), (double)var);
    }
done:
    Py_XDECREF(p);
    Py_XDECREF(c);
    return out;
}

/* Joint.noise_cov(marker_var) -> (3, 3): first-order noise covariance of a
 * child marker in the parent frame for isotropic marker noise. */
static PyObject *Joint_noise_cov(JointObject *self, PyObject *arg)
{
    float var;
    sfit_mat3_t cov;
    sfit_status_t st;
    if (!self->ready) {
        return sfit_py_raise_arg("Joint: not initialised");
    }
    if (sfit_py_nonneg_get(arg, &var, "marker_var") < 0) {
        return NULL;
    }
    st = sfit_joint_noise_cov(&self->j, var, &cov);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "Joint.noise_cov", (long)self->j.frames,
                                    self->rejected_frames);
    }
    return sfit_py_mat3_out(&cov);
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
    {"_center_cov", (PyCFunction)Joint_center_cov, METH_VARARGS, "Internal: see Joint.center_cov."},
    {"noise_cov", (PyCFunction)Joint_noise_cov, METH_O,
     "noise_cov(marker_var) -> ndarray (3, 3)\n\nFirst-order noise covariance of a child marker "
     "in\n"
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

PyTypeObject sfit_py_joint_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sfit._sfit.Joint",
    .tp_basicsize = sizeof(JointObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Streaming functional joint centre (the library's sfit_joint_t).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Joint_init,
    .tp_methods = Joint_methods,
    .tp_getset = Joint_getset,
};

