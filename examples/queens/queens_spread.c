/*
 * Work stealing between ranks (queens_spread.h, docs/scale-out.md).
 *
 * Messages (MPI_COMM_WORLD):
 *   TAG_ASK       a dry rank asks one other rank for work (no payload)
 *   TAG_GIVE      the answer: 0 or more units (half of the asked rank's deque)
 *   TAG_DONE      to rank 0: this many units were counted (uint64)
 *   TAG_FAIL      to rank 0: a rank cannot count (its message)
 *   TAG_STOP      from rank 0: every unit is counted, or a rank failed
 * A dry rank has at most one question open and asks the ranks in turn.
 * Units only move inside answers, and rank 0 stops the search when the
 * counted units reach the total, so no unit is lost or counted twice.
 * After STOP every rank keeps answering questions (with nothing) until its
 * own question is answered, then joins a non-blocking barrier and keeps
 * answering until the barrier completes: no message is left unreceived.
 * The counts are then reduced on rank 0 (MPI_Reduce) and the per-rank
 * reports gathered (MPI_Gather).  Every wait is bounded by the rank
 * timeout (mpi_job.h): a question unanswered that long, a message not
 * taken, a barrier not reached end the job with a message naming the
 * rank; a rank that dies makes mpirun stop the job, and rank 0 says so.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mpi_launch.h"
#include "queens_spread.h"

#if QUEENS_HAVE_MPI
#include <mpi.h>

#include "mpi_job.h"
#endif

enum { TAG_ASK = 11, TAG_GIVE, TAG_DONE, TAG_FAIL, TAG_STOP };

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void nap(long microseconds)
{
    const struct timespec pause = { 0, microseconds * 1000 };
    nanosleep(&pause, NULL);
}

/* The units a rank holds: it counts from the front, gives from the back. */
typedef struct deque {
    queens_node *units;
    size_t head, tail, capacity;
} deque;

static size_t deque_size(const deque *d)
{
    return d->tail - d->head;
}

static int deque_push(deque *d, const queens_node *units, size_t count)
{
    if (d->head > 0) { /* compact */
        memmove(d->units, d->units + d->head, deque_size(d) * sizeof *d->units);
        d->tail -= d->head;
        d->head = 0;
    }
    if (d->tail + count > d->capacity) {
        size_t capacity = d->tail + count;
        queens_node *grown = realloc(d->units, (capacity ? capacity : 1) * sizeof *grown);
        if (!grown)
            return 0;
        d->units = grown;
        d->capacity = capacity;
    }
    memcpy(d->units + d->tail, units, count * sizeof *units);
    d->tail += count;
    return 1;
}

typedef struct rank_state {
    const queens_job *job;
    const char *program;
    double timeout;            /* the rank timeout in seconds */
    int rank, size, local_rank;
    int mpi;                   /* running under MPI (else alone: no MPI call) */
    deque work;
    size_t total;              /* units of the whole tree */
    uint64_t counted_total;    /* rank 0: units counted by all */
    int stopped;               /* STOP seen (or sent, on rank 0) */
    int failed;                /* this rank cannot count */
    int asking;                /* a question is open */
    double asked_at;           /* since when */
    int victim;                /* the rank asked last */
    int refusals;              /* empty answers in a row */
    char failure[PERMA_MESSAGE_MAX + 64]; /* rank 0: the first failure */
    queens_rank_report report;
} rank_state;

#if QUEENS_HAVE_MPI

/* Complete a request that needs rank `peer` (its answer, or its taking a
 * message): one silent for the rank timeout ends the job. */
static void complete(const rank_state *s, MPI_Request *request, int peer, const char *what)
{
    if (!mpi_job_wait(1, request, MPI_STATUSES_IGNORE, s->timeout, NULL, NULL))
        mpi_job_abort(s->program, s->rank, "rank %d has not %s for more than %g s (--rank-timeout; it is stopped "
                      "or stuck); aborting the job", peer, what, s->timeout);
}

static void send_small(const rank_state *s, const void *data, int bytes, int to, int tag)
{
    MPI_Request request;
    MPI_Isend(data, bytes, MPI_BYTE, to, tag, MPI_COMM_WORLD, &request);
    complete(s, &request, to, "taken a message");
}

static void report_failure(rank_state *s, const char *message);

static void stop_everyone(rank_state *s)
{
    if (s->stopped)
        return;
    s->stopped = 1;
    char none = 0;
    for (int r = 1; r < s->size; ++r)
        send_small(s, &none, 1, r, TAG_STOP);
}

/* Handle every message waiting; returns once none is. */
static void serve(rank_state *s)
{
    while (s->mpi) {
        int flag = 0;
        MPI_Status probe;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &probe);
        if (!flag)
            return;
        int bytes = 0, from = probe.MPI_SOURCE;
        MPI_Get_count(&probe, MPI_BYTE, &bytes);
        char *message = malloc(bytes > 0 ? (size_t)bytes : 1);
        if (!message)
            MPI_Abort(MPI_COMM_WORLD, 1);
        MPI_Recv(message, bytes, MPI_BYTE, from, probe.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        switch (probe.MPI_TAG) {
        case TAG_ASK: {
            /* Half of what is left, from the back (the least explored end). */
            size_t give = deque_size(&s->work) / 2;
            s->work.tail -= give;
            if (give) {
                s->report.gifts++;
                s->report.given_units += give;
            }
            send_small(s, s->work.units ? s->work.units + s->work.tail : (void *)message,
                       (int)(give * sizeof(queens_node)), from, TAG_GIVE);
            break;
        }
        case TAG_GIVE: {
            size_t count = (size_t)bytes / sizeof(queens_node);
            s->asking = 0;
            if (count && deque_push(&s->work, (const queens_node *)message, count)) {
                s->report.steals++;
                s->report.stolen_units += count;
                s->refusals = 0;
            } else if (count) {
                /* Out of memory: the units are lost, so the job fails. */
                s->failed = 1;
                report_failure(s, "out of memory for stolen units");
            } else {
                s->refusals++;
            }
            break;
        }
        case TAG_DONE: {
            uint64_t done;
            memcpy(&done, message, sizeof done);
            s->counted_total += done;
            if (s->counted_total >= s->total)
                stop_everyone(s);
            break;
        }
        case TAG_FAIL:
            if (!s->failure[0])
                snprintf(s->failure, sizeof s->failure, "%.*s", bytes, message);
            stop_everyone(s);
            break;
        case TAG_STOP:
            s->stopped = 1;
            break;
        }
        free(message);
    }
}

/* Ask the next rank in turn for work; after a round of empty answers
 * wait a little before the next round. */
static void ask_for_work(rank_state *s)
{
    if (s->refusals >= s->size - 1) {
        nap(1000);
        s->refusals = 0;
    }
    s->victim = (s->victim + 1) % s->size;
    if (s->victim == s->rank)
        s->victim = (s->victim + 1) % s->size;
    char none = 0;
    send_small(s, &none, 0, s->victim, TAG_ASK);
    s->asking = 1;
    s->asked_at = mpi_job_now();
    s->report.requests++;
}

/* An open question unanswered for the rank timeout: the asked rank is
 * stopped or stuck (a rank answers between runs of `chunk` units). */
static void check_question(const rank_state *s)
{
    if (s->asking && mpi_job_now() - s->asked_at > s->timeout)
        mpi_job_abort(s->program, s->rank, "rank %d has not answered a request for work for more than %g s "
                      "(--rank-timeout; it is stopped or stuck); aborting the job", s->victim, s->timeout);
}

static void report_counted(rank_state *s, uint64_t units)
{
    if (s->rank == 0) {
        s->counted_total += units;
        if (s->counted_total >= s->total && s->mpi)
            stop_everyone(s);
        else if (s->counted_total >= s->total)
            s->stopped = 1;
    } else {
        send_small(s, &units, sizeof units, 0, TAG_DONE);
    }
}

static void report_failure(rank_state *s, const char *message)
{
    char text[PERMA_MESSAGE_MAX + 64];
    if (strcmp(s->report.device, "?") == 0)
        snprintf(text, sizeof text, "rank %d: %s", s->rank, message);
    else
        snprintf(text, sizeof text, "rank %d (device %s): %s", s->rank, s->report.device, message);
    if (s->rank == 0) {
        if (!s->failure[0])
            snprintf(s->failure, sizeof s->failure, "%s", s->mpi ? text : message);
        if (s->mpi)
            stop_everyone(s);
        s->stopped = 1;
    } else {
        /* Synchronous: received before this rank can reach the barrier. */
        MPI_Request request;
        MPI_Issend(text, (int)strlen(text), MPI_BYTE, 0, TAG_FAIL, MPI_COMM_WORLD, &request);
        complete(s, &request, 0, "taken this rank's failure");
    }
}

static void serve_callback(void *user)
{
    serve(user);
}

/* A barrier that answers questions meanwhile; one not reached by every
 * rank within the rank timeout ends the job. */
static void barrier(rank_state *s, const char *what)
{
    MPI_Request request;
    MPI_Ibarrier(MPI_COMM_WORLD, &request);
    if (!mpi_job_wait(1, &request, MPI_STATUSES_IGNORE, s->timeout, serve_callback, s))
        mpi_job_abort(s->program, s->rank, "not every rank %s within %g s (--rank-timeout; a rank is stopped "
                      "or stuck); aborting the job", what, s->timeout);
}

/* Every rank has its runtime (compiled) before any searches, so that a
 * slow compile does not look like a slow rank. */
static void start_together(rank_state *s)
{
    if (s->mpi)
        barrier(s, "built its runtime");
}

/* After STOP: answer until the own question is answered and every rank
 * has come this far. */
static void finish_messages(rank_state *s)
{
    if (!s->mpi)
        return;
    while (s->asking) {
        serve(s);
        check_question(s);
        if (s->asking)
            nap(100);
    }
    barrier(s, "reached the end of the search");
}

#else

static void serve(rank_state *s)
{
    (void)s;
}

static void ask_for_work(rank_state *s)
{
    (void)s;
}

static void report_counted(rank_state *s, uint64_t units)
{
    s->counted_total += units;
    if (s->counted_total >= s->total)
        s->stopped = 1;
}

static void report_failure(rank_state *s, const char *message)
{
    snprintf(s->failure, sizeof s->failure, "%s", message);
    s->stopped = 1;
}

static void finish_messages(rank_state *s)
{
    (void)s;
}

static void start_together(rank_state *s)
{
    (void)s;
}

static void check_question(const rank_state *s)
{
    (void)s;
}

#endif

/* The device of this rank: entry (local rank mod count) of the list. */
static perma_status choose_device(rank_state *s, perma_device_ref *device, perma_error *error)
{
    perma_device_ref devices[PERMA_MAX_DEVICES];
    unsigned count = 0;
    perma_status st = perma_device_list(s->job->devices, devices, PERMA_MAX_DEVICES, &count, error);
    if (st != PERMA_OK) {
        char message[PERMA_MESSAGE_MAX];
        snprintf(message, sizeof message, "%s", error->message);
        snprintf(error->message, sizeof error->message, "--devices: %.1000s", message);
        return st;
    }
    *device = devices[(unsigned)s->local_rank % count];
    perma_device_ref_format(device, s->report.device, sizeof s->report.device);
    return PERMA_OK;
}

/* The loop of one rank: count a chunk, answer, ask when dry. */
static void search(rank_state *s, queens_counter *counter)
{
    double start = now();
    while (!s->stopped) {
        serve(s);
        if (s->stopped)
            break;
        size_t have = deque_size(&s->work);
        if (have > 0 && !s->failed) {
            size_t take = have < s->job->chunk ? have : s->job->chunk;
            perma_error error;
            perma_status st = queens_counter_run(counter, s->work.units + s->work.head, take,
                                                 &s->report.counts, &error);
            if (st != PERMA_OK) {
                s->failed = 1;
                report_failure(s, error.message);
                continue;
            }
            s->work.head += take;
            s->report.units += take;
            report_counted(s, take);
        } else if (s->size > 1 && !s->asking && !s->failed) {
            ask_for_work(s);
        } else {
            check_question(s);
            nap(100);
        }
    }
    s->report.seconds = now() - start;
}

int queens_spread_run(const queens_job *job, queens_result *result, int *is_rank0, const char *program)
{
    rank_state s;
    memset(&s, 0, sizeof s);
    s.job = job;
    s.program = program;
    s.timeout = job->rank_timeout > 0.0 ? job->rank_timeout : 660.0;
    s.size = 1;
    int launched = mpi_launch_size();
#if QUEENS_HAVE_MPI
    int using_mpi = launched > 0;
    s.mpi = using_mpi;
    if (using_mpi) {
        /* Blocking collectives: a rank that never comes ends the job. */
        mpi_job_guard(program, mpi_launch_rank(), "the ranks did not all start the job", s.timeout);
        MPI_Init(NULL, NULL);
        MPI_Comm_rank(MPI_COMM_WORLD, &s.rank);
        MPI_Comm_size(MPI_COMM_WORLD, &s.size);
        mpi_job_watch(program, s.rank, s.size);
        if (s.rank == 0)
            mpi_job_state("the search did not finish");
        MPI_Comm local;
        MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, s.rank, MPI_INFO_NULL, &local);
        MPI_Comm_rank(local, &s.local_rank);
        mpi_job_watch_node(local);
        MPI_Comm_free(&local);
        mpi_job_unguard();
    }
#else
    if (launched > 1) {
        if (mpi_launch_rank() == 0)
            fprintf(stderr, "%s: started by mpirun as one of %d ranks, but built without MPI (meson "
                            "-Dmpi=disabled or Open MPI not found); install libopenmpi-dev and rebuild\n",
                    program, launched);
        return 1;
    }
#endif
    *is_rank0 = s.rank == 0;
    s.report.rank = s.rank;
    s.victim = s.rank;
    double start = now();

    /* Every rank cuts the same tree the same way and starts with its share. */
    queens_node *units = NULL;
    queens_counts above = { 0, 0 };
    size_t count = 0;
    int have_units = queens_units(job->n, job->depth, &units, &count, &above);
    s.total = count;
    size_t first = job->start == QUEENS_START_EVEN ? count * (size_t)s.rank / (size_t)s.size : 0;
    size_t last = job->start == QUEENS_START_EVEN ? count * (size_t)(s.rank + 1) / (size_t)s.size
                                                  : (s.rank == 0 ? count : 0);
    have_units = have_units && deque_push(&s.work, units + first, last - first);
    free(units);

    queens_counter *counter = NULL;
    perma_device_ref device;
    perma_error error;
    snprintf(s.report.device, sizeof s.report.device, "?");
    perma_status st = choose_device(&s, &device, &error);
    if (st == PERMA_OK)
        st = queens_counter_create(&device, &counter, &error);
    if (st == PERMA_OK)
        snprintf(s.report.device, sizeof s.report.device, "%s", queens_counter_device(counter));
    /* A rank that cannot count tells rank 0, which stops the search. */
    if (!have_units || st != PERMA_OK) {
        s.failed = 1;
        report_failure(&s, have_units ? error.message : "out of memory for the work units");
    }
    if (s.total == 0)
        s.stopped = 1;
    start_together(&s);
    search(&s, counter);
    finish_messages(&s);
    queens_counter_destroy(counter);
    free(s.work.units);
    int code = 0;

    /* The counts, reduced on rank 0, and what each rank did. */
    queens_counts total = s.report.counts;
    queens_rank_report *reports = s.rank == 0 ? calloc((size_t)s.size, sizeof *reports) : NULL;
#if QUEENS_HAVE_MPI
    if (using_mpi) {
        uint64_t mine[2] = { s.report.counts.solutions, s.report.counts.nodes }, sum[2] = { 0, 0 };
        MPI_Request requests[2];
        MPI_Ireduce(mine, sum, 2, MPI_UINT64_T, MPI_SUM, 0, MPI_COMM_WORLD, &requests[0]);
        MPI_Igather(&s.report, sizeof s.report, MPI_BYTE, reports, sizeof s.report, MPI_BYTE, 0, MPI_COMM_WORLD,
                    &requests[1]);
        if (!mpi_job_wait(2, requests, MPI_STATUSES_IGNORE, s.timeout, NULL, NULL))
            mpi_job_abort(program, s.rank, "the ranks did not all send their counts within %g s (--rank-timeout; "
                          "a rank is stopped or stuck); aborting the job", s.timeout);
        total = (queens_counts){ sum[0], sum[1] };
        mpi_job_unwatch();
        mpi_job_guard(program, s.rank, "the ranks did not all finish the job (MPI_Finalize)", s.timeout);
        MPI_Finalize();
        mpi_job_unguard();
    } else if (reports) {
        reports[0] = s.report;
    }
#else
    if (reports)
        reports[0] = s.report;
#endif
    if (s.rank != 0)
        return s.failed ? 1 : 0;
    if (s.failure[0]) {
        fprintf(stderr, "%s: %s\n", program, s.failure);
        code = 1;
    } else if (!reports) {
        fprintf(stderr, "%s: out of memory for %d reports\n", program, s.size);
        code = 1;
    }
    if (code != 0) {
        free(reports);
        return code;
    }
    result->ranks = s.size;
    result->counts = (queens_counts){ total.solutions + above.solutions, total.nodes + above.nodes };
    result->units = count;
    result->reports = reports;
    result->seconds = now() - start;
    return 0;
}
