/* Whether a program was started by an MPI launcher, from the environment
 * the launchers set (Open MPI's mpirun, MPICH's Hydra, MVAPICH, PMIx):
 * the examples call MPI_Init only then, so that running them directly
 * never needs MPI.  Header-only: shared by reyes-render and perma-queens. */
#ifndef MPI_LAUNCH_H
#define MPI_LAUNCH_H

#include <stdlib.h>

/* The number of ranks the launcher started, or 0 when there is none
 * (1 when a PMIx launcher does not say how many). */
static inline int mpi_launch_size(void)
{
    const char *names[] = { "OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MV2_COMM_WORLD_SIZE" };
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) {
        const char *value = getenv(names[k]);
        if (value && atoi(value) > 0)
            return atoi(value);
    }
    return getenv("PMIX_RANK") ? 1 : 0;
}

/* This process's rank as the launcher says; 0 without one. */
static inline int mpi_launch_rank(void)
{
    const char *names[] = { "OMPI_COMM_WORLD_RANK", "PMI_RANK", "MV2_COMM_WORLD_RANK", "PMIX_RANK" };
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) {
        const char *value = getenv(names[k]);
        if (value)
            return atoi(value);
    }
    return 0;
}

#endif
