/* What a built structure offers, asked of its vtable (never of its name):
 * the engine table says whether packets=on can differ from packets=off. */
#include "accel/accel.h"
#include "bench/bench_yard.h"

int yard_packets_offered(const tt_accel *accel)
{
    return accel && accel->vt && (accel->vt->intersect_packet || accel->vt->occluded_packet) &&
           (!accel->vt->packets_for || accel->vt->packets_for(accel));
}
