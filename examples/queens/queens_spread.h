/*
 * Counting the work units of an N-queens tree over ranks: each rank keeps
 * a deque of units, counts them `chunk` at a time with perma, and when it
 * runs dry asks the other ranks in turn for work; a rank asked gives half
 * of what it holds.  Rank 0 counts completed units and ends the search
 * when all are done; the counts are then reduced on rank 0.  Without MPI
 * (or not under mpirun) the same loop runs in one process.
 */
#ifndef QUEENS_SPREAD_H
#define QUEENS_SPREAD_H

#include "queens.h"

typedef enum queens_start { QUEENS_START_EVEN, QUEENS_START_RANK0 } queens_start;

typedef struct queens_job {
    unsigned n, depth, chunk;
    queens_start start;
    const char *devices;     /* device list; rank r uses entry (local rank mod count) */
    /* MPI: a rank that does not answer for this long (seconds; 0: 660)
     * ends the job with a message naming it. */
    double rank_timeout;
} queens_job;

/* What one rank did. */
typedef struct queens_rank_report {
    int rank;
    uint64_t units;                  /* subtrees it counted */
    queens_counts counts;
    uint64_t requests;               /* steal requests it sent */
    uint64_t steals, stolen_units;   /* requests answered with work, and the units */
    uint64_t gifts, given_units;     /* requests it answered with work */
    double seconds;
    char device[256];
} queens_rank_report;

typedef struct queens_result {
    int ranks;
    queens_counts counts;            /* the whole tree */
    size_t units;                    /* work units at row depth */
    queens_rank_report *reports;     /* one per rank (rank 0 only); free() */
    double seconds;
} queens_result;

/* Run the job.  On rank 0 (or alone) returns 0 with *result filled, or
 * the exit status with a message printed; other ranks return their exit
 * status (result untouched).  `program` prefixes messages. */
int queens_spread_run(const queens_job *job, queens_result *result, int *is_rank0, const char *program);

#endif
