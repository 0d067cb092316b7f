/* The structure's word on packets (vt->packets_pay), asked now and then
 * while a thread of a batch call (batch.c) traces coherent items.
 *
 * Which items a thread probes depends on which items it met before, so
 * under auto the packet counts (and the choice between packets and single
 * rays where a structure says no) can differ from run to run; the answers
 * never do. The renderer does not probe: its counting pass must give the
 * same counts every run (a frame's statistics are compared between runs,
 * test_accel_io), and a per-thread probe made them depend on the tiles'
 * schedule.
 *
 * A coherent item is now and then traced by the counting packet variant
 * and its counts judged; the items between follow the last answer. The gap
 * between probes doubles while the answer holds (up to
 * TT_PROBE_GAP_MAX coherent items) and falls back to TT_PROBE_GAP_MIN
 * when it changes, so a batch of one kind pays a handful of probes (bench
 * D's bunny, 512^2: about 7 of a thread's 210 shadow items; instructions
 * of a shadow batch whose probes all say yes, callgrind: Cornell, Sibenik
 * +0.05%), and a batch whose kind changes halfway is caught within
 * TT_PROBE_GAP_MAX of its items. One probe state per thread and pass. */
#ifndef TT_ACCEL_PACKET_PROBE_H
#define TT_ACCEL_PACKET_PROBE_H

#include <stdint.h>

#include "accel/accel.h"

#define TT_PROBE_GAP_MIN 4u
#define TT_PROBE_GAP_MAX 64u

typedef struct tt_packet_probe {
    int asks;           /* the structure has a word for this ray kind  */
    int pay;            /* the last answer (1 before any probe)        */
    int noes;           /* the structure's "no"s in a row              */
    uint32_t coherent;  /* coherent items this thread has met          */
    uint32_t next, gap; /* the coherent item to probe next, the gap    */
} tt_packet_probe;

/* closest: closest-hit items (else occlusion). A structure without
 * packets_pay, or without the counting packet variant of the kind, is
 * never asked. */
void tt_packet_probe_init(tt_packet_probe *pp, const tt_accel *accel, int closest);

/* For a coherent item about to go as a packet: when it is the one to probe,
 * traces it by the counting packet variant (hits for closest-hit probes,
 * else occ), adds the counts to *sum when sum is not NULL, and returns 1;
 * else returns 0 and sets *packet to the last answer (leaves it alone for a
 * structure that is never asked). */
int tt_packet_probe_trace(tt_packet_probe *pp, const tt_accel *accel, const tt_packet_rays *pr,
                          tt_hit *hits, uint8_t *occ, int *packet, tt_packet_stats *sum);

#endif
