/* SPDX-License-Identifier: MIT */
/**
 * @file py_module.c
 * @brief sfit._sfit: the CPython extension over lib/src (compiled from the
 * same sources, see setup.py). This file only registers: the method table
 * names every function of the families (py_sfit.h), the init adds the
 * types, the exceptions and the constants.
 *
 * The binding is the only place that calls the C library: every sfit_*
 * function and type the Python package uses appears in tools/python/src,
 * and nowhere in the Python layer (sfit/), so that an API rename touches
 * these files only. What they do:
 *  - arrays in: any real numeric array-like of shape (N, 3) (or (3,) for one
 *    sample) is converted to a C-contiguous float32 copy by numpy
 *    (py_array.c);
 *  - rows the library rejects (NaN, Inf, |x| >= 2^SFIT_COORD_MAX_EXP) are
 *    skipped and counted, as the CLI does with such lines;
 *  - results out: dicts of float64 numpy arrays and Python floats holding
 *    the library's float32 values exactly (py_value.c; the Python layer
 *    wraps them);
 *  - a status other than SFIT_OK raises the sfit.Error subclass of that
 *    status, carrying the status name, the code and a message (py_error.c).
 * The GIL is released around the loops over samples of the functions on
 * arrays; methods that change an object's state keep it (no two threads
 * ever update one state at once).
 */
#define SFIT_PY_MODULE /* this file imports numpy's C API for all */
#include "py_sfit.h"

#define KW(f) ((PyCFunction)(void (*)(void))(f)), METH_VARARGS | METH_KEYWORDS

PyDoc_STRVAR(fit_doc,
             "_fit(points, noise_var, noise_cov, mode, refine, planar_ratio, gate) -> dict\n"
             "Internal: see sfit.fit.");

static PyMethodDef module_methods[] = {
    /* py_fit.c */
    {"fit", KW(sfit_py_fit), fit_doc},
    {"fit_multi", KW(sfit_py_fit_multi), "Internal: see sfit.fit_multi."},
    {"refine", KW(sfit_py_refine), "Internal: see sfit.refine."},
    {"residual_noise_var", KW(sfit_py_residual_noise_var),
     "Internal: see sfit.residual_noise_var."},
    {"uncertainty", KW(sfit_py_uncertainty), "Internal: see sfit.uncertainty."},
    /* py_coverage.c */
    {"calibration_std", KW(sfit_py_calibration_std), "Internal: see sfit.calibration_std."},
    {"coverage_eigs", KW(sfit_py_coverage_eigs), "Internal: see sfit.coverage_eigs."},
    {"coverage_max_sigma", KW(sfit_py_coverage_max_sigma),
     "Internal: see sfit.coverage_max_sigma."},
    {"coverage_min_theta", KW(sfit_py_coverage_min_theta),
     "Internal: see sfit.coverage_min_theta."},
    {"coverage_estimate_theta", KW(sfit_py_coverage_estimate_theta),
     "Internal: see sfit.coverage_estimate_theta."},
    /* py_error.c */
    {"status_name", sfit_py_status_name, METH_O, "status_name(code) -> str (the library's name)."},
    /* py_swaps.c, py_pair.c, py_imu.c */
    {"_label_swaps", sfit_py_label_swaps, METH_VARARGS,
     "Internal: label swaps within one cluster (see sfit.joint_center)."},
    {"_pair_solve", sfit_py_pair_solve, METH_VARARGS,
     "Internal: see sfit.joint_center (py_pair.c)."},
    {"_imu_joint", sfit_py_imu_joint, METH_VARARGS, "Internal: see sfit.imu_joint (py_imu.c)."},
    /* py_c3d.c */
    {"_c3d_read", sfit_py_c3d_read, METH_VARARGS, "Internal: see sfit.read_c3d."},
    {"_c3d_write", sfit_py_c3d_write, METH_VARARGS,
     "Internal: see sfit.write_c3d / sfit.write_trc."},
    /* py_session.c */
    {"_session_model", sfit_py_session_model, METH_VARARGS, "Internal: see sfit.session_model."},
    {"_session_calibrate", sfit_py_session_calibrate, METH_VARARGS,
     "Internal: see sfit.calibrate."},
    {"_session_place", sfit_py_session_place, METH_VARARGS, "Internal: see sfit.apply_session."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT, "sfit._sfit",
    "The compiled core of sfit (lib/src). Use the sfit package, not this module.", -1,
    module_methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__sfit(void)
{
    PyObject *m;
    import_array();
    if (PyType_Ready(&sfit_py_moments_type) < 0 || PyType_Ready(&sfit_py_incr_type) < 0
        || PyType_Ready(&sfit_py_cluster_type) < 0 || PyType_Ready(&sfit_py_joint_type) < 0
        || sfit_py_cluster_prepare() < 0) {
        return NULL;
    }
    m = PyModule_Create(&module_def);
    if (m == NULL) {
        return NULL;
    }
    if (sfit_py_error_add(m) < 0
        || PyModule_AddObjectRef(m, "Cluster", (PyObject *)&sfit_py_cluster_type) < 0
        || PyModule_AddObjectRef(m, "Joint", (PyObject *)&sfit_py_joint_type) < 0
        || PyModule_AddIntConstant(m, "CLUSTER_MAX_MARKERS", SFIT_CLUSTER_MAX_MARKERS) < 0
        || PyModule_AddIntConstant(m, "JOINT_MAX_CHILD", SFIT_JOINT_MAX_CHILD) < 0
        || PyModule_AddObjectRef(m, "Moments", (PyObject *)&sfit_py_moments_type) < 0
        || PyModule_AddObjectRef(m, "Incremental", (PyObject *)&sfit_py_incr_type) < 0
        || PyModule_AddIntConstant(m, "VERSION_MAJOR", SFIT_VERSION_MAJOR) < 0
        || PyModule_AddIntConstant(m, "VERSION_MINOR", SFIT_VERSION_MINOR) < 0
        || PyModule_AddIntConstant(m, "VERSION_PATCH", SFIT_VERSION_PATCH) < 0
        || PyModule_AddIntConstant(m, "MIN_SAMPLES", SFIT_MIN_SAMPLES) < 0
        || PyModule_AddIntConstant(m, "COORD_MAX_EXP", SFIT_COORD_MAX_EXP) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
