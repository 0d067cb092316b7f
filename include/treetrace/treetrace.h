/*
 * treetrace: ray tracing triangle scenes through R-trees (Feldmann 2015) and
 * kd-trees with sparse boxes (Havran & Bittner 2007).
 *
 * The API follows the shape of Embree's rtcore: opaque handles with
 * create/destroy pairs, an explicit context (threads, allocator, error
 * callback), status codes on every call and a last-error message on the
 * context naming the cause. The library never prints, exits or aborts.
 *
 * Typical use (examples/quickstart.c is this as a whole program, with its
 * error handling; the tests build and run it):
 *   tt_context *ctx; tt_context_create(NULL, &ctx);
 *   tt_scene *scene; tt_scene_load(ctx, "bunny.ply", &scene);
 *   tt_build_options opt; tt_build_options_default(&opt); opt.accel = "rtree";
 *   tt_accel *acc; tt_accel_build(ctx, scene, &opt, &acc);
 *   tt_ray ray = {...}; tt_hit hit; tt_intersect1(acc, &ray, &hit);
 *   tt_accel_destroy(acc); tt_scene_destroy(scene); tt_context_destroy(ctx);
 * Batches of rays: tt_intersect / tt_occluded (below).
 */
#ifndef TREETRACE_H
#define TREETRACE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Everything declared here is the shared library's interface: the library
 * is compiled with hidden visibility, so only these tt_ functions are
 * exported (libtreetrace.so); internal functions stay internal. */
#if defined(__GNUC__) || defined(__clang__)
#pragma GCC visibility push(default)
#endif

#define TT_VERSION_MAJOR 0
#define TT_VERSION_MINOR 1
#define TT_VERSION_PATCH 0
#define TT_VERSION_STRING "0.1.0"

/* ------------------------------------------------------------------ status */

typedef enum tt_status {
    TT_OK = 0,
    TT_ERR_INVALID_ARGUMENT, /* a caller passed a bad value                  */
    TT_ERR_OUT_OF_MEMORY,    /* an allocation failed                         */
    TT_ERR_IO,               /* a file could not be opened or read           */
    TT_ERR_PARSE,            /* a file's content is malformed                */
    TT_ERR_UNSUPPORTED,      /* not available in this build (Embree, CUDA)   */
    TT_ERR_NO_DEVICE,        /* no usable GPU at run time                    */
    TT_ERR_INVARIANT,        /* tt_accel_check found a broken invariant      */
    TT_ERR_INTERNAL,
    TT_ERR_BUSY,             /* a scene edit or structure update overlapped   */
                             /* traces on another thread (see scene edits)    */
    TT_ERR_STALE             /* the structure predates the scene's last edit: */
                             /* tt_accel_update it first                      */
} tt_status;

/* A short constant description of a status ("out of memory"). */
const char *tt_strerror(tt_status status);
const char *tt_version(void);

/* ----------------------------------------------------------------- context */

typedef struct tt_context tt_context;

/* Allocator hooks; all three must be set, or all NULL for the C library's. */
typedef struct tt_allocator {
    void *(*alloc)(void *user, size_t size);
    void *(*realloc)(void *user, void *ptr, size_t size);
    void (*free)(void *user, void *ptr);
    void *user;
} tt_allocator;

/* Called once for every error the library reports, with the full message. */
typedef void (*tt_error_fn)(void *user, tt_status status, const char *message);

typedef struct tt_context_options {
    int threads;            /* 0: OpenMP's default                           */
    tt_allocator allocator; /* all NULL: malloc/realloc/free                 */
    tt_error_fn on_error;   /* may be NULL                                   */
    void *on_error_user;
} tt_context_options;

void tt_context_options_default(tt_context_options *options);
/* options may be NULL for the defaults. */
tt_status tt_context_create(const tt_context_options *options, tt_context **out);
void tt_context_destroy(tt_context *ctx);
/* The message of the last error reported on this context ("" if none). */
const char *tt_context_last_error(const tt_context *ctx);
int tt_context_threads(const tt_context *ctx);

/* ------------------------------------------------------------------- scene */

typedef struct tt_scene tt_scene;

/* Loads an OBJ or PLY file (by content: a PLY starts with "ply\n"). Errors
 * name the file and the line (or byte offset) and what is wrong. */
tt_status tt_scene_load(tt_context *ctx, const char *path, tt_scene **out);
/* The same from memory; `name` is used in error messages. `format` is "obj",
 * "ply" or NULL to detect. */
tt_status tt_scene_load_memory(tt_context *ctx, const char *name, const char *format,
                               const void *data, size_t size, tt_scene **out);
/* A scene from arrays: vertices are x,y,z triples, indices are triples. */
tt_status tt_scene_create(tt_context *ctx, const float *vertices, size_t vertex_count,
                          const uint32_t *indices, size_t triangle_count, tt_scene **out);
void tt_scene_destroy(tt_scene *scene);
size_t tt_scene_triangle_count(const tt_scene *scene);
size_t tt_scene_vertex_count(const tt_scene *scene);
void tt_scene_bounds(const tt_scene *scene, float min[3], float max[3]);
/* Triangle i's three vertices (9 floats). */
tt_status tt_scene_triangle(const tt_scene *scene, size_t i, float out[9]);

/* ------------------------------------------------------------ scene arrays */

/* The scene's arrays copied out in one call (for bindings such as numpy,
 * which would otherwise call tt_scene_triangle once per triangle). Each
 * pointer may be NULL to skip that array:
 *   vertices   vertex_capacity >= tt_scene_vertex_count: 3 floats a vertex
 *   indices    triangle_capacity >= tt_scene_triangle_count: 3 vertex ids a
 *              triangle, load order
 *   triangles  triangle_capacity as above: 9 floats a triangle (v0, v1, v2),
 *              what tt_scene_triangle gives for each
 * A capacity below the scene's count is TT_ERR_INVALID_ARGUMENT (nothing is
 * written), so a stale size cannot overrun the caller's arrays. */
tt_status tt_scene_copy_arrays(const tt_scene *scene, float *vertices, size_t vertex_capacity,
                               uint32_t *indices, float *triangles, size_t triangle_capacity);
/* The geometric normals of `count` triangles (hit results' prim ids):
 * normalize(cross(v1 - v0, v2 - v0)) of each, 3 floats to normals[3 i];
 * (0, 0, 0) for TT_INVALID_ID (a miss) and for a degenerate triangle. Any
 * other id past the scene's triangles is TT_ERR_INVALID_ARGUMENT, naming
 * its index (the normals before it are written). */
tt_status tt_scene_normals(const tt_scene *scene, const uint32_t *prims, size_t count,
                           float *normals);

/* --------------------------------------------------------------- rays, hits */

#define TT_INVALID_ID 0xFFFFFFFFu

/* Rays cover t in [tmin, tmax), the points org + t * dir. dir need not be
 * normalized. The contract every structure (Embree included) is held to:
 * - org and dir finite; dir's largest component at least 2^-80 (about
 *   8.3e-25) in magnitude: below it 1/d and the watertight test's terms leave
 *   float range (a zero direction is the extreme case). Scale a shorter
 *   direction up; t scales down with it;
 * - 0 <= tmin: rays start at their origin (as in Embree); to find hits behind
 *   a point, move the origin back instead;
 * - tmax may be +inf; tmin >= tmax is a legal empty interval (a miss, not
 *   occluded);
 * - NaN in tmin or tmax, a negative tmin (also -inf), a non-finite origin or
 *   direction, or a zero or too short direction: tt_intersect1(_ex) / tt_occluded1(_ex)
 *   return TT_ERR_INVALID_ARGUMENT with a message naming the cause. */
typedef struct tt_ray {
    float org[3];
    float tmin;
    float dir[3];
    float tmax;
} tt_ray;

typedef struct tt_hit {
    float t;       /* +inf on a miss                                         */
    float u, v;    /* barycentrics of vertices 1 and 2                        */
    uint32_t prim; /* triangle id in load order; TT_INVALID_ID on a miss      */
} tt_hit;

/* Per-ray traversal statistics, summed over the rays traced with them. */
typedef struct tt_ray_stats {
    uint64_t rays;
    uint64_t nodes;     /* nodes visited (interior + leaves)                  */
    uint64_t interior;  /* interior nodes visited (N_I)                       */
    uint64_t leaves;    /* leaves visited (N_L)                               */
    uint64_t boxes;     /* ray-box tests                                      */
    uint64_t triangles; /* ray-triangle tests (r_ITM)                         */
} tt_ray_stats;

/* --------------------------------------------------- acceleration structures */

typedef struct tt_accel tt_accel;

typedef enum tt_rtree_strategy {
    TT_RTREE_MIN_VOLUME = 0,
    TT_RTREE_MIN_SURFACE,
    TT_RTREE_MIN_OVERLAP,
    TT_RTREE_RSTAR,
    TT_RTREE_RSTAR_SURFACE,
    /* The RR*-tree's choice of subtree (Beckmann & Seeger 2009): an entry
     * that already covers the box (the smallest), else among the entries
     * by perimeter enlargement those whose growth would overlap the first,
     * the one adding the least overlap (volume, or perimeter where a box
     * is flat). Splits and forced reinsert as configured. */
    TT_RTREE_RRSTAR
} tt_rtree_strategy;

typedef enum tt_rtree_split { TT_RTREE_SPLIT_RSTAR = 0, TT_RTREE_SPLIT_QUADRATIC } tt_rtree_split;

typedef enum tt_rtree_traversal {
    TT_RTREE_AUTO = 0, /* ordered when the eye is outside the root box        */
    TT_RTREE_STACKLESS,
    TT_RTREE_ORDERED,
    TT_RTREE_STACK
} tt_rtree_traversal;

/* How the R-tree is built: by insertion (Feldmann 2015: Guttman / R*-tree
 * with the strategies above, forced reinsert), or bulk-loaded for a static
 * scene: STR (Leutenegger et al. 1997), Hilbert-sorted packing (Kamel &
 * Faloutsos 1993) or top-down by the surface area heuristic. Every builder
 * keeps the R-tree's rules: all leaves on one level, m..M entries a node. */
typedef enum tt_rtree_build {
    TT_RTREE_BUILD_INSERT = 0,
    TT_RTREE_BUILD_STR,
    TT_RTREE_BUILD_HILBERT,
    TT_RTREE_BUILD_SAH
} tt_rtree_build;

/* Where the built tree lives: the paper's complete M-ary level-order array
 * (empty slots included; stackless index arithmetic), or the compact wide
 * layout of real nodes only (child boxes in SoA, triangles in SIMD blocks). */
typedef enum tt_rtree_layout {
    TT_RTREE_LAYOUT_COMPLETE = 0,
    TT_RTREE_LAYOUT_COMPACT
} tt_rtree_layout;

typedef struct tt_rtree_options {
    tt_rtree_build build;       /* default TT_RTREE_BUILD_SAH                  */
    tt_rtree_layout layout;     /* default TT_RTREE_LAYOUT_COMPACT             */
    tt_rtree_strategy strategy; /* default TT_RTREE_RSTAR_SURFACE              */
    int m, M;                   /* default 2, 0; 2 <= m <= M/2, 4 <= M <= 16;  */
                                /* M = 0: tt_rtree_max_entries's choice       */
    int reinsert;               /* forced reinsert, default 1                  */
    float reinsert_fraction;    /* p = fraction * (M+1), >= 1; default 0.3     */
    int reinsert_far;           /* 1: far reinsert (default), 0: close         */
    tt_rtree_split split;
    tt_rtree_traversal traversal;
    /* Early split clipping (SAH loader, compact layout only; the other
     * builders ignore it): long thin triangles are cut into pieces with
     * tighter boxes before the build, up to split_budget x the triangle
     * count extra references; a triangle may then sit in several leaves
     * (once a leaf), and tt_accel_update rebuilds such a tree instead of
     * updating it in place (tt_accel_updates_in_place says 0). 0: off.
     * Range [0, 4]; default 0. */
    float split_budget;
} tt_rtree_options;

/* The exact SAH builders (Wald & Havran 2006) give the identical tree;
 * TT_KD_BINNED approximates the SAH with binned candidates (faster build). */
/* The R-tree's M for these options: M itself, or for M = 0 (the default)
 * 16 in the compact layout (the fastest measured with the SAH loader) and 4,
 * Feldmann's, in the complete one (whose size grows as M^height). */
int tt_rtree_max_entries(const tt_rtree_options *options);

typedef enum tt_kd_builder { TT_KD_NLOGN = 0, TT_KD_NLOG2N, TT_KD_BINNED } tt_kd_builder;

typedef enum tt_kd_traversal {
    TT_KD_HTR = 0, /* stack-based hierarchical (Algorithm 1)                  */
    TT_KD_BTR,     /* bottom-up with a stack (Algorithm 2)                    */
    TT_KD_SLTR,    /* stackless bottom-up (Algorithm 3)                       */
    TT_KD_SEQ      /* Kaplan's sequential point location                      */
} tt_kd_traversal;

/* Havran & Bittner's d_min, what dmin = 0 gives traversals that use boxes. */
#define TT_KD_DMIN_BOXES 4

typedef struct tt_kdtree_options {
    tt_kd_builder builder;  /* default TT_KD_NLOGN                             */
    int dmin;               /* >= 1: a sparse box every dmin levels; < 0: only */
                            /* the root's box; 0 (default): auto, none for    */
                            /* htr (it reads no boxes), TT_KD_DMIN_BOXES for  */
                            /* the others; resolved in the built accel        */
    float cost_traversal;   /* SAH C_T, default 1                              */
    float cost_intersect;   /* SAH C_I, default 0.2 (the papers' tables: 1.5)  */
    float empty_bonus;      /* in [0, 1): a split with an empty side costs    */
                            /* (1 - bonus) x; default 0.2 (W&H's 0.8 factor)  */
    int max_depth;          /* 0: automatic (8 + 1.3 log2 N)                   */
    tt_kd_traversal traversal;
    int shadow_caster_hint; /* 1: an occlusion ray first searches the box of  */
                            /* the last caster, passed in args->end_hint (not */
                            /* with htr, which uses no boxes); default 0      */
} tt_kdtree_options;

/* The d_min these options build with: dmin itself, or for dmin = 0 (auto)
 * -1 (no boxes) with htr and TT_KD_DMIN_BOXES with the other traversals. */
int tt_kdtree_dmin(const tt_kdtree_options *options);

/* The SIMD instruction set a structure's kernels use. One binary holds the
 * kernels of every ISA (compiled in separate units); TT_ISA_AUTO picks the
 * best one this CPU supports, once, at build time of the structure. Every
 * path returns the same hits (the watertight test, bit for bit). */
typedef enum tt_isa {
    TT_ISA_AUTO = 0,
    TT_ISA_SCALAR, /* portable C: also the code the GPU runs                  */
    TT_ISA_SSE42,
    TT_ISA_AVX2,   /* AVX2 + FMA                                             */
    TT_ISA_AVX512  /* AVX-512 F, VL, BW, DQ                                  */
} tt_isa;

/* "auto", "scalar", "sse4.2", "avx2", "avx512"; "" for an unknown value. */
const char *tt_isa_name(tt_isa isa);
/* 1 and *out for a known name ("auto" included), 0 for an unknown one. */
int tt_isa_from_name(const char *name, tt_isa *out);
/* 1 when this build has kernels for isa and this CPU can run them. */
int tt_isa_supported(tt_isa isa);
/* The best ISA tt_isa_supported accepts (what TT_ISA_AUTO resolves to). */
tt_isa tt_isa_best(void);

/* Embree's BVH build quality (RTC_BUILD_QUALITY_*). The papers' tables
 * compare with HIGH (spatial splits); the engine targets, as Embree's users
 * build by default, with MEDIUM. */
typedef enum tt_embree_quality {
    TT_EMBREE_HIGH = 0,
    TT_EMBREE_MEDIUM,
    TT_EMBREE_LOW
} tt_embree_quality;

typedef struct tt_embree_options {
    tt_embree_quality quality; /* default TT_EMBREE_HIGH                      */
} tt_embree_options;

typedef struct tt_build_options {
    const char *accel; /* "bruteforce", "rtree", "kdtree", "embree"           */
    tt_isa isa;        /* default TT_ISA_AUTO                                 */
    tt_rtree_options rtree;
    tt_kdtree_options kdtree;
    tt_embree_options embree;
} tt_build_options;

void tt_build_options_default(tt_build_options *options);

/* Names of the structures this build offers, NULL-terminated. */
const char *const *tt_accel_names(void);

tt_status tt_accel_build(tt_context *ctx, const tt_scene *scene,
                         const tt_build_options *options, tt_accel **out);
void tt_accel_destroy(tt_accel *accel);
const char *tt_accel_name(const tt_accel *accel);
double tt_accel_build_seconds(const tt_accel *accel);
/* The ISA the structure's kernels run on (TT_ISA_AUTO resolved). */
tt_isa tt_accel_isa(const tt_accel *accel);
size_t tt_accel_memory_bytes(const tt_accel *accel);
/* Verifies every invariant of the built structure; TT_ERR_INVARIANT with the
 * context's last error naming the first broken one. */
tt_status tt_accel_check(const tt_accel *accel);

/* The structure's statistics as key/value pairs (height, nodes, SAH cost ...). */
typedef void (*tt_stat_fn)(void *user, const char *key, double value);
tt_status tt_accel_statistics(const tt_accel *accel, tt_stat_fn fn, void *user);

/* Closest hit on [tmin, tmax). Rejects rays breaking tt_ray's contract
 * (non-finite origin/direction, zero or too short direction, NaN interval ends, negative
 * tmin) with TT_ERR_INVALID_ARGUMENT. */
tt_status tt_intersect1(const tt_accel *accel, const tt_ray *ray, tt_hit *hit);
/* Any hit on [tmin, tmax): *occluded = 1 or 0. */
tt_status tt_occluded1(const tt_accel *accel, const tt_ray *ray, int *occluded);

/* Extended calls: a start hint (kd-tree: the augmented node to start from,
 * TT_INVALID_ID for the root), the node where the ray ended on return, and
 * statistics accumulated into *stats when stats is not NULL. */
typedef struct tt_trace_args {
    uint32_t start_hint;
    uint32_t end_hint;
    tt_ray_stats *stats;
} tt_trace_args;

tt_status tt_intersect1_ex(const tt_accel *accel, const tt_ray *ray, tt_hit *hit,
                           tt_trace_args *args);
tt_status tt_occluded1_ex(const tt_accel *accel, const tt_ray *ray, int *occluded,
                          tt_trace_args *args);
/* The start hint for rays from one point (e.g. all primary rays from the eye). */
uint32_t tt_accel_locate(const tt_accel *accel, const float point[3]);

/* -------------------------------------------------------- saved structures */

/* A built structure saved to a file and loaded back instead of rebuilt
 * (format: docs/accel-file.md). The file is tied to the scene's content (a
 * hash of its triangles) and to this library's layouts (versions, byte
 * order, SIMD block width); a checksum covers all of it. Loading maps the
 * file read-only and uses the structure's arrays in place, so processes
 * loading one file share its pages; a loaded structure traces bit for bit
 * like the one saved. Every structure but embree can be saved (Embree's
 * BVH lives inside Embree, which offers no way to save it):
 * TT_ERR_UNSUPPORTED says so. scene_name (may be NULL) is stored for
 * messages: a load for another scene names it. */
tt_status tt_accel_save(const tt_accel *accel, const char *path, const char *scene_name);
/* Loads a structure saved for `scene` (the same triangles, checked), its
 * kernels chosen for `isa` (TT_ISA_AUTO: this CPU's best; the layout is
 * the same for every ISA). A damaged, truncated, foreign or hostile file
 * gives TT_ERR_PARSE / TT_ERR_UNSUPPORTED / TT_ERR_INVALID_ARGUMENT (another
 * scene) / TT_ERR_IO with a message naming the file and what is wrong. The
 * loaded structure reports its build options as saved;
 * tt_accel_build_seconds is the time the load took. */
tt_status tt_accel_load(tt_context *ctx, const tt_scene *scene, const char *path, tt_isa isa,
                        tt_accel **out);
/* 1 for a structure that came from tt_accel_load. */
int tt_accel_loaded(const tt_accel *accel);
/* The build options a structure was built with (for a loaded one: as
 * saved), accel name included; *out's strings live as long as the accel. */
tt_status tt_accel_options(const tt_accel *accel, tt_build_options *out);

/* ----------------------------------------------------------------- batches */

/* Batches trace n rays on the context's threads (tt_context_options.threads;
 * OpenMP) and write one result per ray. Every result equals what
 * tt_intersect1_ex / tt_occluded1_ex give for that ray with the same start
 * hint (with the default options: tt_intersect1 / tt_occluded1), whatever
 * the structure, ISA or thread count.
 *
 * Errors: NULL accel, NULL rays or results with n > 0, or bad options
 * return TT_ERR_INVALID_ARGUMENT before tracing anything. A ray breaking
 * tt_ray's contract does not stop the batch: that ray gets a miss (t +inf,
 * u = v = 0, prim TT_INVALID_ID; not occluded) and, when ray_status is not
 * NULL, ray_status[i] = TT_ERR_INVALID_ARGUMENT (TT_OK for the others);
 * every other ray is traced as usual; the call then returns
 * TT_ERR_INVALID_ARGUMENT with the context's message naming the first bad
 * ray's index and cause ("ray 17 of 100: ray with a negative tmin ..."). */
typedef struct tt_batch_options {
    /* Start hint of every ray (kd-tree: e.g. tt_accel_locate of the rays'
     * common origin); TT_INVALID_ID (default): the structure's root. */
    uint32_t start_hint;
    /* When not NULL, the counting variant traces the batch and adds the
     * rays' counts here (slower; the default fast path never counts). */
    tt_ray_stats *stats;
    /* Consecutive rays a thread takes at a time; 0 (default): up to 256,
     * fewer for small batches so that every thread gets work. An occlusion
     * batch traced with packets, with chunk and image_width 0, of at least
     * 1024 rays whose sampled rays share a far end or a direction (the
     * shadow rays of a camera's hits in image order, misses left out)
     * instead has its image rows found from its origins and is taken as 8
     * rows x 32 columns at a time; a wrong guess changes speed only. */
    uint32_t chunk;
    /* 0 (default), or the width of an image whose rows the rays are
     * (row-major, like tt_camera_rays'): threads then take 16 x 16 tiles of
     * it instead of runs of consecutive rays, as tt_render does; neighbours
     * in 2D visit the same nodes, so coherent rays trace faster. Results do
     * not depend on it. */
    uint32_t image_width;
    /* Packet traversal (a structure whose vtable offers it): TT_PACKETS_AUTO
     * (0, default) traces each work item (a 16 x 16 tile with image_width,
     * else a run of up to 256 rays) as a packet when its rays are coherent
     * (directions within a cone of about 30 degrees, or ends together
     * within half the shortest ray's length, as shadow rays to a light) and
     * ray by ray otherwise, unless the structure, from the counts of a
     * few probed items, says its packets lose on this batch's rays (the
     * R-tree's shadow rays of a scene scattered by edits): then ray by ray;
     * TT_PACKETS_OFF always ray by ray; TT_PACKETS_ON packets whenever the
     * structure has them. Results do not depend on it. */
    uint32_t packets;
    /* When not NULL, the counting variant traces the batch (as with stats)
     * and adds per-packet counts here (tt_packet_counts, below): packets
     * traced, nodes they visited, rays active at those visits, rays
     * finished one by one inside packet calls. Why packets win or lose. */
    struct tt_packet_counts *packet_stats;
} tt_batch_options;

enum { TT_PACKETS_AUTO = 0, TT_PACKETS_OFF = 1, TT_PACKETS_ON = 2 };

void tt_batch_options_default(tt_batch_options *options);

/* Array-of-structures form. hits[i] / occluded[i] (1 or 0) for rays[i];
 * ray_status may be NULL; options NULL for the defaults. */
tt_status tt_intersect(const tt_accel *accel, const tt_ray *rays, size_t n, tt_hit *hits,
                       tt_status *ray_status, const tt_batch_options *options);
tt_status tt_occluded(const tt_accel *accel, const tt_ray *rays, size_t n, uint8_t *occluded,
                      tt_status *ray_status, const tt_batch_options *options);

/* Strided form: any layout (structure of arrays, an N x 3 array, tt_ray
 * itself, numpy views) without copying. Ray i's origin is the three floats
 * at org[k] + i * org_stride bytes (k = 0, 1, 2 for x, y, z), likewise dir;
 * strides are in bytes and may be 0 (one value for every ray, e.g. the
 * common origin of camera rays) or negative. tmin NULL: 0 for every ray;
 * tmax NULL: +inf. */
typedef struct tt_ray_arrays {
    const float *org[3];
    ptrdiff_t org_stride;
    const float *dir[3];
    ptrdiff_t dir_stride;
    const float *tmin; /* may be NULL                                        */
    ptrdiff_t tmin_stride;
    const float *tmax; /* may be NULL                                        */
    ptrdiff_t tmax_stride;
} tt_ray_arrays;

/* Where ray i's result goes: element i is at pointer + i * stride bytes.
 * A NULL pointer is not written (e.g. only prim and t wanted). */
typedef struct tt_hit_arrays {
    float *t;
    ptrdiff_t t_stride;
    float *u;
    ptrdiff_t u_stride;
    float *v;
    ptrdiff_t v_stride;
    uint32_t *prim;
    ptrdiff_t prim_stride;
} tt_hit_arrays;

tt_status tt_intersect_arrays(const tt_accel *accel, const tt_ray_arrays *rays, size_t n,
                              const tt_hit_arrays *hits, tt_status *ray_status,
                              const tt_batch_options *options);
/* occluded[i * occluded_stride] = 1 or 0 (stride in bytes, 0 means 1). */
tt_status tt_occluded_arrays(const tt_accel *accel, const tt_ray_arrays *rays, size_t n,
                             uint8_t *occluded, ptrdiff_t occluded_stride,
                             tt_status *ray_status, const tt_batch_options *options);

/* ------------------------------------------------------------ camera, views */

typedef struct tt_camera {
    float eye[3], look[3], up[3];
    float fov_deg;  /* vertical field of view                                 */
    float light[3]; /* point light                                            */
    int has_light;
} tt_camera;

/* Primary ray of pixel (x, y), y = 0 the top row, per the conventions.
 * TT_ERR_INVALID_ARGUMENT for a pixel outside the image, or a camera that
 * cannot make rays: NaN/Inf in eye, look, up, fov or (with has_light) the
 * light, eye == look, a zero up vector or one parallel to the view
 * direction, fov outside (0, 180) degrees. */
tt_status tt_camera_ray(const tt_camera *camera, uint32_t width, uint32_t height,
                        uint32_t x, uint32_t y, tt_ray *out);
/* The primary rays of a whole image, row-major from the top-left (width x
 * height rays, out[y * width + x] = tt_camera_ray's ray of pixel (x, y)):
 * the rays tt_render traces, for tracing them with the batch calls. */
tt_status tt_camera_rays(const tt_camera *camera, uint32_t width, uint32_t height, tt_ray *out);
/* A camera framing the scene's bounding box, light above-left of the eye. */
void tt_camera_frame_scene(const tt_scene *scene, tt_camera *out);
/* Shadow ray from a primary hit, per the conventions. Returns 0 and leaves
 * *out untouched when there is no light. */
int tt_shadow_ray(const tt_scene *scene, const tt_camera *camera, const tt_ray *primary,
                  const tt_hit *hit, tt_ray *out);

/* views.tsv: "scene<TAB>view<TAB>eye<TAB>look<TAB>up<TAB>fov_deg<TAB>light".
 * Finds "SCENE:VIEW"; errors name the file and line. */
tt_status tt_view_find(tt_context *ctx, const char *views_path, const char *name,
                       tt_camera *out);
tt_status tt_view_find_memory(tt_context *ctx, const char *views_name, const char *data,
                              size_t size, const char *name, tt_camera *out);

/* ------------------------------------------------ scene edits and updates */

/* A scene changes in place through the calls below; then tt_accel_update
 * brings each structure built on it up to date (an R-tree in the compact
 * layout in place, every other structure by rebuilding it: see
 * tt_accel_updates_in_place). examples/dynamic.c is a whole program.
 *
 * Ids: a triangle's id never changes while it lives; removal does not
 * renumber. A removed id is free and the next addition reuses it (the most
 * recently removed id first); only when no id is free does an addition get
 * a new id, tt_scene_triangle_count() before it. So ids stay below
 * tt_scene_triangle_count(), which counts id slots (live or removed);
 * tt_scene_live_triangle_count() the live ones. A removed slot is a point
 * (no structure hits it) and tt_scene_triangle gives that point.
 *
 * Every edit validates its whole input first: an unknown or removed id, an
 * id given twice, a vertex id out of range or a non-finite coordinate fails
 * with TT_ERR_INVALID_ARGUMENT naming the array index, and nothing changes.
 *
 * Consistency: a structure answers for the scene as it was at its build or
 * its last tt_accel_update, never a mix. Between an edit and the update,
 * tracing through it (tt_intersect1/_ex, tt_occluded1/_ex, the batch calls,
 * tt_render) fails with TT_ERR_STALE and traces nothing.
 *
 * Threading contract: traces may run on any number of threads at once;
 * an edit, or an update of any structure of the scene, runs alone: with no
 * trace of that scene in flight and no other edit or update. This is
 * enforced, not assumed: a call that would overlap gets TT_ERR_BUSY (and
 * does nothing), so a race in the caller's code shows up as an error. */

/* Adds n triangles (9 floats each: three vertices of its own); ids[i]
 * (when ids is not NULL) gets triangle i's id. */
tt_status tt_scene_add_triangles(tt_scene *scene, const float *triangles, size_t n, uint32_t *ids);
/* Removes the live triangles ids[0..n). */
tt_status tt_scene_remove_triangles(tt_scene *scene, const uint32_t *ids, size_t n);
/* Moves whole triangles: ids[i] gets the 9 floats triangles[9 i ..]. A
 * triangle sharing vertices with others gets its own copies first, so the
 * others stay where they are. */
tt_status tt_scene_set_triangles(tt_scene *scene, const uint32_t *ids, const float *triangles,
                                 size_t n);
/* Moves vertices: vertex ids[i] to positions[3 i ..]; ids NULL: vertices
 * 0..n-1 (e.g. all of them for a deformation). Every live triangle using a
 * moved vertex moves with it. Vertex ids are tt_scene_create's / the file's
 * order; triangles added or detached later have vertices past those. */
tt_status tt_scene_move_vertices(tt_scene *scene, const uint32_t *ids, const float *positions,
                                 size_t n);
/* Vertex i's position (3 floats): e.g. the rest pose a deformation starts
 * from; TT_ERR_INVALID_ARGUMENT for i >= tt_scene_vertex_count(). */
tt_status tt_scene_vertex(const tt_scene *scene, size_t i, float out[3]);
/* 1 when id is a live triangle of the scene. */
int tt_scene_triangle_alive(const tt_scene *scene, uint32_t id);
size_t tt_scene_live_triangle_count(const tt_scene *scene);
/* Successful edit calls so far (0 for a scene never edited). */
uint64_t tt_scene_version(const tt_scene *scene);

/* Brings a structure up to date with its scene's edits (nothing to do: TT_OK
 * at once). On an error the structure is left as it was (still answering
 * for the old scene: traces get TT_ERR_STALE until an update succeeds). */
tt_status tt_accel_update(tt_accel *accel);
/* 1 when tt_accel_update changes this structure in place (the R-tree in the
 * compact layout), 0 when it answers by rebuilding (the complete layout,
 * kdtree, bruteforce, embree). */
int tt_accel_updates_in_place(const tt_accel *accel);

/* --------------------------------------------------------------- rendering */

/* Where tt_render traces. The GPU (CUDA, one thread per ray) runs the same
 * traversal code as the CPU for: rtree with the auto, stackless or ordered
 * traversal, and kdtree with sltr or htr (without the shadow-caster hint).
 * Other choices on the GPU are TT_ERR_UNSUPPORTED, as is a build without
 * CUDA; a build with CUDA on a machine without a usable GPU gives
 * TT_ERR_NO_DEVICE. The context's message says which. */
typedef enum tt_device { TT_DEVICE_CPU = 0, TT_DEVICE_GPU } tt_device;

/* TT_OK when tt_render can run on `device` here (for the GPU: this build has
 * CUDA and a usable GPU is present), otherwise the status and message
 * tt_render would give. Cheap enough to call before loading a scene. */
tt_status tt_device_check(tt_context *ctx, tt_device device);

typedef struct tt_render_options {
    uint32_t width, height; /* default 1024 x 1024                            */
    int shadows;            /* trace shadow rays, default 1                   */
    int repeat;             /* trace K times, report min and median; default 1 */
    int stats;              /* gather per-ray statistics (counting variant)   */
    int keep_hits;          /* keep the hit buffer (tt_render_hits)           */
    int keep_image;         /* keep the shaded RGB image                      */
    int keep_pixel_stats;   /* keep per-pixel counts for heatmaps             */
    tt_device device;       /* default TT_DEVICE_CPU                          */
    /* TT_PACKETS_AUTO (default): a structure with packet traversal traces
     * each tile's primary rays, and its shadow rays when they are coherent
     * (within a cone, or ending together at the light), as one packet; TT_PACKETS_OFF ray by ray; TT_PACKETS_ON
     * packets always. The image and hit buffer do not depend on it. */
    uint32_t packets;
} tt_render_options;

void tt_render_options_default(tt_render_options *options);

typedef struct tt_render_result tt_render_result;

/* Per-packet counts (tt_batch_options.packet_stats, tt_render_summary):
 * packets traced (a tile's rays of one direction octant), nodes they
 * visited (once a packet), rays active at those visits (active_lanes /
 * node_visits: the packet's mean width at a node), rays finished one by one
 * inside packet calls (an octant of too few rays). */
typedef struct tt_packet_counts {
    uint64_t packets, node_visits, active_lanes, fallback_rays;
} tt_packet_counts;

typedef struct tt_render_summary {
    uint32_t width, height;
    uint64_t primary_rays, primary_hits, shadow_rays, shadow_occluded;
    double trace_s;        /* min over repeats, primary + shadow              */
    double trace_median_s;
    double primary_s, shadow_s; /* min over repeats                            */
    double mrays_per_s, primary_mrays_per_s, shadow_mrays_per_s;
    int has_stats;
    tt_ray_stats primary_stats, shadow_stats; /* from one (counting) pass      */
    int threads;                /* OpenMP threads the passes ran on            */
    /* Where the passes ran. On the GPU the trace times above are CUDA-event
     * times of the kernels (primary rays are generated on the GPU, inside
     * the primary time), and the copies are timed apart: */
    tt_device device;
    double upload_s;        /* GPU: structure and triangles to the device      */
    double download_s;      /* GPU: the per-pixel results back to the host     */
    char device_name[64];   /* GPU: the device's name; "" on the CPU           */
    /* Packets (tt_render_options.packets): whether the passes traced any,
     * and from the counting pass (has_stats) per kind of ray: packets
     * traced, nodes they visited (once a packet), rays active at those
     * visits (active / nodes: the packet's mean width at a node), and rays
     * finished one by one inside packet calls (an octant of fewer than a
     * few rays, or an ISA without a packet kernel). */
    int packets;
    tt_packet_counts primary_packets, shadow_packets;
} tt_render_summary;

tt_status tt_render(tt_context *ctx, const tt_scene *scene, const tt_accel *accel,
                    const tt_camera *camera, const tt_render_options *options,
                    tt_render_result **out);
void tt_render_result_destroy(tt_render_result *result);
const tt_render_summary *tt_render_get_summary(const tt_render_result *result);
/* 8-bit RGB, row-major from the top-left; NULL unless keep_image. */
const uint8_t *tt_render_image(const tt_render_result *result);
/* The hit buffer per the conventions (12 bytes a pixel); NULL unless keep_hits. */
const uint8_t *tt_render_hits(const tt_render_result *result, size_t *size);

typedef enum tt_heat_metric {
    TT_HEAT_NODES = 0,
    TT_HEAT_INTERIOR,
    TT_HEAT_LEAVES,
    TT_HEAT_TRIANGLES,
    TT_HEAT_BOXES
} tt_heat_metric;

/* Per-pixel counts of the primary ray (needs keep_pixel_stats); NULL if absent. */
const uint32_t *tt_render_pixel_stats(const tt_render_result *result, tt_heat_metric metric);

/* ---------------------------------------------------------------- file out */

tt_status tt_write_png(tt_context *ctx, const char *path, const uint8_t *rgb,
                       uint32_t width, uint32_t height);
tt_status tt_write_file(tt_context *ctx, const char *path, const void *data, size_t size);
/* False-colour heatmap (0 dark blue .. >= 255 dark red) with a colour bar. */
tt_status tt_write_heatmap_png(tt_context *ctx, const char *path, const uint32_t *counts,
                               uint32_t width, uint32_t height);

#if defined(__GNUC__) || defined(__clang__)
#pragma GCC visibility pop
#endif

#ifdef __cplusplus
}
#endif
#endif
