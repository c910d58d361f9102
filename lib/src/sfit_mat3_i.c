/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_mat3_i.c
 * @brief Internal 3x3 layer (sfit_mat3_i.h): packed symmetric storage,
 * forward substitution, the SPD inverse from a Cholesky factor, products.
 */
#include "sfit_mat3_i.h"

void sfit_i_sym_unpack(const float p[6], sfit_mat3_t *a)
{
    a->m[0] = p[0]; a->m[1] = p[3]; a->m[2] = p[4];
    a->m[3] = p[3]; a->m[4] = p[1]; a->m[5] = p[5];
    a->m[6] = p[4]; a->m[7] = p[5]; a->m[8] = p[2];
}

void sfit_i_sym_full(const sfit_mat3_t *a, float A[9])
{
    A[0] = a->m[0]; A[4] = a->m[4]; A[8] = a->m[8];
    A[1] = a->m[3]; A[3] = a->m[3];
    A[2] = a->m[6]; A[6] = a->m[6];
    A[5] = a->m[7]; A[7] = a->m[7];
}

void sfit_i_sym_pack(const sfit_mat3_t *a, float p[6])
{
    p[0] = a->m[0];
    p[1] = a->m[4];
    p[2] = a->m[8];
    p[3] = 0.5f * (a->m[1] + a->m[3]);
    p[4] = 0.5f * (a->m[2] + a->m[6]);
    p[5] = 0.5f * (a->m[5] + a->m[7]);
}

void sfit_i_chol_forward(const sfit_mat3_t *l, const float b[3], float y[3])
{
    const float *L = l->m;
    y[0] = b[0] / L[0];
    y[1] = (b[1] - L[3] * y[0]) / L[4];
    y[2] = (b[2] - L[6] * y[0] - L[7] * y[1]) / L[8];
}

void sfit_i_chol_inverse(const sfit_mat3_t *l, sfit_mat3_t *inv)
{
    float p[6];
    int j;
    for (j = 0; j < 3; j++) {
        sfit_vec3_t e = {{0.0f, 0.0f, 0.0f}}, x = {{0.0f, 0.0f, 0.0f}};
        e.v[j] = 1.0f;
        sfit_i_chol_solve(l, e.v, x.v);
        inv->m[j] = x.v[0];
        inv->m[3 + j] = x.v[1];
        inv->m[6 + j] = x.v[2];
    }
    sfit_i_sym_pack(inv, p);
    sfit_i_sym_unpack(p, inv);
}

void sfit_i_mat3_vec(const sfit_mat3_t *a, const float x[3], float y[3])
{
    int i;
    for (i = 0; i < 3; i++) {
        y[i] = sfit_i_dot3(&a->m[3 * i], x);
    }
}

void sfit_i_mat3_mul(const sfit_mat3_t *a, const sfit_mat3_t *b, sfit_mat3_t *p)
{
    int i, j;
    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++) {
            p->m[3 * i + j] = a->m[3 * i] * b->m[j] + a->m[3 * i + 1] * b->m[3 + j]
                              + a->m[3 * i + 2] * b->m[6 + j];
        }
    }
}

void sfit_i_spread(const sfit_vec3_t *p, uint32_t count, const float c[3], sfit_mat3_t *j)
{
    uint32_t i;
    int a, b;
    memset(j, 0, sizeof *j);
    for (i = 0; i < count; i++) {
        float q[3], q2;
        for (a = 0; a < 3; a++) {
            q[a] = p[i].v[a] - c[a];
        }
        q2 = sfit_i_dot3(q, q);
        for (a = 0; a < 3; a++) {
            for (b = 0; b < 3; b++) {
                j->m[3 * a + b] += ((a == b) ? q2 : 0.0f) - q[a] * q[b];
            }
        }
    }
}
