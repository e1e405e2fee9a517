/*
 * The ranks of a reyes-render MPI job agree on the job before any renders
 * (reyes_settings.h): rank 0's settings go to every rank, each compares
 * them with its own, and when one differs every rank refuses the job; rank
 * 0 names the first differing setting of each such rank.  Every wait is
 * bounded by the rank timeout (a rank that never comes ends the job).
 */
#ifndef REYES_MPI_AGREE_H
#define REYES_MPI_AGREE_H

#include "reyes_settings.h"

/* Collective over MPI_COMM_WORLD.  `mine` is NULL on a rank whose job did
 * not set up (it reports that itself, later); when rank 0's did not, there
 * is nothing to compare.  Returns 1 when the ranks agree, 0 when every
 * rank must refuse the job (rank 0 has printed why). */
int reyes_mpi_agree(const reyes_setting *mine, size_t count, int rank, int size, double timeout,
                    const char *program);

#endif
