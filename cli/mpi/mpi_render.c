/* `treetrace render` as one rank of an MPI job (Open MPI). Every rank loads
 * the scene and builds or maps (--accel-file) the structure; a failure on
 * any rank ends the job on every rank with that rank's message (one
 * all-reduce of "loaded", so nobody waits for a rank that is gone). The
 * frame's 16x16 tiles are then shared out:
 *  - queue (default): a counter in rank 0's memory (an MPI window) hands out
 *    runs of tiles by an atomic fetch-and-add, so a rank that drew cheap
 *    tiles comes back for more; rank 0 traces too, and serving costs it
 *    nothing (one-sided: no loop answering requests);
 *  - interleave: rank r traces tiles r, r + N, ... (no communication).
 * Rank 0 then gathers each rank's tiles' per-pixel results (primary hit,
 * distance, shadow flag, per-pixel counts for a heatmap) into its frame and
 * makes the result through the library's own steps (tt_frame_result):
 * the PNG and hit buffer are byte for byte the single process's, since a
 * tile's results never depend on who traced it. Statistics are summed by a
 * reduction. `--frames N` spreads whole frames instead (render_frames.c). */
#include <mpi.h>
#include <stdio.h>
#include <time.h>
#include <stdlib.h>
#include <string.h>

#include "accel_file.h"
#include "cli.h"
#include "common.h"
#include "core/context.h"
#include "mpi/mpi.h"
#include "render/frame.h"
#include "render_frames.h"

typedef struct job {
    int rank, size;
    render_args *r;
    tt_context *ctx;
    tt_scene *scene;
    tt_accel *accel;
    tt_camera cam;
    double load_s;
} job;

/* Every rank says whether it got this far; a failed rank prints its own
 * message. Returns 1 when all succeeded. */
static int all_ok(job *j, int ok, const char *what)
{
    if (!ok)
        fprintf(stderr, "treetrace render: rank %d of %d: %s: %s\n", j->rank, j->size, what,
                tt_context_last_error(j->ctx));
    int all = 0;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (!all && ok && j->rank == 0)
        fprintf(stderr, "treetrace render: rank 0: another rank failed; the job ends\n");
    return all;
}

/* The tiles a rank traces in one pass, appended to mine[]. */
static uint32_t take_tiles(job *j, tt_frame *f, MPI_Win win, uint32_t *mine, int counting,
                           tt_ray_stats *counts, double *times)
{
    const uint32_t n = tt_frame_tile_count(f);
    const int shadows = !j->r->no_shadows;
    uint32_t count = 0;
    if (j->r->mpi_split == 1) { /* interleave */
        for (uint32_t t = (uint32_t)j->rank; t < n; t += (uint32_t)j->size) mine[count++] = t;
        tt_frame_trace_tiles(f, mine, count, shadows, counting ? counts : NULL, times);
        return count;
    }
    /* queue: runs of `chunk` tiles, a few per thread, from rank 0's counter */
    const long chunk = 4L * (f->threads > 0 ? f->threads : 1);
    for (;;) {
        long first = 0;
        MPI_Fetch_and_op(&chunk, &first, MPI_LONG, 0, 0, MPI_SUM, win);
        MPI_Win_flush(0, win);
        if (first >= (long)n) break;
        uint32_t k = 0;
        for (long t = first; t < first + chunk && t < (long)n; t++) mine[count + k++] = (uint32_t)t;
        tt_frame_trace_tiles(f, mine + count, k, shadows, counting ? counts : NULL, times);
        count += k;
    }
    return count;
}

/* One distributed pass over the frame; returns this rank's tiles. */
static uint32_t pass(job *j, tt_frame *f, MPI_Win win, long *counter, uint32_t *mine,
                     int counting, tt_ray_stats *counts, double *times)
{
    if (j->rank == 0) {
        MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, win);
        *counter = 0;
        MPI_Win_unlock(0, win);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    MPI_Win_lock_all(0, win);
    uint32_t count = take_tiles(j, f, win, mine, counting, counts, times);
    MPI_Win_unlock_all(win);
    return count;
}

/* Per pixel on the wire: prim, t, shadow (the per-pixel counts of a
 * heatmap come from the counting pass, whose tiles were shared out apart:
 * they are summed by a reduction instead, each pixel counted on one rank). */
static size_t pixel_bytes(const tt_frame *f)
{
    (void)f;
    return 9;
}

static void pack_tile(const tt_frame *f, uint32_t tile, uint8_t **p, int unpack)
{
    uint32_t x0, y0, x1, y1;
    tt_frame_tile_rect(f, tile, &x0, &y0, &x1, &y1);
    for (uint32_t y = y0; y < y1; y++)
        for (uint32_t x = x0; x < x1; x++) {
            const size_t i = (size_t)y * f->width + x;
            void *fields[3] = {&f->prim[i], &f->t[i], &f->shadow[i]};
            const size_t sizes[3] = {4, 4, 1};
            for (int k = 0; k < 3; k++) {
                if (unpack) memcpy(fields[k], *p, sizes[k]);
                else memcpy(*p, fields[k], sizes[k]);
                *p += sizes[k];
            }
        }
}

/* Byte runs of any size, in messages of at most 1 GiB (MPI counts are int). */
#define PIECE ((size_t)1 << 30)
static void send_bytes(const uint8_t *p, size_t n)
{
    for (size_t at = 0; at < n || at == 0; at += PIECE) {
        MPI_Send(p + at, (int)(n - at < PIECE ? n - at : PIECE), MPI_BYTE, 0, 3, MPI_COMM_WORLD);
        if (n == 0) break;
    }
}
static void recv_bytes(uint8_t *p, size_t n, int src)
{
    for (size_t at = 0; at < n || at == 0; at += PIECE) {
        MPI_Recv(p + at, (int)(n - at < PIECE ? n - at : PIECE), MPI_BYTE, src, 3, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
        if (n == 0) break;
    }
}

/* Rank 0 receives every other rank's tiles into its frame. */
static int gather(job *j, tt_frame *f, const uint32_t *mine, uint32_t count)
{
    const size_t per_tile = (size_t)TT_TILE * TT_TILE * pixel_bytes(f);
    if (j->rank != 0) {
        uint8_t *buf = malloc(per_tile * (count ? count : 1)), *p = buf;
        if (!buf) return 0;
        for (uint32_t i = 0; i < count; i++) pack_tile(f, mine[i], &p, 0);
        MPI_Send(&count, 1, MPI_UINT32_T, 0, 1, MPI_COMM_WORLD);
        MPI_Send(mine, (int)count, MPI_UINT32_T, 0, 2, MPI_COMM_WORLD);
        send_bytes(buf, (size_t)(p - buf));
        free(buf);
        return 1;
    }
    uint32_t *tiles = malloc(sizeof *tiles * tt_frame_tile_count(f));
    uint8_t *buf = malloc(per_tile * tt_frame_tile_count(f));
    int ok = tiles && buf;
    for (int src = 1; src < j->size; src++) {
        uint32_t n = 0;
        MPI_Recv(&n, 1, MPI_UINT32_T, src, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        MPI_Recv(tiles, (int)n, MPI_UINT32_T, src, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        /* what the sender packed: its tiles' pixels (edge tiles are smaller) */
        size_t bytes = 0;
        for (uint32_t i = 0; i < n; i++) {
            uint32_t x0, y0, x1, y1;
            tt_frame_tile_rect(f, tiles[i], &x0, &y0, &x1, &y1);
            bytes += (size_t)(x1 - x0) * (y1 - y0) * pixel_bytes(f);
        }
        recv_bytes(buf, bytes, src);
        uint8_t *p = buf;
        for (uint32_t i = 0; i < n && ok; i++) pack_tile(f, tiles[i], &p, 1);
    }
    free(tiles);
    free(buf);
    return ok;
}

typedef struct mpi_report {
    int ranks;
    const char *split;
    double *busy; /* per rank: fast-pass seconds of the best repeat */
    double *tiles;
    double *cpu;  /* per rank: CPU seconds of the best repeat's pass */
} mpi_report;

static void emit_mpi(cli_emit *e, void *user)
{
    const mpi_report *m = user;
    emit_int(e, "mpi_ranks", m->ranks);
    emit_str(e, "mpi_split", m->split);
    char key[64];
    for (int i = 0; i < m->ranks; i++) {
        snprintf(key, sizeof key, "rank_%d_busy_s", i);
        emit_num(e, key, m->busy[i]);
        snprintf(key, sizeof key, "rank_%d_tiles", i);
        emit_u64(e, key, (uint64_t)m->tiles[i]);
        snprintf(key, sizeof key, "rank_%d_cpu_s", i);
        emit_num(e, key, m->cpu[i]);
    }
}

/* CPU seconds of this process (all its threads): the measure of a rank's
 * work that other load on the machine does not inflate. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int render_tiles(job *j)
{
    render_args *r = j->r;
    tt_render_options ro;
    tt_render_options_default(&ro);
    ro.width = r->width;
    ro.height = r->height;
    ro.shadows = !r->no_shadows;
    ro.repeat = r->repeat;
    ro.stats = r->stats;
    ro.keep_hits = r->hits != NULL;
    ro.keep_image = r->png != NULL;
    ro.keep_pixel_stats = r->heatmap != NULL;
    ro.packets = (uint32_t)r->packets;
    tt_frame f;
    int ok = tt_frame_open(j->ctx, j->scene, j->accel, &j->cam, &ro, &f) == TT_OK;
    uint32_t *mine = ok ? malloc(sizeof *mine * tt_frame_tile_count(&f)) : NULL;
    if (!all_ok(j, ok && mine, "render")) {
        free(mine);
        if (ok) tt_frame_close(j->ctx, &f);
        return CLI_RUNTIME;
    }
    long *counter = NULL;
    MPI_Win win;
    MPI_Win_allocate(j->rank == 0 ? (MPI_Aint)sizeof(long) : 0, sizeof(long), MPI_INFO_NULL,
                     MPI_COMM_WORLD, &counter, &win);
    tt_render_summary s;
    memset(&s, 0, sizeof s);
    s.width = ro.width;
    s.height = ro.height;
    s.threads = f.threads;
    s.device = TT_DEVICE_CPU;
    tt_ray_stats counts[2];
    memset(counts, 0, sizeof counts);
    double scratch[2] = {0, 0};
    if (ro.stats || ro.keep_pixel_stats) { /* the counting pass first, as tt_render */
        pass(j, &f, win, counter, mine, 1, counts, scratch);
        s.has_stats = 1;
        const int pixels = (int)(ro.width * ro.height);
        for (int m = 0; m < TT_HEAT_METRIC_COUNT && f.pixel_stats[m]; m++)
            MPI_Reduce(j->rank == 0 ? MPI_IN_PLACE : f.pixel_stats[m], f.pixel_stats[m], pixels,
                       MPI_UINT32_T, MPI_SUM, 0, MPI_COMM_WORLD);
    }
    double *walls = malloc(sizeof(double) * (size_t)ro.repeat);
    double best_busy = 1e300, best[2] = {1e300, 1e300}, best_cpu = 1e300;
    uint32_t count = 0;
    for (int k = 0; k < ro.repeat; k++) {
        double times[2] = {0, 0};
        MPI_Barrier(MPI_COMM_WORLD);
        double t0 = MPI_Wtime(), c0 = cpu_now();
        count = pass(j, &f, win, counter, mine, 0, NULL, times);
        double local = MPI_Wtime() - t0, wall = 0, tmax[2], cpu = cpu_now() - c0;
        if (cpu < best_cpu) best_cpu = cpu;
        MPI_Allreduce(&local, &wall, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        MPI_Allreduce(times, tmax, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        walls[k] = wall;
        if (tmax[0] < best[0]) best[0] = tmax[0];
        if (tmax[1] < best[1]) best[1] = tmax[1];
        if (times[0] + times[1] < best_busy) best_busy = times[0] + times[1];
    }
    MPI_Win_free(&win);
    /* statistics: summed over ranks */
    uint64_t mine_counts[12], sum_counts[12];
    memcpy(mine_counts, counts, sizeof mine_counts);
    MPI_Reduce(mine_counts, sum_counts, 12, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    double busy_tiles[3] = {best_busy, (double)count, best_cpu}, *all = NULL;
    if (j->rank == 0) all = malloc(sizeof(double) * 3 * (size_t)j->size);
    MPI_Gather(busy_tiles, 3, MPI_DOUBLE, all, 3, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    ok = gather(j, &f, mine, count);
    int st = CLI_OK;
    if (j->rank == 0) {
        memcpy(&s.primary_stats, sum_counts, sizeof s.primary_stats);
        memcpy(&s.shadow_stats, sum_counts + 6, sizeof s.shadow_stats);
        qsort(walls, (size_t)ro.repeat, sizeof *walls, cmp_double);
        s.trace_s = walls[0];
        int mid = ro.repeat / 2;
        s.trace_median_s = ro.repeat % 2 ? walls[mid] : 0.5 * (walls[mid - 1] + walls[mid]);
        s.primary_s = best[0];
        s.shadow_s = best[1];
        tt_render_result *res = NULL;
        if (!ok || tt_frame_result(j->ctx, &f, &ro, &s, &res) != TT_OK) {
            st = cli_runtime_error("render", j->ctx);
        } else {
            /* the rates over the job's wall time */
            tt_render_summary *sum = (tt_render_summary *)tt_render_get_summary(res);
            sum->mrays_per_s = s.trace_s > 0 ? (double)(sum->primary_rays + sum->shadow_rays) /
                                                   s.trace_s * 1e-6 : 0.0;
            st = render_write_outputs(j->ctx, r, res);
            double *busy = malloc(sizeof(double) * (size_t)j->size);
            double *tiles = malloc(sizeof(double) * (size_t)j->size);
            double *cpus = malloc(sizeof(double) * (size_t)j->size);
            for (int i = 0; i < j->size; i++) {
                busy[i] = all[3 * i];
                tiles[i] = all[3 * i + 1];
                cpus[i] = all[3 * i + 2];
            }
            mpi_report m = {j->size, r->mpi_split ? "interleave" : "queue", busy, tiles, cpus};
            if (st == CLI_OK)
                render_emit_results(r, r->scene, j->scene, j->load_s, j->accel, &j->cam, res,
                                    emit_mpi, &m);
            free(busy);
            free(tiles);
            free(cpus);
        }
        tt_render_result_destroy(res);
    }
    free(all);
    free(walls);
    free(mine);
    tt_frame_close(j->ctx, &f);
    return st;
}

static int render_frames(job *j)
{
    render_args *r = j->r;
    frame_row *rows = calloc((size_t)r->frames, sizeof *rows);
    frame_row *all = calloc((size_t)r->frames, sizeof *rows);
    MPI_Barrier(MPI_COMM_WORLD);
    double t0 = MPI_Wtime();
    int st = rows && all ? render_frames_run(j->ctx, r, j->scene, j->accel, &j->cam, j->rank,
                                             j->size, j->rank, rows)
                         : CLI_RUNTIME;
    int ok = st == CLI_OK, every = 0;
    MPI_Allreduce(&ok, &every, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    /* rows are zero but for a rank's own frames: a sum gathers them */
    MPI_Reduce(rows, all, 4 * r->frames, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    double wall = MPI_Wtime() - t0;
    if (j->rank == 0 && every) render_frames_emit(r, j->accel, all, wall, j->size);
    free(rows);
    free(all);
    return every ? CLI_OK : CLI_RUNTIME;
}

int cli_mpi_render(render_args *r)
{
    if (r->device != 0) {
        fprintf(stderr, "treetrace render: MPI ranks trace on the CPU (--device gpu is one "
                        "process's)\n");
        return CLI_USAGE;
    }
    MPI_Init(NULL, NULL);
    job j;
    memset(&j, 0, sizeof j);
    j.r = r;
    MPI_Comm_rank(MPI_COMM_WORLD, &j.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &j.size);
    tt_context_options copt;
    tt_context_options_default(&copt);
    copt.threads = r->threads;
    int ok = tt_context_create(&copt, &j.ctx) == TT_OK;
    if (ok) {
        double t0 = tt_now();
        ok = tt_scene_load(j.ctx, r->scene, &j.scene) == TT_OK;
        j.load_s = tt_now() - t0;
    }
    const char *what = "loading the scene";
    if (ok) {
        what = r->accel_file ? "loading the structure" : "building the structure";
        ok = (r->accel_file
                  ? tt_accel_load(j.ctx, j.scene, r->accel_file, r->accel.build.isa, &j.accel)
                  : tt_accel_build(j.ctx, j.scene, &r->accel.build, &j.accel)) == TT_OK;
    }
    if (ok) {
        what = "the camera";
        ok = render_make_camera(j.ctx, r, j.scene, &j.cam) == CLI_OK;
    }
    int st = CLI_RUNTIME;
    if (all_ok(&j, ok, what)) st = r->frames > 0 ? render_frames(&j) : render_tiles(&j);
    tt_accel_destroy(j.accel);
    tt_scene_destroy(j.scene);
    tt_context_destroy(j.ctx);
    MPI_Finalize();
    return st;
}
