/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_port.h
 * @brief The platform contract. The library includes only this header for
 * platform services; it pulls the chosen port's sfit_port_impl.h (the port
 * directory, port/<SFIT_PORT>/, is on the include path) and supplies a
 * fallback for every hook the port leaves undefined.
 *
 * Hooks (all optional; each may also come from SFIT_USER_CONFIG):
 *  - SFIT_SQRTF(x)   single-precision square root (never sqrt on a double)
 *  - SFIT_FABSF(x)   single-precision absolute value
 *  - SFIT_INLINE     keyword(s) for small internal helpers
 *  - SFIT_RESTRICT   the C99 restrict qualifier, or nothing
 *  - SFIT_ASSERT(c)  internal-invariant check; active only when
 *                    SFIT_ENABLE_ASSERT is 1 (host tests route it to cmocka)
 *  - SFIT_CYCLES()   a cycle counter, for tools and benchmarks only
 * The library never includes a device header.
 */
#ifndef SFIT_PORT_H
#define SFIT_PORT_H

#include "sfit/sfit_config.h"
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

#ifndef SFIT_RESTRICT
#define SFIT_RESTRICT restrict
#endif

#ifndef SFIT_ASSERT
#if SFIT_ENABLE_ASSERT
#include <assert.h>
#define SFIT_ASSERT(c) assert(c)
#else
#define SFIT_ASSERT(c) ((void)0)
#endif
#endif

#endif /* SFIT_PORT_H */
