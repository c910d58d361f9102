/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_kernels.c
 * @brief libFuzzer harness for the stateless entry points: the 3x3 kernels
 * (Cholesky, its solve, Jacobi) and the noise / coverage design aids, fed
 * arbitrary floats. Contract: a defined status; outputs untouched on
 * failure; finite outputs on success; for the Cholesky factor, the upper
 * triangle zero and a positive diagonal; Jacobi eigenvalues ascending with
 * orthonormal eigenvectors that reconstruct the matrix (checked only where
 * the matrix is moderate, so that the residual bound is meaningful).
 *
 * Program: [opcode][operands]... as in fuzz_stream.c.
 */
#include "fuzz_common.h"

#define FZ_MAX_OPS 128

static void fz_matrix(fz_in_t *in, sfit_mat3_t *a)
{
    const uint8_t b = fz_u8(in);
    int r, c;
    for (r = 0; r < 3; r++) {
        for (c = 0; c <= r; c++) {
            const float x = fz_float(in);
            a->m[3 * r + c] = x;
            a->m[3 * c + r] = x;
        }
    }
    if ((b & 1u) != 0u) { /* an asymmetric upper triangle: must be ignored */
        a->m[1] = fz_float(in);
    }
    if ((b & 2u) != 0u) { /* make it SPD-ish: add a multiple of I */
        const float d = fabsf(fz_float(in));
        a->m[0] += d;
        a->m[4] += d;
        a->m[8] += d;
    }
}

/* The symmetric matrix the kernels see: the lower triangle of a. */
static void fz_lower(const sfit_mat3_t *a, sfit_mat3_t *s)
{
    int r, c;
    for (r = 0; r < 3; r++) {
        for (c = 0; c <= r; c++) {
            s->m[3 * r + c] = a->m[3 * r + c];
            s->m[3 * c + r] = a->m[3 * r + c];
        }
    }
}

static float fz_mat_max(const sfit_mat3_t *a)
{
    float big = 0.0f;
    int k;
    for (k = 0; k < 9; k++) {
        if (fabsf(a->m[k]) > big) {
            big = fabsf(a->m[k]);
        }
    }
    return big;
}

static void fz_chol(fz_in_t *in)
{
    sfit_mat3_t a, l, before;
    sfit_vec3_t b, x;
    sfit_status_t st;
    int k;
    fz_matrix(in, &a);
    memcpy(&before, &a, sizeof before);
    memset(&l, FZ_SENTINEL, sizeof l);
    st = sfit_mat3_chol(&a, &l);
    FZ_CHECK_OUT(st, l, "sfit_mat3_chol");
    FZ_CHECK(st == SFIT_OK || st == SFIT_E_NOT_POSDEF, "chol: status");
    FZ_CHECK(memcmp(&before, &a, sizeof a) == 0, "chol modified its input");
    if (st != SFIT_OK) {
        return;
    }
    FZ_CHECK(fz_all_finite(l.m, 9), "chol: non-finite factor");
    FZ_CHECK(l.m[1] == 0.0f && l.m[2] == 0.0f && l.m[5] == 0.0f, "chol: upper triangle not zero");
    FZ_CHECK(l.m[0] > 0.0f && l.m[4] > 0.0f && l.m[8] > 0.0f, "chol: diagonal not positive");
    for (k = 0; k < 3; k++) {
        b.v[k] = fz_float(in);
    }
    memset(&x, FZ_SENTINEL, sizeof x);
    st = sfit_mat3_chol_solve(&l, &b, &x);
    /* A finite solution, or SFIT_E_RANGE (non-finite b, overflow) with x
     * untouched. */
    FZ_CHECK(st == SFIT_OK || st == SFIT_E_RANGE, "chol_solve: status with valid pointers");
    FZ_CHECK_OUT(st, x, "chol_solve");
    FZ_CHECK(st != SFIT_OK || fz_all_finite(x.v, 3), "chol_solve: OK with a non-finite x");
    {
        /* Aliasing allowed: x may be b (b untouched on failure). */
        const sfit_vec3_t b0 = b;
        const sfit_status_t sa = sfit_mat3_chol_solve(&l, &b, &b);
        FZ_CHECK(sa == st, "chol_solve: aliased status");
        FZ_CHECK(sa == SFIT_OK ? memcmp(&x, &b, sizeof x) == 0 : memcmp(&b0, &b, sizeof b) == 0,
                 "chol_solve: aliased result differs");
    }
    /* chol(a, a): in place. */
    st = sfit_mat3_chol(&a, &a);
    FZ_CHECK(st == SFIT_OK && memcmp(&a, &l, sizeof a) == 0, "chol: in-place result differs");
}

static void fz_eig(fz_in_t *in)
{
    sfit_mat3_t a, v, before;
    sfit_vec3_t w;
    sfit_status_t st;
    const int want_v = (fz_u8(in) & 1u) == 0u;
    int i, j, k;
    fz_matrix(in, &a);
    memcpy(&before, &a, sizeof before);
    memset(&w, FZ_SENTINEL, sizeof w);
    memset(&v, FZ_SENTINEL, sizeof v);
    st = sfit_mat3_eig_sym(&a, &w, want_v ? &v : NULL);
    FZ_CHECK_OUT(st, w, "sfit_mat3_eig_sym (w)");
    FZ_CHECK(memcmp(&before, &a, sizeof a) == 0, "eig modified its input");
    if (st != SFIT_OK || !want_v) {
        FZ_CHECK(fz_untouched(&v, sizeof v), "eig wrote v on failure / when not asked");
    }
    fz_lower(&before, &a); /* from here on, a is what the kernel read */
    if (!fz_all_finite(a.m, 9)) {
        FZ_CHECK(st == SFIT_E_NONFINITE, "eig: NaN/Inf input not reported");
        return;
    }
    /* SFIT_E_RANGE: a rotation overflowed (entries near FLT_MAX). */
    FZ_CHECK(st == SFIT_OK || st == SFIT_E_NO_CONVERGENCE || st == SFIT_E_RANGE,
             "eig: status on a finite matrix");
    if (st != SFIT_OK) {
        return;
    }
    FZ_CHECK(fz_all_finite(w.v, 3), "eig: non-finite eigenvalue");
    FZ_CHECK(w.v[0] <= w.v[1] && w.v[1] <= w.v[2], "eig: not ascending");
    if (!want_v) {
        return;
    }
    FZ_CHECK(fz_all_finite(v.m, 9), "eig: non-finite eigenvector");
    /* Orthonormality (in double) and reconstruction, relative to max|a|,
     * where neither can overflow or drown in subnormals. */
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            double d = 0.0;
            for (k = 0; k < 3; k++) {
                d += (double)v.m[3 * k + i] * (double)v.m[3 * k + j];
            }
            FZ_CHECK(fabs(d - ((i == j) ? 1.0 : 0.0)) < 1e-5, "eig: V not orthonormal");
        }
    }
    {
        const float big = fz_mat_max(&a);
        if (big > 1e-30f && big < 1e30f) {
            for (i = 0; i < 3; i++) {
                for (j = 0; j < 3; j++) {
                    double d = 0.0;
                    for (k = 0; k < 3; k++) {
                        d += (double)v.m[3 * i + k] * (double)w.v[k] * (double)v.m[3 * j + k];
                    }
                    /* only the lower triangle is the input */
                    if (j <= i && fabs(d - (double)a.m[3 * i + j]) > 1e-5 * (double)big) {
                        (void)fprintf(stderr, "eig residual %g at (%d,%d), max|a| %g\n",
                                      fabs(d - (double)a.m[3 * i + j]), i, j, (double)big);
                        FZ_CHECK(0, "eig: V diag(w) V^T differs from A");
                    }
                }
            }
        }
    }
}

static void fz_coverage(fz_in_t *in)
{
    const uint8_t b = fz_u8(in);
    const sfit_coverage_kind_t kind = (sfit_coverage_kind_t)(b % 3u); /* 2 is invalid */
    const float theta = ((b & 4u) != 0u) ? fz_float(in) : ldexpf((float)fz_u8(in), -6); /* 0..4 */
    const float r = ((b & 8u) != 0u) ? fz_float(in) : 100.0f;
    float lmin, lmax, sg, th;
    sfit_vec3_t eig;
    sfit_status_t st;
    int k;

    memset(&lmin, FZ_SENTINEL, sizeof lmin);
    memset(&lmax, FZ_SENTINEL, sizeof lmax);
    st = sfit_coverage_eigs(kind, theta, r, &lmin, &lmax);
    FZ_CHECK_OUT(st, lmin, "sfit_coverage_eigs");
    FZ_CHECK_OUT(st, lmax, "sfit_coverage_eigs");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_finite(lmin) && fz_finite(lmax), "coverage_eigs: non-finite");
        FZ_CHECK(lmin >= 0.0f && lmin <= lmax * 1.000001f, "coverage_eigs: lmin > lmax or negative");
        FZ_CHECK(kind == SFIT_COVERAGE_CAP || kind == SFIT_COVERAGE_ARC, "coverage_eigs: bad kind accepted");
    } else if (!fz_finite(theta) || !fz_finite(r)) {
        FZ_CHECK(st == SFIT_E_NONFINITE || st == SFIT_E_ARG, "coverage_eigs: non-finite input");
    } else {
        /* E_ARG or E_RANGE */
    }
    if ((b & 16u) != 0u) {
        st = sfit_coverage_cap_eigs(theta, r, &lmin, NULL);
        FZ_CHECK(fz_status_defined(st), "cap_eigs: status");
        st = sfit_coverage_arc_eigs(theta, r, NULL, &lmax);
        FZ_CHECK(fz_status_defined(st), "arc_eigs: status");
    }
    memset(&sg, FZ_SENTINEL, sizeof sg);
    st = sfit_coverage_max_sigma(kind, theta, r, &sg);
    FZ_CHECK_OUT(st, sg, "sfit_coverage_max_sigma");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_finite(sg) && sg >= 0.0f, "max_sigma: bad value");
    }
    memset(&th, FZ_SENTINEL, sizeof th);
    st = sfit_coverage_min_theta(kind, ((b & 32u) != 0u) ? fz_float(in) : ldexpf((float)fz_u8(in), -9), &th);
    FZ_CHECK_OUT(st, th, "sfit_coverage_min_theta");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_finite(th) && th >= 0.0f && th <= 3.1416f, "min_theta: outside [0, pi]");
    }
    for (k = 0; k < 3; k++) {
        eig.v[k] = fz_float(in);
    }
    if ((b & 64u) != 0u) { /* sort, so that the ordering check passes more often */
        float t;
        if (eig.v[0] > eig.v[1]) { t = eig.v[0]; eig.v[0] = eig.v[1]; eig.v[1] = t; }
        if (eig.v[1] > eig.v[2]) { t = eig.v[1]; eig.v[1] = eig.v[2]; eig.v[2] = t; }
        if (eig.v[0] > eig.v[1]) { t = eig.v[0]; eig.v[0] = eig.v[1]; eig.v[1] = t; }
    }
    memset(&th, FZ_SENTINEL, sizeof th);
    st = sfit_coverage_estimate_theta(kind, &eig, &th);
    FZ_CHECK_OUT(st, th, "sfit_coverage_estimate_theta");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_finite(th) && th > 0.0f && th <= 3.1416f, "estimate_theta: outside (0, pi]");
    }
}

static void fz_calib_std(fz_in_t *in)
{
    const float var = fz_float(in);
    const float r0 = fz_float(in);
    const uint32_t n = fz_u32(in);
    float sd;
    sfit_status_t st;
    memset(&sd, FZ_SENTINEL, sizeof sd);
    st = sfit_noise_calib_std(var, r0, n, &sd);
    FZ_CHECK_OUT(st, sd, "sfit_noise_calib_std");
    if (st == SFIT_OK) {
        FZ_CHECK(fz_finite(sd) && sd >= 0.0f, "calib_std: bad value");
    }
    FZ_CHECK(sfit_noise_calib_std(var, r0, n, NULL) != SFIT_OK, "calib_std(NULL) succeeded");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fz_in_t in;
    int ops = 0;
    in.p = data;
    in.n = size;
    in.i = 0u;
    while (fz_more(&in) && ops < FZ_MAX_OPS) {
        const uint8_t op = fz_u8(&in);
        switch (op % 5u) {
        case 0:
            fz_chol(&in);
            break;
        case 1:
            fz_eig(&in);
            break;
        case 2:
            fz_coverage(&in);
            break;
        case 3:
            fz_calib_std(&in);
            break;
        default: {
            const char *name = sfit_status_str((sfit_status_t)(int8_t)fz_u8(&in));
            FZ_CHECK(name != NULL && name[0] != '\0', "status_str");
            break;
        }
        }
        ops++;
    }
    return 0;
}
