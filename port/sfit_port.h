/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_port.h
 * @brief The platform contract. The library includes only this header for
 * platform services; it pulls the chosen port's sfit_port_impl.h (the port
 * directory, port/<SFIT_PORT>/, is on the include path) and supplies a
 * fallback for every hook the port leaves undefined. It depends on nothing
 * of the library.
 *
 * Hooks used by the library (each may also come from -D or SFIT_USER_CONFIG):
 *  - SFIT_SQRTF(x)   single-precision square root (never sqrt on a double)
 *  - SFIT_FABSF(x)   single-precision absolute value
 *  - SFIT_INLINE     keyword(s) of the small helpers in lib/src/sfit_float.h
 *  - SFIT_ASSERT(c)  internal-invariant check; active only when
 *                    SFIT_ENABLE_ASSERT is defined to 1
 * A port may add tool-only hooks (the Cortex-M4F port's SFIT_CYCLES(), read
 * by its QEMU smoke test); the library never calls them.
 */
#ifndef SFIT_PORT_H
#define SFIT_PORT_H

#include "sfit_port_impl.h"

#ifndef SFIT_SQRTF
#include <math.h>
#define SFIT_SQRTF(x) sqrtf(x)
#endif

#ifndef SFIT_FABSF
#include <math.h>
#define SFIT_FABSF(x) fabsf(x)
#endif

#ifndef SFIT_INLINE
#define SFIT_INLINE static inline
#endif

#ifndef SFIT_ASSERT
#if defined(SFIT_ENABLE_ASSERT) && SFIT_ENABLE_ASSERT
#include <assert.h>
#define SFIT_ASSERT(c) assert(c)
#else
#define SFIT_ASSERT(c) ((void)0)
#endif
#endif

#endif /* SFIT_PORT_H */
