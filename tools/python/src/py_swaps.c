/* SPDX-License-Identifier: MIT */
/**
 * @file py_swaps.c
 * @brief sfit._sfit._label_swaps: the label-swap check of `sfit joint`
 * (tools/lab/swaps.c, compiled into the extension) over one cluster's
 * frames, for sfit.joint_center. Registered in py_module.c.
 *
 * _label_swaps(buf, frames, markers, repair) -> dict
 *   buf: a writable C-contiguous float32 buffer of frames * markers * 3
 *   values (a private copy made by the Python layer); repaired in place
 *   when repair is true. The dict: checked, why, frames_checked, noise,
 *   decidable_above, no_fit_above, swapped_frames, no_fit, ambiguous,
 *   status (bytes: one native int16 per frame, swaps.h), candidates
 *   (list of (labels tuple, moved, count, pattern, decidable); [0] = the
 *   labels as given).
 */
#include "py_sfit.h"

#include "swaps.h"

static PyObject *cand_list(const swaps_t *s)
{
    PyObject *list = PyList_New(s->ncand);
    int c, u;
    if (list == NULL) {
        return NULL;
    }
    for (c = 0; c < s->ncand; c++) {
        const swaps_cand_t *k = &s->cand[c];
        PyObject *lab = PyTuple_New(s->m), *item;
        if (lab == NULL) {
            Py_DECREF(list);
            return NULL;
        }
        for (u = 0; u < s->m; u++) {
            PyTuple_SET_ITEM(lab, u, PyLong_FromLong((long)k->lab[u]));
        }
        item = Py_BuildValue("(Nildi)", lab, k->moved, k->count, k->pattern, k->decidable);
        if (item == NULL) {
            Py_DECREF(list);
            return NULL;
        }
        PyList_SET_ITEM(list, c, item);
    }
    return list;
}

PyObject *sfit_py_label_swaps(PyObject *self, PyObject *args)
{
    Py_buffer view;
    Py_ssize_t nframes;
    int m, repair, rc;
    swaps_t *s;
    PyObject *res = NULL, *cands;
    (void)self;
    if (!PyArg_ParseTuple(args, "w*nip", &view, &nframes, &m, &repair)) {
        return NULL;
    }
    if (nframes < 0 || m < 1 || m > SWAPS_MAX_MARKERS || nframes > 0xffffffffL
        || view.len != nframes * (Py_ssize_t)m * 3 * (Py_ssize_t)sizeof(float)) {
        PyBuffer_Release(&view);
        PyErr_SetString(PyExc_ValueError, "_label_swaps: buffer size does not match");
        return NULL;
    }
    s = (swaps_t *)PyMem_Malloc(sizeof *s);
    if (s == NULL) {
        PyBuffer_Release(&view);
        return PyErr_NoMemory();
    }
    Py_BEGIN_ALLOW_THREADS
    rc = swaps_run((sfit_vec3_t *)view.buf, (long)nframes, m, 0, m, 0, (long)nframes - 1,
                       repair, s);
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&view);
    if (rc != 0) {
        swaps_free(s);
        PyMem_Free(s);
        return PyErr_NoMemory();
    }
    cands = cand_list(s);
    if (cands != NULL) {
        res = Py_BuildValue("{s:O,s:s,s:l,s:d,s:d,s:d,s:l,s:l,s:l,s:y#,s:N}", "checked",
                            s->checked ? Py_True : Py_False, "why", swaps_why(s->why),
                            "frames_checked", s->frames_checked, "noise", s->scale,
                            "decidable_above", s->decide, "no_fit_above", s->misfit,
                            "swapped_frames", s->frames_swapped, "no_fit", s->frames_no_fit,
                            "ambiguous", s->frames_ambiguous, "status",
                            (const char *)s->status,
                            (Py_ssize_t)((size_t)nframes * sizeof *s->status), "candidates",
                            cands);
    }
    swaps_free(s);
    PyMem_Free(s);
    return res;
}
