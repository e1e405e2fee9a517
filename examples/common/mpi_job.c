/* Bounded waits and stop messages of the MPI examples (mpi_job.h). */
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "mpi_job.h"

double mpi_job_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int mpi_job_wait(int count, MPI_Request *requests, MPI_Status *statuses, double seconds,
                 void (*serve)(void *user), void *user)
{
    const struct timespec pause = { 0, 200000 }; /* 0.2 ms */
    double last = mpi_job_now(), deadline = last + seconds;
    int done = 0;
    while (MPI_Testall(count, requests, &done, statuses), !done) {
        double t = mpi_job_now();
        deadline += mpi_job_own_pause(t - last);
        last = t;
        if (t > deadline)
            return 0;
        if (serve)
            serve(user);
        nanosleep(&pause, NULL);
    }
    return 1;
}

double mpi_job_own_pause(double since_last_look)
{
    return since_last_look > 1.0 ? since_last_look : 0.0;
}

void mpi_job_abort(const char *program, int rank, const char *format, ...)
{
    char message[2048];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    mpi_job_unwatch();
    fprintf(stderr, "%s: rank %d: %s\n", program, rank, message);
    fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, 1);
    _exit(1); /* MPI_Abort does not return; this says so to the compiler */
}

/* ---- Guards ---- */

static pthread_mutex_t guard_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t guard_changed;
static int guard_initialized, guard_started, guard_armed;
static struct timespec guard_deadline;
static const char *guard_program, *guard_what;
static int guard_rank;
static double guard_seconds;

static void *guard_thread(void *unused)
{
    (void)unused;
    pthread_mutex_lock(&guard_lock);
    for (;;) {
        if (!guard_armed) {
            pthread_cond_wait(&guard_changed, &guard_lock);
            continue;
        }
        if (pthread_cond_timedwait(&guard_changed, &guard_lock, &guard_deadline) == ETIMEDOUT && guard_armed) {
            fprintf(stderr, "%s: rank %d: %s within %g s (--rank-timeout; a rank is stopped or stuck); ending "
                            "the job\n", guard_program, guard_rank, guard_what, guard_seconds);
            fflush(stderr);
            _exit(1);
        }
    }
    return NULL;
}

void mpi_job_guard(const char *program, int rank, const char *what, double seconds)
{
    pthread_mutex_lock(&guard_lock);
    if (!guard_initialized) {
        pthread_condattr_t attributes;
        pthread_condattr_init(&attributes);
        pthread_condattr_setclock(&attributes, CLOCK_MONOTONIC);
        pthread_cond_init(&guard_changed, &attributes);
        pthread_condattr_destroy(&attributes);
        guard_initialized = 1;
    }
    if (!guard_started) {
        pthread_t thread;
        guard_started = pthread_create(&thread, NULL, guard_thread, NULL) == 0;
        if (guard_started)
            pthread_detach(thread);
    }
    clock_gettime(CLOCK_MONOTONIC, &guard_deadline);
    guard_deadline.tv_sec += (time_t)seconds;
    guard_deadline.tv_nsec += (long)((seconds - (double)(time_t)seconds) * 1e9);
    if (guard_deadline.tv_nsec >= 1000000000L) {
        guard_deadline.tv_sec++;
        guard_deadline.tv_nsec -= 1000000000L;
    }
    guard_program = program;
    guard_rank = rank;
    guard_what = what;
    guard_seconds = seconds;
    guard_armed = 1;
    pthread_cond_signal(&guard_changed);
    pthread_mutex_unlock(&guard_lock);
}

void mpi_job_unguard(void)
{
    pthread_mutex_lock(&guard_lock);
    guard_armed = 0;
    if (guard_started)
        pthread_cond_signal(&guard_changed);
    pthread_mutex_unlock(&guard_lock);
}

/* ---- Stops ---- */

enum { NODE_MAX = 1024, STATE_MAX = 2048 };

static const char *watch_program = "";
static int watch_size;
/* Rank 0: the ranks on its node and their process ids. */
static int node_count;
static int node_rank[NODE_MAX];
static pid_t node_pid[NODE_MAX];
/* Rank 0: two state buffers; the handler reads the one `state_current` names. */
static char state_text[2][STATE_MAX];
static volatile sig_atomic_t state_current;

/* Async-signal-safe text building. */
typedef struct line {
    char text[STATE_MAX + 1024];
    size_t used;
} line;

static void put(line *l, const char *text)
{
    while (*text && l->used < sizeof l->text - 2)
        l->text[l->used++] = *text++;
}

static void put_number(line *l, long value)
{
    char digits[24];
    int n = 0;
    unsigned long v = value < 0 ? (unsigned long)-value : (unsigned long)value;
    do
        digits[n++] = (char)('0' + v % 10);
    while ((v /= 10) && n < (int)sizeof digits);
    if (value < 0 && l->used < sizeof l->text - 2)
        l->text[l->used++] = '-';
    while (n > 0 && l->used < sizeof l->text - 2)
        l->text[l->used++] = digits[--n];
}

/* Whether process `pid` still runs: it exists and is not a zombie (a rank
 * that died but was not yet reaped).  Async-signal-safe. */
static int running(pid_t pid)
{
    line path = { .used = 0 };
    put(&path, "/proc/");
    put_number(&path, pid);
    put(&path, "/stat");
    path.text[path.used] = '\0';
    int fd = open(path.text, O_RDONLY);
    if (fd < 0)
        return kill(pid, 0) == 0 || errno == EPERM; /* no /proc: existence only */
    char stat[512];
    ssize_t n = read(fd, stat, sizeof stat - 1);
    close(fd);
    if (n <= 0)
        return 0;
    stat[n] = '\0';
    /* "pid (name) S ...": the state follows the last ')'. */
    const char *close_paren = NULL;
    for (const char *c = stat; *c; ++c)
        if (*c == ')')
            close_paren = c;
    return close_paren && close_paren[1] == ' ' && close_paren[2] != 'Z' && close_paren[2] != 'X';
}

static void on_stop_rank0(int signal_number)
{
    line l = { .used = 0 };
    put(&l, watch_program);
    put(&l, ": rank 0: ");
    if (signal_number == SIGINT) {
        put(&l, "the job was interrupted (SIGINT)");
    } else {
        int ended = 0;
        pid_t self = getpid();
        int count = __atomic_load_n(&node_count, __ATOMIC_ACQUIRE);
        for (int k = 0; k < count; ++k) {
            if (node_pid[k] == self || running(node_pid[k]))
                continue;
            put(&l, ended ? ", " : "the job was stopped by mpirun after rank ");
            put_number(&l, node_rank[k]);
            ++ended;
        }
        if (ended)
            put(&l, " ended early (died, was killed or aborted the job: see its message and mpirun's report)");
        else if (count == watch_size)
            put(&l, "the job was interrupted (SIGTERM from mpirun: mpirun was sent SIGINT or SIGTERM, "
                    "e.g. Ctrl-C)");
        else
            put(&l, "the job was stopped by mpirun (SIGTERM: it was interrupted, or a rank on another "
                    "node ended early; see mpirun's report)");
    }
    const char *state = state_text[state_current];
    if (state[0]) {
        put(&l, "; ");
        put(&l, state);
    }
    l.text[l.used++] = '\n';
    ssize_t ignored = write(STDERR_FILENO, l.text, l.used);
    (void)ignored;
    _exit(1);
}

static void on_stop_other(int signal_number)
{
    (void)signal_number;
    /* Alive a little longer, so rank 0 can tell an interrupt from a rank
     * that ended (mpirun sends SIGKILL 1 s after SIGTERM anyway). */
    const struct timespec pause = { 0, 300000000 };
    nanosleep(&pause, NULL);
    _exit(1);
}

void mpi_job_watch(const char *program, int rank, int size)
{
    watch_program = program;
    watch_size = size;
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = rank == 0 ? on_stop_rank0 : on_stop_other;
    sigemptyset(&action.sa_mask);
    sigaddset(&action.sa_mask, SIGTERM);
    sigaddset(&action.sa_mask, SIGINT);
    sigaction(SIGTERM, &action, NULL);
    sigaction(SIGINT, &action, NULL);
}

void mpi_job_watch_node(MPI_Comm node)
{
    int world_rank = 0, node_size = 0, node_index = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
    MPI_Comm_size(node, &node_size);
    MPI_Comm_rank(node, &node_index);
    int64_t mine[2] = { world_rank, (int64_t)getpid() };
    int64_t *all = node_index == 0 ? malloc((size_t)node_size * sizeof mine) : NULL;
    MPI_Gather(mine, 2, MPI_INT64_T, all, 2, MPI_INT64_T, 0, node);
    if (world_rank == 0 && all) {
        /* The entries first, then the count: the handler (on any thread)
         * reads only entries below the count. */
        int count = node_size < NODE_MAX ? node_size : NODE_MAX;
        for (int k = 0; k < count; ++k) {
            node_rank[k] = (int)all[2 * k];
            node_pid[k] = (pid_t)all[2 * k + 1];
        }
        __atomic_store_n(&node_count, count, __ATOMIC_RELEASE);
    }
    free(all);
}

void mpi_job_state(const char *text)
{
    int next = !state_current;
    snprintf(state_text[next], sizeof state_text[next], "%s", text);
    state_current = next;
}

void mpi_job_unwatch(void)
{
    signal(SIGTERM, SIG_DFL);
    signal(SIGINT, SIG_DFL);
}
