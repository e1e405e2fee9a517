/* The ranks agree on the job before rendering (reyes_mpi_agree.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mpi.h>

#include "mpi_job.h"
#include "reyes_mpi_agree.h"

/* What a rank tells rank 0: its first setting that differs from rank
 * 0's (differing 0: none), and how many differ. */
typedef struct difference {
    int32_t differing;
    reyes_setting mine;        /* name "nothing": rank 0 has settings this rank lacks */
} difference;

static void wait_or_abort(MPI_Request *request, int rank, double timeout, const char *program)
{
    if (!mpi_job_wait(1, request, MPI_STATUSES_IGNORE, timeout, NULL, NULL))
        mpi_job_abort(program, rank, "the ranks did not all start the job within %g s (--rank-timeout); "
                      "aborting the job", timeout);
}

static void say_difference(const char *program, int rank, const difference *d, const reyes_setting *rank0,
                           size_t rank0_count)
{
    const reyes_setting *theirs = reyes_settings_find(rank0, rank0_count, d->mine.name);
    char more[64] = "";
    if (d->differing > 1)
        snprintf(more, sizeof more, " (and %d more setting%s)", d->differing - 1, d->differing > 2 ? "s" : "");
    if (strcmp(d->mine.name, "nothing") == 0)
        fprintf(stderr, "%s: rank %d lacks settings that rank 0 has%s\n", program, rank, more);
    else if (!theirs)
        fprintf(stderr, "%s: rank %d has %s %s where rank 0 has none%s\n", program, rank, d->mine.name,
                d->mine.value, more);
    else if (strcmp(d->mine.value, theirs->value) != 0)
        fprintf(stderr, "%s: rank %d has %s %s where rank 0 has %s%s\n", program, rank, d->mine.name,
                d->mine.value, theirs->value, more);
    else /* the same text, other contents: a model file that differs between nodes */
        fprintf(stderr, "%s: rank %d's %s %s differs from rank 0's in its contents%s\n", program, rank,
                d->mine.name, d->mine.value, more);
}

int reyes_mpi_agree(const reyes_setting *mine, size_t count, int rank, int size, double timeout,
                    const char *program)
{
    /* Rank 0's settings to every rank (-1: rank 0 has none to give). */
    int32_t rank0_count = rank == 0 ? (mine ? (int32_t)count : -1) : 0;
    MPI_Request request;
    MPI_Ibcast(&rank0_count, 1, MPI_INT32_T, 0, MPI_COMM_WORLD, &request);
    wait_or_abort(&request, rank, timeout, program);
    if (rank0_count < 0)
        return 1;
    reyes_setting *rank0 = rank == 0 ? (reyes_setting *)mine : calloc(rank0_count ? (size_t)rank0_count : 1, sizeof *rank0);
    if (!rank0)
        mpi_job_abort(program, rank, "out of memory for %d settings", (int)rank0_count);
    MPI_Ibcast(rank0, rank0_count * (int)sizeof *rank0, MPI_BYTE, 0, MPI_COMM_WORLD, &request);
    wait_or_abort(&request, rank, timeout, program);

    difference d;
    memset(&d, 0, sizeof d);
    if (rank != 0 && mine) {
        size_t differing = 0;
        size_t first = reyes_settings_compare(mine, count, rank0, (size_t)rank0_count, &differing);
        if (first != SIZE_MAX) {
            d.differing = (int32_t)differing;
            if (first < count)
                d.mine = mine[first];
            else
                snprintf(d.mine.name, sizeof d.mine.name, "nothing");
        }
    }
    /* Who differs: every rank learns whether any does, rank 0 learns how. */
    int differs = d.differing > 0, any = 0;
    difference *all = rank == 0 ? calloc((size_t)size, sizeof *all) : NULL;
    if (rank == 0 && !all)
        mpi_job_abort(program, rank, "out of memory for %d ranks", size);
    MPI_Request requests[2];
    MPI_Igather(&d, sizeof d, MPI_BYTE, all, sizeof d, MPI_BYTE, 0, MPI_COMM_WORLD, &requests[0]);
    MPI_Iallreduce(&differs, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD, &requests[1]);
    if (!mpi_job_wait(2, requests, MPI_STATUSES_IGNORE, timeout, NULL, NULL))
        mpi_job_abort(program, rank, "the ranks did not all start the job within %g s (--rank-timeout); "
                      "aborting the job", timeout);
    if (any && rank == 0) {
        int shown = 0;
        for (int r = 1; r < size; ++r) {
            if (all[r].differing > 0 && shown++ < 8)
                say_difference(program, r, &all[r], rank0, (size_t)rank0_count);
        }
        if (shown > 8)
            fprintf(stderr, "%s: and %d more ranks differ\n", program, shown - 8);
        fprintf(stderr, "%s: every rank must be started with the same models and image options; nothing "
                        "rendered\n", program);
    }
    free(all);
    if (rank != 0)
        free(rank0);
    return !any;
}
