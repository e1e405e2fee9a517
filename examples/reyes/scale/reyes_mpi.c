/*
 * reyes-render across MPI ranks (reyes_mpi.h, docs/scale-out.md).
 *
 * Messages (MPI_COMM_WORLD, all small but the tiles):
 *   worker -> 0  TAG_RESULT  header + rgb + coverage of the item it did
 *                            (item -1: none yet), and a request for the next
 *   0 -> worker  TAG_ITEM    the next item, or -1: no more
 *   worker -> 0  TAG_REPORT  its reyes_work_report, after the -1
 *   worker -> 0  TAG_FAIL    status and message; it takes no more items
 *   0 -> worker  TAG_ALIVE   to a rank that reported, every rank timeout / 4:
 *                            rank 0 still runs (the others are rendering)
 *   0 -> worker  TAG_RELEASE everything is gathered: finalize
 * Before any of these every rank compares its job with rank 0's
 * (reyes_mpi_agree.h).  Every wait is a test-and-sleep loop, so a waiting
 * rank leaves the cores to the renderers (Open MPI's blocking calls spin),
 * and is bounded by --rank-timeout: rank 0 ends the job when a worker is
 * silent that long, a worker when rank 0 is (mpi_job.h).  Rank 0's main
 * thread does all of its MPI calls (MPI_THREAD_FUNNELED); its render
 * thread only takes from and delivers to the pool.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mpi_launch.h"
#include "reyes_mpi.h"

int reyes_mpi_launched(void)
{
    return mpi_launch_size();
}

int reyes_mpi_launched_rank(void)
{
    return mpi_launch_rank();
}

#if !REYES_HAVE_MPI

int reyes_mpi_available(void)
{
    return 0;
}

int reyes_mpi_main(const reyes_cli *cli, const char *program)
{
    (void)cli;
    fprintf(stderr, "%s: started by mpirun as one of %d ranks, but built without MPI (meson "
                    "-Dmpi=disabled or Open MPI not found); install libopenmpi-dev and rebuild\n",
            program, reyes_mpi_launched());
    return 1;
}

#else

#include <mpi.h>

#include "mpi_job.h"
#include "reyes_farm.h"
#include "reyes_mpi_agree.h"
#include "reyes_report.h"

enum { TAG_RESULT = 1, TAG_ITEM, TAG_REPORT, TAG_FAIL, TAG_RELEASE, TAG_ALIVE };

/* The fixed part of a result message. */
typedef struct result_header {
    int32_t item;
    uint32_t rect[4];
    float seconds;             /* the worker's time for the item */
} result_header;

/* A failure message: status, then the text. */
typedef struct fail_message {
    int32_t status;
    char text[REYES_MESSAGE_MAX + 128];
} fail_message;

int reyes_mpi_available(void)
{
    return 1;
}

/* What this rank renders with. */
typedef struct rank_setup {
    int rank, size, local_rank;
    const char *program;
    double timeout;            /* --rank-timeout, or its default */
    perma_device_ref device;
    int device_known;
    reyes_job job;
    int have_job;
    reyes_status status;       /* of the setup */
    reyes_error error;
    char trace_path[4200];     /* --trace FILE as this rank writes it: FILE-rankN */
} rank_setup;

/* Frames are numbered from 1 in messages, as in their file names. */
static long shown_item(const reyes_job *job, int32_t item)
{
    return job->frames ? (long)item + 1 : (long)item;
}

static const char *item_kind(const reyes_job *job)
{
    return job->frames ? "frame" : "bucket";
}

static void setup_rank(rank_setup *s, const reyes_cli *cli)
{
    /* Blocking collectives: a rank that never comes ends the job. */
    mpi_job_guard(s->program, s->rank, "the ranks did not all start the job", s->timeout);
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, s->rank, MPI_INFO_NULL, &local);
    MPI_Comm_rank(local, &s->local_rank);
    int lowest = 0;
    MPI_Allreduce(&s->rank, &lowest, 1, MPI_INT, MPI_MIN, local);
    mpi_job_watch_node(local);
    MPI_Comm_free(&local);
    mpi_job_unguard();
    /* A coordinating rank 0 uses no device: its node's other ranks take
     * the list from its first entry. */
    if (cli->coordinator_only && lowest == 0)
        s->local_rank--;
    if (cli->coordinator_only && s->rank == 0) {
        s->status = reyes_job_init(&s->job, cli, &s->error);
        s->have_job = 1;
        if (s->status == REYES_OK && s->size < 2)
            s->status = reyes_fail(&s->error, REYES_ERR_ARGUMENT, "--coordinator-only needs 2 or more "
                                   "ranks (rank 0 renders nothing)");
        return;
    }
    perma_device_ref devices[PERMA_MAX_DEVICES];
    unsigned count = 0;
    perma_error perr;
    perma_status st = perma_device_list(cli->devices, devices, PERMA_MAX_DEVICES, &count, &perr);
    if (st != PERMA_OK) {
        s->status = reyes_fail(&s->error, st == PERMA_ERR_ARGUMENT ? REYES_ERR_ARGUMENT : REYES_ERR_RUNTIME,
                               "--devices: %s", perr.message);
        return;
    }
    /* One rank per device of a node: local ranks take the list in turn. */
    s->device = devices[(unsigned)s->local_rank % count];
    s->device_known = 1;
    s->status = reyes_job_init(&s->job, cli, &s->error);
    s->have_job = 1;
    if (s->status == REYES_OK)
        s->job.options.device = &s->device;
    if (s->status == REYES_OK && cli->render.trace_path) {
        /* Ranks are processes: one trace file each (trace.json: trace-rank1.json). */
        const char *path = cli->render.trace_path, *slash = strrchr(path, '/');
        const char *dot = strrchr(slash ? slash + 1 : path, '.');
        int stem = dot && dot != (slash ? slash + 1 : path) ? (int)(dot - path) : (int)strlen(path);
        snprintf(s->trace_path, sizeof s->trace_path, "%.*s-rank%d%s", stem, path, s->rank, path + stem);
        s->job.options.trace_path = s->trace_path;
    }
}

/* Every rank compares its job with rank 0's before rendering; 0 when they
 * must all refuse it. */
static int agree_on_job(const rank_setup *s, const reyes_cli *cli)
{
    size_t count = 0;
    reyes_setting *mine = NULL;
    if (s->have_job && s->status == REYES_OK) {
        mine = reyes_job_settings(&s->job, cli, &count);
        if (!mine)
            mpi_job_abort(s->program, s->rank, "out of memory for the job's settings");
    }
    int agree = reyes_mpi_agree(mine, count, s->rank, s->size, s->timeout, s->program);
    free(mine);
    return agree;
}

/* ---- Workers (rank > 0) ---- */

typedef struct worker {
    rank_setup *setup;
    uint8_t *pending;          /* the result message being built */
    size_t pending_bytes, capacity;
    double started;            /* when the item being rendered came */
} worker;

/* Complete requests to or from rank 0, which answers at once when it
 * runs: one silent for the rank timeout is stopped or stuck. */
static void with_rank0(const rank_setup *s, int count, MPI_Request *requests, MPI_Status *statuses)
{
    if (!mpi_job_wait(count, requests, statuses, s->timeout, NULL, NULL))
        mpi_job_abort(s->program, s->rank, "rank 0 has not answered for more than %g s (--rank-timeout; "
                      "it is stopped or stuck); aborting the job", s->timeout);
}

static int worker_next(void *user, unsigned *item)
{
    worker *w = user;
    if (w->pending_bytes == 0) {
        result_header none = { -1, { 0, 0, 0, 0 }, 0.0f };
        memcpy(w->pending, &none, sizeof none);
        w->pending_bytes = sizeof none;
    }
    int32_t next = -1;
    MPI_Request requests[2];
    MPI_Isend(w->pending, (int)w->pending_bytes, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD, &requests[0]);
    MPI_Irecv(&next, sizeof next, MPI_BYTE, 0, TAG_ITEM, MPI_COMM_WORLD, &requests[1]);
    with_rank0(w->setup, 2, requests, MPI_STATUSES_IGNORE);
    w->pending_bytes = 0;
    if (next < 0)
        return 0;
    *item = (unsigned)next;
    w->started = mpi_job_now();
    return 1;
}

static reyes_status worker_done(void *user, unsigned item, const reyes_image *image, unsigned x0,
                                unsigned y0, unsigned x1, unsigned y1, reyes_error *error)
{
    worker *w = user;
    size_t pixels = (size_t)(x1 - x0) * (y1 - y0);
    size_t bytes = sizeof(result_header) + pixels * 4;
    if (bytes > w->capacity) {
        uint8_t *grown = realloc(w->pending, bytes);
        if (!grown)
            return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a %zu-byte tile", bytes);
        w->pending = grown;
        w->capacity = bytes;
    }
    result_header header = { (int32_t)item, { x0, y0, x1, y1 }, (float)(mpi_job_now() - w->started) };
    memcpy(w->pending, &header, sizeof header);
    reyes_image_pack_rect(image, header.rect, w->pending + sizeof header, w->pending + sizeof header + pixels * 3);
    w->pending_bytes = bytes;
    return REYES_OK;
}

static void send_to_rank0(const rank_setup *s, const void *data, int bytes, int tag)
{
    MPI_Request request;
    MPI_Isend(data, bytes, MPI_BYTE, 0, tag, MPI_COMM_WORLD, &request);
    with_rank0(s, 1, &request, MPI_STATUSES_IGNORE);
}

static void send_failure(const rank_setup *s, reyes_status status, const char *message)
{
    fail_message fail = { (int32_t)status, "" };
    char label[64] = "";
    if (s->device_known)
        perma_device_ref_format(&s->device, label, sizeof label);
    snprintf(fail.text, sizeof fail.text, "rank %d%s%s%s: %s", s->rank, label[0] ? " (device " : "",
             label, label[0] ? ")" : "", message);
    send_to_rank0(s, &fail, (int)(offsetof(fail_message, text) + strlen(fail.text) + 1), TAG_FAIL);
}

/* After its report: wait for the others to finish (rank 0 says it is
 * alive meanwhile), then RELEASE. */
static void wait_for_release(const rank_setup *s)
{
    for (;;) {
        char byte;
        MPI_Request request;
        MPI_Status status;
        MPI_Irecv(&byte, 1, MPI_BYTE, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &request);
        with_rank0(s, 1, &request, &status);
        if (status.MPI_TAG == TAG_RELEASE)
            return;
    }
}

static int run_worker(rank_setup *s)
{
    reyes_work_report report;
    memset(&report, 0, sizeof report);
    report.rank = s->rank;
    perma_device_ref_format(&s->device, report.device, sizeof report.device);
    reyes_renderer *renderer = NULL;
    reyes_status status = s->status;
    reyes_error error = s->error;
    worker w = { s, malloc(sizeof(result_header)), 0, sizeof(result_header), 0.0 };
    if (status == REYES_OK && !w.pending)
        status = reyes_fail(&error, REYES_ERR_NO_MEMORY, "out of memory");
    double start = mpi_job_now();
    if (status == REYES_OK)
        status = reyes_renderer_create(&s->job.options, &renderer, &error);
    report.create_seconds = mpi_job_now() - start;
    if (status == REYES_OK) {
        snprintf(report.summary, sizeof report.summary, "%s", reyes_renderer_device(renderer));
        reyes_bucket_source source = { worker_next, worker_done, &w };
        status = reyes_job_work(&s->job, renderer, &source, &report, &error);
    }
    if (status == REYES_OK)
        send_to_rank0(s, &report, sizeof report, TAG_REPORT);
    else
        send_failure(s, status, error.message);
    reyes_renderer_destroy(renderer);
    free(w.pending);
    wait_for_release(s);
    return status == REYES_OK ? 0 : 1;
}

/* ---- Rank 0 ---- */

typedef struct holding {
    int32_t item;              /* -1: none */
    double since;
    int active;                /* has not sent its report or failure */
} holding;

/* What rank 0 says when the job is stopped: what is written, who held what. */
static void update_state(reyes_pool *pool, const holding *held, int size)
{
    char text[2048];
    reyes_pool_describe_written(pool, text, sizeof text);
    size_t used = strlen(text);
    for (int r = 1; r < size && used < sizeof text; ++r)
        if (held[r].item >= 0)
            used += (size_t)snprintf(text + used, sizeof text - used, "; rank %d held %s %ld", r,
                                     item_kind(pool->job), shown_item(pool->job, held[r].item));
    mpi_job_state(text);
}

/* A result's header and size fit the item its rank holds. */
static int result_fits(const reyes_pool *pool, const result_header *header, int32_t held, int bytes)
{
    unsigned rect[4];
    if (header->item != held || !reyes_pool_item_rect(pool, header->item, rect))
        return 0;
    for (int k = 0; k < 4; ++k)
        if (header->rect[k] != rect[k])
            return 0;
    size_t pixels = (size_t)(rect[2] - rect[0]) * (rect[3] - rect[1]);
    return (size_t)bytes == sizeof *header + pixels * 4;
}

/* Rank 0's view of the job for its stop message: the state is refreshed
 * whenever its own render thread delivered since the last look, also while
 * rank 0 waits for a message's body (a rank killed in the middle of sending
 * one never completes it, and the frames written meanwhile must be in the
 * message mpirun's SIGTERM prints). */
typedef struct coordinator_view {
    reyes_pool *pool;
    const holding *held;
    int size;
    unsigned delivered; /* pool->delivered at the last refresh */
} coordinator_view;

static void refresh_state(void *user)
{
    coordinator_view *v = user;
    pthread_mutex_lock(&v->pool->lock);
    int changed = v->pool->delivered != v->delivered;
    v->delivered = v->pool->delivered;
    pthread_mutex_unlock(&v->pool->lock);
    if (changed)
        update_state(v->pool, v->held, v->size);
}

/* Receive and handle one message from a worker: a result is delivered
 * and answered with the next item; a report or failure ends the rank.
 * The body is waited for at most `timeout` seconds. */
static void handle_message(coordinator_view *view, MPI_Status *probe, holding *held, reyes_work_report *reports,
                           int *active, double timeout, const char *program)
{
    reyes_pool *pool = view->pool;
    int source = probe->MPI_SOURCE, bytes = 0;
    MPI_Get_count(probe, MPI_BYTE, &bytes);
    uint8_t *message = malloc(bytes > 0 ? (size_t)bytes : 1);
    if (!message)
        mpi_job_abort(program, 0, "out of memory for a %d-byte message from rank %d", bytes, source);
    MPI_Request request;
    MPI_Irecv(message, bytes, MPI_BYTE, source, probe->MPI_TAG, MPI_COMM_WORLD, &request);
    if (!mpi_job_wait(1, &request, MPI_STATUSES_IGNORE, timeout, refresh_state, view)) {
        char written[2048];
        reyes_pool_describe_written(pool, written, sizeof written);
        mpi_job_abort(program, 0, "rank %d stopped in the middle of a %d-byte message for more than %g s "
                      "(--rank-timeout); aborting the job; %s", source, bytes, timeout, written);
    }
    held[source].since = mpi_job_now();
    if (probe->MPI_TAG == TAG_RESULT && (size_t)bytes >= sizeof(result_header)) {
        result_header header;
        memcpy(&header, message, sizeof header);
        if (header.item >= 0) {
            reyes_error error;
            char who[32];
            snprintf(who, sizeof who, "rank %d", source);
            size_t pixels = (size_t)(header.rect[2] - header.rect[0]) * (header.rect[3] - header.rect[1]);
            if (!result_fits(pool, &header, held[source].item, bytes))
                reyes_pool_fail(pool, who, REYES_ERR_RUNTIME, "a result that does not fit the item it was "
                                "given (was it started with other options?)");
            else if (reyes_pool_deliver(pool, (unsigned)header.item, header.rect, message + sizeof header,
                                        message + sizeof header + pixels * 3, header.seconds, &error)
                     != REYES_OK)
                reyes_pool_fail(pool, "rank 0", error.status, error.message);
        }
        unsigned item;
        int32_t next = reyes_pool_take(pool, source, &item) ? (int32_t)item : -1;
        held[source].item = next;
        MPI_Send(&next, sizeof next, MPI_BYTE, source, TAG_ITEM, MPI_COMM_WORLD);
    } else if (probe->MPI_TAG == TAG_REPORT && (size_t)bytes == sizeof(reyes_work_report)) {
        memcpy(&reports[source], message, sizeof reports[source]);
        held[source].active = 0;
        --*active;
    } else if (probe->MPI_TAG == TAG_FAIL && (size_t)bytes > offsetof(fail_message, text)) {
        fail_message fail;
        memset(&fail, 0, sizeof fail);
        memcpy(&fail, message, (size_t)bytes < sizeof fail ? (size_t)bytes : sizeof fail);
        fail.text[sizeof fail.text - 1] = '\0';
        /* The text names the rank: "rank 2 (device 0:0): ..." */
        const char *colon = strstr(fail.text, ": ");
        char who[128];
        snprintf(who, sizeof who, "%.*s", colon ? (int)(colon - fail.text) : 0, fail.text);
        reyes_pool_fail(pool, who, (reyes_status)fail.status, colon ? colon + 2 : fail.text);
        held[source].item = -1;
        held[source].active = 0;
        --*active;
    } else {
        reyes_pool_fail(pool, "rank 0", REYES_ERR_RUNTIME, "an unexpected message");
    }
    free(message);
}

static int run_coordinator(rank_setup *s, const reyes_cli *cli, const char *program)
{
    double start = mpi_job_now();
    int size = s->size;
    holding *held = calloc((size_t)size, sizeof *held);
    reyes_work_report *reports = calloc((size_t)size, sizeof *reports);
    if (!held || !reports)
        mpi_job_abort(program, 0, "out of memory for %d ranks", size);
    /* A job that did not set up still runs the loop: every rank is told
     * there is nothing to do, so they all end cleanly. */
    reyes_job empty;
    memset(&empty, 0, sizeof empty);
    empty.frames = 1;
    reyes_pool pool;
    reyes_error error = s->error;
    reyes_status status = s->status;
    /* Rank 0 writes the files: a path it cannot write ends the job now. */
    if (status == REYES_OK)
        status = reyes_job_check_outputs(&s->job, cli->stats_path, &error);
    if (status == REYES_OK) {
        if (!cli->quiet)
            reyes_job_print_notes(&s->job, stderr);
        status = reyes_pool_init(&pool, &s->job, &error);
    }
    if (status != REYES_OK) {
        reyes_pool_init(&pool, &empty, NULL);
        reyes_pool_fail(&pool, "rank 0", status, error.message);
    }
    for (int r = 0; r < size; ++r)
        held[r] = (holding){ -1, start, r > 0 };
    int active = size - 1;
    const reyes_job *job = pool.job;

    update_state(&pool, held, size);
    /* The progress line, for the whole job: every rank's deliveries. */
    reyes_progress progress;
    int terminal, shown = status == REYES_OK && reyes_progress_wanted(cli->progress, cli->quiet, &terminal);
    if (shown) {
        reyes_progress_start(&progress, stderr, terminal, program, job->frames ? "frames" : "buckets", job->items);
        pool.progress = &progress;
    }
    /* Rank 0 renders too, in a thread, as renderer 0 of the pool. */
    reyes_farm_worker local;
    char device[64], who[96];
    perma_device_ref_format(&s->device, device, sizeof device);
    snprintf(who, sizeof who, "rank 0 (device %s)", device);
    reyes_farm_worker_init(&local, &pool, 0, &s->device, who);
    int local_running = 0;
    if (status == REYES_OK && !cli->coordinator_only) {
        local_running = pthread_create(&local.thread, NULL, reyes_farm_worker_run, &local) == 0;
        if (!local_running)
            reyes_pool_fail(&pool, "rank 0", REYES_ERR_NO_MEMORY, "cannot start the render thread");
    }
    coordinator_view view = { &pool, held, size, 0 };
    double alive_sent = start, last_look = start;
    while (active > 0 || (local_running && !local.finished)) {
        double t = mpi_job_now();
        double paused = mpi_job_own_pause(t - last_look);
        last_look = t;
        for (int r = 1; r < size; ++r)
            held[r].since += paused;
        int flag = 0;
        MPI_Status probe;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &probe);
        if (flag) {
            handle_message(&view, &probe, held, reports, &active, s->timeout, program);
            update_state(&pool, held, size);
            continue;
        }
        refresh_state(&view); /* frames this rank's own thread wrote */
        /* Ranks that reported wait for the others: tell them rank 0 runs. */
        if (t - alive_sent > s->timeout / 4) {
            char alive = 0;
            for (int r = 1; r < size; ++r)
                if (!held[r].active)
                    MPI_Send(&alive, 1, MPI_BYTE, r, TAG_ALIVE, MPI_COMM_WORLD);
            alive_sent = t;
        }
        /* A rank silent for too long (holding an item, or not yet asking
         * for one, or not reporting) is stuck: end the job. */
        for (int r = 1; r < size; ++r) {
            if (held[r].active && t - held[r].since > s->timeout) {
                char what[64] = "sent nothing", written[2048];
                if (held[r].item >= 0)
                    snprintf(what, sizeof what, "held %s %ld", item_kind(job), shown_item(job, held[r].item));
                reyes_pool_describe_written(&pool, written, sizeof written);
                mpi_job_abort(program, 0, "rank %d has %s for more than %g s (--rank-timeout); aborting the "
                              "job; %s", r, what, s->timeout, written);
            }
        }
        const struct timespec pause = { 0, 200000 }; /* 0.2 ms */
        nanosleep(&pause, NULL);
    }
    if (local_running)
        pthread_join(local.thread, NULL);
    char release = 0;
    for (int r = 1; r < size; ++r)
        MPI_Send(&release, 1, MPI_BYTE, r, TAG_RELEASE, MPI_COMM_WORLD);
    mpi_job_unwatch();

    status = reyes_pool_finish(&pool, &error);
    const bool pool_failed = status != REYES_OK; /* else only writing the outputs can fail */
    double seconds = mpi_job_now() - start;
    reports[0] = local.report;
    if (cli->coordinator_only)
        snprintf(reports[0].device, sizeof reports[0].device, "none");
    if (status == REYES_OK)
        status = reyes_report_write_outputs(&pool, reports, (unsigned)size, seconds, cli->stats_path, &error);
    if (shown) {
        reyes_progress_finish(&progress, status == REYES_OK);
        reyes_progress_free(&progress);
    }
    if (status == REYES_OK && !cli->quiet)
        reyes_report_print(stdout, &s->job, reports, (unsigned)size, "rank", seconds);
    if (status != REYES_OK) {
        char written[2048] = "";
        if (job->frames && pool_failed)
            reyes_pool_describe_written(&pool, written, sizeof written);
        fprintf(stderr, "%s: %s%s%s\n", program, error.message, written[0] ? "; " : "", written);
    }
    reyes_pool_free(&pool);
    free(held);
    free(reports);
    return status == REYES_OK ? 0 : status == REYES_ERR_ARGUMENT ? 2 : 1;
}

int reyes_mpi_main(const reyes_cli *cli, const char *program)
{
    rank_setup setup;
    memset(&setup, 0, sizeof setup);
    setup.program = program;
    setup.timeout = cli->rank_timeout > 0.0f ? cli->rank_timeout : 660.0;
    int provided = 0;
    mpi_job_guard(program, reyes_mpi_launched_rank(), "the ranks did not all start MPI", setup.timeout);
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        fprintf(stderr, "%s: MPI_Init_thread failed\n", program);
        return 1;
    }
    mpi_job_unguard();
    MPI_Comm_rank(MPI_COMM_WORLD, &setup.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &setup.size);
    /* From here on rank 0 says why it stops when mpirun stops it. */
    mpi_job_watch(program, setup.rank, setup.size);
    if (setup.rank == 0)
        mpi_job_state("no image written");
    int code;
    if (provided < MPI_THREAD_FUNNELED) {
        if (setup.rank == 0)
            fprintf(stderr, "%s: the MPI library gives no thread support (MPI_THREAD_FUNNELED)\n", program);
        code = 1;
    } else {
        setup_rank(&setup, cli);
        if (!agree_on_job(&setup, cli))
            code = 2;
        else
            code = setup.rank == 0 ? run_coordinator(&setup, cli, program) : run_worker(&setup);
    }
    mpi_job_unwatch();
    if (setup.have_job)
        reyes_job_free(&setup.job);
    mpi_job_guard(program, setup.rank, "the ranks did not all finish the job (MPI_Finalize)", setup.timeout);
    MPI_Finalize();
    mpi_job_unguard();
    return code;
}

#endif
