/* The compact layout's traversal functions, chosen once when the tree is
 * built: the stackless walk is scalar (it tests one box a step, the GPU's
 * form); the stack traversal comes in one unit per ISA. */
#include "accel/rtree/rtc.h"

void rtc_select(rtc_tree *t, int traversal, tt_isa isa)
{
    t->packet = t->packet_stats = NULL;
    if (traversal == TT_RTREE_STACKLESS) {
        t->trace = tt_rtc_stackless_scalar;
        t->trace_stats = tt_rtc_stackless_scalar_stats;
        t->rows = tt_rtc_stackless_scalar_rows;
        return;
    }
    /* auto, stack and ordered: the near-to-far stack traversal */
    t->trace = tt_rtc_stack_scalar;
    t->trace_stats = tt_rtc_stack_scalar_stats;
    t->rows = tt_rtc_stack_scalar_rows;
#ifdef TT_HAVE_X86_KERNELS
    if (isa == TT_ISA_SSE42) {
        t->trace = tt_rtc_stack_sse42;
        t->trace_stats = tt_rtc_stack_sse42_stats;
        t->rows = tt_rtc_stack_sse42_rows;
    } else if (isa == TT_ISA_AVX2) {
        t->trace = tt_rtc_stack_avx2;
        t->trace_stats = tt_rtc_stack_avx2_stats;
        t->rows = tt_rtc_stack_avx2_rows;
        t->packet = tt_rtc_packet_avx2;
        t->packet_stats = tt_rtc_packet_avx2_stats;
    } else if (isa == TT_ISA_AVX512) {
        t->trace = tt_rtc_stack_avx512;
        t->trace_stats = tt_rtc_stack_avx512_stats;
        t->rows = tt_rtc_stack_avx512_rows;
        t->packet = tt_rtc_packet_avx512;
        t->packet_stats = tt_rtc_packet_avx512_stats;
    }
#else
    (void)isa;
#endif
}
