/* SPDX-License-Identifier: MIT */
/**
 * @file py_sfit.h
 * @brief The internal header of sfit._sfit, the CPython extension over
 * lib/src: what its files share. Not installed; nothing outside
 * tools/python/src includes it.
 *
 * One file per family of the library (py_fit.c, py_moments.c, py_incr.c,
 * py_coverage.c, py_cluster.c, py_joint.c, py_pair.c, py_imu.c), one per
 * host-code family it binds (py_c3d.c, py_session.c, py_swaps.c), the
 * shared pieces (py_error.c: exceptions; py_array.c: the one array
 * converter and the per-frame loop; py_value.c: values out; py_option.c:
 * options in) and py_module.c, which only registers: its method table
 * names every function below, its init adds the types, exceptions and
 * constants. Every exported name starts with sfit_py_.
 *
 * numpy's C API is one table shared by every file (PY_ARRAY_UNIQUE_SYMBOL);
 * py_module.c defines SFIT_PY_MODULE before this header and imports it.
 */
#ifndef SFIT_PY_SFIT_H
#define SFIT_PY_SFIT_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#ifndef NPY_NO_DEPRECATED_API
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#endif
#define PY_ARRAY_UNIQUE_SYMBOL sfit_py_ARRAY_API
#ifndef SFIT_PY_MODULE
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include <stdint.h>

#include "sfit/sfit.h"
#include "sfit/sfit_cluster.h"
#include "sfit/sfit_joint.h"

#include "json_out.h" /* tools/formats: json_out_flag_t */
#include "names.h"    /* tools/lab: the status texts and flag names */

/* ------------------------------------------------------------------------ */
/* Exceptions (py_error.c)                                                  */
/* ------------------------------------------------------------------------ */

/** Create sfit.Error and one subclass per status; add them to m. 0 or -1. */
int sfit_py_error_add(PyObject *m);
/** Raise the exception of status st; `what` names the operation; n and
 *  rejected (>= 0) are attached when given. Returns NULL. */
PyObject *sfit_py_raise_status(sfit_status_t st, const char *what, long n, long rejected);
/** An ArgError of the binding itself (shape, dtype, option value). NULL. */
PyObject *sfit_py_raise_arg(const char *fmt, ...);
/** status_name(code) -> str (the library's name). */
PyObject *sfit_py_status_name(PyObject *self, PyObject *arg);

/* ------------------------------------------------------------------------ */
/* Arrays in (py_array.c)                                                   */
/* ------------------------------------------------------------------------ */

/** The converter's options (bits). */
enum {
    SFIT_PY_ONE = 1,   /**< one row / frame: ndim - 1 dimensions accepted too */
    SFIT_PY_EMPTY = 2, /**< [] is an empty (0, 3) array */
    SFIT_PY_LIMIT = 4  /**< more than UINT32_MAX rows / frames: RangeError */
};

/** Why the converter refused an argument (no exception raised yet). */
typedef enum sfit_py_why {
    SFIT_PY_OK = 0,
    SFIT_PY_RAISED,   /**< an exception is set (memory, a failed range check) */
    SFIT_PY_NOT_ARRAY, /**< numpy cannot make an array (its exception is set) */
    SFIT_PY_NOT_REAL, /**< not float, int or uint */
    SFIT_PY_SHAPE     /**< not the dimensions asked for, or last not 3 */
} sfit_py_why_t;

/** The one array converter: obj as a C-contiguous float32 copy (*out) of
 *  ndim dimensions, the last 3 (opts: SFIT_PY_*). On refusal *out is NULL
 *  and the reason returned; *probe (when probe is not NULL) then holds
 *  numpy's view of obj for the caller's message (a new reference, or
 *  NULL). */
sfit_py_why_t sfit_py_f32_get(PyObject *obj, int ndim, int opts, const char *what,
                              PyArrayObject **out, PyObject **probe);

/** obj as float32 of ndim dimensions (3: frames, markers, 3; 2: markers,
 *  3), no other option; NULL with a ValueError (or numpy's error) set. */
PyArrayObject *sfit_py_f32_value(PyObject *obj, int ndim, const char *what);

/** A float32 (n, 3) view of the caller's samples. */
typedef struct sfit_py_pts {
    PyArrayObject *arr; /* owned reference (C-contiguous float32) */
    const sfit_vec3_t *v;
    size_t n;
} sfit_py_pts_t;

/** points of shape (N, 3) (or (3,) when allow_one) as float32; 0, or -1
 *  with an ArgError set. */
int sfit_py_pts_get(PyObject *obj, sfit_py_pts_t *p, const char *what, int allow_one);
void sfit_py_pts_release(sfit_py_pts_t *p);
/** The valid rows of p (the library's own test, sfit_moments_add), also
 *  accumulated into acc (if not NULL); see py_array.c. Rejected count, or
 *  -1 (memory). */
long sfit_py_pts_filter(const sfit_py_pts_t *p, sfit_moments_t *acc, const sfit_vec3_t **out,
                        sfit_vec3_t **own, size_t *nout);

/** Frames (F, M, 3) (or (M, 3) as one frame when allow_one); 0, or -1
 *  with an ArgError set. */
typedef struct sfit_py_frames {
    PyArrayObject *arr; /* owned reference (C-contiguous float32) */
    const sfit_vec3_t *v;
    size_t nframes, count;
} sfit_py_frames_t;
int sfit_py_frames_get(PyObject *obj, sfit_py_frames_t *f, const char *what, int allow_one);

/** obj as a C-contiguous float64 array of minnd..maxnd dimensions of real
 *  numbers; else NULL with any exception cleared. */
PyArrayObject *sfit_py_real_f64(PyObject *obj, int minnd, int maxnd);
/** A 3-vector argument (3 real numbers); 0, or -1 with an ArgError. */
int sfit_py_vec3_get(PyObject *obj, sfit_vec3_t *v, const char *what);

/** One frame's point and direction in the global frame; 0, or non-zero
 *  when the frame cannot be placed. Runs without the GIL. */
typedef int (*sfit_py_place_fn)(void *ctx, const sfit_vec3_t *frame, size_t count, double c[3],
                                double a[3]);
/** (centers (F, 3), axes (F, 3), valid (F,)) over the frames of f, NaN
 *  rows and valid False where fn fails. */
PyObject *sfit_py_frames_place(const sfit_py_frames_t *f, sfit_py_place_fn fn, void *ctx);

/* ------------------------------------------------------------------------ */
/* Values out (py_value.c)                                                  */
/* ------------------------------------------------------------------------ */

PyObject *sfit_py_vec3_out(const float *v);
PyObject *sfit_py_mat3_out(const sfit_mat3_t *m);
/** dict[key] = value, stealing value; -1 on failure (value freed). */
int sfit_py_put(PyObject *dict, const char *key, PyObject *value);
PyObject *sfit_py_flt(float x);
/** The names of the bits of flags that the n entries of tab name, in table
 *  order, as a list of str. */
PyObject *sfit_py_flag_names(uint32_t flags, const json_out_flag_t *tab, size_t n);
/** The same for a family of the host tools' one flag-name table (names.h). */
PyObject *sfit_py_family_names(uint32_t flags, names_family_t fam);
/** The names of the noise estimate's flags (sfit_noise_estimate_t). */
PyObject *sfit_py_noise_flag_names(uint32_t flags);
/** The fields of a result into d; 0 or -1. */
int sfit_py_result_into(PyObject *d, const sfit_result_t *r);
int sfit_py_multi_into(PyObject *d, const sfit_multi_result_t *r);
int sfit_py_uncert_into(PyObject *d, const sfit_uncert_t *u);

/* ------------------------------------------------------------------------ */
/* Options in (py_option.c)                                                 */
/* ------------------------------------------------------------------------ */

int sfit_py_nonneg_get(PyObject *o, float *x, const char *what);
int sfit_py_cfg_get(PyObject *noise_var, PyObject *noise_cov, PyObject *mode,
                    double planar_ratio, sfit_fit_cfg_t *cfg);
int sfit_py_weight_get(const char *w, sfit_multi_weight_t *out);
int sfit_py_count_get(PyObject *o, unsigned long long max, unsigned long long *out,
                      const char *what);
int sfit_py_is_auto(PyObject *o);

/* ------------------------------------------------------------------------ */
/* The families: functions of the module table (py_module.c)               */
/* ------------------------------------------------------------------------ */

/* py_fit.c: fit, fit_multi, refine, residual_noise_var, uncertainty */
PyObject *sfit_py_fit(PyObject *self, PyObject *args, PyObject *kw);
PyObject *sfit_py_fit_multi(PyObject *self, PyObject *args, PyObject *kw);
PyObject *sfit_py_refine(PyObject *self, PyObject *args, PyObject *kw);
PyObject *sfit_py_residual_noise_var(PyObject *self, PyObject *args, PyObject *kw);
PyObject *sfit_py_uncertainty(PyObject *self, PyObject *args, PyObject *kw);
/* py_coverage.c: noise calibration and coverage (scalars) */
PyObject *sfit_py_calibration_std(PyObject *self, PyObject *args, PyObject *kw);
PyObject *sfit_py_coverage_eigs(PyObject *self, PyObject *args, PyObject *kw);
PyObject *sfit_py_coverage_max_sigma(PyObject *self, PyObject *args, PyObject *kw);
PyObject *sfit_py_coverage_min_theta(PyObject *self, PyObject *args, PyObject *kw);
PyObject *sfit_py_coverage_estimate_theta(PyObject *self, PyObject *args, PyObject *kw);
/* py_swaps.c: _label_swaps(buf, frames, markers, repair) -> dict */
PyObject *sfit_py_label_swaps(PyObject *self, PyObject *args);
/* py_pair.c: _pair_solve */
PyObject *sfit_py_pair_solve(PyObject *self, PyObject *args);
/* py_imu.c: _imu_joint */
PyObject *sfit_py_imu_joint(PyObject *self, PyObject *args);
/* py_c3d.c: _c3d_read, _c3d_write */
PyObject *sfit_py_c3d_read(PyObject *self, PyObject *args);
PyObject *sfit_py_c3d_write(PyObject *self, PyObject *args);
/* py_session.c: _session_model, _session_calibrate, _session_place */
PyObject *sfit_py_session_model(PyObject *self, PyObject *args);
PyObject *sfit_py_session_calibrate(PyObject *self, PyObject *args);
PyObject *sfit_py_session_place(PyObject *self, PyObject *args);

/* ------------------------------------------------------------------------ */
/* The types                                                                */
/* ------------------------------------------------------------------------ */

extern PyTypeObject sfit_py_moments_type; /* py_moments.c: Moments */
extern PyTypeObject sfit_py_incr_type;    /* py_incr.c: Incremental */
extern PyTypeObject sfit_py_cluster_type; /* py_cluster.c: Cluster */
extern PyTypeObject sfit_py_joint_type;   /* py_joint.c: Joint */

/** A Cluster object (py_cluster.c; Joint reads its template). */
typedef struct sfit_py_cluster {
    PyObject_HEAD
    sfit_cluster_t cl;
    long frames_used;
} sfit_py_cluster_t;

/** Cluster.from_frames' private shell argument; 0 or -1 (py_cluster.c). */
int sfit_py_cluster_prepare(void);

#endif /* SFIT_PY_SFIT_H */
