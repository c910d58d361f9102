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

#include "sfit/sfit_joint.h"

/** Joint._center_cov(raw result, parent (F, Mp, 3), child (F, K, 3), var_given)
 *  -> (code, cov (3, 3) or None, marker variance used): the mgdk centre's
 *  covariance as the CLI reports it (cli_joint_mgdk_cov); var_given < 0 =
 *  from the parent's registration residuals. */
PyObject *sfit_py_joint_center_cov(const sfit_joint_t *j, PyObject *args);

#endif /* SFIT_PAIR_PY_H */
