/* The trace file: every traced run of a process in one file of Chrome trace
 * events (JSON), viewable in Perfetto (ui.perfetto.dev) or chrome://tracing
 * and summarised by runtime/tools/trace_to_svg.py.
 *
 * Each run is a process of the trace (pid = the run's number in the file,
 * named "run N: SCHEDULE, G groups"), its work-groups (or its host steps)
 * the threads; timestamps are host microseconds since the start of the
 * process's first traced run, so the runs follow each other on one time
 * line.  The first run a process traces into a path
 * writes the file anew; each later one (from any runtime of the process)
 * writes it again with its events after the earlier runs', through a
 * temporary file renamed into place (perma_output_*), so the file is valid
 * JSON after every run and a failed write leaves it as it was.  A process-wide list remembers the files
 * written and their identity (device and inode): a file replaced or
 * removed meanwhile is written anew. */
#include "internal.h"
#include "trace.h"
#include "trace_file.h"

#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define FOOTER "\n]}\n"

static const char *const kind_names[] = { "run", "steal", "local", "donate", "stack" };
/* The name of events of the work-first stacks as a whole: no procedure's
 * name, which is an identifier, can be it. */
#define STACKS_NAME "(stacks)"

typedef struct traced_file {
    struct traced_file *next;
    char *path;
    pid_t pid;          /* the process that wrote it (a forked child starts its own) */
    dev_t device;       /* the file as last written */
    ino_t inode;
    unsigned runs;      /* runs in it; 0: write it anew */
} traced_file;

static pthread_mutex_t files_lock = PTHREAD_MUTEX_INITIALIZER;
static traced_file *files;   /* kept until the process exits */
static double epoch;         /* host time of microsecond 0: the process's first traced run's start */
static pid_t epoch_pid;

void perma_trace_file_run_begins(double start)
{
    pthread_mutex_lock(&files_lock);
    if (epoch_pid != getpid()) {
        epoch = start;
        epoch_pid = getpid();
    }
    pthread_mutex_unlock(&files_lock);
}

/* This process's entry for `path` (made if there is none; NULL without
 * memory), with runs 0 if the file is not the one it last wrote. */
static traced_file *file_entry(const char *path)
{
    traced_file *t = files;
    while (t && (t->pid != getpid() || strcmp(t->path, path) != 0))
        t = t->next;
    if (!t) {
        t = calloc(1, sizeof *t);
        if (!t || !(t->path = strdup(path))) {
            free(t);
            return NULL;
        }
        t->pid = getpid();
        t->next = files;
        files = t;
    }
    struct stat st;
    if (stat(path, &st) != 0 || st.st_dev != t->device || st.st_ino != t->inode)
        t->runs = 0;
    return t;
}

static void write_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s)
        if (*s == '"' || *s == '\\')
            fprintf(f, "\\%c", *s);
        else if ((unsigned char)*s < 0x20)
            fprintf(f, "\\u%04x", *s);
        else
            fputc(*s, f);
    fputc('"', f);
}

/* The run's events, from its metadata on (no leading comma). */
static void write_run(FILE *f, const perma_runtime *rt, unsigned run, double zero)
{
    bool host = !perma_trace_on_device(rt);
    size_t count;
    double start;
    const perma_trace_event *events = perma_trace_events(rt, &count, &start);
    char schedule[128];
    if (perma_schedule_format(&rt->config.schedule, schedule, sizeof schedule) < 0)
        snprintf(schedule, sizeof schedule, "?");
    char name[256];
    snprintf(name, sizeof name, "run %u: %s, %u group%s", run, schedule, rt->work_groups,
             rt->work_groups == 1 ? "" : "s");
    fprintf(f, "{\"name\":\"process_name\",\"ph\":\"M\",\"pid\":%u,\"args\":{\"name\":", run);
    write_string(f, name);
    fprintf(f, ",\"run\":%u,\"schedule\":", run);
    write_string(f, schedule);
    fprintf(f, ",\"work_groups\":%u,\"start_us\":%.3f,\"seconds\":%.6f,\"clock\":\"%s\"", rt->work_groups,
            (start - zero) * 1e6, rt->stats.seconds,
            host ? "host" : "device ticks timed by host samples");
    /* Work-first: the stacks' size, the items run from them (the "stack"
     * events and part of the others' items), the deepest stack and the
     * items spilled from stacks to the queues. */
    fprintf(f, ",\"stack_items\":%u,\"stacked_items\":%llu,\"stack_peak\":%u,\"stack_spills\":%llu}}",
            rt->stats.stack_items, (unsigned long long)rt->stats.stacked_items, rt->stats.stack_peak,
            (unsigned long long)rt->stats.stack_spills);
    fprintf(f, ",\n{\"name\":\"process_sort_index\",\"ph\":\"M\",\"pid\":%u,\"args\":{\"sort_index\":%u}}", run, run);
    if (host)
        fprintf(f, ",\n{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":%u,\"tid\":0,\"args\":{\"name\":\"host steps\"}}",
                run);
    else
        for (unsigned g = 0; g < rt->work_groups; ++g)
            fprintf(f, ",\n{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":%u,\"tid\":%u,\"args\":{\"name\":\"group %u\"}}",
                    run, g, g);
    for (size_t i = 0; i < count; ++i) {
        const perma_trace_event *e = &events[i];
        double duration = e->end > e->start ? e->end - e->start : 0.0;
        fprintf(f, ",\n{\"name\":\"%s\",\"cat\":\"%s\",\"ph\":\"X\",\"pid\":%u,\"tid\":%u,\"ts\":%.3f,\"dur\":%.3f,"
                   "\"args\":{\"items\":%u,\"kind\":\"%s\"}}",
                e->proc == PERMA_TRACE_STACKS ? STACKS_NAME : rt->procs[e->proc].name, kind_names[e->kind], run, e->group == UINT32_MAX ? 0u : e->group,
                (e->start - zero) * 1e6, duration * 1e6, e->items, kind_names[e->kind]);
    }
}

/* Copy the runs already in the file at t->path to `out`, without its
 * closing: true if the file is the one this process left (it ends with
 * FOOTER), false if it must be written anew. */
static bool copy_earlier_runs(const traced_file *t, FILE *out)
{
    if (t->runs == 0)
        return false;
    FILE *in = fopen(t->path, "rb");
    if (!in)
        return false;
    const long footer = (long)strlen(FOOTER);
    char tail[sizeof FOOTER] = "";
    long size = -1;
    bool ours = fseek(in, -footer, SEEK_END) == 0 && (size = ftell(in)) >= 0 &&
                fread(tail, 1, (size_t)footer, in) == (size_t)footer && strcmp(tail, FOOTER) == 0 &&
                fseek(in, 0, SEEK_SET) == 0;
    char buffer[65536];
    for (long left = size; ours && left > 0;) {
        size_t n = fread(buffer, 1, left < (long)sizeof buffer ? (size_t)left : sizeof buffer, in);
        if (n == 0 || fwrite(buffer, 1, n, out) != n)
            ours = false;
        left -= (long)n;
    }
    fclose(in);
    return ours;
}

/* Write the trace file with this run added: the earlier runs copied from
 * the file as it is and this one after them, into a new file that
 * replaces the old one only when complete (perma_output_*), so a failed
 * write (a full disk) leaves the earlier runs as they were. */
perma_status perma_trace_write(perma_runtime *rt)
{
    const char *path = rt->config.trace_path;
    if (!path)
        return PERMA_OK;
    pthread_mutex_lock(&files_lock);
    traced_file *t = file_entry(path);
    if (!t) {
        pthread_mutex_unlock(&files_lock);
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the trace '%s'", path);
    }
    perma_output *out;
    perma_error error;
    if (perma_output_open(path, &out, &error) != PERMA_OK) {
        pthread_mutex_unlock(&files_lock);
        return perma_set_error(rt, error.status, "cannot write the trace: %s", error.message);
    }
    FILE *f = perma_output_stream(out);
    unsigned runs = t->runs;
    if (copy_earlier_runs(t, f)) {
        fputs(",\n", f);
    } else {
        runs = 0;
        fprintf(f, "{\"displayTimeUnit\":\"ns\",\"otherData\":{\"runtime\":\"perma %s\",\"clock\":\"host "
                   "microseconds since the start of the process's first traced run\"},\n\"traceEvents\":[\n",
                PERMA_VERSION_STRING);
    }
    write_run(f, rt, runs + 1, epoch);
    fputs(FOOTER, f);
    if (perma_output_commit(out, &error) != PERMA_OK) {
        pthread_mutex_unlock(&files_lock);
        return perma_set_error(rt, error.status, "cannot write the trace: %s", error.message);
    }
    t->runs = runs + 1;
    struct stat st;
    if (stat(path, &st) == 0) {
        t->device = st.st_dev;
        t->inode = st.st_ino;
    }
    pthread_mutex_unlock(&files_lock);
    return PERMA_OK;
}
