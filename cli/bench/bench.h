/* `treetrace bench`: the benchmark that reproduces the tables of the two
 * papers (Feldmann 2015, Havran & Bittner 2007) with Embree beside every
 * number. The pieces, one file each:
 *   bench_options.c   command line, --help
 *   bench_scenes.c    scenes.tsv / views.tsv of the scenes folder
 *   bench_matrix.c    which runs each table needs (scene x view x structure
 *                     x build options x traversal x ray kind x size)
 *   bench_yard*.c     the engine table (E): our batch calls against Embree's
 *                     own loops (bench_yard.h, bench_embree.h, embree/)
 *   bench_runner.c    loads, builds and renders; fills the results
 *   bench_agree.c     hit buffers against Embree's, per the conventions
 *   bench_csv.c       results.csv
 *   bench_report.c    report.md (with bench_paper.c: the papers' numbers;
 *                     bench_report_gpu.c: the GPU section with --device gpu)
 *   bench_figures.c   the figures: python3 -m treetrace.plots (matplotlib)
 *   bench_progress.c  progress on stderr
 *   bench_machine.c   CPU, cores, compiler, date for the report */
#ifndef TT_CLI_BENCH_H
#define TT_CLI_BENCH_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "treetrace/treetrace.h"

/* The entry point, called by the CLI's command table for `treetrace bench`.
 * argv[0] is "bench". Returns the process exit status: 0 done, 1 a run-time
 * failure (scenes missing, output not writable), 2 bad options. */
int tt_cli_bench(int argc, char **argv);

/* ------------------------------------------------------------------ tables */

/* The tables and figures the benchmark reproduces; a run feeds one or more. */
enum {
    BENCH_F1 = 1 << 0, /* Feldmann Table 1: insertion strategies            */
    BENCH_F2 = 1 << 1, /* Feldmann Table 2: no forced reinsert              */
    BENCH_F3 = 1 << 2, /* Feldmann Table 3: R-tree traversals               */
    BENCH_F4 = 1 << 3, /* Feldmann Table 4: R*-tree vs kd-tree              */
    BENCH_F5 = 1 << 4, /* Feldmann Table 5: construction times              */
    BENCH_H1 = 1 << 5, /* Havran & Bittner Table 1: kd traversals           */
    BENCH_H3 = 1 << 6, /* Havran & Bittner Figure 3: d_min sweep            */
    BENCH_E1 = 1 << 7, /* the engine table: batch calls vs Embree's loops   */
    BENCH_ALL_TABLES = (1 << 8) - 1,
    /* not among the default tables (frames, not single renders): only with
     * --only D (bench_dynamic.c) */
    BENCH_D = 1 << 8 /* dynamic scenes: updates against Embree's commits   */
};

typedef struct bench_table_name {
    unsigned bit;
    const char *id;    /* for --only: "F1" ...                               */
    const char *title; /* the report's heading                               */
} bench_table_name;

extern const bench_table_name bench_tables[];
extern const size_t bench_table_count;
const char *bench_table_title(unsigned bit);

/* ----------------------------------------------------------------- options */

typedef struct bench_size {
    uint32_t width, height;
} bench_size;

typedef struct bench_options {
    const char *scenes_dir; /* NULL: found next to the executable / source    */
    const char *out_dir;    /* NULL: bench/results-<date>                      */
    int threads;            /* 0: OpenMP's default                             */
    int repeat;             /* timed repeats after the warm-up pass            */
    int quick;
    unsigned tables;    /* BENCH_* bits                                    */
    char **scene_names; /* --scene: only these (tiny ones allowed); NULL: all big */
    size_t scene_name_count;
    bench_size rtree_size; /* Feldmann tables (1024 x 1024)                   */
    bench_size kd_size;    /* Havran & Bittner tables (800 x 600)             */
    int dmins[32];         /* Figure 3's d_min values (1 .. 12)               */
    int dmin_count;
    int all_views; /* 0: the first view of each scene only            */
    int heatmaps;
    double budget_s; /* timed repeats are cut so one run stays near this */
    tt_device device; /* TT_DEVICE_GPU: the GPU's configurations again on it */
    /* The engine table (E, bench_yard.h): its structures are built this
     * many times (the minimum is reported), it times `rounds` interleaved
     * rounds (5 like raybench; --repeat sets it too), and each primary hit
     * casts ao_samples ambient-occlusion rays. */
    int builds;
    int rounds;
    int ao_samples;
    int frames;       /* table D: frames a sequence (default 100; --frames)  */
    /* Under mpirun (cli/mpi/mpi_bench.c): this rank runs the scenes whose
     * index is rank mod ranks; rank 0 gathers and writes. ranks <= 1: all. */
    int rank, ranks;
} bench_options;

/* Parses argv (argv[0] = "bench"). Returns 0 ok, 1 --help was printed (exit
 * 0), 2 an error was printed (exit 2). Free with bench_options_free. */
int bench_parse_options(int argc, char **argv, bench_options *out, FILE *err);
void bench_options_free(bench_options *o);
void bench_print_help(FILE *f);

/* ------------------------------------------------------------------ scenes */

typedef struct bench_view {
    char name[64]; /* "main"                                             */
    tt_camera camera;
} bench_view;

typedef struct bench_scene {
    char name[64];   /* "bunny"                                            */
    char path[4096]; /* the model file                                     */
    long triangles;  /* as listed in scenes.tsv (-1 if absent)             */
    bench_view *views;
    size_t view_count;
} bench_scene;

typedef struct bench_scene_list {
    bench_scene *items;
    size_t count;
    char dir[4096];
} bench_scene_list;

/* The scenes folder to use when --scenes is not given; NULL if none found. */
const char *bench_default_scenes_dir(char *buf, size_t size);
/* Reads DIR/scenes.tsv and DIR/views.tsv and keeps the scenes selected by the
 * options (named ones, or all but the tiny test scenes). Messages go to err.
 * Returns 0 on success, -2 when --scene names a scene the folder lacks (a
 * bad option), -1 on other failures. */
int bench_scenes_read(tt_context *ctx, const char *dir, const bench_options *o,
                      bench_scene_list *out, FILE *err);
void bench_scenes_free(bench_scene_list *l);
/* --quick runs only scenes up to this size (bunny, sibenik) unless named. */
#define BENCH_QUICK_MAX_TRIANGLES 100000
/* The tiny unit-test scenes the full matrix leaves out unless named. */
int bench_scene_is_tiny(const char *name);

/* Table D (bench_dynamic.c): deformation, edits and growth frame by frame,
 * treetrace's in-place update against Embree's commits in the same run;
 * writes OUT/dynamic.csv and OUT/dynamic.md. Returns 0, or 1 on failure. */
int bench_dynamic_run(tt_context *ctx, const bench_options *o, const bench_scene_list *scenes,
                      const char *out, FILE *err);

/* ------------------------------------------------------------------ matrix */

typedef enum bench_rays { BENCH_PRIMARY = 0, BENCH_PRIMARY_SHADOW = 1 } bench_rays;

/* One render: a structure built with `build` on a scene, traced from a view. */
typedef struct bench_run {
    size_t scene, view;
    bench_size size;
    tt_build_options build;
    bench_rays rays;
    unsigned tables; /* BENCH_* bits of the tables this run feeds          */
    int heatmap;     /* write the primary rays' node-count heatmap          */
    tt_device device; /* where it is traced (CPU unless --device gpu)      */
} bench_run;

typedef struct bench_matrix {
    bench_run *runs;
    size_t count, cap;
} bench_matrix;

/* Fills the runs every selected table needs, with the Embree runs they are
 * compared with. Duplicates are merged (their table bits or-ed). With
 * --device gpu, every run the GPU can trace (bench_gpu_traces) is also made
 * on the GPU, and the R-trees of Feldmann's Tables 1 and 2 also with the
 * ordered traversal, which his GPU rows used. */
int bench_matrix_make(const bench_options *o, const bench_scene_list *scenes, bench_matrix *m);
void bench_matrix_free(bench_matrix *m);
/* The build options the matrix uses (defaults but for the arguments). */
tt_build_options bench_rtree_build(tt_rtree_strategy s, int reinsert, tt_rtree_traversal t);
/* dmin < 0: no sparse boxes. */
tt_build_options bench_kdtree_build(tt_kd_builder builder, int dmin, tt_kd_traversal t);
tt_build_options bench_named_build(const char *accel);
/* Whether the GPU traces this configuration (rtree: auto, stackless,
 * ordered; kdtree: sltr, htr without the caster hint). */
int bench_gpu_traces(const tt_build_options *b);
/* Finds the run equal to r in everything but the tables; NULL if none. */
const bench_run *bench_matrix_find(const bench_matrix *m, const bench_run *r);
/* Two build options that give the same structure (fields the accel ignores
 * do not count). */
int bench_same_build(const tt_build_options *a, const tt_build_options *b);

/* ----------------------------------------------------------------- results */

/* What a structure's tt_accel_statistics said, the keys the report needs. */
typedef struct bench_accel_stats {
    double boxes;  /* kd-tree: augmented nodes (sparse boxes), N_B; -1 absent */
    double nodes;  /* total nodes; -1 absent                                  */
    double height; /* -1 absent                                               */
    char all[512]; /* every key=value, ';'-separated, for the CSV             */
} bench_accel_stats;

typedef struct bench_result {
    const bench_run *run;
    int ok; /* 0: error holds why                            */
    char error[256];
    double load_s; /* loading the scene (once per scene)             */
    size_t triangles, vertices;
    double build_s; /* of the structure this run used                 */
    size_t memory_bytes;
    tt_isa isa; /* the kernels the structure ran on                   */
    bench_accel_stats accel_stats;
    int repeats;               /* timed passes actually made                     */
    tt_render_summary summary; /* timings from the timed call, stats from warm-up */
    /* Embree's run with the same scene, view, size and rays (NULL for Embree
     * itself or when Embree is absent), and the agreement with it. */
    const struct bench_result *embree;
    uint64_t agree_pixels, compared_pixels;
    /* The pixels that disagree with Embree are retraced with bruteforce, the
     * ground truth (up to BENCH_ARBITRATE_MAX of them): how many were, and on
     * how many this run's pixel equals bruteforce's (then Embree was off). */
    uint64_t arbitrated_pixels, ours_match_bruteforce;
} bench_result;

typedef struct bench_results {
    bench_result *items; /* parallel to the matrix's runs                    */
    size_t count;
    char **skipped; /* "kdtree: not in this build" lines for the report */
    size_t skipped_count;
    double total_s;
    int threads; /* the threads the renders ran on                   */
    /* The engine table's measurements (bench_yard.h; NULL without E):
     * not renders, so not in the matrix. Owned by the caller. */
    const struct bench_yard *engine;
} bench_results;

/* Runs the whole matrix, writing heatmaps under out_dir/heatmaps. */
int bench_run_all(tt_context *ctx, const bench_options *o, const bench_scene_list *scenes,
                  const bench_matrix *m, const char *out_dir, bench_results *res, FILE *err);
void bench_results_free(bench_results *r);

/* Per-ray averages of a summary's statistics; 0 when there were no rays. */
double bench_per_ray(uint64_t count, uint64_t rays);
/* Median time of the run (primary + shadow, or primary only). */
double bench_time_s(const bench_result *r);
double bench_mrays(const bench_result *r);

/* ------------------------------------------------------------- agreement */

/* Counts the pixels of two hit buffers (12 bytes a pixel, per the scenes
 * README) that agree: both miss, or the same triangle, or t within 1e-4
 * relative, and equal shadow flags. */
uint64_t bench_agree_count(const uint8_t *a, const uint8_t *b, uint64_t pixels);
/* The same rule for one pixel (12 bytes each). */
int bench_pixel_agrees(const uint8_t *a, const uint8_t *b);
/* Bruteforce's pixel (x, y) of a width x height frame of the camera, encoded
 * as in a hit buffer (with the shadow flag when shadows is set). */
void bench_bruteforce_pixel(const tt_scene *scene, const tt_accel *bruteforce,
                            const tt_camera *camera, bench_size size, uint32_t x, uint32_t y,
                            int shadows, uint8_t out[12]);
#define BENCH_ARBITRATE_MAX 1000

/* ----------------------------------------------------------------- writers */

int bench_write_csv(const char *path, const bench_scene_list *s, const bench_matrix *m,
                    const bench_results *r, FILE *err);
int bench_write_report(tt_context *ctx, const char *out_dir, const bench_options *o,
                       const bench_scene_list *s, const bench_matrix *m, const bench_results *r,
                       FILE *err);

/* The papers' numbers (bench_paper.c). */
typedef struct bench_paper_value {
    const char *row;    /* scene as the paper names it                        */
    const char *column; /* the paper's column                                 */
    double value;       /* seconds (or the table's unit); < 0: not given      */
} bench_paper_value;

/* Our scene name -> the paper's (Feldmann: "Bunny", "Cathedral",
 * "Conference"); NULL when the paper has no such scene. */
const char *bench_feldmann_scene(const char *ours);
/* Feldmann Table t (1..5), CPU rows; column per the table. < 0 if absent. */
double bench_feldmann_value(int table, const char *paper_scene, const char *column);
/* The GPU rows of Tables 1-3 (GeForce GTX 780), in seconds; < 0 if absent. */
double bench_feldmann_gpu_value(int table, const char *paper_scene, const char *column);
extern const char *const bench_feldmann_scenes[4];

typedef struct bench_havran_row {
    const char *scene, *method;
    double n_b, m_kd, r_itm, n_l, n_i, t_r; /* N_B in millions, M_KD in MB       */
} bench_havran_row;
extern const bench_havran_row bench_havran_table1[];
extern const size_t bench_havran_table1_count;

/* ---------------------------------------------------------------- figures */

/* The figures are drawn by the Python package (python3 -m treetrace.plots
 * OUT: matplotlib, PDF + PNG) after results.csv and report.md are written.
 * The interpreter that can (python3 with matplotlib and the package),
 * probed once; NULL when there is none (the figures are optional). */
const char *bench_figures_python(void);
/* Draws them; without Python prints how to draw them later and returns 0;
 * -1 when the plotting module failed. */
int bench_figures_draw(const char *out_dir, FILE *err);
/* The sentence saying how to draw them later (for the report and stderr). */
void bench_figures_hint(FILE *f, const char *out_dir);

/* --------------------------------------------------------------- progress */

typedef struct bench_progress {
    FILE *f;
    int tty;
    size_t total, done;
    double t0;
} bench_progress;

/* Seconds on a monotonic clock. */
double bench_now(void);
void bench_progress_start(bench_progress *p, FILE *f, size_t total);
void bench_progress_step(bench_progress *p, const char *what);
void bench_progress_end(bench_progress *p);

/* ---------------------------------------------------------------- machine */

typedef struct bench_machine {
    char cpu[256];
    int cores; /* online logical CPUs                                    */
    char compiler[128];
    char date[64]; /* local time, ISO 8601                                   */
    char embree[64];
} bench_machine;

void bench_machine_read(bench_machine *m);

/* ------------------------------------------------------------------ names */

const char *bench_rays_name(bench_rays r);            /* "primary", "primary+shadow" */
const char *bench_strategy_name(tt_rtree_strategy s); /* "minVolume" ...            */
const char *bench_rtree_traversal_name(tt_rtree_traversal t);
const char *bench_kd_traversal_name(tt_kd_traversal t);
/* The traversal of a build: "stackless", "HTR", "-" for Embree/bruteforce. */
const char *bench_traversal_name(const tt_build_options *b);
/* A compact description of the build options that matter for its accel. */
void bench_options_string(const tt_build_options *b, char *buf, size_t size);

/* mkdir -p; 0 on success. */
int bench_mkdirs(const char *path);

#endif
