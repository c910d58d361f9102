/* SPDX-License-Identifier: MIT */
/** @file pair_py.h  The pair-of-segments binding (pair_py.c), registered by sfitmodule.c. */
#ifndef SFIT_PAIR_PY_H
#define SFIT_PAIR_PY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

/** numpy's C API for pair_py.c; 0, or -1 with an exception set. */
int sfit_py_pair_import(void);

/** _sfit._pair_solve (see pair_py.c). */
PyObject *sfit_py_pair_solve(PyObject *self, PyObject *args);

#endif /* SFIT_PAIR_PY_H */
