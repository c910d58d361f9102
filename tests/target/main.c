/* SPDX-License-Identifier: MIT */
/**
 * @file main.c
 * @brief On-target test runner (Cortex-M4F under QEMU mps2-an386): runs
 * every suite, prints one line per failed check and ends with
 * "N passed, N failed"; the exit status is 0 only when nothing failed.
 * nano printf has no %f: values are printed as scaled integers.
 */
#include <stdio.h>

#include "tt.h"

int main(void);
void tt_mat3(void);
void tt_moments(void);
void tt_fit(void);
void tt_multi(void);
void tt_noise(void);
void tt_incr(void);
void tt_beyond(void);
void tt_joint(void);
void tt_hostile(void);
void tt_pair(void);
void tt_imu(void);

typedef void (*tt_suite_fn)(void);
static const struct {
    const char *name;
    tt_suite_fn fn;
} tt_suites[] = {
    {"mat3", tt_mat3},
    {"moments", tt_moments},
    {"fit", tt_fit},
    {"multi", tt_multi},
    {"noise", tt_noise},
    {"incr", tt_incr},
    {"beyond", tt_beyond},
    {"joint", tt_joint},
    {"hostile", tt_hostile},
    {"pair", tt_pair},
    {"imu", tt_imu},
};

static unsigned tt_pass;
static unsigned tt_fail;
static const char *tt_cur = "";

void tt_case(const char *name)
{
    tt_cur = name;
}

int tt_check(int cond, const char *expr, const char *file, int line)
{
    if (cond) {
        tt_pass++;
    } else {
        tt_fail++;
        printf("FAIL %s: %s:%d: %s\n", tt_cur, file, line, expr);
    }
    return cond;
}

/* v as sign, integer part and 6 significant digits of exponent form. */
static void tt_print_num(double v)
{
    int e = 0;
    long mant;
    if (v != v) {
        printf("nan");
        return;
    }
    if (v < 0.0) {
        printf("-");
        v = -v;
    }
    if (v > 1e300) {
        printf("inf");
        return;
    }
    if (v != 0.0) {
        while (v >= 10.0) {
            v /= 10.0;
            e++;
        }
        while (v < 1.0) {
            v *= 10.0;
            e--;
        }
    }
    mant = (long)(v * 100000.0 + 0.5);
    printf("%ld.%05lde%d", mant / 100000, mant % 100000, e);
}

int tt_near(double got, double want, double tol, const char *expr, const char *file, int line)
{
    double d = got - want;
    int ok = (d <= tol) && (-d <= tol); /* false for NaN */
    if (!tt_check(ok, expr, file, line)) {
        printf("     got ");
        tt_print_num(got);
        printf(" want ");
        tt_print_num(want);
        printf(" tol ");
        tt_print_num(tol);
        printf("\n");
    }
    return ok;
}

int main(void)
{
    unsigned i;
    for (i = 0; i < sizeof tt_suites / sizeof tt_suites[0]; i++) {
        unsigned f0 = tt_fail;
        tt_cur = tt_suites[i].name;
        tt_suites[i].fn();
        printf("suite %s: %s\n", tt_suites[i].name, tt_fail == f0 ? "ok" : "FAILED");
    }
    printf("%u passed, %u failed\n", tt_pass, tt_fail);
    return tt_fail == 0u ? 0 : 1;
}
