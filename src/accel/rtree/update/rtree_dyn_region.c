/* The leaves of a level-1 node in its region of the slack layout
 * (rtree_dyn.h): every leaf owns a slot of lanes that stays where it is
 * while the leaf fits it, so an edit rewrites the lanes of the leaves it
 * changed and no others.
 *
 * A slot is a power of two of lanes up to a block, aligned to its size
 * (so it never straddles a block, as rtc_pack's leaves of up to a block
 * do not), or whole blocks for a bigger leaf. A leaf that outgrows its
 * slot takes a free one of the right size elsewhere in the region; a
 * leaf that shrinks keeps its slot. Only when no free slot fits is the
 * region laid out again, entry 0 first (the traversal's block set counts
 * from entry 0's block, which must be the node's lowest), then the others
 * by size, largest first: in that order the slots pack without holes but
 * in entry 0's block, so the region needs at most one block more than
 * the slots' lanes fill.
 *
 * The first-fit packing in entry order this replaces moved every leaf
 * behind one that grew or shrank: on the bunny's 1%-edits frames ~20k
 * lanes were rewritten a frame for ~1.4k changed triangles, half the
 * update's instructions.
 *
 * Per leaf l (level 0; these arrays are the records' of interior nodes):
 * grp_of[l] its slot's first global lane, grp_hi[l] the slot's lanes,
 * rec_of[l] the level-1 node whose region the slot is in. A slot is valid
 * while that node is l's parent and its region was not exchanged since
 * (RT_DYN_REGION_FRESH); lanes no leaf of the region holds are cleared
 * (the traversal tests whole blocks). */
#include <math.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "accel/rtree/update/rtree_dyn.h"

#define W TT_TRI_BLOCK_W
_Static_assert(TT_TRI_BLOCK_W == 8, "a region's lane set holds a block in a byte");
/* lanes of the biggest region (2^(classes - 1) blocks) */
#define REGION_LANES (W << (RT_DYN_REGION_CLASSES - 1))
#define SET_WORDS (REGION_LANES / 64)

/* The lanes of a slot for a leaf of cnt triangles. */
static uint32_t slot_lanes(uint32_t cnt)
{
    static const uint8_t lanes[2 * W + 1] = {1, 1, 2, 4, 4, 8, 8, 8, 8,
                                             16, 16, 16, 16, 16, 16, 16, 16};
    if (cnt <= 2 * W) return lanes[cnt];
    return tt_tri_block_count(cnt) * W;
}

/* The lanes of slot [g, g + lanes) that hold a triangle cleared. */
static void slot_clear(const tt_rtc *c, uint64_t g, uint32_t lanes)
{
    for (uint64_t e = g + lanes; g < e; g++) {
        tt_tri_block *bk = (tt_tri_block *)c->block + g / W;
        const uint32_t l = (uint32_t)(g % W);
        if (bk->prim[l] == TT_INVALID_ID) continue;
        for (int q = 0; q < 9; q++) bk->v[q][l] = NAN;
        bk->prim[l] = TT_INVALID_ID;
    }
}

void rt_dyn_slot_clear(const tt_rtc *c, uint32_t packed)
{
    slot_clear(c, packed & RT_DYN_SLOT_LANE_MASK, (packed >> RT_DYN_SLOT_LANE_BITS) + 1);
}

uint32_t rt_dyn_region_need(rt_dyn *d, const tt_rtc *c, uint32_t n)
{
    const rt_builder *b = &d->b;
    const uint32_t *ch = rt_node_child(b, n);
    const int cnt = b->hdr[n].count;
    if (cnt == 0) return 1;
    uint32_t sum = 0;
    for (int i = 0; i < cnt; i++) {
        const uint32_t l = ch[i];
        sum += slot_lanes(b->hdr[l].count);
        /* a leaf that came from another region since the last sync: its
         * lanes there cleared now, before any region is written (the slot
         * is free there from now on) */
        if (c && d->rec_of[l] != n && d->grp_of[l] != TT_INVALID_ID) {
            slot_clear(c, d->grp_of[l], d->grp_hi[l]);
            d->grp_of[l] = TT_INVALID_ID;
        }
    }
    const uint32_t s0 = slot_lanes(b->hdr[ch[0]].count);
    sum -= s0;
    /* entry 0's block and the others packed after it (see above) */
    return s0 % W == 0 ? (s0 + sum + W - 1) / W : 1 + (sum + W - 1) / W;
}

/* Lanes [first, first + lanes) into the set. */
static inline void set_add(uint64_t *set, uint32_t first, uint32_t lanes)
{
    if ((first & 63) + lanes < 64) { /* every slot up to a block */
        set[first >> 6] |= ((1ull << lanes) - 1) << (first & 63);
        return;
    }
    while (lanes) {
        const uint32_t room = 64 - (first & 63), n = lanes < room ? lanes : room;
        set[first >> 6] |= (n == 64 ? ~0ull : (1ull << n) - 1) << (first & 63);
        first += n;
        lanes -= n;
    }
}

/* An empty set but for the lanes past the region's `blocks`. */
static void set_start(uint64_t *set, uint32_t blocks)
{
    memset(set, 0, SET_WORDS * sizeof *set);
    if (blocks * W < REGION_LANES) set_add(set, blocks * W, REGION_LANES - blocks * W);
}

/* The lowest free slot of `lanes` lanes starting in blocks [0, lim), or
 * -1: for a slot up to a block, the free lanes folded so that bit i says
 * lanes i .. i + lanes - 1 are free, at the slot size's alignment. */
static int find_slot(const uint64_t *set, uint32_t lanes, uint32_t lim)
{
    if (lanes <= W) {
        static const uint64_t align[4] = {~0ull, 0x5555555555555555ull, 0x1111111111111111ull,
                                          0x0101010101010101ull};
        const uint32_t a = lanes == 1 ? 0 : lanes == 2 ? 1 : lanes == 4 ? 2 : 3;
        for (uint32_t w = 0; w * 64 < lim * W; w++) {
            uint64_t f = ~set[w];
            for (uint32_t s = 1; s < lanes; s <<= 1) f &= f >> s;
            f &= align[a];
            if (lim * W < (w + 1) * 64) f &= (1ull << (lim * W - w * 64)) - 1;
            if (f) return (int)(w * 64 + (uint32_t)__builtin_ctzll(f));
        }
        return -1;
    }
    const uint32_t nb = lanes / W;
    for (uint32_t k = 0; k < lim && k + nb <= REGION_LANES / W; k++) {
        uint32_t j = 0;
        while (j < nb && !((set[(k + j) >> 3] >> ((k + j) & 7) * 8) & 0xff)) j++;
        if (j == nb) return (int)(k * W);
    }
    return -1;
}

/* Every entry placed anew: entry 0 at lane 0, the others largest first.
 * Returns 0 where they do not fit (cannot happen in a region of
 * rt_dyn_region_need's blocks within 2 M - 1 of its start). */
static int lay_out(const rt_builder *b, uint32_t n, uint32_t blocks, uint32_t lim,
                   uint32_t *slot, uint64_t *set)
{
    const uint32_t *ch = rt_node_child(b, n);
    const int cnt = b->hdr[n].count;
    set_start(set, blocks);
    uint32_t order[TT_RT_CAP], lanes[TT_RT_CAP];
    int m = 0;
    for (int i = 1; i < cnt; i++) { /* insertion sort by lanes, descending */
        const uint32_t s = slot_lanes(b->hdr[ch[i]].count);
        int j = m++;
        for (; j > 0 && lanes[j - 1] < s; j--) {
            lanes[j] = lanes[j - 1];
            order[j] = order[j - 1];
        }
        lanes[j] = s;
        order[j] = (uint32_t)i;
    }
    const uint32_t s0 = slot_lanes(b->hdr[ch[0]].count);
    if (s0 > blocks * W) return 0;
    slot[0] = 0;
    set_add(set, 0, s0);
    for (int k = 0; k < m; k++) {
        const int at = find_slot(set, lanes[k], lim);
        if (at < 0) return 0;
        slot[order[k]] = (uint32_t)at;
        set_add(set, (uint32_t)at, lanes[k]);
    }
    return 1;
}

tt_status rt_dyn_region_write(rt_dyn *d, const tt_rtc *c, const tt_scene *scene, uint32_t n,
                              uint32_t *ref)
{
    const rt_builder *b = &d->b;
    const uint32_t *ch = rt_node_child(b, n);
    const int cnt = b->hdr[n].count;
    /* a new region: every leaf placed (their old slots were in the old
     * region, cleared when it was freed, perhaps handed out since) */
    const int fresh = (d->grp_hi[n] & RT_DYN_REGION_FRESH) != 0;
    d->grp_hi[n] &= (uint8_t)~RT_DYN_REGION_FRESH;
    const uint32_t blocks = 1u << d->grp_hi[n], lim2 = 2 * c->M - 1;
    const uint32_t lim = blocks < lim2 ? blocks : lim2; /* slots start in blocks [0, lim) */
    const uint64_t base = (uint64_t)d->grp_of[n] * W;
    uint32_t slot[TT_RT_CAP];
    /* 0: to place; 1: in its slot, lanes to write (touched); 2: in its
     * slot, lanes as they are; 3: placed again where it was, lanes as they
     * are */
    uint8_t keep[TT_RT_CAP], work[TT_RT_CAP];
    int place = 0, nw = 0;
    const uint8_t *touched = d->touched;
    const uint32_t tcap = d->touched_cap;
    /* 1. the leaves that keep their slots (entry 0 only in block 0), their
     *    references; a leaf with a slot here has grp_of set
     *    (rt_dyn_region_need dropped those of leaves from elsewhere). On
     *    an edits frame most leaves of a touched region are untouched and
     *    cost only this loop. */
    for (int i = 0; i < cnt; i++) {
        const uint32_t l = ch[i], g = d->grp_of[l], k = b->hdr[l].count;
        int kp = !fresh && g != TT_INVALID_ID && k <= d->grp_hi[l] && (i > 0 || g - base < W);
        if (kp) {
            slot[i] = (uint32_t)(g - base);
            ref[i] = tt_rtc_leaf_ref(g / W, g % W, k);
            kp = l < tcap && touched[l] ? 1 : 2;
        }
        keep[i] = (uint8_t)kp;
        place += !kp;
        if (kp != 2) work[nw++] = (uint8_t)i;
    }
    /* 2. the others into free slots, entry 0 into block 0; none free: the
     *    region laid out again (a leaf that lands where it was, untouched,
     *    keeps its lanes) */
    if (place) {
        uint64_t set[SET_WORDS];
        set_start(set, blocks);
        for (int i = 0; i < cnt; i++)
            if (keep[i]) set_add(set, slot[i], d->grp_hi[ch[i]]);
        int ok = 1;
        for (int i = 0; i < cnt && ok; i++) {
            if (keep[i]) continue;
            const uint32_t sl = slot_lanes(b->hdr[ch[i]].count);
            const int at = find_slot(set, sl, i == 0 ? 1 : lim);
            ok = at >= 0;
            if (!ok) break;
            slot[i] = (uint32_t)at;
            set_add(set, slot[i], sl);
        }
        if (!ok) {
            if (!lay_out(b, n, blocks, lim, slot, set)) /* cannot happen: see lay_out */
                return tt_error(b->ctx, TT_ERR_INTERNAL,
                                "rtree update: the leaves of node %u do not fit its region", n);
            nw = 0;
            for (int i = 0; i < cnt; i++) { /* every slot handed out again */
                keep[i] = keep[i] == 2 && base + slot[i] == d->grp_of[ch[i]] ? 3 : 0;
                work[nw++] = (uint8_t)i;
            }
        }
        /* the old slots of the leaves that move cleared before any lane
         * is written (a new slot may overlap one) */
        for (int j = 0; j < nw && !fresh; j++) {
            const uint32_t l = ch[work[j]];
            if (keep[work[j]] == 0 && d->grp_of[l] != TT_INVALID_ID)
                slot_clear(c, d->grp_of[l], d->grp_hi[l]);
        }
    }
    /* 3. the lanes, slots and references of the leaves that changed or
     *    moved */
    tt_tri_block *blk = (tt_tri_block *)c->block;
    const uint64_t *stamp = d->lanes_trust ? scene->stamp : NULL, since = d->lanes_since;
    for (int j = 0; j < nw; j++) {
        const int i = work[j];
        const uint32_t l = ch[i], k = b->hdr[l].count, *id = rt_node_child(b, l);
        const uint64_t g0 = base + slot[i];
        ref[i] = tt_rtc_leaf_ref((uint32_t)(g0 / W), (uint32_t)(g0 % W), k);
        if (keep[i] == 3) {
            d->grp_hi[l] = (uint8_t)slot_lanes(k);
            continue;
        }
        for (uint32_t q = 0; q < k; q++) {
            const uint64_t g = g0 + q;
            tt_tri_block *bk = blk + g / W;
            const uint32_t lane = (uint32_t)(g % W);
            /* a leaf that kept its slot changed in a lane or two (an entry
             * added at the end, a removed one's place taken by the last):
             * the other lanes hold their triangles as they are, and their
             * lane_of names them already (a lane holds an id only as
             * written below or by the packer, both with lane_of, and the
             * lanes a leaf leaves are cleared; checked over 100 frames of
             * bunny and 40 of conference edits). The write for them was
             * ~10k L2 misses a conference edits frame (callgrind, 1 MB
             * LL: 0.432M -> 0.422M) */
            if (stamp && bk->prim[lane] == id[q] && stamp[id[q]] <= since) continue;
            d->lane_of[id[q]] = (uint32_t)g;
            const float *v = scene->tri + 9 * (size_t)id[q];
            const int dead = tt_tri_is_degenerate(v, v + 3, v + 6); /* as rtc_pack */
            for (int e = 0; e < 9; e++) bk->v[e][lane] = dead ? NAN : v[e];
            bk->prim[lane] = id[q];
        }
        d->last_blocks += tt_tri_block_count(k); /* its slot's blocks, written */
        if (keep[i] == 1) { /* it may have shrunk: the rest of its slot */
            slot_clear(c, g0 + k, d->grp_hi[l] - k);
        } else {
            d->grp_of[l] = (uint32_t)g0;
            d->grp_hi[l] = (uint8_t)slot_lanes(k);
            d->rec_of[l] = n;
        }
    }
    return TT_OK;
}
