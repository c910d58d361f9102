/* SPDX-License-Identifier: MIT */
/**
 * @file py_fit.c
 * @brief The fits over a caller's array (sfit_fit.h, sfit_multi.h,
 * sfit_gate.h, sfit_selfcal.h, sfit_refine.h, sfit_uncert.h): fit,
 * fit_multi, refine, residual_noise_var, uncertainty. Rows the library
 * rejects (NaN, Inf, |x| >= 2^SFIT_COORD_MAX_EXP) are skipped and counted,
 * as the CLI does with such lines; the GIL is released around the loops
 * over samples.
 */
#include "py_sfit.h"

#include <math.h>
#include <string.h>

#include "refine.h" /* the recipe's flat result as the CLI prints it: tools/lab */

PyObject *sfit_py_fit(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "noise_var", "noise_cov", "mode", "refine",
                             "planar_ratio", "gate", NULL};
    PyObject *points, *noise_var = Py_None, *noise_cov = Py_None, *mode = NULL, *gate = Py_None;
    int refine = 0, auto_noise;
    double planar_ratio = 0.0;
    sfit_fit_cfg_t cfg;
    sfit_py_pts_t p;
    sfit_moments_t acc;
    const sfit_vec3_t *v = NULL;
    sfit_vec3_t *own = NULL;
    size_t nv = 0;
    long rejected = 0, outliers = 0;
    sfit_status_t st;
    sfit_result_t r;
    sfit_uncert_t u;
    int has_u = 0, has_noise = 0, noise_est = 0, capped = 0, refined = 0;
    float nvar = 0.0f, rms = 0.0f;
    unsigned long iters = 0;
    float gate_k = 0.0f;
    PyObject *d;
    (void)self;

    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|OOOpdO", kwlist, &points, &noise_var,
                                     &noise_cov, &mode, &refine, &planar_ratio, &gate)) {
        return NULL;
    }
    auto_noise = sfit_py_is_auto(noise_var);
    if (sfit_py_cfg_get(auto_noise ? Py_None : noise_var, noise_cov, mode, planar_ratio, &cfg)
        < 0) {
        return NULL;
    }
    if (auto_noise && cfg.noise != SFIT_NOISE_NONE) {
        return sfit_py_raise_arg("give noise_var or noise_cov, not both");
    }
    if (gate != Py_None) {
        double k = PyFloat_AsDouble(gate);
        if ((k == -1.0 && PyErr_Occurred()) || !(k > 1.0) || !isfinite(k)) {
            PyErr_Clear();
            return sfit_py_raise_arg("gate must be a number K > 1 (sigmas)");
        }
        if (auto_noise || refine) {
            return sfit_py_raise_arg("gate does not combine with noise_var='auto' or refine=True");
        }
        gate_k = (float)k;
    }
    if (refine && cfg.noise != SFIT_NOISE_NONE) {
        return sfit_py_raise_arg("refine=True estimates the noise itself (self-calibrated start): "
                         "no noise_var / noise_cov");
    }
    if ((auto_noise || refine) && cfg.mode == SFIT_MODE_PLANAR) {
        return sfit_py_raise_arg(
            "noise_var='auto' and refine=True fit spheres (not mode='planar')");
    }
    if (sfit_py_pts_get(points, &p, "points", 0) < 0) {
        return NULL;
    }
    memset(&u, 0, sizeof u);
    if (gate_k > 0.0f) {
        /* the gate judges every sample: a rejected row is counted, an
         * outlier is counted separately */
        sfit_gate_cfg_t gc = sfit_gate_cfg_default;
        sfit_gate_t *g = (sfit_gate_t *)PyMem_Malloc(sizeof *g);
        sfit_gate_stats_t gs;
        size_t i;
        if (g == NULL) {
            sfit_py_pts_release(&p);
            return PyErr_NoMemory();
        }
        gc.fit = cfg;
        gc.k = gate_k;
        if (cfg.noise == SFIT_NOISE_ISO) {
            gc.noise_var = cfg.noise_var;
        }
        st = sfit_gate_init(g, &gc);
        if (st == SFIT_OK) {
            Py_BEGIN_ALLOW_THREADS
            for (i = 0; i < p.n; i++) {
                if (sfit_gate_add(g, &p.v[i], NULL) != SFIT_OK) {
                    rejected++;
                }
            }
            st = sfit_gate_fit(g, &r);
            Py_END_ALLOW_THREADS
            (void)sfit_gate_stats(g, &gs);
            outliers = (long)gs.outliers;
            if (st == SFIT_OK && cfg.noise == SFIT_NOISE_ISO && r.mode == SFIT_MODE_SPHERE
                && sfit_gate_moments(g) != NULL) {
                has_noise = 1;
                nvar = cfg.noise_var;
                has_u = (sfit_uncert_moments(sfit_gate_moments(g), &r.center, r.radius, nvar,
                                             SFIT_UNCERT_NOISE_KNOWN, &u) == SFIT_OK);
            }
        }
        PyMem_Free(g);
        nv = p.n - (size_t)rejected;
        sfit_py_pts_release(&p);
        if (st != SFIT_OK) {
            return sfit_py_raise_status(st, "fit", (long)nv - outliers, rejected);
        }
        nv = (size_t)r.n;
    } else {
        (void)sfit_moments_init(&acc);
        rejected = sfit_py_pts_filter(&p, &acc, &v, &own, &nv);
        if (rejected < 0) {
            sfit_py_pts_release(&p);
            return NULL;
        }
        Py_BEGIN_ALLOW_THREADS
        if (refine) {
            st = SFIT_OK; /* the recipe below makes its own start */
        } else if (auto_noise) {
            sfit_selfcal_result_t sc;
            sfit_selfcal_cfg_t scc = sfit_selfcal_cfg_default;
            scc.planar_ratio = cfg.planar_ratio;
            st = sfit_selfcal_points(v, nv, &scc, &sc);
            if (st == SFIT_OK) {
                r = sc.fit;
                has_noise = 1;
                nvar = sc.noise_var;
                noise_est = 1;
                iters = sc.iterations;
                capped = (sc.flags & SFIT_SELFCAL_FLAG_CAPPED) != 0u;
            }
        } else {
            st = sfit_fit_moments(&acc, &cfg, &r);
            if (st == SFIT_OK && cfg.noise == SFIT_NOISE_ISO) {
                has_noise = 1;
                nvar = cfg.noise_var;
            }
        }
        if (st == SFIT_OK && refine) {
            /* the library's recipe (sfit_refine_fit), one call and one flat
             * result, printed as the CLI prints it (cli_refine.h) */
            sfit_refine_result_t rf;
            sfit_refined_cfg_t rc = sfit_refined_cfg_default;
            rc.selfcal.planar_ratio = cfg.planar_ratio;
            st = sfit_refine_fit(v, nv, &rc, &rf);
            if (st == SFIT_OK) {
                refine_parts(&rf, &r, &u);
                refined = 1;
                has_noise = 1;
                nvar = rf.noise_var;
                noise_est = 1;
                iters = rf.iterations;
                rms = rf.rms;
                capped = (rf.flags & SFIT_SELFCAL_FLAG_CAPPED) != 0u;
                has_u = 1;
            }
        } else if (st == SFIT_OK && has_noise && r.mode == SFIT_MODE_SPHERE) {
            /* self-calibrated: its own sandwich (as sfit fit --noise-var auto) */
            has_u = noise_est ? (sfit_uncert_selfcal(v, nv, &r.center, r.radius, nvar,
                                                     &u) == SFIT_OK)
                              : (sfit_uncert_moments(&acc, &r.center, r.radius, nvar,
                                                     SFIT_UNCERT_NOISE_KNOWN, &u) == SFIT_OK);
        }
        Py_END_ALLOW_THREADS
        PyMem_RawFree(own);
        sfit_py_pts_release(&p);
        if (st != SFIT_OK) {
            return sfit_py_raise_status(st, "fit", (long)nv, rejected);
        }
    }
    d = PyDict_New();
    if (d == NULL || sfit_py_result_into(d, &r) < 0
        || sfit_py_put(d, "rejected", PyLong_FromLong(rejected)) < 0
        || sfit_py_put(d, "outliers", PyLong_FromLong(outliers)) < 0
        || sfit_py_put(d, "noise_var", has_noise ? sfit_py_flt(nvar) : Py_NewRef(Py_None)) < 0
        || sfit_py_put(d, "noise_estimated", PyBool_FromLong(noise_est)) < 0
        || sfit_py_put(d, "noise_capped", PyBool_FromLong(capped)) < 0
        || sfit_py_put(d, "iterations", PyLong_FromUnsignedLong(iters)) < 0
        || sfit_py_put(d, "rms", refined ? sfit_py_flt(rms) : Py_NewRef(Py_None)) < 0
        || (refined && sfit_py_put(d, "method", PyUnicode_FromString("geometric")) < 0)
        || (has_u && sfit_py_uncert_into(d, &u) < 0)) {
        Py_XDECREF(d);
        return NULL;
    }
    return d;
}

/* ------------------------------------------------------------------------ */
/* fit_multi()                                                              */
/* ------------------------------------------------------------------------ */

/* The most items fit_multi reads from a sequence: far more markers than
 * any cluster has, few enough that their states stay small (about 50 MB). */
#define PY_MULTI_MAX_ITEMS 262144

/* A tuple of the items of obj, read one by one from its iterator: the
 * tuple grows with the items actually read, never with what __len__ (or
 * __length_hint__) claims, and stops with an ArgError past max items. A
 * non-iterable obj or an error while iterating is an ArgError too. */
static PyObject *items_read(PyObject *obj, Py_ssize_t max, const char *what)
{
    PyObject *it, *list, *item, *tup;
    if (PyTuple_Check(obj) || PyList_Check(obj)) {
        if (PySequence_Fast_GET_SIZE(obj) > max) {
            return sfit_py_raise_arg("%s: more than %zd items", what, max);
        }
        return PySequence_Tuple(obj); /* the size is the items held */
    }
    it = PyObject_GetIter(obj);
    if (it == NULL) {
        PyErr_Clear();
        return sfit_py_raise_arg("%s must be a sequence of (N, 3) arrays", what);
    }
    list = PyList_New(0);
    if (list == NULL) {
        Py_DECREF(it);
        return NULL;
    }
    while ((item = PyIter_Next(it)) != NULL) {
        const int rc = (PyList_GET_SIZE(list) >= max) ? -2 : PyList_Append(list, item);
        Py_DECREF(item);
        if (rc != 0) {
            Py_DECREF(it);
            Py_DECREF(list);
            if (rc == -2) {
                return sfit_py_raise_arg("%s: more than %zd items", what, max);
            }
            return NULL;
        }
    }
    Py_DECREF(it);
    if (PyErr_Occurred()) {
        Py_DECREF(list);
        PyErr_Clear();
        return sfit_py_raise_arg("%s must be a sequence of (N, 3) arrays", what);
    }
    tup = PyList_AsTuple(list);
    Py_DECREF(list);
    return tup;
}

PyObject *sfit_py_fit_multi(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"markers", "noise_var", "noise_cov", "mode", "weight",
                             "planar_ratio", NULL};
    PyObject *markers, *noise_var = Py_None, *noise_cov = Py_None, *mode = NULL, *seq;
    const char *weight = "equal";
    double planar_ratio = 0.0;
    sfit_multi_cfg_t mc = sfit_multi_cfg_default;
    sfit_moments_t *acc = NULL;
    float *radii = NULL;
    long *rej = NULL;
    Py_ssize_t count, k;
    long rejected = 0;
    sfit_multi_result_t r;
    sfit_status_t st;
    PyObject *d = NULL, *ra = NULL, *na = NULL, *rja = NULL;
    (void)self;

    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|OOOsd", kwlist, &markers, &noise_var,
                                     &noise_cov, &mode, &weight, &planar_ratio)) {
        return NULL;
    }
    if (sfit_py_is_auto(noise_var)) {
        return sfit_py_raise_arg("fit_multi: noise_var='auto' is not supported (give a number)");
    }
    if (sfit_py_cfg_get(noise_var, noise_cov, mode, planar_ratio, &mc.fit) < 0) {
        return NULL;
    }
    if (sfit_py_weight_get(weight, &mc.weight) < 0) {
        return NULL;
    }
    if (PyArray_Check(markers) && PyArray_NDIM((PyArrayObject *)markers) != 3) {
        return sfit_py_raise_arg(
            "fit_multi: markers must be a list of (N, 3) arrays or one (M, N, 3) array");
    }
    /* a tuple of our own: PySequence_Fast would hand back the caller's list
     * itself, whose items an item's __array__ may remove while we use them */
    seq = items_read(markers, PY_MULTI_MAX_ITEMS, "fit_multi: markers");
    if (seq == NULL) {
        return NULL;
    }
    count = PyTuple_GET_SIZE(seq);
    if (count == 0) {
        Py_DECREF(seq);
        return sfit_py_raise_status(SFIT_E_TOO_FEW, "fit_multi", 0, 0);
    }
    acc = (sfit_moments_t *)PyMem_Calloc((size_t)count, sizeof *acc);
    radii = (float *)PyMem_Calloc((size_t)count, sizeof *radii);
    rej = (long *)PyMem_Calloc((size_t)count, sizeof *rej);
    if (acc == NULL || radii == NULL || rej == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    for (k = 0; k < count; k++) {
        sfit_py_pts_t p;
        const sfit_vec3_t *v;
        sfit_vec3_t *own;
        size_t nv;
        (void)sfit_moments_init(&acc[k]);
        if (sfit_py_pts_get(PyTuple_GET_ITEM(seq, k), &p, "fit_multi: markers[i]", 0) < 0) {
            goto done;
        }
        rej[k] = sfit_py_pts_filter(&p, &acc[k], &v, &own, &nv);
        PyMem_RawFree(own);
        sfit_py_pts_release(&p);
        if (rej[k] < 0) {
            goto done;
        }
        rejected += rej[k];
    }
    Py_BEGIN_ALLOW_THREADS
    st = sfit_multi_fit(acc, (size_t)count, &mc, &r, radii);
    Py_END_ALLOW_THREADS
    if (st != SFIT_OK) {
        long n = 0;
        for (k = 0; k < count; k++) {
            n += (long)sfit_moments_count(&acc[k]);
        }
        sfit_py_raise_status(st, "fit_multi", n, rejected);
        goto done;
    }
    {
        npy_intp dim = count;
        ra = PyArray_SimpleNew(1, &dim, NPY_FLOAT64);
        na = PyArray_SimpleNew(1, &dim, NPY_INT64);
        rja = PyArray_SimpleNew(1, &dim, NPY_INT64);
        if (ra == NULL || na == NULL || rja == NULL) {
            goto done;
        }
        for (k = 0; k < count; k++) {
            ((double *)PyArray_DATA((PyArrayObject *)ra))[k] = (double)radii[k];
            ((npy_int64 *)PyArray_DATA((PyArrayObject *)na))[k] =
                (npy_int64)sfit_moments_count(&acc[k]);
            ((npy_int64 *)PyArray_DATA((PyArrayObject *)rja))[k] = (npy_int64)rej[k];
        }
    }
    d = PyDict_New();
    if (d == NULL || sfit_py_multi_into(d, &r) < 0
        || sfit_py_put(d, "weight", PyUnicode_FromString(weight)) < 0
        || sfit_py_put(d, "rejected", PyLong_FromLong(rejected)) < 0
        || PyDict_SetItemString(d, "radii", ra) < 0 || PyDict_SetItemString(d, "marker_n", na) < 0
        || PyDict_SetItemString(d, "marker_rejected", rja) < 0) {
        Py_CLEAR(d);
    }
done:
    Py_XDECREF(ra);
    Py_XDECREF(na);
    Py_XDECREF(rja);
    Py_DECREF(seq);
    PyMem_Free(acc);
    PyMem_Free(radii);
    PyMem_Free(rej);
    return d;
}

/* ------------------------------------------------------------------------ */
/* Functions over a caller's array                                          */
/* ------------------------------------------------------------------------ */

/* Shared prologue: points -> valid rows. */
typedef struct valid {
    sfit_py_pts_t p;
    const sfit_vec3_t *v;
    sfit_vec3_t *own;
    size_t n;
    long rejected;
} valid_t;

static int valid_get(PyObject *points, valid_t *w, const char *what)
{
    if (sfit_py_pts_get(points, &w->p, what, 0) < 0) {
        return -1;
    }
    w->rejected = sfit_py_pts_filter(&w->p, NULL, &w->v, &w->own, &w->n);
    if (w->rejected < 0) {
        sfit_py_pts_release(&w->p);
        return -1;
    }
    return 0;
}

static void valid_release(valid_t *w)
{
    PyMem_RawFree(w->own);
    w->own = NULL;
    sfit_py_pts_release(&w->p);
}

PyObject *sfit_py_refine(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "center", "max_iters", "tol", NULL};
    PyObject *points, *center, *iters_o = NULL;
    unsigned long long max_iters = 0;
    double tol = 0.0;
    sfit_refine_cfg_t cfg = sfit_refine_cfg_default;
    sfit_vec3_t c0;
    sfit_refine_result_t r;
    sfit_status_t st;
    valid_t w;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|Od", kwlist, &points, &center, &iters_o,
                                     &tol)) {
        return NULL;
    }
    /* 0 = the library default; more than 1000 iterations are 1000 */
    if ((iters_o != NULL && sfit_py_count_get(iters_o, 1000u, &max_iters, "max_iters") < 0)
        || sfit_py_vec3_get(center, &c0, "center") < 0) {
        return NULL;
    }
    cfg.max_iters = (uint32_t)max_iters;
    cfg.tol = (float)tol;
    if (valid_get(points, &w, "points") < 0) {
        return NULL;
    }
    Py_BEGIN_ALLOW_THREADS
    st = sfit_refine_points(w.v, w.n, &c0, &cfg, &r);
    Py_END_ALLOW_THREADS
    valid_release(&w);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "refine", (long)w.n, w.rejected);
    }
    return Py_BuildValue("{s:N,s:N,s:N,s:N,s:k,s:k,s:l}", "center", sfit_py_vec3_out(r.center.v),
                         "radius", sfit_py_flt(r.radius), "rms", sfit_py_flt(r.rms), "noise_var",
                         sfit_py_flt(r.noise_var), "n", (unsigned long)r.n, "iterations",
                         (unsigned long)r.iterations, "rejected", w.rejected);
}

PyObject *sfit_py_residual_noise_var(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "center", "radius", NULL};
    PyObject *points, *center;
    double radius;
    sfit_vec3_t c;
    float nv;
    sfit_status_t st;
    valid_t w;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOd", kwlist, &points, &center, &radius)) {
        return NULL;
    }
    if (sfit_py_vec3_get(center, &c, "center") < 0 || valid_get(points, &w, "points") < 0) {
        return NULL;
    }
    Py_BEGIN_ALLOW_THREADS
    st = sfit_selfcal_noise_var(w.v, w.n, &c, (float)radius, &nv);
    Py_END_ALLOW_THREADS
    valid_release(&w);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "residual_noise_var", (long)w.n, w.rejected);
    }
    return sfit_py_flt(nv);
}

PyObject *sfit_py_uncertainty(PyObject *self, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "center", "radius", "noise_var", NULL};
    PyObject *points, *center, *nvo = Py_None, *d;
    double radius = 0.0;
    float nvar = 0.0f;
    sfit_vec3_t c;
    sfit_uncert_t u;
    sfit_status_t st;
    valid_t w;
    int geometric;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|dO", kwlist, &points, &center, &radius,
                                     &nvo)) {
        return NULL;
    }
    geometric = (nvo == Py_None);
    if (sfit_py_vec3_get(center, &c, "center") < 0
        || (!geometric && sfit_py_nonneg_get(nvo, &nvar, "noise_var") < 0)
        || valid_get(points, &w, "points") < 0) {
        return NULL;
    }
    Py_BEGIN_ALLOW_THREADS
    if (geometric) {
        st = sfit_uncert_geometric(w.v, w.n, &c, &u);
    } else {
        st = sfit_uncert_points(w.v, w.n, &c, (float)radius, nvar, &u);
    }
    Py_END_ALLOW_THREADS
    valid_release(&w);
    if (st != SFIT_OK) {
        return sfit_py_raise_status(st, "uncertainty", (long)w.n, w.rejected);
    }
    d = PyDict_New();
    if (d == NULL || sfit_py_uncert_into(d, &u) < 0) {
        Py_XDECREF(d);
        return NULL;
    }
    return d;
}

