/* Whether a launcher started us (shared by builds with and without MPI, so
 * that `mpirun -np 2 treetrace render` on a build without MPI refuses
 * instead of rendering the whole frame twice). */
#include <stdlib.h>

#include "mpi/mpi.h"

int cli_mpi_env_size(void)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE",
                                       "MPI_LOCALNRANKS"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++) {
        const char *v = getenv(vars[i]);
        if (v && atoi(v) > 0) return atoi(v);
    }
    return 1;
}

int cli_mpi_wanted(int option_given) { return option_given || cli_mpi_env_size() > 1; }
