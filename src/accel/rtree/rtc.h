/* The R-tree's compact layout on the CPU (rtc_layout.h is the part shared
 * with the GPU): the owned arrays, the packer from the builder's pointer
 * tree, the check, the statistics, and the traversal entry points of each
 * ISA unit. The traversal is chosen once when the tree is built (ISA and
 * traversal option) and kept as function pointers; nothing is dispatched
 * per ray. */
#ifndef TT_ACCEL_RTREE_RTC_H
#define TT_ACCEL_RTREE_RTC_H

#include "accel/accel.h" /* tt_packet_stats */
#include "accel/rtree/layout/rtc_layout.h"
#include "accel/rtree/build/rtree_build.h"
#include "core/context.h"
#include "io/scene.h"

/* A traversal: closest hit into *hit (any = 0) or occlusion (any = 1);
 * returns whether something was hit. The _stats forms add to *stats. */
typedef int (*tt_rtc_trace_fn)(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,
                               tt_ray_stats *stats);

/* A packet traversal (rtc_packet.h): rays->n <= TT_PACKET_MAX rows, each
 * answered exactly as the single-ray traversal answers it: closest hits
 * into hits (any = 0) or occlusion bytes into occ (any = 1). The _stats
 * form adds to *stats. */
typedef void (*tt_rtc_packet_fn)(const tt_rtc *t, const tt_packet_rays *rays, int any,
                                 tt_hit *hits, uint8_t *occ, tt_packet_stats *stats);

/* Rows traced one by one (the vtable's intersect_rows / occluded_rows):
 * rays->n <= TT_PACKET_MAX rows, row i answered exactly as the unit's
 * single-ray traversal answers tt_wray_init of it, into hits[i] (any = 0)
 * or occ[i] (any = 1). A loop in the unit (rtc_rows.h) over its own
 * traversal: the rays prepared eight at a time (accel/wray_rows.h), no
 * call through a pointer a ray. */
typedef void (*tt_rtc_rows_fn)(const tt_rtc *t, const tt_packet_rays *rays, int any,
                               tt_hit *hits, uint8_t *occ);

typedef struct rtc_tree {
    tt_rtc c;
    void *node_mem, *block_mem; /* the allocations behind c.node, c.block */
    int m;                      /* the fill minimum the check enforces */
    /* 1: built with split references (rtree_split_refs.h): a triangle may
     * sit in several leaves (once a leaf), each leaf box bounds the parts
     * of its triangles in it (not their whole boxes); never updated in
     * place. Set by the build, and on load when lanes outnumber triangles. */
    int split;
    tt_rtc_trace_fn trace, trace_stats;
    /* NULL where this ISA has no packet kernel (scalar, SSE4.2) or the
     * traversal is the stackless one: the rays then go one by one */
    tt_rtc_packet_fn packet, packet_stats;
    /* trace's rows form (NULL: the vtable loops over trace itself) */
    tt_rtc_rows_fn rows;
} rtc_tree;

/* Packs the finished pointer tree (any builder's) into t; on error t holds
 * what was allocated, for rtc_free. */
tt_status rtc_pack(tt_context *ctx, const rt_builder *b, const float *scene_tri, rtc_tree *t);
/* The same layout from the SAH loader's level form (rtree_bulk.h), the
 * same records and blocks as rtc_pack writes for that tree. */
struct rt_bulk_levels;
tt_status rtc_pack_levels(tt_context *ctx, const struct rt_bulk_levels *lv, const float *scene_tri,
                          rtc_tree *t);
void rtc_free(tt_context *ctx, rtc_tree *t);
size_t rtc_bytes(const rtc_tree *t);

/* The traversal functions for option `traversal` (tt_rtree_traversal) on
 * ISA `isa` (resolved, not TT_ISA_AUTO). */
void rtc_select(rtc_tree *t, int traversal, tt_isa isa);

/* Child i's box of node record rec. */
static inline void rtc_child_box(const tt_rtc *c, const float *rec, uint32_t i, float out[6])
{
    tt_rtc_child_box(c, rec, i, out);
}

/* Writes a record's child boxes: `count` exact boxes in SoA rows of
 * `stride` (box[k stride + i], row k of lo x y z, hi x y z); entries
 * count .. S - 1 get the +inf mark. For the packer and for anything that
 * updates a record in place (a refit). */
void rtc_set_boxes(const tt_rtc *c, float *rec, const float *box, uint32_t stride, uint32_t count);

tt_status rtc_check(tt_context *ctx, const rtc_tree *t, const tt_scene *scene);
void rtc_statistics(const rtc_tree *t, tt_stat_fn fn, void *user);

/* The entry points of the traversal units. */
int tt_rtc_stackless_scalar(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,
                            tt_ray_stats *stats);
int tt_rtc_stackless_scalar_stats(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,
                                  tt_ray_stats *stats);
void tt_rtc_stackless_scalar_rows(const tt_rtc *t, const tt_packet_rays *rays, int any,
                                  tt_hit *hits, uint8_t *occ);
#define TT_RTC_DECLARE_STACK(isa)                                                                 \
    int tt_rtc_stack_##isa(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,               \
                           tt_ray_stats *stats);                                                  \
    int tt_rtc_stack_##isa##_stats(const tt_rtc *t, const tt_wray *r, int any, tt_hit *hit,       \
                                   tt_ray_stats *stats);                                          \
    void tt_rtc_stack_##isa##_rows(const tt_rtc *t, const tt_packet_rays *rays, int any,          \
                                   tt_hit *hits, uint8_t *occ);
TT_RTC_DECLARE_STACK(scalar)
#ifdef TT_HAVE_X86_KERNELS
TT_RTC_DECLARE_STACK(sse42)
TT_RTC_DECLARE_STACK(avx2)
TT_RTC_DECLARE_STACK(avx512)
#endif

/* The packet units (rtc_packet_<isa>.c). */
#ifdef TT_HAVE_X86_KERNELS
#define TT_RTC_DECLARE_PACKET(isa)                                                                \
    void tt_rtc_packet_##isa(const tt_rtc *t, const tt_packet_rays *rays, int any,           \
                             tt_hit *hits, uint8_t *occ, tt_packet_stats *stats);                 \
    void tt_rtc_packet_##isa##_stats(const tt_rtc *t, const tt_packet_rays *rays, int any,   \
                                     tt_hit *hits, uint8_t *occ, tt_packet_stats *stats);
TT_RTC_DECLARE_PACKET(avx2)
TT_RTC_DECLARE_PACKET(avx512)
#endif

/* For the units: RTC_FN(name) appends the unit's RTC_ISA suffix. */
#define RTC_CAT2(a, b) a##b
#define RTC_CAT(a, b) RTC_CAT2(a, b)
#define RTC_FN(name) RTC_CAT(name, RTC_ISA)

#endif
