/* SPDX-License-Identifier: MIT */
/**
 * @file sfit_port_impl.h
 * @brief Host port: the C library's <math.h> and <assert.h>.
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
#if defined(SFIT_ENABLE_ASSERT) && SFIT_ENABLE_ASSERT
#include <assert.h>
#define SFIT_ASSERT(c) assert(c)
#endif
#endif

#endif /* SFIT_PORT_IMPL_H */
