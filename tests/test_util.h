/* SPDX-License-Identifier: MIT */
/**
 * @file test_util.h
 * @brief Header-only helpers for sfit tests and host tools (plain C99, no
 *        cmocka): deterministic PRNG, Gaussian noise, samplers on spherical
 *        caps and circular arcs, an x,y,z CSV loader, small vector helpers.
 *
 * Everything is `static inline`, so unused helpers raise no warnings.
 * The PRNG is splitmix64 (Steele, Lea, Flood 2014): 64-bit state, the same
 * sequence on every platform. Gaussian deviates use Marsaglia's polar
 * method (only sqrt and log from libm).
 */
#ifndef SFIT_TEST_UTIL_H
#define SFIT_TEST_UTIL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TU_PI 3.14159265358979323846

/** PRNG state (caller-owned, copyable). */
typedef struct {
    uint64_t s;     /**< splitmix64 state */
    int has_spare;  /**< a second polar-method deviate is cached */
    double spare;   /**< the cached deviate */
} tu_rng_t;

/* The byte of a bool (or any object) without loading it as a bool: for a
 * bool that holds a sentinel byte (an output written only on SFIT_OK) or a
 * garbage byte given to the library (sfit_types.h, "Yes/no"). */
static inline unsigned tu_byte(const void *p)
{
    unsigned char c;
    memcpy(&c, p, sizeof c);
    return c;
}

/* Store byte b into a bool (or any object): a value C cannot assign to a bool. */
static inline void tu_set_byte(void *p, unsigned b)
{
    const unsigned char c = (unsigned char)b;
    memcpy(p, &c, sizeof c);
}

static inline void tu_rng_seed(tu_rng_t *g, uint64_t seed)
{
    g->s = seed;
    g->has_spare = 0;
    g->spare = 0.0;
}

/** splitmix64: seed 0 gives 0xE220A8397B1DCDAF first. */
static inline uint64_t tu_rng_u64(tu_rng_t *g)
{
    uint64_t z = (g->s += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

/** Uniform double in [0, 1) with 53 random bits. */
static inline double tu_rng_uniform(tu_rng_t *g)
{
    return (double)(tu_rng_u64(g) >> 11) * (1.0 / 9007199254740992.0);
}

/** Standard normal deviate (Marsaglia polar method). */
static inline double tu_rng_gauss(tu_rng_t *g)
{
    double u, v, s, f;
    if (g->has_spare) {
        g->has_spare = 0;
        return g->spare;
    }
    do {
        u = 2.0 * tu_rng_uniform(g) - 1.0;
        v = 2.0 * tu_rng_uniform(g) - 1.0;
        s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    f = sqrt(-2.0 * log(s) / s);
    g->spare = v * f;
    g->has_spare = 1;
    return u * f;
}

static inline double tu_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline double tu_norm3(const double a[3])
{
    return sqrt(tu_dot3(a, a));
}

/** e^T P^-1 e for a symmetric 3x3 P, row-major (sfit_mat3_t::m: every
 *  covariance of the API; the lower triangle is read), by a double Cholesky
 *  factor; -1 when P is not positive definite. */
static inline double tu_mahal(const float p[9], const double e[3])
{
    double l[3][3] = {{0.0}}, y[3], d2 = 0.0;
    int i, j, k;
    for (j = 0; j < 3; ++j) {
        double s = (double)p[3 * j + j];
        for (k = 0; k < j; ++k) {
            s -= l[j][k] * l[j][k];
        }
        if (!(s > 0.0)) {
            return -1.0;
        }
        l[j][j] = sqrt(s);
        for (i = j + 1; i < 3; ++i) {
            double t = (double)p[3 * i + j];
            for (k = 0; k < j; ++k) {
                t -= l[i][k] * l[j][k];
            }
            l[i][j] = t / l[j][j];
        }
    }
    for (i = 0; i < 3; ++i) {
        double t = e[i];
        for (k = 0; k < i; ++k) {
            t -= l[i][k] * y[k];
        }
        y[i] = t / l[i][i];
        d2 += y[i] * y[i];
    }
    return d2;
}

static inline double tu_dist3(const double a[3], const double b[3])
{
    double d[3];
    d[0] = a[0] - b[0];
    d[1] = a[1] - b[1];
    d[2] = a[2] - b[2];
    return tu_norm3(d);
}

static inline void tu_cross3(const double a[3], const double b[3], double o[3])
{
    double t[3];
    t[0] = a[1] * b[2] - a[2] * b[1];
    t[1] = a[2] * b[0] - a[0] * b[2];
    t[2] = a[0] * b[1] - a[1] * b[0];
    o[0] = t[0];
    o[1] = t[1];
    o[2] = t[2];
}

/** Orthonormal frame: n = axis normalised, e1, e2 perpendicular to it,
 *  (e1, e2, n) right-handed. Deterministic (no randomness). */
static inline void tu_frame(const double axis[3], double n[3], double e1[3],
                            double e2[3])
{
    double len = tu_norm3(axis), t[3] = {0.0, 0.0, 0.0};
    int i, k = 0;
    for (i = 0; i < 3; ++i) {
        n[i] = axis[i] / len;
    }
    /* the coordinate axis least aligned with n */
    for (i = 1; i < 3; ++i) {
        if (fabs(n[i]) < fabs(n[k])) {
            k = i;
        }
    }
    t[k] = 1.0;
    tu_cross3(n, t, e1);
    len = tu_norm3(e1);
    for (i = 0; i < 3; ++i) {
        e1[i] /= len;
    }
    tu_cross3(n, e1, e2);
}

/** Adds isotropic Gaussian noise of std sigma to p. */
/* Rotation matrix (row-major) of angle ang about the axis ax (any length). */
static inline void tu_rot_axis_angle(const double ax[3], double ang, double r[9])
{
    const double n = tu_norm3(ax), c = cos(ang), s = sin(ang), C = 1.0 - c;
    const double a0 = ax[0] / n, a1 = ax[1] / n, a2 = ax[2] / n;
    r[0] = c + a0 * a0 * C;
    r[1] = a0 * a1 * C - a2 * s;
    r[2] = a0 * a2 * C + a1 * s;
    r[3] = a1 * a0 * C + a2 * s;
    r[4] = c + a1 * a1 * C;
    r[5] = a1 * a2 * C - a0 * s;
    r[6] = a2 * a0 * C - a1 * s;
    r[7] = a2 * a1 * C + a0 * s;
    r[8] = c + a2 * a2 * C;
}

static inline void tu_add_noise(tu_rng_t *g, double sigma, double p[3])
{
    int i;
    if (sigma > 0.0) {
        for (i = 0; i < 3; ++i) {
            p[i] += sigma * tu_rng_gauss(g);
        }
    }
}

/** A point uniform on the spherical cap of half-angle theta (radians)
 *  around axis (any length), centre c, radius r, plus isotropic Gaussian
 *  noise of std sigma. theta = pi: the whole sphere. Uniform on the cap:
 *  cos(polar) ~ U[cos theta, 1], azimuth ~ U[0, 2 pi). */
static inline void tu_sample_cap(tu_rng_t *g, const double c[3], double r,
                                 const double axis[3], double theta,
                                 double sigma, double out[3])
{
    double n[3], e1[3], e2[3], h, omz, z, sp, phi;
    int i;
    tu_frame(axis, n, e1, e2);
    h = 2.0 * sin(0.5 * theta) * sin(0.5 * theta); /* 1 - cos theta */
    omz = tu_rng_uniform(g) * h;                   /* 1 - z, exact-ish */
    z = 1.0 - omz;
    sp = sqrt(omz * (2.0 - omz));                  /* sqrt(1 - z^2) */
    phi = 2.0 * TU_PI * tu_rng_uniform(g);
    for (i = 0; i < 3; ++i) {
        out[i] = c[i] + r * (z * n[i] + sp * (cos(phi) * e1[i] +
                                              sin(phi) * e2[i]));
    }
    tu_add_noise(g, sigma, out);
}

/** A point uniform on the circular arc of half-angle theta, centre c,
 *  radius r, in the plane normal to axis, centred on the in-plane
 *  direction of ref_dir (its component along axis is removed), plus
 *  isotropic 3-D Gaussian noise of std sigma. theta = pi: full circle. */
static inline void tu_sample_arc(tu_rng_t *g, const double c[3], double r,
                                 const double axis[3], const double ref_dir[3],
                                 double theta, double sigma, double out[3])
{
    double n[3], u[3], w[3], len, a, ca, sa;
    int i;
    len = tu_norm3(axis);
    for (i = 0; i < 3; ++i) {
        n[i] = axis[i] / len;
    }
    len = tu_dot3(ref_dir, n);
    for (i = 0; i < 3; ++i) {
        u[i] = ref_dir[i] - len * n[i];
    }
    len = tu_norm3(u);
    for (i = 0; i < 3; ++i) {
        u[i] /= len;
    }
    tu_cross3(n, u, w);
    a = theta * (2.0 * tu_rng_uniform(g) - 1.0);
    ca = cos(a);
    sa = sin(a);
    for (i = 0; i < 3; ++i) {
        out[i] = c[i] + r * (ca * u[i] + sa * w[i]);
    }
    tu_add_noise(g, sigma, out);
}

/** Reads an "x,y,z" CSV (one header line; a first line that parses as
 *  three numbers is taken as data). Blank lines are skipped, CR/LF
 *  tolerated. Returns 0 on success, -1 if the file cannot be opened, -2 on
 *  a malformed line, -3 if there are more than cap rows (then *n = cap and
 *  out holds the first cap rows). */
static inline int tu_load_csv(const char *path, double (*out)[3], size_t cap,
                              size_t *n)
{
    char line[512];
    FILE *f;
    size_t cnt = 0;
    int first = 1, rc = 0;

    *n = 0;
    f = fopen(path, "r");
    if (f == NULL) {
        return -1;
    }
    while (fgets(line, (int)sizeof line, f) != NULL) {
        double v[3];
        char *p = line, *end;
        int k, ok = 1;
        if (strchr(line, '\n') == NULL && !feof(f)) {
            rc = -2; /* line too long */
            break;
        }
        while (*p == ' ' || *p == '\t') {
            ++p;
        }
        if (*p == '\n' || *p == '\r' || *p == '\0') {
            continue;
        }
        for (k = 0; k < 3 && ok; ++k) {
            v[k] = strtod(p, &end);
            if (end == p) {
                ok = 0;
                break;
            }
            p = end;
            while (*p == ' ' || *p == '\t') {
                ++p;
            }
            if (k < 2) {
                if (*p != ',') {
                    ok = 0;
                } else {
                    ++p;
                }
            }
        }
        if (ok && *p != '\n' && *p != '\r' && *p != '\0') {
            ok = 0;
        }
        if (!ok) {
            if (first) {
                first = 0; /* header */
                continue;
            }
            rc = -2;
            break;
        }
        first = 0;
        if (cnt == cap) {
            rc = -3;
            break;
        }
        out[cnt][0] = v[0];
        out[cnt][1] = v[1];
        out[cnt][2] = v[2];
        ++cnt;
    }
    fclose(f);
    *n = cnt;
    return rc;
}

#endif /* SFIT_TEST_UTIL_H */
