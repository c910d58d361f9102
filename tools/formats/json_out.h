/* SPDX-License-Identifier: MIT */
/**
 * @file json_out.h
 * @brief The JSON pieces every host writer shares, to any FILE *: the one
 * string escaper, float vectors and matrices at round-trip precision, a
 * flag list from a (bit, name) table. Host only.
 */
#ifndef SFIT_JSON_OUT_H
#define SFIT_JSON_OUT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "sfit/sfit_types.h"

/** json_out_str option: also write '<' as \u003c (a string inside an HTML <script>). */
#define JSON_OUT_HTML 1u

/**
 * Write `s` as a JSON string literal: quotes, backslashes and control
 * characters escaped (\u00XX), every other byte as is (UTF-8 passes).
 */
void json_out_str(FILE *f, const char *s, unsigned opts);

/** A JSON array of 3 floats, [%.9g,%.9g,%.9g]. */
void json_out_vec(FILE *f, const float *v);

/** A JSON array of 3 doubles, [%.9g,%.9g,%.9g]. */
void json_out_vecd(FILE *f, const double *v);

/** A 3x3 float matrix as the JSON array of its 3 rows. */
void json_out_mat(FILE *f, const sfit_mat3_t *m);

/** A 3x3 double matrix as the JSON array of its 3 rows. */
void json_out_matd(FILE *f, const double m[3][3]);

/** One flag of a name table: a bit and its JSON name. */
typedef struct json_out_flag {
    uint32_t bit;
    const char *name;
} json_out_flag_t;

/** The JSON array of the names of the bits of `flags` that `tab` names, in table order. */
void json_out_flags(FILE *f, uint32_t flags, const json_out_flag_t *tab, size_t n);

#endif /* SFIT_JSON_OUT_H */
