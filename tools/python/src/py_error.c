/* SPDX-License-Identifier: MIT */
/**
 * @file py_error.c
 * @brief sfit.Error and its subclasses, one per status of the library:
 * a status other than SFIT_OK raises the subclass of that status, carrying
 * the status name, the code and a message (and the samples used and rows
 * skipped, when the call had samples). Also status_name(code).
 */
#include "py_sfit.h"

#define N_STATUS 8 /* SFIT_OK .. SFIT_E_RANGE (0 .. -7) */
static PyObject *g_error;            /* sfit.Error */
static PyObject *g_exc[N_STATUS];    /* per status code (index -code), [0] unused */

static const char *const g_exc_names[N_STATUS] = {
    NULL,               "ArgError",       "TooFewError",     "NotPosDefError",
    "NoConvergenceError", "DegenerateError", "NonFiniteError", "RangeError"};

/* The status texts are Python's words of the host tools' one table
 * (names_status_message, tools/lab/names.h). */

/* Raise the exception of status st; `what` names the operation. n and
 * rejected (>= 0) are attached as attributes when given. Returns NULL. */
PyObject *sfit_py_raise_status(sfit_status_t st, const char *what, long n, long rejected)
{
    const int idx = (st < 0 && st > -N_STATUS) ? -(int)st : 0;
    PyObject *cls = (idx > 0) ? g_exc[idx] : g_error;
    PyObject *msg, *exc;
    if (n >= 0) {
        msg = PyUnicode_FromFormat("%s failed (%s): %s [n=%ld, rejected=%ld]", what,
                                   sfit_status_str(st), names_status_message(st, NAMES_PY), n,
                                   rejected);
    } else {
        msg = PyUnicode_FromFormat("%s failed (%s): %s", what, sfit_status_str(st),
                                   names_status_message(st, NAMES_PY));
    }
    if (msg == NULL) {
        return NULL;
    }
    exc = PyObject_CallOneArg(cls, msg);
    Py_DECREF(msg);
    if (exc == NULL) {
        return NULL;
    }
    {
        PyObject *s = PyUnicode_FromString(sfit_status_str(st));
        PyObject *c = PyLong_FromLong((long)st);
        PyObject *m = PyUnicode_FromString(names_status_message(st, NAMES_PY));
        PyObject *nn = (n >= 0) ? PyLong_FromLong(n) : Py_NewRef(Py_None);
        PyObject *rr = (n >= 0) ? PyLong_FromLong(rejected) : Py_NewRef(Py_None);
        int bad = (s == NULL || c == NULL || m == NULL || nn == NULL || rr == NULL)
                  || PyObject_SetAttrString(exc, "status", s) < 0
                  || PyObject_SetAttrString(exc, "code", c) < 0
                  || PyObject_SetAttrString(exc, "message", m) < 0
                  || PyObject_SetAttrString(exc, "n", nn) < 0
                  || PyObject_SetAttrString(exc, "rejected", rr) < 0;
        Py_XDECREF(s);
        Py_XDECREF(c);
        Py_XDECREF(m);
        Py_XDECREF(nn);
        Py_XDECREF(rr);
        if (bad) {
            Py_DECREF(exc);
            return NULL;
        }
    }
    PyErr_SetObject(cls, exc);
    Py_DECREF(exc);
    return NULL;
}

/* An argument error of the binding itself (shape, dtype, option value). */
PyObject *sfit_py_raise_arg(const char *fmt, ...)
{
    va_list ap;
    PyObject *msg, *exc;
    va_start(ap, fmt);
    msg = PyUnicode_FromFormatV(fmt, ap);
    va_end(ap);
    if (msg == NULL) {
        return NULL;
    }
    exc = PyObject_CallOneArg(g_exc[1], msg);
    if (exc != NULL) {
        PyObject *s = PyUnicode_FromString(sfit_status_str(SFIT_E_ARG));
        PyObject *c = PyLong_FromLong((long)SFIT_E_ARG);
        if (s != NULL && c != NULL && PyObject_SetAttrString(exc, "status", s) == 0
            && PyObject_SetAttrString(exc, "code", c) == 0
            && PyObject_SetAttrString(exc, "message", msg) == 0
            && PyObject_SetAttrString(exc, "n", Py_None) == 0
            && PyObject_SetAttrString(exc, "rejected", Py_None) == 0) {
            PyErr_SetObject(g_exc[1], exc);
        }
        Py_XDECREF(s);
        Py_XDECREF(c);
        Py_DECREF(exc);
    }
    Py_DECREF(msg);
    return NULL;
}

PyObject *sfit_py_status_name(PyObject *self, PyObject *arg)
{
    long c = PyLong_AsLong(arg);
    (void)self;
    if (c == -1 && PyErr_Occurred()) {
        return NULL;
    }
    if (c < -1000 || c > 1000) { /* no status: not truncated into one */
        c = -1000;
    }
    return PyUnicode_FromString(sfit_status_str((sfit_status_t)c));
}


int sfit_py_error_add(PyObject *m)
{
    int i;
    g_error = PyErr_NewExceptionWithDoc(
        "sfit.Error",
        "A status other than ok from the sfit library. Attributes: status (the library's "
        "status name), code (its negative value), message, n and rejected (samples used and "
        "rows skipped, when the call had samples; else None).",
        NULL, NULL);
    if (g_error == NULL || PyModule_AddObjectRef(m, "Error", g_error) < 0) {
        return -1;
    }
    for (i = 1; i < N_STATUS; i++) {
        char qual[64];
        /* ArgError and RangeError are ValueErrors too */
        PyObject *bases = (i == 1 || i == 7) ? PyTuple_Pack(2, g_error, PyExc_ValueError)
                                             : PyTuple_Pack(1, g_error);
        if (bases == NULL) {
            return -1;
        }
        PyOS_snprintf(qual, sizeof qual, "sfit.%s", g_exc_names[i]);
        g_exc[i] = PyErr_NewExceptionWithDoc(
            qual, names_status_message((sfit_status_t)(-i), NAMES_PY), bases, NULL);
        Py_DECREF(bases);
        if (g_exc[i] == NULL || PyModule_AddObjectRef(m, g_exc_names[i], g_exc[i]) < 0) {
            return -1;
        }
    }
    return 0;
}
