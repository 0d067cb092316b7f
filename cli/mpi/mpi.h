/* `treetrace render` across MPI ranks (Open MPI): mpi_render.c when the
 * build has MPI (CMake found it; TT_HAVE_MPI), mpi_none.c otherwise, which
 * says so. The non-MPI render path never calls into MPI. */
#ifndef TT_CLI_MPI_MPI_H
#define TT_CLI_MPI_MPI_H

#include "render_args.h"

/* Whether the command should run as an MPI job: an MPI option was given
 * (option_given), or an MPI launcher started more than one process
 * (OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX size > 1 in the environment). */
int cli_mpi_wanted(int option_given);
/* Runs the render as one rank of the job (rank 0 gathers, writes and
 * reports); without MPI, prints that this build has none. */
int cli_mpi_render(render_args *r);

/* `treetrace bench` under mpirun (mpi_bench.c): begin (MPI_Init; this
 * rank and the world size), rank 0's gathering of the other ranks' runs
 * into its results, and the end (the job's status: the worst rank's). */
struct bench_matrix;
struct bench_results;
int cli_mpi_bench_begin(int *rank, int *ranks);
int cli_mpi_bench_gather(const struct bench_matrix *m, struct bench_results *res);
int cli_mpi_bench_end(int rc);

/* The launcher's world size from the environment (1 when not launched). */
int cli_mpi_env_size(void);

#endif
