/* A build without MPI: the MPI options and mpirun say so clearly. */
#include <stdio.h>

#include "cli.h"
#include "mpi/mpi.h"

int cli_mpi_render(render_args *r)
{
    (void)r;
    fprintf(stderr,
            "treetrace render: this build has no MPI (--mpi-split, mpirun -np %d): install "
            "libopenmpi-dev and openmpi-bin and rerun scripts/bootstrap.sh, or run it as one "
            "process\n", cli_mpi_env_size());
    return CLI_USAGE;
}

int cli_mpi_bench_begin(int *rank, int *ranks)
{
    *rank = 0;
    *ranks = 1;
    fprintf(stderr,
            "treetrace bench: this build has no MPI (mpirun -np %d): install libopenmpi-dev and "
            "openmpi-bin and rerun scripts/bootstrap.sh, or run it as one process\n",
            cli_mpi_env_size());
    return -1;
}

int cli_mpi_bench_gather(const struct bench_matrix *m, struct bench_results *res)
{
    (void)m;
    (void)res;
    return -1;
}

int cli_mpi_bench_end(int rc) { return rc; }
