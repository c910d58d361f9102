/* SPDX-License-Identifier: MIT */
/**
 * @file tt.h
 * @brief Minimal test harness of the on-target tests (no cmocka on the
 * target): checks count passes/failures and print the failing line; main.c
 * runs every registered test and ends with the line "N passed, N failed".
 *
 * Adding a test file: tests/target/tt_<module>.c defining
 * `void tt_<module>(void)` (calls tt_case() per case), plus one line in
 * TT_SUITES of main.c.
 */
#ifndef SFIT_TT_H
#define SFIT_TT_H

#include <stdint.h>

/** Start a test case (printed when it fails). */
void tt_case(const char *name);

/** Record one check; returns cond. */
int tt_check(int cond, const char *expr, const char *file, int line);

/** Record |got - want| <= tol (doubles); prints values on failure. */
int tt_near(double got, double want, double tol, const char *expr, const char *file, int line);

#define TT_TRUE(c) tt_check((c) ? 1 : 0, #c, __FILE__, __LINE__)
#define TT_EQ_INT(a, b) tt_check((long)(a) == (long)(b), #a " == " #b, __FILE__, __LINE__)
#define TT_NEAR(got, want, tol) tt_near((double)(got), (double)(want), (double)(tol), #got, __FILE__, __LINE__)

#endif /* SFIT_TT_H */
