/* SPDX-License-Identifier: MIT */
/**
 * @file py_cluster.c
 * @brief sfit._sfit.Cluster: a rigid marker cluster's template and its
 * registration (sfit_cluster.h), over frames (F, M, 3) or one (M, 3).
 */
#include "py_sfit.h"

#include <math.h>
#include <string.h>

typedef sfit_py_cluster_t ClusterObject;

/* The private argument of Cluster.from_frames' cls(g_cluster_shell): an
 * empty shell that the classmethod fills in (Cluster(None) is an error). */
static PyObject *g_cluster_shell;

static int Cluster_init(ClusterObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"template", NULL};
    PyObject *tpl;
    sfit_py_frames_t f;
    sfit_status_t st;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O", kwlist, &tpl)
        || sfit_py_frames_get(tpl, &f, "Cluster(template)", 1) < 0) {
        return -1;
    }
    if (f.nframes != 1u) {
        Py_DECREF(f.arr);
        sfit_py_raise_arg("Cluster(template): expected one (markers, 3) array");
        return -1;
    }
    st = sfit_cluster_init(&self->cl, f.v, f.count);
    Py_DECREF(f.arr);
    if (st != SFIT_OK) {
        sfit_py_raise_status(st, "Cluster", -1, -1);
        return -1;
    }
    self->frames_used = 1;
    return 0;
}

/* Cluster._from_frames(frames): a template from one (M, 3) or several
 * (F, M, 3) measured frames (NaN = occluded). */
static PyObject *Cluster_from_frames(PyObject *cls, PyObject *arg)
{
    sfit_py_frames_t f;
    sfit_cluster_t cl;
    size_t used = 1;
    sfit_status_t st;
    ClusterObject *o;
    if (sfit_py_frames_get(arg, &f, "Cluster.from_frames", 1) < 0) {
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
        return sfit_py_raise_status(st, "Cluster.from_frames", -1, -1);
    }
    o = (ClusterObject *)PyObject_CallOneArg(cls, g_cluster_shell);
    if (o == NULL) {
        return NULL;
    }
    if (!PyObject_TypeCheck((PyObject *)o, &sfit_py_cluster_type)) {
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
    return Py_BuildValue("{s:N,s:N,s:N,s:k}", "rotation", sfit_py_mat3_out(&p->r), "translation",
                         sfit_py_vec3_out(p->t.v), "rms", sfit_py_flt(fit->rms), "used",
                         (unsigned long)fit->used);
}

static PyObject *Cluster_register(ClusterObject *self, PyObject *arg)
{
    sfit_py_frames_t f;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    sfit_status_t st;
    if (sfit_py_frames_get(arg, &f, "Cluster.register", 1) < 0) {
        return NULL;
    }
    if (PyArray_NDIM(f.arr) != 2) {
        Py_DECREF(f.arr);
        return sfit_py_raise_arg("Cluster.register: expected one frame (markers, 3)");
    }
    if (f.count != (size_t)self->cl.count) {
        Py_DECREF(f.arr);
        return sfit_py_raise_arg("Cluster.register: %zu markers, the template has %lu", f.count,
                         (unsigned long)self->cl.count);
    }
    st = sfit_cluster_register(&self->cl, f.v, f.count, &pose, &fit);
    Py_DECREF(f.arr);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "Cluster.register", -1, -1);
    }
    return pose_out(&pose, &fit);
}

/* Cluster._place(frames, center, axis) -> (centers (F, 3), axes (F, 3),
 * valid (F,)): a point and a direction of the segment frame in the global
 * frame of every (M, 3) frame of frames, R center + t and R axis (double,
 * as numpy's R @ c + t of the pose); NaN rows and valid False where the
 * frame cannot be registered. One C loop instead of F register() calls. */
typedef struct place {
    const sfit_cluster_t *cl;
    double c[3], ax[3];
} place_t;

static int place_one(void *ctx, const sfit_vec3_t *frame, size_t count, double c[3], double a[3])
{
    const place_t *p = (const place_t *)ctx;
    sfit_pose_t pose;
    sfit_cluster_fit_t fit;
    int r;
    if (sfit_cluster_register(p->cl, frame, count, &pose, &fit) != SFIT_OK) {
        return -1;
    }
    for (r = 0; r < 3; r++) {
        const float *row = &pose.r.m[3 * r];
        c[r] = (double)row[0] * p->c[0] + (double)row[1] * p->c[1] + (double)row[2] * p->c[2];
        a[r] = (double)row[0] * p->ax[0] + (double)row[1] * p->ax[1] + (double)row[2] * p->ax[2];
        c[r] += (double)pose.t.v[r];
    }
    return 0;
}

static PyObject *Cluster_place(ClusterObject *self, PyObject *args)
{
    PyObject *fo, *out;
    place_t p;
    sfit_py_frames_t f;
    p.cl = &self->cl;
    if (!PyArg_ParseTuple(args, "O(ddd)(ddd)", &fo, &p.c[0], &p.c[1], &p.c[2], &p.ax[0],
                          &p.ax[1], &p.ax[2])
        || sfit_py_frames_get(fo, &f, "Cluster._place", 1) < 0) {
        return NULL;
    }
    if (f.count != (size_t)self->cl.count) {
        Py_DECREF(f.arr);
        return sfit_py_raise_arg("Cluster._place: %zu markers, the template has %lu", f.count,
                                 (unsigned long)self->cl.count);
    }
    out = sfit_py_frames_place(&f, place_one, &p);
    Py_DECREF(f.arr);
    return out;
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

PyTypeObject sfit_py_cluster_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sfit._sfit.Cluster",
    .tp_basicsize = sizeof(ClusterObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "Rigid marker cluster template (the library's sfit_cluster_t).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Cluster_init_any,
    .tp_methods = Cluster_methods,
    .tp_getset = Cluster_getset,
};

int sfit_py_cluster_prepare(void)
{
    if (g_cluster_shell == NULL) {
        g_cluster_shell = PyObject_CallNoArgs((PyObject *)&PyBaseObject_Type);
    }
    return (g_cluster_shell != NULL) ? 0 : -1;
}
