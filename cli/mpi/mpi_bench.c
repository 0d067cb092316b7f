/* `treetrace bench` across MPI ranks: the matrix's scenes are shared out
 * (scene i on rank i mod N, so each rank loads only its scenes, and a run
 * is compared with Embree's run of the same scene on the same rank); rank
 * 0 gathers every other rank's results into its own (bench_runner.c fills
 * them, parallel to the matrix's runs) and writes results.csv and
 * report.md as one process would. Heatmaps are written by the rank that
 * traced them (a shared folder). */
#include <mpi.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "mpi/mpi.h"

int cli_mpi_bench_begin(int *rank, int *ranks)
{
    MPI_Init(NULL, NULL);
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, ranks);
    return 0;
}

int cli_mpi_bench_end(int rc)
{
    int worst = rc;
    MPI_Allreduce(&rc, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return worst;
}

/* The owner of run i: the rank of its scene. */
static int owner(const bench_matrix *m, size_t i, int ranks)
{
    return (int)(m->runs[i].scene % (size_t)ranks);
}

int cli_mpi_bench_gather(const bench_matrix *m, bench_results *res)
{
    int rank, ranks;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    /* a result travels as its bytes; its two pointers as indices */
    const int bytes = (int)sizeof(bench_result);
    for (size_t i = 0; i < m->count; i++) {
        const int src = owner(m, i, ranks);
        if (src == 0) continue;
        bench_result *r = &res->items[i];
        long embree = -1;
        if (rank == src) {
            embree = r->embree ? (long)(r->embree - res->items) : -1;
            MPI_Send(r, bytes, MPI_BYTE, 0, 10, MPI_COMM_WORLD);
            MPI_Send(&embree, 1, MPI_LONG, 0, 11, MPI_COMM_WORLD);
        } else if (rank == 0) {
            MPI_Recv(r, bytes, MPI_BYTE, src, 10, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            MPI_Recv(&embree, 1, MPI_LONG, src, 11, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            r->run = &m->runs[i];
            r->embree = embree >= 0 && (size_t)embree < res->count ? &res->items[embree] : NULL;
        }
    }
    return 0;
}
