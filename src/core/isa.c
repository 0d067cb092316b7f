/* CPU feature detection for the run-time kernel choice (see core/isa.h). */
#include "core/isa.h"

#include <string.h>

static const char *const isa_names[] = {"auto", "scalar", "sse4.2", "avx2", "avx512"};

const char *tt_isa_name(tt_isa isa)
{
    return (unsigned)isa <= (unsigned)TT_ISA_LAST ? isa_names[isa] : "";
}

int tt_isa_from_name(const char *name, tt_isa *out)
{
    if (!name) return 0;
    for (unsigned i = 0; i <= (unsigned)TT_ISA_LAST; i++)
        if (strcmp(name, isa_names[i]) == 0) {
            if (out) *out = (tt_isa)i;
            return 1;
        }
    /* Accepted spellings besides the canonical names. */
    if (strcmp(name, "sse42") == 0 || strcmp(name, "sse") == 0) {
        if (out) *out = TT_ISA_SSE42;
        return 1;
    }
    if (strcmp(name, "avx-512") == 0 || strcmp(name, "avx512f") == 0) {
        if (out) *out = TT_ISA_AVX512;
        return 1;
    }
    return 0;
}

/* What the CPU (and the OS, which must save the wider registers) allows.
 * __builtin_cpu_supports checks both for AVX and AVX-512 in gcc and clang. */
static int cpu_has(tt_isa isa)
{
#if defined(TT_HAVE_X86_KERNELS) && (defined(__x86_64__) || defined(__i386__))
    __builtin_cpu_init();
    switch (isa) {
    case TT_ISA_SCALAR: return 1;
    case TT_ISA_SSE42: return __builtin_cpu_supports("sse4.2") != 0;
    case TT_ISA_AVX2:
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case TT_ISA_AVX512:
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    default: return 0;
    }
#else
    return isa == TT_ISA_SCALAR;
#endif
}

int tt_isa_supported(tt_isa isa)
{
    if (isa <= TT_ISA_AUTO || isa > TT_ISA_LAST) return 0;
    return cpu_has(isa);
}

tt_isa tt_isa_best(void)
{
    for (int i = (int)TT_ISA_LAST; i > (int)TT_ISA_SCALAR; i--)
        if (tt_isa_supported((tt_isa)i)) return (tt_isa)i;
    return TT_ISA_SCALAR;
}

tt_status tt_isa_resolve(tt_context *ctx, tt_isa requested, tt_isa *out)
{
    if (requested == TT_ISA_AUTO) {
        *out = tt_isa_best();
        return TT_OK;
    }
    if ((unsigned)requested > (unsigned)TT_ISA_LAST)
        return tt_error(ctx, TT_ERR_INVALID_ARGUMENT, "unknown isa %d", (int)requested);
    if (!tt_isa_supported(requested))
        return tt_error(ctx, TT_ERR_UNSUPPORTED,
                        "isa '%s' is not available here (this CPU and build offer up to '%s')",
                        tt_isa_name(requested), tt_isa_name(tt_isa_best()));
    *out = requested;
    return TT_OK;
}
