/* SPDX-License-Identifier: MIT */
/**
 * @file smoke.c
 * @brief End-to-end check of the Cortex-M4F chain: boot stub (FPU on, .data,
 * .bss, constructors), hard-float math through the port macros, semihosted
 * printf/argv/exit status, and the fault path.
 *
 * Usage (through run.sh): smoke            -> checks, prints, returns 0/1
 *                         smoke exit N     -> returns N (exit status check)
 *                         smoke fault      -> calls an unmapped address
 *                         smoke assert     -> fails an SFIT_ASSERT (UDF)
 *                         smoke cycles     -> prints two SFIT_CYCLES() reads
 *                         smoke hang       -> spins forever (run.sh timeout check)
 * nano printf has no %f: results are printed as scaled integers.
 */
#define SFIT_ENABLE_ASSERT 1
#include "sfit_port_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

float smoke_rnorm3(const float *v);
int main(int argc, char **argv);

static int prv_data = 42; /* .data: written by QEMU's loader */
static int prv_bss;       /* .bss: zeroed by crt0 */
static int prv_ctor;      /* set by a constructor (init_array) */

__attribute__((constructor)) static void prv_init(void)
{
    prv_ctor = 7;
}

/** 1 / |v|: 3 vmul, 2 vadd, 1 vsqrt, 1 vdiv (the count_insns.sh example). */
__attribute__((noinline)) float smoke_rnorm3(const float *v)
{
    return 1.0f / SFIT_SQRTF(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

static long prv_milli(float x)
{
    return (long)(x * 1000.0f + (x < 0.0f ? -0.5f : 0.5f));
}

static int prv_check(void)
{
    static volatile float in[3] = {2.0f, 3.0f, 6.0f}; /* |in| = 7 */
    float v[3];
    float acc = 0.0f;
    long r;
    long s;
    long q;
    int i;
    int fails = 0;

    for (i = 0; i < 10; i++) {
        v[0] = in[0]; /* volatile reloads keep the 10 calls in the loop */
        v[1] = in[1];
        v[2] = in[2];
        acc += smoke_rnorm3(v); /* 10/7 */
    }
    r = prv_milli(acc);
    s = prv_milli(sqrtf(v[0]));                    /* libm name, same vsqrt */
    q = prv_milli(SFIT_FABSF(-v[2]) / v[1]);       /* 2 */
    printf("smoke: acc*1000=%ld sqrt2*1000=%ld q*1000=%ld data=%d bss=%d ctor=%d\n", r, s, q,
           prv_data, prv_bss, prv_ctor);
    fails += (r != 1429);
    fails += (s != 1414);
    fails += (q != 2000);
    fails += (prv_data != 42) + (prv_bss != 0) + (prv_ctor != 7);
    return fails;
}

int main(int argc, char **argv)
{
    int i;

    printf("smoke: argc=%d", argc);
    for (i = 0; i < argc; i++) {
        printf(" [%s]", argv[i]);
    }
    printf("\n");

    if (argc >= 3 && strcmp(argv[1], "exit") == 0) {
        return atoi(argv[2]);
    }
    if (argc >= 2 && strcmp(argv[1], "fault") == 0) {
        void (*volatile bad)(void) = (void (*)(void))0x30000001u; /* unmapped */
        bad();
        return 0;
    }
    if (argc >= 2 && strcmp(argv[1], "assert") == 0) {
        SFIT_ASSERT(argc < 2);
        return 0;
    }
    if (argc >= 2 && strcmp(argv[1], "cycles") == 0) {
        uint32_t c0;
        uint32_t c1;
        SFIT_CYCLES_ENABLE();
        c0 = SFIT_CYCLES();
        c1 = SFIT_CYCLES();
        printf("smoke: cycles %lu %lu\n", (unsigned long)c0, (unsigned long)c1);
        return 0;
    }
    if (argc >= 2 && strcmp(argv[1], "hang") == 0) {
        volatile int spin = 1;
        while (spin != 0) {
        }
    }
    i = prv_check();
    printf("smoke: %s\n", i == 0 ? "PASS" : "FAIL");
    return i == 0 ? 0 : 1;
}
