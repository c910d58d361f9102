/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_port_impl.h
 * @brief Host port: the C library's <math.h>, <assert.h>, clock() for tools.
 */
#ifndef SFIT_PORT_IMPL_H
#define SFIT_PORT_IMPL_H

#include <math.h>

#ifndef SFIT_SQRTF
#define SFIT_SQRTF(x) sqrtf(x)
#endif

#ifndef SFIT_FABSF
#define SFIT_FABSF(x) fabsf(x)
#endif

#ifndef SFIT_INLINE
#define SFIT_INLINE static inline
#endif

#ifndef SFIT_ASSERT
#if SFIT_ENABLE_ASSERT
#include <assert.h>
#define SFIT_ASSERT(c) assert(c)
#endif
#endif

#ifndef SFIT_CYCLES
#include <time.h>
#define SFIT_CYCLES() ((unsigned long)clock())
#endif

#endif /* SFIT_PORT_IMPL_H */
