/* SPDX-License-Identifier: MIT */
/**
 * @file cmd_imu.c
 * @brief `sfit imu-joint`: the joint between two IMUs (sfit_imu.h) from a
 * CSV of both sensors' specific force and angular rate.
 *
 *   sfit imu-joint [--json] FILE.csv
 *
 * Header: time,acc1_x,acc1_y,acc1_z,gyr1_x,gyr1_y,gyr1_z,acc2_x,...,gyr2_z
 * (any order; s, m/s^2, rad/s). The rate is the mean sample rate of the
 * time column, which must increase evenly.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "names.h"
#include "sfit/sfit_imu.h"

#define IMU_NCOL 13
#define IMU_RATE_TOL 0.05 /* largest relative spread of the sample interval */

static const char *const imu_cols[IMU_NCOL] = {
    "time",   "acc1_x", "acc1_y", "acc1_z", "gyr1_x", "gyr1_y", "gyr1_z",
    "acc2_x", "acc2_y", "acc2_z", "gyr2_x", "gyr2_y", "gyr2_z"};

static void imu_usage(FILE *f)
{
    fputs("usage: sfit imu-joint [--json] FILE.csv\n"
          "  The joint between two IMUs on two segments: the joint centre in each\n"
          "  sensor's frame (ball) or the hinge axis and its point nearest each sensor.\n"
          "  FILE.csv: comma-separated, a header naming the 13 columns\n"
          "    time,acc1_x,acc1_y,acc1_z,gyr1_x,gyr1_y,gyr1_z,\n"
          "    acc2_x,acc2_y,acc2_z,gyr2_x,gyr2_y,gyr2_z\n"
          "  (s, m/s^2, rad/s; any order), evenly sampled; '-' reads stdin.\n"
          "  --json   one JSON object on stdout\n",
          f);
}

typedef struct imu_rows {
    double *v; /* IMU_NCOL per row, in imu_cols order */
    size_t n, cap;
} imu_rows_t;

static int imu_fail(int json, const char *status, const char *fmt, const char *a,
                    unsigned long line)
{
    char msg[256];
    snprintf(msg, sizeof msg, fmt, a, line);
    if (json) {
        printf("{\"status\":");
        json_out_str(stdout, status, 0);
        printf(",\"message\":");
        json_out_str(stdout, msg, 0);
        printf("}\n");
    } else {
        fprintf(stderr, "sfit imu-joint: %s\n", msg);
    }
    return CLI_IO;
}

static char *imu_trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t') {
        s++;
    }
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' || e[-1] == '\n')) {
        *--e = '\0';
    }
    return s;
}

/* Read the whole file; 0 or the exit status (after the message). */
static int imu_read(FILE *fp, int json, imu_rows_t *rows)
{
    char line[CLI_LINE_MAX];
    int map[IMU_NCOL], seen[IMU_NCOL] = {0}, ncol = 0, k;
    unsigned long ln = 1;
    if (fgets(line, sizeof line, fp) == NULL) {
        return imu_fail(json, "format_error", "%sempty file (line %lu)", "", ln);
    }
    {
        char *tok = strtok(line, ",");
        while (tok != NULL) {
            char *name = imu_trim(tok);
            int found = -1;
            for (k = 0; k < IMU_NCOL; k++) {
                if (strcmp(name, imu_cols[k]) == 0) {
                    found = k;
                }
            }
            if (found < 0) {
                return imu_fail(json, "format_error", "unknown column '%s' (line %lu)", name,
                                ln);
            }
            if (seen[found] || ncol >= IMU_NCOL) {
                return imu_fail(json, "format_error", "column '%s' twice (line %lu)", name, ln);
            }
            seen[found] = 1;
            map[ncol++] = found;
            tok = strtok(NULL, ",");
        }
    }
    for (k = 0; k < IMU_NCOL; k++) {
        if (!seen[k]) {
            return imu_fail(json, "format_error", "missing column '%s' (line %lu)",
                            imu_cols[k], ln);
        }
    }
    while (fgets(line, sizeof line, fp) != NULL) {
        double row[IMU_NCOL];
        char *p = line;
        ln++;
        if (imu_trim(line)[0] == '\0') {
            continue;
        }
        for (k = 0; k < IMU_NCOL; k++) {
            char *end;
            errno = 0;
            row[map[k]] = strtod(p, &end);
            if (end == p) {
                return imu_fail(json, "format_error", "column '%s': not a number (line %lu)",
                                imu_cols[map[k]], ln);
            }
            if (!isfinite(row[map[k]])) {
                return imu_fail(json, "format_error",
                                "column '%s': not a finite number (line %lu)",
                                imu_cols[map[k]], ln);
            }
            while (*end == ' ' || *end == '\t') {
                end++;
            }
            if (k + 1 < IMU_NCOL ? *end != ',' : (*end != '\0' && *end != '\r' && *end != '\n')) {
                return imu_fail(json, "format_error", "%sexpected 13 comma-separated values "
                                "(line %lu)", "", ln);
            }
            p = end + 1;
        }
        if (rows->n > 0 && !(row[0] > rows->v[(rows->n - 1) * IMU_NCOL])) {
            return imu_fail(json, "format_error", "%stime does not increase (line %lu)", "",
                            ln);
        }
        if (rows->n == rows->cap) {
            const size_t cap = rows->cap ? 2 * rows->cap : 4096;
            double *nv = realloc(rows->v, cap * IMU_NCOL * sizeof *nv);
            if (nv == NULL) {
                return imu_fail(json, "io_error", "%sout of memory (line %lu)", "", ln);
            }
            rows->v = nv;
            rows->cap = cap;
        }
        memcpy(rows->v + rows->n * IMU_NCOL, row, sizeof row);
        rows->n++;
    }
    return 0;
}

static void imu_vec_json(const char *key, const sfit_vec3_t *v)
{
    printf(",\"%s\":", key);
    json_out_vec(stdout, v->v);
}

static void imu_mat_json(const char *key, const sfit_mat3_t *m)
{
    printf(",\"%s\":", key);
    json_out_mat(stdout, m);
}

static void imu_print_json(const sfit_imu_result_t *r, double rate)
{
    size_t k, nf;
    const json_out_flag_t *tab = names_flags(NAMES_IMU, &nf);
    const char *sep = "";
    printf("{\"status\":\"ok\",\"n\":%lu,\"used\":%lu,\"rate\":%.9g,\"joint\":\"%s\"",
           (unsigned long)r->n, (unsigned long)r->used, rate, r->hinge ? "hinge" : "ball");
    imu_vec_json("r1", &r->r1);
    imu_vec_json("r2", &r->r2);
    imu_mat_json("r1_cov", &r->r1_cov);
    imu_mat_json("r2_cov", &r->r2_cov);
    if (r->hinge) {
        imu_vec_json("axis1", &r->axis1);
        imu_vec_json("axis2", &r->axis2);
        imu_mat_json("axis1_cov", &r->axis1_cov);
        imu_mat_json("axis2_cov", &r->axis2_cov);
    } else {
        printf(",\"axis1\":null,\"axis2\":null,\"axis1_cov\":null,\"axis2_cov\":null");
    }
    imu_vec_json("acc_bias1", &r->acc_bias1);
    imu_vec_json("acc_bias2", &r->acc_bias2);
    printf(",\"resid_rms\":%.9g,\"noise_rms\":%.9g,\"hinge_ratio\":%.9g,\"wobble_deg\":%.9g,"
           "\"line_sd\":%.9g,\"line_ratio\":%.9g,\"line_off\":%.9g,\"force_ratio\":%.9g,"
           "\"rate_rms1\":%.9g,\"rate_rms2\":%.9g",
           (double)r->resid_rms, (double)r->noise_rms, (double)r->hinge_ratio,
           (double)r->wobble_deg, (double)r->line_sd, (double)r->line_ratio, (double)r->line_off,
           (double)r->force_ratio, (double)r->rate_rms1, (double)r->rate_rms2);
    printf(",\"flags\":{\"untrusted\":%s,\"names\":[",
           (r->flags & SFIT_FLAG_UNTRUSTED) ? "true" : "false");
    for (k = 0; k < nf; k++) {
        if (r->flags & tab[k].bit) {
            printf("%s\"%s\"", sep, tab[k].name);
            sep = ",";
        }
    }
    printf("],\"reason\":");
    if (r->flags & SFIT_FLAG_UNTRUSTED) {
        char why[512];
        json_out_str(stdout, names_imu_reasons(r->flags, why, sizeof why), 0);
    } else {
        printf("null");
    }
    printf("}}\n");
}

static void imu_print_cov_sd(const char *what, const sfit_mat3_t *c, double scale,
                             const char *unit)
{
    printf("  %-8s SD %.3g %.3g %.3g %s\n", what, sqrt(fabs((double)c->m[0])) * scale,
           sqrt(fabs((double)c->m[4])) * scale, sqrt(fabs((double)c->m[8])) * scale, unit);
}

static void imu_print_human(const char *file, const sfit_imu_result_t *r, double rate)
{
    size_t k, nf;
    const json_out_flag_t *tab = names_flags(NAMES_IMU, &nf);
    printf("file          %s\n", file);
    printf("samples       %lu at %.6g Hz, %lu kept for the solve\n", (unsigned long)r->n, rate,
           (unsigned long)r->used);
    printf("joint         %s\n", r->hinge ? "hinge" : "ball");
    printf("%s in sensor 1  %.4f %.4f %.4f m\n", r->hinge ? "axis point" : "centre    ",
           (double)r->r1.v[0], (double)r->r1.v[1], (double)r->r1.v[2]);
    imu_print_cov_sd("", &r->r1_cov, 1e3, "mm");
    printf("%s in sensor 2  %.4f %.4f %.4f m\n", r->hinge ? "axis point" : "centre    ",
           (double)r->r2.v[0], (double)r->r2.v[1], (double)r->r2.v[2]);
    imu_print_cov_sd("", &r->r2_cov, 1e3, "mm");
    if (r->hinge) {
        printf("axis in sensor 1        %.4f %.4f %.4f\n", (double)r->axis1.v[0],
               (double)r->axis1.v[1], (double)r->axis1.v[2]);
        printf("axis in sensor 2        %.4f %.4f %.4f\n", (double)r->axis2.v[0],
               (double)r->axis2.v[1], (double)r->axis2.v[2]);
    }
    printf("residual      %.4g m/s^2 rms (the noise predicts %.4g)\n", (double)r->resid_rms,
           (double)r->noise_rms);
    printf("rotation      %.3g and %.3g rad/s rms\n", (double)r->rate_rms1,
           (double)r->rate_rms2);
    printf("evidence      hinge residual %.3g of the rates, wobble %.3g degrees, free line %.3g",
           (double)r->hinge_ratio, (double)r->wobble_deg, (double)r->line_ratio);
    if (r->hinge) {
        printf(" (off the axes %.3g), force ratio %.3g", (double)r->line_off,
               (double)r->force_ratio);
    }
    printf("\n");
    if (r->flags & SFIT_FLAG_UNTRUSTED) {
        printf("UNTRUSTED     do not use this result:\n");
        for (k = 0; k < nf; k++) {
            if (r->flags & tab[k].bit) {
                printf("              %s\n", names_imu_reason(tab[k].bit));
            }
        }
    } else {
        printf("trusted       the covariances describe the error\n");
    }
}

int cli_cmd_imu(int argc, char **argv)
{
    const char *file = NULL;
    int json = 0, i, rc;
    imu_rows_t rows = {NULL, 0, 0};
    FILE *fp;
    static sfit_imu_t s;
    sfit_imu_result_t r;
    sfit_status_t st = SFIT_OK;
    double rate, dt, dmin, dmax;
    size_t k;
    cli_input_t in;

    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            imu_usage(stdout);
            return CLI_OK;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            fprintf(stderr, "sfit: unknown option '%s'\n", argv[i]);
            imu_usage(stderr);
            return CLI_USAGE;
        } else if (file == NULL) {
            file = argv[i];
        } else {
            fprintf(stderr, "sfit: one FILE only\n");
            imu_usage(stderr);
            return CLI_USAGE;
        }
    }
    if (file == NULL) {
        imu_usage(stderr);
        return CLI_USAGE;
    }
    fp = (strcmp(file, "-") == 0) ? stdin : fopen(file, "r");
    if (fp == NULL) {
        return cli_open_failed(file, json);
    }
    rc = imu_read(fp, json, &rows);
    if (fp != stdin) {
        fclose(fp);
    }
    if (rc != 0) {
        free(rows.v);
        return rc;
    }
    memset(&in, 0, sizeof in);
    in.accepted = (unsigned long)rows.n;
    if (rows.n < 3) {
        free(rows.v);
        return cli_report_failure(SFIT_E_TOO_FEW, "imu joint", "fewer than 3 samples", json,
                                  &in);
    }
    dt = (rows.v[(rows.n - 1) * IMU_NCOL] - rows.v[0]) / (double)(rows.n - 1);
    dmin = dmax = rows.v[IMU_NCOL] - rows.v[0];
    for (k = 1; k + 1 < rows.n; k++) {
        const double d = rows.v[(k + 1) * IMU_NCOL] - rows.v[k * IMU_NCOL];
        dmin = (d < dmin) ? d : dmin;
        dmax = (d > dmax) ? d : dmax;
    }
    if (dmax - dmin > IMU_RATE_TOL * dt) {
        char a[64];
        snprintf(a, sizeof a, "%.6g to %.6g s", dmin, dmax);
        free(rows.v);
        return imu_fail(json, "format_error",
                        "the time steps vary from %s: not evenly sampled (%lu rows)", a,
                        (unsigned long)rows.n);
    }
    rate = 1.0 / dt;
    st = sfit_imu_init(&s, (float)rate, NULL);
    for (k = 0; k < rows.n && st == SFIT_OK; k++) {
        const double *v = rows.v + k * IMU_NCOL;
        sfit_imu_sample_t x;
        int c;
        for (c = 0; c < 3; c++) {
            x.acc1.v[c] = (float)v[1 + c];
            x.gyr1.v[c] = (float)v[4 + c];
            x.acc2.v[c] = (float)v[7 + c];
            x.gyr2.v[c] = (float)v[10 + c];
        }
        st = sfit_imu_add(&s, &x);
        if (st != SFIT_OK) {
            char a[64];
            snprintf(a, sizeof a, "%s", names_status_message(st, NAMES_CLI));
            free(rows.v);
            return imu_fail(json, "format_error", "a sample is refused: %s (row %lu)", a,
                            (unsigned long)k + 2ul);
        }
    }
    free(rows.v);
    if (st == SFIT_OK) {
        st = sfit_imu_solve(&s, &r);
    }
    if (st != SFIT_OK) {
        return cli_report_failure(st, "imu joint", NULL, json, &in);
    }
    if (json) {
        imu_print_json(&r, rate);
    } else {
        imu_print_human(file, &r, rate);
    }
    return CLI_OK;
}
