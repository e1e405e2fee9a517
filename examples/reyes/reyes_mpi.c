/*
 * reyes-render across MPI ranks (reyes_mpi.h, docs/scale-out.md).
 *
 * Messages (MPI_COMM_WORLD, all small but the tiles):
 *   worker -> 0  TAG_RESULT  header + rgb + coverage of the item it did
 *                            (item -1: none yet), and a request for the next
 *   0 -> worker  TAG_ITEM    the next item, or -1: no more
 *   worker -> 0  TAG_REPORT  its reyes_work_report, after the -1
 *   worker -> 0  TAG_FAIL    status and message; it takes no more items
 *   0 -> worker  TAG_RELEASE everything is gathered: finalize
 * Every wait is a test-and-sleep loop, so a waiting rank leaves the cores
 * to the renderers (Open MPI's blocking calls spin).  Rank 0's main thread
 * does all of its MPI calls (MPI_THREAD_FUNNELED); its render thread only
 * takes from and delivers to the pool.
 */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

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

#include "reyes_farm.h"
#include "reyes_report.h"

enum { TAG_RESULT = 1, TAG_ITEM, TAG_REPORT, TAG_FAIL, TAG_RELEASE };

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

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void nap(void)
{
    const struct timespec pause = { 0, 200000 }; /* 0.2 ms */
    nanosleep(&pause, NULL);
}

/* Complete a request without spinning. */
static void wait_quietly(MPI_Request *request)
{
    int done = 0;
    while (MPI_Test(request, &done, MPI_STATUS_IGNORE), !done)
        nap();
}

static void send_quietly(const void *data, int bytes, int to, int tag)
{
    MPI_Request request;
    MPI_Isend(data, bytes, MPI_BYTE, to, tag, MPI_COMM_WORLD, &request);
    wait_quietly(&request);
}

static void receive_quietly(void *data, int bytes, int from, int tag)
{
    MPI_Request request;
    MPI_Irecv(data, bytes, MPI_BYTE, from, tag, MPI_COMM_WORLD, &request);
    wait_quietly(&request);
}

/* What this rank renders with. */
typedef struct rank_setup {
    int rank, size, local_rank;
    perma_device_ref device;
    int device_known;
    reyes_job job;
    int have_job;
    reyes_status status;       /* of the setup */
    reyes_error error;
} rank_setup;

static void setup_rank(rank_setup *s, const reyes_cli *cli)
{
    MPI_Comm local;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, s->rank, MPI_INFO_NULL, &local);
    MPI_Comm_rank(local, &s->local_rank);
    int lowest = 0;
    MPI_Allreduce(&s->rank, &lowest, 1, MPI_INT, MPI_MIN, local);
    MPI_Comm_free(&local);
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
}

/* ---- Workers (rank > 0) ---- */

typedef struct worker {
    rank_setup *setup;
    uint8_t *pending;          /* the result message being built */
    size_t pending_bytes, capacity;
    double started;            /* when the item being rendered came */
} worker;

static int worker_next(void *user, unsigned *item)
{
    worker *w = user;
    if (w->pending_bytes == 0) {
        result_header none = { -1, { 0, 0, 0, 0 }, 0.0f };
        memcpy(w->pending, &none, sizeof none);
        w->pending_bytes = sizeof none;
    }
    send_quietly(w->pending, (int)w->pending_bytes, 0, TAG_RESULT);
    w->pending_bytes = 0;
    int32_t next = -1;
    receive_quietly(&next, sizeof next, 0, TAG_ITEM);
    if (next < 0)
        return 0;
    *item = (unsigned)next;
    w->started = now();
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
    result_header header = { (int32_t)item, { x0, y0, x1, y1 }, (float)(now() - w->started) };
    memcpy(w->pending, &header, sizeof header);
    reyes_image_pack_rect(image, header.rect, w->pending + sizeof header, w->pending + sizeof header + pixels * 3);
    w->pending_bytes = bytes;
    return REYES_OK;
}

static void send_failure(const rank_setup *s, reyes_status status, const char *message)
{
    fail_message fail = { (int32_t)status, "" };
    char label[64] = "";
    if (s->device_known)
        perma_device_ref_format(&s->device, label, sizeof label);
    snprintf(fail.text, sizeof fail.text, "rank %d%s%s%s: %s", s->rank, label[0] ? " (device " : "",
             label, label[0] ? ")" : "", message);
    send_quietly(&fail, (int)(offsetof(fail_message, text) + strlen(fail.text) + 1), 0, TAG_FAIL);
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
    double start = now();
    if (status == REYES_OK)
        status = reyes_renderer_create(&s->job.options, &renderer, &error);
    report.create_seconds = now() - start;
    if (status == REYES_OK) {
        snprintf(report.summary, sizeof report.summary, "%s", reyes_renderer_device(renderer));
        reyes_bucket_source source = { worker_next, worker_done, &w };
        status = reyes_job_work(&s->job, renderer, &source, &report, &error);
    }
    if (status == REYES_OK)
        send_quietly(&report, sizeof report, 0, TAG_REPORT);
    else
        send_failure(s, status, error.message);
    reyes_renderer_destroy(renderer);
    free(w.pending);
    char release;
    receive_quietly(&release, 1, 0, TAG_RELEASE);
    return status == REYES_OK ? 0 : 1;
}

/* ---- Rank 0 ---- */

/* What the SIGTERM handler says when mpirun stops the job (another rank
 * died): two buffers, the handler reads the one `term_current` names. */
static char term_text[2][1024];
static volatile sig_atomic_t term_current;

static void on_term(int signal_number)
{
    (void)signal_number;
    const char *text = term_text[term_current];
    ssize_t ignored = write(STDERR_FILENO, text, strlen(text));
    (void)ignored;
    _exit(1);
}

typedef struct holding {
    int32_t item;              /* -1: none */
    double since;
    int active;                /* has not sent its report or failure */
} holding;

static void update_term_text(const char *program, const char *kind, const holding *held, int size)
{
    int next = !term_current;
    char *text = term_text[next];
    size_t used = (size_t)snprintf(text, sizeof term_text[0], "%s: rank 0: the job was stopped "
                                   "(SIGTERM from mpirun: a rank died or was killed; see mpirun's "
                                   "report); no image written", program);
    for (int r = 1; r < size && used < sizeof term_text[0]; ++r)
        if (held[r].item >= 0)
            used += (size_t)snprintf(text + used, sizeof term_text[0] - used, "; rank %d held %s %d", r, kind,
                                     (int)held[r].item);
    if (used < sizeof term_text[0] - 1)
        strcat(text, "\n");
    term_current = next;
}

/* Receive and handle one message from a worker: a result is delivered
 * and answered with the next item; a report or failure ends the rank. */
static void handle_message(reyes_pool *pool, MPI_Status *probe, holding *held, reyes_work_report *reports,
                           int *active)
{
    int source = probe->MPI_SOURCE, bytes = 0;
    MPI_Get_count(probe, MPI_BYTE, &bytes);
    uint8_t *message = malloc(bytes > 0 ? (size_t)bytes : 1);
    if (!message) {
        fprintf(stderr, "rank 0: out of memory for a %d-byte message\n", bytes);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Recv(message, bytes, MPI_BYTE, source, probe->MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    held[source].since = now();
    if (probe->MPI_TAG == TAG_RESULT && (size_t)bytes >= sizeof(result_header)) {
        result_header header;
        memcpy(&header, message, sizeof header);
        if (header.item >= 0) {
            size_t pixels = (size_t)(header.rect[2] - header.rect[0]) * (header.rect[3] - header.rect[1]);
            reyes_error error;
            if ((size_t)bytes != sizeof header + pixels * 4 || header.item != held[source].item)
                reyes_pool_fail(pool, "rank 0", REYES_ERR_RUNTIME, "a malformed result message");
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
    double start = now();
    int size = s->size;
    holding *held = calloc((size_t)size, sizeof *held);
    reyes_work_report *reports = calloc((size_t)size, sizeof *reports);
    if (!held || !reports) {
        fprintf(stderr, "%s: rank 0: out of memory for %d ranks\n", program, size);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    /* A job that did not set up still runs the loop: every rank is told
     * there is nothing to do, so they all end cleanly. */
    reyes_job empty;
    memset(&empty, 0, sizeof empty);
    empty.frames = 1;
    reyes_pool pool;
    reyes_error error;
    reyes_status status = s->status;
    if (status == REYES_OK)
        status = reyes_pool_init(&pool, &s->job, &error);
    else
        error = s->error;
    if (status != REYES_OK) {
        reyes_pool_init(&pool, &empty, NULL);
        reyes_pool_fail(&pool, "rank 0", status, error.message);
    }
    for (int r = 0; r < size; ++r)
        held[r] = (holding){ -1, start, r > 0 };
    int active = size - 1;
    double rank_timeout = cli->rank_timeout > 0.0 ? cli->rank_timeout : 660.0;
    const char *kind = s->job.frames ? "frame" : "bucket";

    update_term_text(program, kind, held, size);
    /* The progress line, for the whole job: every rank's deliveries. */
    reyes_progress progress;
    int terminal, shown = status == REYES_OK && reyes_progress_wanted(cli->progress, cli->quiet, &terminal);
    if (shown) {
        reyes_progress_start(&progress, stderr, terminal, program, s->job.frames ? "frames" : "buckets",
                             s->job.items);
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
    while (active > 0 || (local_running && !local.finished)) {
        int flag = 0;
        MPI_Status probe;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &probe);
        if (flag) {
            handle_message(&pool, &probe, held, reports, &active);
            update_term_text(program, kind, held, size);
            continue;
        }
        /* A rank silent for too long (holding an item, or not yet asking
         * for one, or not reporting) is stuck: end the job. */
        double t = now();
        for (int r = 1; r < size; ++r) {
            if (held[r].active && t - held[r].since > rank_timeout) {
                char what[64] = "sent nothing";
                if (held[r].item >= 0)
                    snprintf(what, sizeof what, "held %s %d", kind, (int)held[r].item);
                fprintf(stderr, "%s: rank %d has %s for more than %g s (--rank-timeout); aborting the "
                                "job\n", program, r, what, rank_timeout);
                fflush(stderr);
                MPI_Abort(MPI_COMM_WORLD, 1);
            }
        }
        nap();
    }
    if (local_running)
        pthread_join(local.thread, NULL);
    char release = 0;
    for (int r = 1; r < size; ++r)
        MPI_Send(&release, 1, MPI_BYTE, r, TAG_RELEASE, MPI_COMM_WORLD);
    signal(SIGTERM, SIG_DFL);

    status = reyes_pool_finish(&pool, &error);
    if (status == REYES_OK && !s->job.frames)
        status = reyes_write_png(s->job.output, &pool.image, &error);
    if (shown) {
        reyes_progress_finish(&progress, status == REYES_OK);
        reyes_progress_free(&progress);
    }
    double seconds = now() - start;
    reports[0] = local.report;
    if (cli->coordinator_only)
        snprintf(reports[0].device, sizeof reports[0].device, "none");
    if (status == REYES_OK && !cli->quiet)
        reyes_report_print(stdout, &s->job, reports, (unsigned)size, "rank", seconds);
    if (status == REYES_OK && cli->stats_path)
        status = reyes_report_save_json(cli->stats_path, &pool, reports, (unsigned)size, seconds, &error);
    if (status != REYES_OK)
        fprintf(stderr, "%s: %s\n", program, error.message);
    reyes_pool_free(&pool);
    free(held);
    free(reports);
    return status == REYES_OK ? 0 : status == REYES_ERR_ARGUMENT ? 2 : 1;
}

int reyes_mpi_main(const reyes_cli *cli, const char *program)
{
    int provided = 0;
    if (MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        fprintf(stderr, "%s: MPI_Init_thread failed\n", program);
        return 1;
    }
    rank_setup setup;
    memset(&setup, 0, sizeof setup);
    MPI_Comm_rank(MPI_COMM_WORLD, &setup.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &setup.size);
    if (setup.rank == 0) {
        /* From here on rank 0 says why it stops when mpirun stops it. */
        update_term_text(program, "item", NULL, 0);
        signal(SIGTERM, on_term);
    }
    int code;
    if (provided < MPI_THREAD_FUNNELED) {
        if (setup.rank == 0)
            fprintf(stderr, "%s: the MPI library gives no thread support (MPI_THREAD_FUNNELED)\n", program);
        code = 1;
    } else {
        setup_rank(&setup, cli);
        code = setup.rank == 0 ? run_coordinator(&setup, cli, program) : run_worker(&setup);
    }
    if (setup.have_job)
        reyes_job_free(&setup.job);
    MPI_Finalize();
    return code;
}

#endif
