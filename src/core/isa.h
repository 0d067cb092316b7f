/* Run-time choice of SIMD kernels. Kernels for each ISA live in their own
 * translation units named *_sse42.c, *_avx2.c and *_avx512.c beside the code
 * they serve; CMakeLists.txt compiles each with that ISA's flags (and only
 * on x86-64, where TT_HAVE_X86_KERNELS is then defined), while every other
 * unit stays baseline x86-64, so one binary runs everywhere. A structure
 * resolves its ISA once when it is built (tt_isa_resolve) and stores the
 * kernel pointers it needs; nothing is re-dispatched per ray. */
#ifndef TT_CORE_ISA_H
#define TT_CORE_ISA_H

#include "core/context.h"

/* The ISA a build with options->isa runs on: `requested` itself when
 * supported, the best supported one for TT_ISA_AUTO. An unsupported or
 * unknown request is TT_ERR_UNSUPPORTED / TT_ERR_INVALID_ARGUMENT through
 * tt_error naming it and what this CPU offers. */
tt_status tt_isa_resolve(tt_context *ctx, tt_isa requested, tt_isa *out);

/* Every ISA value from TT_ISA_SCALAR up, for tests that run each path. */
#define TT_ISA_FIRST TT_ISA_SCALAR
#define TT_ISA_LAST TT_ISA_AVX512

#endif
