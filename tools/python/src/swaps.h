/* SPDX-License-Identifier: MIT */
/** @file swaps.h  sfit._sfit._label_swaps (swaps.c), registered in sfitmodule.c. */
#ifndef SFIT_PY_SWAPS_H
#define SFIT_PY_SWAPS_H

#include <Python.h>

/** _label_swaps(buf, frames, markers, repair) -> dict (see swaps.c). */
PyObject *sfit_py_label_swaps(PyObject *self, PyObject *args);

#endif /* SFIT_PY_SWAPS_H */
