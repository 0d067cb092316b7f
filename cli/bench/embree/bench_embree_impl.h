/* The Embree side's state, shared by its two files (scene, trace). */
#ifndef TT_CLI_BENCH_EMBREE_IMPL_H
#define TT_CLI_BENCH_EMBREE_IMPL_H

#include <embree3/rtcore.h>
#include <stdatomic.h>

struct bench_embree {
    RTCDevice device;
    RTCScene scene;
    atomic_llong bytes; /* live bytes, from the memory monitor          */
    atomic_int error_claimed;
    char error[256];
};

#endif
