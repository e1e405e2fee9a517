/*
 * reyes-render as an MPI job (`mpirun -n N reyes-render ...`): rank 0
 * holds the pool of buckets (or frames), hands them out one at a time to
 * the ranks that ask (itself included, in a render thread), gathers the
 * tiles and writes the PNG.  Each rank renders on one device: the entry
 * (local rank mod count) of --devices, or PERMA_DEVICE's first.  A rank
 * that fails ends the job with its message on rank 0; a rank that dies
 * makes mpirun stop the job (rank 0 says so); a rank that holds an item
 * longer than --rank-timeout makes rank 0 abort the job.  See
 * docs/scale-out.md.
 */
#ifndef REYES_MPI_H
#define REYES_MPI_H

#include "reyes_cli.h"

/* The number of ranks when this process was started by an MPI launcher
 * (Open MPI's mpirun, Hydra or another PMI/PMIx one), else 0. */
int reyes_mpi_launched(void);

/* This process's rank as the launcher says (0 if not launched). */
int reyes_mpi_launched_rank(void);

/* Whether reyes-render was built with MPI (meson -Dmpi). */
int reyes_mpi_available(void);

/* Run the parsed command line as one rank; returns the exit status. */
int reyes_mpi_main(const reyes_cli *cli, const char *program);

#endif
