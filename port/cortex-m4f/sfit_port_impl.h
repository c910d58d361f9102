/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_port_impl.h
 * @brief Cortex-M4F port (FPv4-SP single-precision FPU, GCC/Clang).
 *
 * Maps the hooks of port/sfit_port.h onto compiler builtins so that no libm
 * call is emitted: with -fno-math-errno (set by toolchain.cmake) SFIT_SQRTF
 * is one vsqrt.f32 and SFIT_FABSF one vabs.f32. Every hook is guarded by
 * #ifndef, so SFIT_USER_CONFIG (included first via sfit_config.h) or -D can
 * replace any of them. No device header is included.
 */
#ifndef SFIT_PORT_IMPL_H
#define SFIT_PORT_IMPL_H

#include <stdint.h>

/** Square root of a float; vsqrt.f32 (14 cycles on M4F) given -fno-math-errno. */
#ifndef SFIT_SQRTF
#define SFIT_SQRTF(x) __builtin_sqrtf(x)
#endif

/** Absolute value of a float; vabs.f32. */
#ifndef SFIT_FABSF
#define SFIT_FABSF(x) __builtin_fabsf(x)
#endif

/** Keywords for small internal helpers. */
#ifndef SFIT_INLINE
#define SFIT_INLINE static inline
#endif

/**
 * Internal-invariant check. Off unless SFIT_ENABLE_ASSERT is 1; when on, a
 * failed check executes a permanently undefined instruction (UDF): cheap, no
 * stdio pulled in, and under QEMU startup.c reports the faulting PC (map it
 * back with arm-none-eabi-addr2line) and exits non-zero.
 */
#ifndef SFIT_ASSERT
#if defined(SFIT_ENABLE_ASSERT) && SFIT_ENABLE_ASSERT
#define SFIT_ASSERT(c) ((c) ? (void)0 : __builtin_trap())
#else
#define SFIT_ASSERT(c) ((void)0)
#endif
#endif

/**
 * DWT cycle counter (DWT_CYCCNT, 0xE0001004), for tools and benchmarks only;
 * the library never calls it. Call SFIT_CYCLES_ENABLE() once first (sets
 * DEMCR.TRCENA and DWT_CTRL.CYCCNTENA). The counter wraps every 2^32 cycles:
 * take differences as uint32_t. QEMU does not model the DWT: there both
 * macros are harmless and SFIT_CYCLES() always reads 0.
 */
#ifndef SFIT_CYCLES
#define SFIT_CYCLES() (*(volatile const uint32_t *)0xE0001004u)
#endif

#ifndef SFIT_CYCLES_ENABLE
#define SFIT_CYCLES_ENABLE()                                                   \
    do {                                                                       \
        *(volatile uint32_t *)0xE000EDFCu |= (uint32_t)1u << 24; /* DEMCR */   \
        *(volatile uint32_t *)0xE0001004u = 0u;                  /* CYCCNT */  \
        *(volatile uint32_t *)0xE0001000u |= 1u;                 /* DWT_CTRL */\
    } while (0)
#endif

#endif /* SFIT_PORT_IMPL_H */
