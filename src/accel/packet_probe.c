/* tt_packet_probe (packet_probe.h): when to ask the structure, and what its
 * answers make of the items between. */
#include <string.h>

#include "accel/packet_probe.h"

void tt_packet_probe_init(tt_packet_probe *pp, const tt_accel *accel, int closest)
{
    const tt_accel_vtable *vt = accel->vt;
    memset(pp, 0, sizeof *pp);
    pp->asks = vt->packets_pay &&
               (closest ? vt->intersect_packet_stats != NULL : vt->occluded_packet_stats != NULL);
    pp->pay = 1;
    pp->gap = TT_PROBE_GAP_MIN / 2u;
}

int tt_packet_probe_trace(tt_packet_probe *pp, const tt_accel *accel, const tt_packet_rays *pr,
                          tt_hit *hits, uint8_t *occ, int *packet, tt_packet_stats *sum)
{
    if (!pp->asks) return 0;
    if (pp->coherent++ != pp->next) {
        *packet = pp->pay;
        return 0;
    }
    const tt_accel_vtable *vt = accel->vt;
    tt_packet_stats ps;
    memset(&ps, 0, sizeof ps);
    if (hits) vt->intersect_packet_stats(accel, pr, hits, &ps);
    else vt->occluded_packet_stats(accel, pr, occ, &ps);
    if (sum) {
        tt_ray_stats_add(&sum->rays, &ps.rays);
        sum->packets += ps.packets;
        sum->node_visits += ps.node_visits;
        sum->active_lanes += ps.active_lanes;
        sum->fallback_rays += ps.fallback_rays;
    }
    /* Packets stop only after two "no"s in a row: one item is a small
     * sample (a tile of a coherent view can fall below the structure's bound
     * alone: test_packet_rule saw Sibenik's shadow batches lose a fifth of
     * their packets to single "no"s), a batch that does not pay says it
     * again at the next probe. */
    pp->noes = vt->packets_pay(accel, hits == NULL, &ps) ? 0 : pp->noes + 1;
    const int pay = pp->noes < 2;
    /* (after a first "no" the next item is probed) */
    pp->gap = pp->noes == 1 ? 1u
              : pay == pp->pay ? (pp->gap * 2u < TT_PROBE_GAP_MAX ? pp->gap * 2u : TT_PROBE_GAP_MAX)
                               : TT_PROBE_GAP_MIN;
    pp->pay = pay;
    pp->next = pp->coherent - 1u + pp->gap;
    return 1;
}
