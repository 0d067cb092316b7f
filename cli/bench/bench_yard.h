/* The engine table's yardstick (`treetrace bench --only E`): our public
 * batch calls against Embree 3 in its own tight loop over the same ray
 * arrays, the way Embree's users run it (issue 17), with Embree's packets
 * beside it (issue 18). Per scene and view:
 *   - the rays: a view's primary rays (tt_camera_rays), the shadow rays of
 *     their hits (tt_shadow_ray, the conventions' rule) and ambient-occlusion
 *     rays (a few cosine-distributed directions from each hit);
 *   - our side: tt_intersect (image_width set) / tt_occluded per structure,
 *     with tt_batch_options.packets auto, off and on;
 *   - Embree's side (bench_embree.h): rtcIntersect1 / rtcOccluded1 with the
 *     default scene flags at medium build quality (the headline), the same
 *     with RTC_SCENE_FLAG_ROBUST, and 8- and 16-wide coherent packets;
 *   - interleaved rounds, the minimum time of each measurement; builds the
 *     minimum of several; memory; agreement with Embree, with bruteforce on
 *     a sample, and bit-identity with the default R-tree.
 * Files: bench_yard_rays.c (rays), bench_yard_run.c (builds, rounds),
 * bench_yard_check.c (agreement), bench_yard_caps.c (packets offered),
 * bench_yard_csv.c (engine.csv), bench_report_engine.c (report.md). */
#ifndef TT_CLI_BENCH_YARD_H
#define TT_CLI_BENCH_YARD_H

#include "bench/bench.h"

typedef enum yard_kind { YARD_PRIMARY = 0, YARD_SHADOW, YARD_AO, YARD_KINDS } yard_kind;

/* Our packet modes, in tt_batch_options.packets order of the report. */
typedef enum yard_mode { YARD_AUTO = 0, YARD_OFF, YARD_ON, YARD_MODES } yard_mode;

/* Embree's sides: single rays with default flags (the reference), single
 * rays with ROBUST, 8- and 16-wide packets (default flags). */
typedef enum yard_side {
    YARD_E_SINGLE = 0,
    YARD_E_ROBUST,
    YARD_E_P8,
    YARD_E_P16,
    YARD_SIDES
} yard_side;

/* AO rays: this many directions per primary hit, up to this fraction of
 * the scene's bounding-box diagonal, from this seed. */
#define YARD_AO_DEFAULT_SAMPLES 2
#define YARD_AO_RADIUS 0.1f
#define YARD_AO_SEED 0x7474616fu /* "ttao" */
/* Bruteforce retraces per kind: an even sample and, on top, up to this many
 * rays that disagree with Embree. */
#define YARD_BRUTEFORCE_SAMPLE 128
#define YARD_BRUTEFORCE_DISAGREE 128

const char *yard_kind_name(yard_kind k);  /* "primary", "shadow", "ao"   */
const char *yard_mode_name(yard_mode m);  /* "auto", "off", "on"         */
uint32_t yard_mode_packets(yard_mode m);  /* TT_PACKETS_*                */
const char *yard_side_name(yard_side s);  /* "single", "robust", "p8" .. */

/* One of our structures on one view. */
typedef struct yard_config {
    int ok; /* built and traced; 0: error holds why                      */
    char error[256];
    double build_s; /* minimum over the builds                           */
    size_t memory_bytes;
    tt_isa isa;
    int packets_offered; /* the vtable has packet entries                */
    double sah_cost;     /* NaN when the structure reports none           */
    double best_s[YARD_MODES][YARD_KINDS];
    /* agreement, per kind (over the rays of the packets=auto pass) */
    uint64_t agree_embree[YARD_KINDS];
    uint64_t bf_checked[YARD_KINDS], bf_equal[YARD_KINDS];
    uint64_t same_as_reference[YARD_KINDS];
    /* rays whose answer with packets off / on differs from auto's (must
     * stay 0: results never depend on the packet mode) */
    uint64_t mode_mismatch[YARD_MODES][YARD_KINDS];
    /* counting pass (primary, shadow): per-ray averages; NaN if none */
    double nodes_per_ray[YARD_KINDS], triangles_per_ray[YARD_KINDS];
} yard_config;

/* Embree on one view; NaN where not measured (AO: single rays only). */
typedef struct yard_embree {
    int ok; /* 0: error holds why ("not in this build" without Embree) */
    char error[256];
    double build_s[2]; /* default flags, robust; minimum over the builds */
    size_t memory_bytes[2];
    double best_s[YARD_SIDES][YARD_KINDS];
} yard_embree;

typedef struct yard_view {
    size_t scene, view;
    size_t triangles;
    uint64_t rays[YARD_KINDS];
    uint64_t primary_hits, shadow_occluded, ao_occluded; /* the reference's */
    yard_embree embree;
    yard_config *configs; /* parallel to bench_engine_configs()            */
} yard_view;

typedef struct bench_yard {
    yard_view *views;
    size_t count;
    bench_size size;
    int rounds, builds, ao_samples, threads;
    char embree_version[64]; /* "Embree 3.13.5", or why there is none    */
    double total_s;
} bench_yard;

/* The engine table's structures, in order: the default R-tree (SAH +
 * compact; the reference whose hits make the shadow and AO rays), the
 * default kd-tree (exact build, HTR), the binned kd-tree, Feldmann's
 * R-tree (insertion, complete layout); the library's defaults otherwise. */
typedef struct bench_engine_config {
    char label[64];
    tt_build_options build;
} bench_engine_config;
const bench_engine_config *bench_engine_configs(size_t *count);
/* Whether b is the library's default of its structure. */
int bench_engine_is_default(const tt_build_options *b);

/* Measures every scene and view (the scenes are loaded here, one at a
 * time). Returns 0, or -1 on a failure that stops the benchmark (out of
 * memory); a view or structure that fails is recorded and the run goes on. */
int bench_yard_run(tt_context *ctx, const bench_options *o, const bench_scene_list *scenes,
                   bench_yard *out, FILE *err);
void bench_yard_free(bench_yard *y);
/* engine.csv, documented in bench_yard_csv.c. */
int bench_yard_write_csv(const char *path, const bench_scene_list *s, const bench_yard *y,
                         FILE *err);

/* Rays (bench_yard_rays.c). AO ray j of primary hit i: the shadow-ray
 * convention's offset origin, a cosine-distributed direction about the
 * normal facing the primary ray, [0, radius * diagonal), random numbers
 * from a hash of (seed, ray index), so the batch never depends on threads.
 * Returns the count written (hits * samples at most). */
size_t yard_ao_rays(const tt_scene *scene, const tt_ray *primary, const tt_hit *hits, size_t n,
                    int samples, tt_ray *out);
/* The shadow rays of the hits (compacted, image order); the count. */
size_t yard_shadow_rays(const tt_scene *scene, const tt_camera *cam, const tt_ray *primary,
                        const tt_hit *hits, size_t n, tt_ray *out);

/* Whether ours is timed with packet mode m on ray kind k: auto always;
 * off and on only when the structure offers packets (otherwise all three
 * run the same single-ray code); on not for AO rays, which are incoherent
 * by design (auto against off is what the AO column must show). */
int yard_measured(const yard_config *c, yard_mode m, int k);

/* Whether the built structure's vtable offers packet traversal
 * (bench_yard_caps.c): only then can off and on differ. */
int yard_packets_offered(const tt_accel *accel);

/* Agreement (bench_yard_check.c). */
/* raybench's rule: the same triangle (both misses count). */
uint64_t yard_agree_hits(const tt_hit *a, const tt_hit *b, size_t n);
uint64_t yard_agree_flags(const uint8_t *a, const uint8_t *b, size_t n);
/* Bit-identical: prim, t, u and v. */
uint64_t yard_same_hits(const tt_hit *a, const tt_hit *b, size_t n);
/* The rays bruteforce retraces: an even sample of n plus up to
 * YARD_BRUTEFORCE_DISAGREE where `disagree` (may be NULL) is set; sorted,
 * unique. Returns the count (<= cap of idx). */
size_t yard_pick_rays(size_t n, const uint8_t *disagree, size_t *idx, size_t cap);
/* Bruteforce's answers for the picked rays (intersect: hits, else flags).
 * Returns TT_OK or the failing call's status. */
tt_status yard_bruteforce(const tt_accel *bf, const tt_ray *rays, const size_t *idx, size_t m,
                          tt_hit *hits, uint8_t *flags);

#endif
