/* SPDX-License-Identifier: MIT */
/** @file json_out.c  JSON pieces to any FILE * (json_out.h). */
#include "json_out.h"

void json_out_str(FILE *f, const char *s, unsigned opts)
{
    const unsigned char *c = (const unsigned char *)s;
    fputc('"', f);
    for (; *c != '\0'; c++) {
        if (*c == '"' || *c == '\\') {
            fputc('\\', f);
            fputc(*c, f);
        } else if (*c == '<' && (opts & JSON_OUT_HTML) != 0u) {
            fputs("\\u003c", f);
        } else if (*c < 0x20u) {
            fprintf(f, "\\u%04x", (unsigned)*c);
        } else {
            fputc(*c, f);
        }
    }
    fputc('"', f);
}

void json_out_vec(FILE *f, const float *v)
{
    fprintf(f, "[%.9g,%.9g,%.9g]", (double)v[0], (double)v[1], (double)v[2]);
}

void json_out_vecd(FILE *f, const double *v)
{
    fprintf(f, "[%.9g,%.9g,%.9g]", v[0], v[1], v[2]);
}

void json_out_mat(FILE *f, const sfit_mat3_t *m)
{
    int r;
    fputc('[', f);
    for (r = 0; r < 3; r++) {
        if (r > 0) {
            fputc(',', f);
        }
        json_out_vec(f, &m->m[3 * r]);
    }
    fputc(']', f);
}

void json_out_matd(FILE *f, const double m[3][3])
{
    int r;
    fputc('[', f);
    for (r = 0; r < 3; r++) {
        if (r > 0) {
            fputc(',', f);
        }
        json_out_vecd(f, m[r]);
    }
    fputc(']', f);
}

void json_out_flags(FILE *f, uint32_t flags, const json_out_flag_t *tab, size_t n)
{
    const char *sep = "";
    size_t k;
    fputc('[', f);
    for (k = 0; k < n; k++) {
        if ((flags & tab[k].bit) != 0u) {
            fprintf(f, "%s\"%s\"", sep, tab[k].name);
            sep = ",";
        }
    }
    fputc(']', f);
}
