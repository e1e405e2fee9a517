/*
 * What the MPI examples (reyes-render, perma-queens) share as jobs of
 * several ranks: waits that neither spin nor last forever, ending the job
 * with a message, and what rank 0 says when mpirun stops the job.
 *
 * Waits.  Open MPI's blocking calls spin, and a spinning rank takes a core
 * from a renderer on the same node; so every wait here tests and naps.  A
 * wait is bounded by the job's rank timeout: a rank that does not answer
 * for that long (stopped, stuck) ends the job with a message naming it,
 * instead of the job hanging until mpirun's own timeout.
 *
 * Stops.  mpirun stops the job with SIGCONT then SIGTERM to every rank
 * (and SIGKILL a second later) both when a rank died and when mpirun
 * itself was interrupted (Ctrl-C, or SIGTERM sent to it).  To tell these
 * apart rank 0 keeps the process ids of the ranks on its node: when one of
 * them is gone, a rank ended early; when none is, the job was interrupted.
 * The other ranks delay their own exit on SIGTERM by 0.3 s, so that on an
 * interrupt rank 0 still finds them alive.  Ranks on other nodes cannot be
 * checked: rank 0 then says that either may have happened.
 */
#ifndef MPI_JOB_H
#define MPI_JOB_H

#include <mpi.h>

/* Seconds on a monotonic clock. */
double mpi_job_now(void);

/* Complete `count` requests, testing every 0.2 ms and calling serve(user)
 * (if not NULL) between tests; statuses may be MPI_STATUSES_IGNORE.
 * Returns 1 when all completed, 0 when `seconds` passed first (the
 * requests are then still pending: the caller ends the job). */
int mpi_job_wait(int count, MPI_Request *requests, MPI_Status *statuses, double seconds,
                 void (*serve)(void *user), void *user);

/* Time a waiting rank did not run itself (stopped, or descheduled on a
 * loaded machine) does not count against the rank it waits for: given the
 * seconds since it last looked (a loop that looks every 0.2 ms), the
 * seconds to add to its deadlines (0, or all of them past 1 s). */
double mpi_job_own_pause(double since_last_look);

/* Print "PROGRAM: rank RANK: MESSAGE" (printf format) on stderr and end
 * every rank of the job with status 1 (MPI_Abort).  Does not return. */
void mpi_job_abort(const char *program, int rank, const char *format, ...)
    __attribute__((format(printf, 3, 4), noreturn));

/* A deadline for MPI calls that have no non-blocking form and wait for
 * every rank (MPI_Init_thread, MPI_Comm_split_type, MPI_Finalize): when
 * the calls between mpi_job_guard and mpi_job_unguard take longer than
 * `seconds`, a watchdog thread prints "PROGRAM: rank RANK: WHAT within
 * SECONDS s (--rank-timeout; a rank is stopped or stuck)" and exits with
 * status 1, which makes mpirun end the job.  `what` must outlive the
 * guard. */
void mpi_job_guard(const char *program, int rank, const char *what, double seconds);
void mpi_job_unguard(void);

/* Handle SIGTERM and SIGINT from here on: rank 0 prints why the job
 * stopped (the process ids of its node's ranks come from
 * mpi_job_watch_node) and what the job has done (mpi_job_state), then
 * exits with status 1; the other ranks exit with status 1 after 0.3 s.
 * `program` must outlive the job. */
void mpi_job_watch(const char *program, int rank, int size);

/* Collective over `node` (the ranks of one node, MPI_Comm_split_type, in
 * world-rank order): rank 0 learns the process ids of the ranks on its
 * node. */
void mpi_job_watch_node(MPI_Comm node);

/* Rank 0: what the job has done so far, added to the message when it is
 * stopped ("no image written; rank 1 held bucket 404").  Not from a
 * signal handler; copied, so `text` may be reused. */
void mpi_job_state(const char *text);

/* The default actions of SIGTERM and SIGINT again (before the job's own
 * MPI_Abort or its end). */
void mpi_job_unwatch(void);

#endif
