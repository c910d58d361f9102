/* SPDX-License-Identifier: MIT */
/**
 * @file py_pair.c
 * @brief sfit._sfit._pair_solve: the pair of segments (sfit_pair.h) over
 * trajectories, for sfit.joint_center(method="default" | "score" | "sara").
 *
 * _pair_solve(parent, child, parent_template, child_template, method, mode,
 *             noise, marker_var) -> (code, result or None, frames rejected)
 *   parent (F, Mp, 3), child (F, Mc, 3): markers (global), NaN = occluded;
 *   the templates (Mp, 3), (Mc, 3) in each segment frame; method 0 default,
 *   1 plain SCoRE / SARA; mode 0 auto, 1 ball, 2 hinge; noise 0 the
 *   registration residuals, 1 marker_var given. Frames that either cluster
 *   cannot register are skipped and counted. code is the library's status
 *   (0 ok); the Python layer raises the matching sfit.Error. Every value of
 *   the result dict is the library's float32 value, exactly.
 */
#include "py_sfit.h"

#include <string.h>

#include "names.h" /* names_pair_reason: the one name table */
#include "sfit/sfit_pair.h"

/* The information bits (facts about the data, not faults). */
static PyObject *result_dict(const sfit_pair_result_t *r)
{
    PyObject *d = PyDict_New();
    if (d == NULL) {
        return NULL;
    }
    if (sfit_py_put(d, "center", sfit_py_vec3_out(r->center_p.v))
        || sfit_py_put(d, "center_child", sfit_py_vec3_out(r->center_c.v))
        || sfit_py_put(d, "axis", sfit_py_vec3_out(r->axis_p.v))
        || sfit_py_put(d, "axis_child", sfit_py_vec3_out(r->axis_c.v))
        || sfit_py_put(d, "center_cov", sfit_py_mat3_out(&r->center_cov))
        || sfit_py_put(d, "axis_cov",
                       r->mode == SFIT_PAIR_MODE_HINGE ? sfit_py_mat3_out(&r->axis_cov)
                                                       : (Py_INCREF(Py_None), Py_None))
        || sfit_py_put(d, "center_cov_model", sfit_py_mat3_out(&r->center_cov_model))
        || sfit_py_put(d, "axis_cov_model",
                       r->mode == SFIT_PAIR_MODE_HINGE ? sfit_py_mat3_out(&r->axis_cov_model)
                                                       : (Py_INCREF(Py_None), Py_None))
        || sfit_py_put(d, "skin_rms", PyFloat_FromDouble((double)r->sta_rms))
        || sfit_py_put(d, "skin_ratio", PyFloat_FromDouble((double)r->sta_ratio))
        || sfit_py_put(d, "wobble_rms", PyFloat_FromDouble((double)r->wobble_rms))
        || sfit_py_put(d, "info", sfit_py_family_names(r->info, NAMES_PAIR_INFO))
        || sfit_py_put(d, "eigenvalues", sfit_py_vec3_out(r->eigenvalues.v))
        || sfit_py_put(d, "trust_ratio", PyFloat_FromDouble((double)r->trust_ratio))
        || sfit_py_put(d, "misfit", PyFloat_FromDouble((double)r->misfit))
        || sfit_py_put(d, "model_rms", PyFloat_FromDouble((double)r->rms))
        || sfit_py_put(d, "marker_noise_var", PyFloat_FromDouble((double)r->marker_var))
        || sfit_py_put(d, "marker_noise_var_parent", PyFloat_FromDouble((double)r->marker_var_p))
        || sfit_py_put(d, "marker_noise_var_child", PyFloat_FromDouble((double)r->marker_var_c))
        || sfit_py_put(d, "noise_source",
                       PyUnicode_FromString(
                           r->noise == SFIT_PAIR_NOISE_GIVEN ? "given" : "registration_residuals"))
        || sfit_py_put(d, "frames", PyLong_FromUnsignedLong((unsigned long)r->frames))
        || sfit_py_put(d, "flags", sfit_py_family_names(r->flags, NAMES_PAIR))
        || sfit_py_put(d, "flags_mask", PyLong_FromUnsignedLong((unsigned long)r->flags))
        || sfit_py_put(d, "untrusted",
                       PyBool_FromLong((r->flags & (uint32_t)SFIT_FLAG_UNTRUSTED) != 0u))
        || sfit_py_put(d, "reason", PyUnicode_FromString(names_pair_reason(r->reason)))
        || sfit_py_put(
            d, "mode",
            PyUnicode_FromString(r->mode == SFIT_PAIR_MODE_HINGE ? "planar" : "sphere"))) {
        Py_DECREF(d);
        return NULL;
    }
    return d;
}

/* A template from (M, 3) positions; status. */
static sfit_status_t template_of(PyArrayObject *a, sfit_cluster_t *cl)
{
    const npy_intp m = PyArray_DIM(a, 0);
    if (m < 3 || m > SFIT_CLUSTER_MAX_MARKERS) {
        return SFIT_E_ARG;
    }
    return sfit_cluster_init(cl, (const sfit_vec3_t *)PyArray_DATA(a), (size_t)m);
}

PyObject *sfit_py_pair_solve(PyObject *self, PyObject *args)
{
    PyObject *po, *co, *pto, *cto, *out = NULL;
    PyArrayObject *p = NULL, *c = NULL, *pt = NULL, *ct = NULL;
    int method, mode, noise;
    double var;
    sfit_pair_cfg_t cfg = sfit_pair_cfg_default;
    sfit_cluster_t pcl, ccl;
    sfit_pair_t *s = NULL;
    sfit_pair_result_t r;
    sfit_status_t st = SFIT_OK;
    long rejected = 0;
    (void)self;
    if (!PyArg_ParseTuple(args, "OOOOiiid", &po, &co, &pto, &cto, &method, &mode, &noise, &var)) {
        return NULL;
    }
    if (method < 0 || method > 1 || mode < 0 || mode > 2 || noise < 0 || noise > 1
        || !(var >= 0.0) || !(var < 3.0e38)) {
        return Py_BuildValue("(iOl)", (int)SFIT_E_ARG, Py_None, 0L);
    }
    p = sfit_py_f32_value(po, 3, "parent");
    c = (p != NULL) ? sfit_py_f32_value(co, 3, "child") : NULL;
    pt = (c != NULL) ? sfit_py_f32_value(pto, 2, "parent template") : NULL;
    ct = (pt != NULL) ? sfit_py_f32_value(cto, 2, "child template") : NULL;
    if (ct == NULL) {
        goto done;
    }
    if (PyArray_DIM(p, 0) != PyArray_DIM(c, 0) || PyArray_DIM(p, 1) != PyArray_DIM(pt, 0)
        || PyArray_DIM(c, 1) != PyArray_DIM(ct, 0) || PyArray_DIM(p, 0) > (npy_intp)UINT32_MAX) {
        out = Py_BuildValue("(iOl)", (int)SFIT_E_ARG, Py_None, 0L);
        goto done;
    }
    cfg.method = (sfit_pair_method_t)method;
    cfg.mode = (sfit_pair_mode_t)mode;
    cfg.noise = (sfit_pair_noise_t)noise;
    cfg.marker_var = (float)var;
    st = template_of(pt, &pcl);
    if (st == SFIT_OK) {
        st = template_of(ct, &ccl);
    }
    s = (st == SFIT_OK) ? PyMem_Malloc(sizeof *s) : NULL;
    if (st == SFIT_OK && s == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    if (st == SFIT_OK) {
        st = sfit_pair_init(s, &pcl, &ccl, &cfg);
    }
    if (st == SFIT_OK) {
        const npy_intp nf = PyArray_DIM(p, 0), mp = PyArray_DIM(p, 1), mc = PyArray_DIM(c, 1);
        const sfit_vec3_t *pv = (const sfit_vec3_t *)PyArray_DATA(p);
        const sfit_vec3_t *cv = (const sfit_vec3_t *)PyArray_DATA(c);
        npy_intp f;
        Py_BEGIN_ALLOW_THREADS
        for (f = 0; f < nf; f++) {
            if (sfit_pair_add_markers(s, &pcl, pv + f * mp, (size_t)mp, &ccl, cv + f * mc,
                                      (size_t)mc) != SFIT_OK) {
                rejected++;
            }
        }
        Py_END_ALLOW_THREADS
        st = sfit_pair_solve(s, &r);
    }
    if (st != SFIT_OK) {
        out = Py_BuildValue("(iOl)", (int)st, Py_None, rejected);
    } else {
        PyObject *d = result_dict(&r);
        if (d != NULL) {
            out = Py_BuildValue("(iNl)", 0, d, rejected);
        }
    }
done:
    PyMem_Free(s);
    Py_XDECREF(p);
    Py_XDECREF(c);
    Py_XDECREF(pt);
    Py_XDECREF(ct);
    return out;
}
