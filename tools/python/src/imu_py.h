/* SPDX-License-Identifier: MIT */
/** @file imu_py.h  The IMU joint binding (imu_py.c), registered by sfitmodule.c. */
#ifndef SFIT_IMU_PY_H
#define SFIT_IMU_PY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

/** numpy's C API for imu_py.c; 0, or -1 with an exception set. */
int sfit_py_imu_import(void);

/** _sfit._imu_joint (see imu_py.c). */
PyObject *sfit_py_imu_joint(PyObject *self, PyObject *args);

#endif /* SFIT_IMU_PY_H */
