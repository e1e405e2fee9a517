/* Internal declarations shared by the runtime's host modules. */
#ifndef PERMA_INTERNAL_H
#define PERMA_INTERNAL_H

#include "perma.h"
#include "perma_abi.h"
#include "queues.h"
#include "environment.h"
#include "state.h"
#include "strbuf.h"

#include <stdarg.h>
#include <stdbool.h>
#include <string.h>

/* A block of OpenCL C with the name compiler messages use for it. */
typedef struct perma_source_text {
    char *text;
    char *name;
} perma_source_text;


/* A registered procedure: an owned copy of its description plus what the
 * build derives from it. */
typedef struct perma_proc_info {
    char *name;
    char *item_type;
    char *function;
    perma_source_text source;
    size_t item_size;
    unsigned threads_per_item;
    size_t local_bytes_per_item;
    int priority;
    int cooperative;
    unsigned emit_count;
    char *emit_target_name[PERMA_MAX_EMITS];
    unsigned emit_max[PERMA_MAX_EMITS];

    /* Filled by the build. */
    bool simple;                       /* one thread per item and not cooperative: a work-item may run
                                          several of its items one after another, so its batches may
                                          exceed the group size */
    unsigned full_batch;               /* items of a batch when __local memory does not cut it:
                                          group_size * items_per_work_item if simple, else
                                          group_size / threads_per_item */
    int emit_target[PERMA_MAX_EMITS];  /* procedure ids */
    unsigned depth;                    /* distance from a root of the graph */
    unsigned max_batch;                /* items per batch */
    unsigned max_batch_local;          /* items per batch __local memory allows (>= max_batch; more when the
                                          staging of the emits cut it) */
    unsigned items_off, scratch_off, counters_off; /* arena offsets, words */
    unsigned lane_counts_off;          /* per work-item emit counters (simple procedures) */
    unsigned lane_items;               /* items a lane stages for (0: staging per item) */
    unsigned scratch_words;            /* per item */
    unsigned stage_off[PERMA_MAX_EMITS]; /* words into the group's staging area, per edge */
    unsigned lq_off;                   /* local front queue offset, words */

    /* Items seeded for the next run (item_size bytes each). */
    unsigned char *seeds;
    size_t seed_count, seed_alloc;

    perma_procedure_stats stats;
} perma_proc_info;

typedef struct perma_buffer_binding {
    char *name;
    char *type;
    cl_mem mem;
    void *host;      /* perma_bind_host: memory copied in and/or out */
    size_t bytes;
    unsigned flags;
    /* perma_bind_host_array: the element type and its size on the host,
     * checked against the device's when the program is built; NULL, 0
     * for the other bindings. */
    char *element_type;
    size_t element_size;
} perma_buffer_binding;

/* A declared reduction (reductions.c). */
typedef struct perma_reduction {
    char *name;
    perma_reduce_op op;
    perma_value_type type;
    void *result;          /* the host variable every successful run sets, or NULL */
    unsigned offset;       /* its first word in a work-item's lane (64-bit words) */
    unsigned words;        /* its words in a lane */
    union {
        uint32_t u;
        int32_t i;
        uint64_t ul;
        int64_t l;
        float f;
        double d;
    } value;               /* the result of the last run */
} perma_reduction;

/* What the device is and how its OpenCL implementation behaves, found
 * once when it is opened (device.c).  Modules ask these instead of
 * testing the implementation where a quirk bites (docs/design.md,
 * Portability: quirk -> capability -> file). */
typedef struct perma_device_caps {
    bool is_cpu;             /* CL_DEVICE_TYPE_CPU: groups at most the physical cores (device.c); its
                                buffers are the process's memory (memory.c) */
    bool watch_visible;      /* the host sees the watch page change while a kernel runs (a CPU or
                                unified memory): the stall limit and live progress (watchdog.c, progress.c) */
    bool caches_programs;    /* the implementation keeps compiled programs in a cache of its own
                                (PoCL): program_cache.c does not store them too, and locks per host */
    cl_uint compute_units;
    size_t local_mem_size;
    cl_ulong max_alloc;
    size_t max_group_size;
    char name[256];          /* CL_DEVICE_NAME, with the sub-device */
} perma_device_caps;

struct perma_executor;
typedef struct perma_watchdog perma_watchdog;
typedef struct perma_progress_state perma_progress_state;

/* What the host-driven techniques keep between launches of a run
 * (steps.c). */
typedef struct perma_steps_state {
    unsigned cursor;         /* kernel-per-procedure: where the round-robin goes on */
    int traced_proc;         /* the step in flight, for the trace; -1: none */
    cl_event running;        /* the step kernel in flight; NULL: none */
    uint32_t traced_items;
    double traced_start;
} perma_steps_state;

struct perma_runtime {
    perma_config config;
    const struct perma_executor *executor; /* the technique (executor.h) */
    char message[PERMA_MESSAGE_MAX];
    char summary[512];

    cl_platform_id platform;
    cl_device_id device;
    cl_context context;
    cl_command_queue queue;
    perma_device_caps caps;    /* what the device is and does (device.c) */
    perma_settings settings;   /* the PERMA_* environment variables (environment.c) */
    unsigned work_groups;
    unsigned group_size;

    perma_source_text sources[PERMA_MAX_PROCEDURES];
    unsigned source_count;
    perma_proc_info procs[PERMA_MAX_PROCEDURES];
    unsigned proc_count;
    perma_buffer_binding buffers[PERMA_MAX_BUFFERS];
    unsigned buffer_count;
    perma_reduction reductions[PERMA_MAX_REDUCTIONS];
    unsigned reduction_count;
    unsigned reduce_words;          /* words of a work-item's lane, all reductions (set at build) */
    bool reductions_valid;          /* the values are those of the last run, which succeeded */

    /* Build products. */
    bool built;
    unsigned build_serial;         /* builds so far */
    /* What the last run grew the queues to, when it succeeded (run.c): the
     * next run of the same build starts from them, memory permitting. */
    size_t *learned_capacities;    /* learned_count entries; NULL: none */
    unsigned learned_count, learned_build;
    perma_build_info build_info;   /* how the last build got its program */
    cl_program program;
    cl_kernel kernel;          /* perma_megakernel */
    cl_kernel step_kernel;     /* perma_step_kernel (host-driven techniques) */
    cl_kernel take_kernel;     /* perma_take_kernel */
    cl_kernel relayout_kernel; /* perma_relayout_kernel (queue growth) */
    unsigned max_edges;
    unsigned arena_words;
    unsigned stage_words;      /* a group's staging area for emits (global memory), words */
    unsigned local_queue_items;        /* 0: no local front queue */
    unsigned lq_words;
    unsigned order[PERMA_MAX_PROCEDURES];
    unsigned queue_sets;            /* 1 (shared) or one per group (distributed) */
    const struct perma_strategy_info *strategy; /* the schedule table's row (schedule_table.h) */
    perma_queue_layout queue_layout; /* what the queue planner knows of the build (queues.h) */
    unsigned device_trace_events;   /* trace records per group the device keeps; 0: none */

    perma_device_state *state;      /* state.c's, opaque elsewhere (state.h) */
    perma_group_stats *group_stats; /* work_groups entries */
    bool hung;                      /* a kernel ignored the watchdog; do not wait on it */
    perma_runtime *next_hung;       /* runtime.c's list of the hung runtimes perma_destroy kept */
    bool grow_starved;              /* a group starved of room may stop a launch to grow queues */
    perma_watchdog *watchdog;       /* watchdog.c */
    perma_progress_state *progress; /* progress.c */
    bool debug;                     /* PERMA_DEBUG: one group, -DPERMA_DEBUG */

    perma_stats stats;
    perma_steps_state steps;

    /* Trace of the current run (trace.c). */
    unsigned trace_events;          /* per group and launch */
    struct perma_trace_event *trace;
    size_t trace_count, trace_alloc;
    double trace_start_time;        /* host time of the run's start */
    /* The launch's trace clock as the host saw it (trace.c). */
    struct perma_trace_sample *trace_samples;
    size_t trace_sample_count, trace_sample_alloc;
    bool trace_pending;             /* the clock showed the last sample's tick still at: */
    double trace_pending_time;
};

typedef struct perma_trace_event {
    uint32_t group;     /* track; UINT32_MAX for host steps */
    uint32_t proc;
    uint32_t kind;      /* 0 run, 1 steal, 2 local, 3 donate */
    uint32_t items;
    double start, end;  /* host time (perma_now) */
} perma_trace_event;

/* At host time `time` the trace clock (PERMA_WATCH_CLOCK) showed `tick`. */
typedef struct perma_trace_sample {
    double time;
    uint32_t tick;
} perma_trace_sample;

/* Format the runtime's message and return `status`. */
perma_status perma_set_error(perma_runtime *rt, perma_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
perma_status perma_set_error_va(perma_runtime *rt, perma_status status, const char *fmt, va_list ap);
/* The error a module reported as a value, as the runtime's. */
perma_status perma_take_error(perma_runtime *rt, const perma_error *error);

/* The start of every public call on rt that returns a status: the message
 * is "" until something fails (perma_errmsg).  A call that uses or changes
 * the program or the device state (`uses_device`) is PERMA_ERR_STATE after
 * a kernel did not stop (rt->hung); the message names `call`. */
perma_status perma_call_begin(perma_runtime *rt, const char *call, bool uses_device);

/* Name of an OpenCL error code, e.g. "CL_OUT_OF_RESOURCES". */
const char *perma_cl_error_name(cl_int code);

/* PERMA_ERR_OPENCL naming the call that failed with `code`. */
perma_status perma_cl_error(perma_runtime *rt, const char *call, cl_int code);
/* Fail with PERMA_ERR_OPENCL naming the call, if code is not CL_SUCCESS. */
#define PERMA_CL_CHECK(rt, call, code)                                                     \
    do {                                                                                    \
        cl_int perma_code_ = (code);                                                        \
        if (perma_code_ != CL_SUCCESS)                                                      \
            return perma_cl_error((rt), (call), perma_code_);                               \
    } while (0)

/* program_cache.c: the disk cache of built programs.  An entry is one
 * build's key (everything its binary depends on) and file, worked out once
 * for the load, the lock and the store; without a cache it is not usable
 * and they all do nothing.  perma_cache_load gives the built program from
 * the cache (NULL: none; a damaged entry is removed with a notice).
 * perma_cache_lock takes the entry's build lock, waiting (bounded) while
 * another process or thread holds it: after it, load again before
 * building.  perma_cache_store stores rt->program, built from source,
 * when its build took enough CPU time (true: stored);
 * perma_cache_entry_close lets go of the lock. */
typedef struct perma_cache_entry {
    bool usable;
    perma_strbuf key;
    char dir[1024];
    char path[1100];
    bool stores;          /* the implementation's programs are stored here (not PoCL's) */
    int lock_fd;          /* the build lock while held; -1 otherwise */
    double waited;        /* seconds perma_cache_lock waited */
} perma_cache_entry;
void perma_cache_entry_open(perma_runtime *rt, const char *source, const char *options, perma_cache_entry *entry);
void perma_cache_entry_close(perma_cache_entry *entry);
cl_program perma_cache_load(perma_runtime *rt, const perma_cache_entry *entry, const char *options);
bool perma_cache_lock(perma_cache_entry *entry);
bool perma_cache_store(perma_runtime *rt, const perma_cache_entry *entry, double cpu_seconds);

/* device.c */
perma_status perma_device_open(perma_runtime *rt);

/* The tighter of the process's memory limits (memory.c): false if none is set. */
typedef struct perma_headroom {
    size_t free, limit, used; /* bytes */
    const char *name;         /* "address-space limit (ulimit -v)" */
} perma_headroom;
bool perma_memory_headroom(perma_headroom *out);
/* False, with the message, if the limits leave less than the OpenCL
 * driver needs to load, start and run at all (checked before the first
 * OpenCL call of the process), or, for a `runtime` after the first, less
 * than another runtime needs. */
bool perma_memory_driver_fits(char *message, size_t size, bool runtime);
void perma_device_close(perma_runtime *rt);


/* files.c: read a whole text file; the message names the path. */
perma_status perma_read_text_file(perma_runtime *rt, const char *path, char **out);
bool perma_is_identifier(const char *s);

/* abi.c: the generated program's layout checks, and the sentence for a
 * build log in which one failed (false when none did). */
void perma_abi_append_struct_checks(perma_strbuf *sb);
void perma_abi_append_item_checks(const perma_runtime *rt, perma_strbuf *sb);
void perma_abi_append_element_checks(const perma_runtime *rt, perma_strbuf *sb);
bool perma_abi_explain_log(const perma_runtime *rt, const char *log, char *out, size_t size);

/* barriers.c: around the source of a procedure that is not .cooperative,
 * turn barrier() and work_group_*() into a compile error at the caller's
 * line; the sentence for a build log that has one (false when none). */
void perma_barriers_forbid(const perma_runtime *rt, unsigned proc, perma_strbuf *sb);
void perma_barriers_allow(perma_strbuf *sb);
/* The same source: the same name and the same text (procedures registered
 * from one source share it, the program includes it once, and its
 * barriers are forbidden unless one of them is cooperative). */
bool perma_same_source(const perma_source_text *a, const perma_source_text *b);
bool perma_barriers_explain_log(const perma_runtime *rt, const char *log, char *out, size_t size);

/* build_log.c: whether line[0..length) is a compiler diagnostic of `kind`
 * ("error", "warning"); if so its location ("FILE:LINE:COL") in where[]
 * and *text at its message, whichever form the compiler wrote it in. */
bool perma_build_log_diagnostic(const char *line, size_t length, const char *kind, char *where, size_t where_size,
                                const char **text);
/* After a build: its warnings if it succeeded, or the whole log with
 * PERMA_BUILD_LOG, to config.build_log or stderr.  Returns the number of
 * warnings (0 for a failed build). */
unsigned perma_build_log_show(perma_runtime *rt, const char *log, bool failed);
/* A one-line notice about the build (e.g. a damaged cache entry), to
 * config.build_log or stderr; the newline is added. */
void perma_notice(perma_runtime *rt, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* layout.c, codegen.c, program.c */
perma_status perma_build_layout(perma_runtime *rt);
/* The __local memory one group may use: the device's, or
 * config.local_memory_limit when lower. */
size_t perma_local_memory(const perma_runtime *rt);
/* The program's text, with the reductions' parts (perma_reductions_generate). */
perma_status perma_generate_program(perma_runtime *rt, const perma_strbuf *reduce_constants,
                                    const perma_strbuf *reduce_helpers, perma_strbuf *out);
/* run.c: let go of what the runs learned (perma_destroy). */
void perma_run_release(perma_runtime *rt);
/* perma_build after the call's start (perma_call_begin): build unless built. */
perma_status perma_build_program(perma_runtime *rt);
void perma_release_program(perma_runtime *rt);

/* reductions.c: at build, the lane layout and the reductions' two parts
 * of the generated program (`constants`, which go before perma_ctx; after
 * it `helpers`, the reduce_NAME() functions and the lane's initialisation
 * and fold); before a run the slots' identities, after one the results. */
void perma_reductions_generate(perma_runtime *rt, perma_strbuf *constants, perma_strbuf *helpers);
/* Every work-item's slot filled with the identities (before a run; *slots
 * NULL without reductions; the caller frees it). */
perma_status perma_reductions_identities(perma_runtime *rt, uint64_t **slots, size_t *words);
/* Combine the slots into the results and set the host variables (after a
 * successful run); invalidate the results (after a failed one). */
perma_status perma_reductions_collect(perma_runtime *rt);
void perma_reductions_invalidate(perma_runtime *rt);
void perma_reductions_release(perma_runtime *rt);

/* exact_sum.c: the host's half of the exact float and double sums: add
 * one slot's digits (and its infinity and NaN flags) into a total, and
 * round a total once to the type. */
typedef struct perma_exact_total {
    int64_t digits[PERMA_EXACT_DOUBLE_DIGITS];
    uint64_t flags;
} perma_exact_total;
void perma_exact_total_add(perma_exact_total *total, const uint64_t *slot, unsigned digits);
double perma_exact_total_double(perma_exact_total *total);
float perma_exact_total_float(perma_exact_total *total);

/* buffers.c: copy the host memory of perma_bind_host buffers to the
 * device (PERMA_READ) or back (PERMA_WRITE). */
perma_status perma_buffers_copy(perma_runtime *rt, unsigned flag);

/* layout.c: the build's queue layout for the planner (queues.h): queue
 * sets (one per persistent group with a distributed strategy, else 1),
 * the queues' starting capacity and the cap on their bytes
 * (config.queue_memory_limit, or half the device's largest allocation: a
 * regrowth holds the old and the new queue buffers at once). */
unsigned perma_queue_sets(const perma_runtime *rt);
size_t perma_queue_memory_limit(const perma_runtime *rt);
void perma_queue_layout_fill(const perma_runtime *rt, unsigned sets, perma_queue_layout *out);

/* watchdog.c: waiting for a kernel under the time limit and the stall
 * limit.  Past the deadline, or when no item completed anywhere for the
 * stall limit, the abort flag is raised (every group polls it) and the
 * reason kept for perma_watchdog_stop_error; PERMA_ERR_TIMEOUT only if the
 * kernel does not stop within the grace period (rt->hung: the runtime is
 * then unusable). */
perma_status perma_watchdog_open(perma_runtime *rt);
/* Frees the watchdog and stops its waiter thread: joined, or detached if
 * rt->hung (it is blocked on the kernel that never ended). */
void perma_watchdog_close(perma_runtime *rt);
/* Launch `kernel` and wait for it. */
perma_status perma_launch_watched(perma_runtime *rt, cl_kernel kernel, size_t global, size_t local, double deadline);
/* Wait for the command of event `done` (enqueued and flushed), lending
 * the runtime's waiter thread to it (started at the first call). */
perma_status perma_watch_event(perma_runtime *rt, cl_event done, double deadline);
/* The error of a launch the watchdog stopped (status ABORTED): the time
 * limit, or the stall with the procedures that had items in flight. */
perma_status perma_watchdog_stop_error(perma_runtime *rt);

/* progress.c: the progress of a run (perma_get_progress, config.progress),
 * told by the run loop and sampled by the watchdog from the watch page. */
perma_status perma_progress_open(perma_runtime *rt);
void perma_progress_close(perma_runtime *rt);
void perma_progress_run_begins(perma_runtime *rt, double start); /* the seeds are uploaded */
void perma_progress_launch_begins(perma_runtime *rt);            /* the watch page is cleared */
void perma_progress_kernel_started(perma_runtime *rt);           /* a watched kernel is enqueued */
void perma_progress_sample(perma_runtime *rt, double now);       /* while it runs */
void perma_progress_launch_ends(perma_runtime *rt);              /* the statistics are collected */
double perma_progress_stop_clock(perma_runtime *rt);             /* the run's seconds, as readers see them */
void perma_progress_run_ends(perma_runtime *rt);                 /* the final statistics are in */

/* outcome.c: the error of a launch's failure status (not DONE or
 * NEEDS_ROOM). */
perma_status perma_outcome_error(perma_runtime *rt, const perma_ctl_header *outcome);

/* stats.c */
void perma_stats_reset(perma_runtime *rt);
perma_status perma_stats_collect(perma_runtime *rt);  /* after each launch */
/* At the end of a run, from the queues' records (state.h). */
void perma_stats_finish(perma_runtime *rt, const perma_queue_state *queues, unsigned count);

/* trace.c: the run's batches in host time. */
bool perma_trace_on_device(const perma_runtime *rt);     /* the megakernel records batches */
void perma_trace_reset(perma_runtime *rt, double start); /* at the start of a run */
void perma_trace_launch_begins(perma_runtime *rt, double now); /* the megakernel is enqueued */
void perma_trace_read_clock(perma_runtime *rt, double now); /* while it runs */
void perma_trace_launch_ends(perma_runtime *rt, double now); /* it ended */
perma_status perma_trace_collect(perma_runtime *rt);       /* after each launch */
perma_status perma_trace_host_step(perma_runtime *rt, unsigned proc, uint32_t items, double start, double end);
void perma_trace_release(perma_runtime *rt);
/* Most seconds between two readings of the trace clock while the
 * megakernel runs (the watchdog's loop wakes that often). */
#define PERMA_TRACE_SAMPLE_SECONDS 0.001

/* trace_file.c: every traced run of the process in its file. */
void perma_trace_file_run_begins(double start);           /* a traced run starts */
perma_status perma_trace_write(perma_runtime *rt);         /* at the end of a run */

/* clock.c */
double perma_now(void);
double perma_cpu_now(void);
double perma_time_limit(const perma_runtime *rt);
double perma_stall_limit(const perma_runtime *rt);

#endif
