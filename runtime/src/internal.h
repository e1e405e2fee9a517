/* internal.h: what the runtime's host modules share: the runtime itself
 * (struct perma_runtime: the configuration, the device, the registered
 * procedures, sources, buffers and reductions, the build's products and
 * each module's state), the registered procedures' records, and errors.
 * Each module's functions and the types it owns are in its own header
 * (program.h, watchdog.h, trace.h, ...); a module includes this one only
 * when it takes the runtime. */
#ifndef PERMA_INTERNAL_H
#define PERMA_INTERNAL_H

#include "perma.h"
#include "perma_abi.h"
#include "device.h"
#include "environment.h"
#include "program.h"
#include "queues.h"

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
    int queue_only;
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
    bool stackable;                    /* work-first: its items may run from a work-item's stack (simple,
                                          no scratch, every target stackable, its emits fit a stack) */
    unsigned wf_need;                  /* work-first: its declared emits, the stack room an item needs */

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
    bool guarded;    /* PERMA_CHECK_BOUNDS: guard words follow the bytes on the device (buffers.c) */
} perma_buffer_binding;

struct perma_executor;

struct perma_runtime {
    perma_config config;
    const struct perma_executor *executor; /* the technique (executor.h) */
    char message[PERMA_MESSAGE_MAX];
    char summary[512];
    const char *current_call;  /* the public call running on it, NULL between calls (errors.c) */

    cl_platform_id platform;
    cl_device_id device;
    cl_context context;
    cl_command_queue queue;
    perma_device_caps caps;    /* what the device is and does (device.c) */
    perma_settings settings;   /* the PERMA_* environment variables (environment.c) */
    unsigned work_groups;
    unsigned group_size;
    char work_groups_reason[PERMA_REASON_MAX]; /* how work_groups was chosen (device.c) */
    unsigned work_groups_bound;     /* work_groups at perma_create, which a build never passes */
    unsigned resident_groups;       /* groups of the built megakernel the device holds at once (device.c);
                                       0: a CPU, or not built */
    size_t kernel_local_bytes;      /* its CL_KERNEL_LOCAL_MEM_SIZE (0: not built) */

    perma_source_text sources[PERMA_MAX_PROCEDURES];
    unsigned source_count;
    perma_proc_info procs[PERMA_MAX_PROCEDURES];
    unsigned proc_count;
    perma_buffer_binding buffers[PERMA_MAX_BUFFERS];
    unsigned buffer_count;
    struct perma_reductions_state *reductions; /* reductions.c's, opaque elsewhere (reductions.h) */

    bool built;                     /* the build products are those of the procedures, sources,
                                       buffers and reductions registered now */
    perma_build_products build;     /* program.h */

    struct perma_device_state *state; /* state.c's, opaque elsewhere (state.h) */
    perma_group_stats *group_stats; /* group_stats_count >= work_groups entries (stats.c) */
    unsigned group_stats_count;
    bool hung;                      /* a kernel ignored the watchdog; do not wait on it */
    perma_runtime *next_hung;       /* runtime.c's list of the hung runtimes perma_destroy kept */
    bool grow_starved;              /* a group starved of room may stop a launch to grow queues */
    struct perma_watchdog *watchdog; /* watchdog.c's, opaque elsewhere (watchdog.h) */
    struct perma_progress_state *progress; /* progress.c's, opaque elsewhere (progress.h) */
    bool debug;                     /* PERMA_DEBUG: one group, -DPERMA_DEBUG */

    perma_stats stats;
    struct perma_steps_state *steps; /* steps.c's, opaque elsewhere (steps.h); NULL until a
                                        host-driven run */

    struct perma_trace_state *trace; /* trace.c's, opaque elsewhere (trace.h); NULL: no trace */
};

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

/* A runtime takes one public call at a time (perma.h, *Threads*): claim
 * it for `call`, or PERMA_ERR_STATE when another call holds it (the
 * message, naming both calls, is this thread's: perma_errmsg); release it
 * when the call ends. */
perma_status perma_call_claim(perma_runtime *rt, const char *call);
void perma_call_release(perma_runtime *rt);

/* perma_check_memory inside a call that holds the runtime (memory.c). */
perma_status perma_memory_check(perma_runtime *rt, size_t bytes, const char *what);

/* The body of a public call: the runtime claimed for `name` while `body`
 * (an expression giving the status) runs. */
#define PERMA_EXCLUSIVE_CALL(rt, name, body)                                                 \
    do {                                                                                    \
        if (!(rt))                                                                          \
            return PERMA_ERR_ARGUMENT;                                                      \
        perma_status claimed_ = perma_call_claim((rt), (name));                             \
        if (claimed_ != PERMA_OK)                                                           \
            return claimed_;                                                                \
        perma_status result_ = (body);                                                      \
        perma_call_release(rt);                                                             \
        return result_;                                                                     \
    } while (0)

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

#endif
