/* Internal declarations shared by the runtime's host modules. */
#ifndef PERMA_INTERNAL_H
#define PERMA_INTERNAL_H

#include "perma.h"
#include "control.h"
#include "strbuf.h"

#include <stdarg.h>
#include <stdbool.h>

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
    int emit_target[PERMA_MAX_EMITS];  /* procedure ids */
    unsigned depth;                    /* distance from a root of the graph */
    unsigned max_batch;                /* items per batch */
    unsigned items_off, scratch_off, counters_off; /* arena offsets, words */
    unsigned lane_counts_off;          /* per work-item emit counters (simple procedures) */
    unsigned lane_items;               /* items a lane stages for (0: staging per item) */
    unsigned scratch_words;            /* per item */
    unsigned stage_off[PERMA_MAX_EMITS];
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
} perma_buffer_binding;

/* Items waiting in one queue, laid out linearly (host side of a relaunch). */
typedef struct perma_queue_image {
    uint32_t *words;
    size_t count;     /* items */
    size_t capacity;  /* items, a power of two */
    unsigned regrowths;
} perma_queue_image;

struct perma_runtime {
    perma_config config;
    char message[PERMA_MESSAGE_MAX];
    char summary[512];

    cl_platform_id platform;
    cl_device_id device;
    cl_context context;
    cl_command_queue queue;
    bool device_is_cpu;
    cl_uint compute_units;
    size_t local_mem_size;
    cl_ulong max_alloc;
    unsigned work_groups;
    unsigned group_size;

    perma_source_text sources[PERMA_MAX_PROCEDURES];
    unsigned source_count;
    perma_proc_info procs[PERMA_MAX_PROCEDURES];
    unsigned proc_count;
    perma_buffer_binding buffers[PERMA_MAX_BUFFERS];
    unsigned buffer_count;

    /* Build products. */
    bool built;
    cl_program program;
    cl_kernel kernel;          /* perma_megakernel */
    cl_kernel step_kernel;     /* perma_step_kernel (host-driven techniques) */
    cl_kernel take_kernel;     /* perma_take_kernel */
    cl_mem input_mem;          /* items a step kernel consumes */
    size_t input_mem_words;
    unsigned max_edges;
    unsigned arena_words;
    unsigned local_queue_items;        /* 0: no local front queue */
    unsigned lq_words;
    unsigned order[PERMA_MAX_PROCEDURES];

    /* Device state of a run. */
    cl_mem ctl_mem, data_mem, stats_mem, abort_mem;
    size_t data_mem_words;
    uint32_t *abort_flag;           /* host memory the kernel polls */
    unsigned queue_sets;            /* 1 (shared) or one per group (distributed) */
    perma_queue_image *images;      /* queue_sets * proc_count, index set * procs + proc */
    unsigned image_count;
    perma_group_stats *group_stats; /* work_groups entries */
    bool hung;                      /* a kernel ignored the watchdog; do not wait on it */
    bool grow_starved;              /* a group starved of room may stop a launch to grow queues */
    bool debug;                     /* PERMA_DEBUG: one group, -DPERMA_DEBUG */

    perma_stats stats;

    /* Trace of the current run (trace.c). */
    unsigned trace_events;          /* per group and launch */
    cl_mem trace_mem;
    size_t trace_mem_words;
    struct perma_trace_event *trace;
    size_t trace_count, trace_alloc;
    double trace_clock_base;        /* logical ticks of earlier launches */
    double trace_start_time;        /* host time of the run's start */
};

typedef struct perma_trace_event {
    uint32_t group;     /* track; UINT32_MAX for host steps */
    uint32_t proc;
    uint32_t kind;      /* 0 run, 1 steal, 2 local, 3 donate */
    uint32_t items;
    double start, end;  /* microseconds (host) or ticks (logical) */
} perma_trace_event;

/* Format the runtime's message and return `status`. */
perma_status perma_set_error(perma_runtime *rt, perma_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
perma_status perma_set_error_va(perma_runtime *rt, perma_status status, const char *fmt, va_list ap);

/* Name of an OpenCL error code, e.g. "CL_OUT_OF_RESOURCES". */
const char *perma_cl_error_name(cl_int code);

/* Fail with PERMA_ERR_OPENCL naming the call, if code is not CL_SUCCESS. */
#define PERMA_CL_CHECK(rt, call, code)                                                     \
    do {                                                                                    \
        cl_int perma_code_ = (code);                                                        \
        if (perma_code_ != CL_SUCCESS)                                                      \
            return perma_set_error((rt), PERMA_ERR_OPENCL, "%s failed: %s (%d)", (call),    \
                                   perma_cl_error_name(perma_code_), (int)perma_code_);     \
    } while (0)

/* device.c */
perma_status perma_device_open(perma_runtime *rt);
void perma_device_close(perma_runtime *rt);

/* files.c: read a whole text file; the message names the path. */
perma_status perma_read_text_file(perma_runtime *rt, const char *path, char **out);
bool perma_is_identifier(const char *s);

/* layout.c */
perma_status perma_build_layout(perma_runtime *rt);
/* One thread per item and not cooperative: a work-item may run several of
 * its items one after another, so its batches may exceed the group size. */
static inline bool perma_proc_is_simple(const perma_proc_info *p)
{
    return p->threads_per_item == 1 && !p->cooperative;
}
perma_status perma_generate_program(perma_runtime *rt, perma_strbuf *out);
void perma_release_program(perma_runtime *rt);

/* queues.c */
perma_status perma_queues_prepare(perma_runtime *rt);
perma_status perma_queues_upload(perma_runtime *rt);
perma_status perma_queues_download(perma_runtime *rt);
perma_status perma_queues_grow(perma_runtime *rt, unsigned starved_queue);
void perma_queues_release(perma_runtime *rt);
/* Make *mem a buffer of at least `words` words (keeps a big enough one). */
perma_status perma_ensure_buffer(perma_runtime *rt, cl_mem *mem, size_t *have_words, size_t words, const char *what);
/* Grow queue qi (set 0 only) to hold `needed` more items, relaying out all
 * queues; only between launches. */
perma_status perma_queues_make_room(perma_runtime *rt, const size_t *needed);

/* launch.c */
/* The first user buffer argument of the megakernel and of the step kernel
 * (kernels/perma_scheduler.cl, perma_host_steps.cl). */
enum { PERMA_MEGAKERNEL_USER_ARG = 5, PERMA_STEP_USER_ARG = 8 };
perma_status perma_launch_megakernel(perma_runtime *rt, double deadline, uint32_t *kernel_status);
perma_status perma_set_common_args(perma_runtime *rt, cl_kernel kernel, cl_uint first_user_arg);

/* steps.c: the host-driven techniques. */
perma_status perma_run_steps(perma_runtime *rt, double deadline);
perma_status perma_warm_up_steps(perma_runtime *rt);

/* run.c */
perma_status perma_kernel_status_error(perma_runtime *rt, const uint32_t *kernel_status);

/* stats.c */
void perma_stats_reset(perma_runtime *rt);
perma_status perma_stats_collect(perma_runtime *rt);

/* trace.c */
perma_status perma_trace_prepare(perma_runtime *rt);       /* buffer for a launch */
perma_status perma_trace_collect(perma_runtime *rt);       /* after a megakernel launch */
perma_status perma_trace_host_step(perma_runtime *rt, unsigned proc, uint32_t items, double start, double end);
perma_status perma_trace_write(perma_runtime *rt);         /* at the end of a run */
void perma_trace_release(perma_runtime *rt);

/* time */
double perma_now(void);

#endif
