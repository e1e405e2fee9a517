/*
 * perma: a persistent-megakernel task-scheduling runtime on OpenCL.
 *
 * A program describes *procedures*: OpenCL C functions that each process one
 * work item of a fixed size and may emit new items into other procedures'
 * queues.  The host seeds some queues and calls perma_run(), which launches
 * one persistent kernel.  Its work-groups loop: pick a non-empty queue, take a
 * batch of items, run the procedure on them, enqueue what it emitted, until no
 * item is queued or being processed anywhere.
 *
 * Host usage, in order:
 *
 *     perma_config cfg;            perma_config_init(&cfg);
 *     perma_runtime *rt;           perma_error err;
 *     if (perma_create(&cfg, &rt, &err) != PERMA_OK) { puts(err.message); ... }
 *     perma_add_source(rt, "struct node { uint depth; uint id; };", "types.cl");
 *     perma_procedure split = { .name = "split", .item_type = "struct node",
 *         .item_size = 8, .threads_per_item = 1, .source = SPLIT_SRC,
 *         .function = "split", .emits = { { "split", 2 } } };
 *     perma_proc id;               perma_register(rt, &split, &id);
 *     perma_declare_reduction(rt, "leaves", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &leaves);
 *     perma_seed(rt, id, &root, 1);
 *     perma_run(rt);               // leaves now holds the result
 *     perma_print_stats(rt, stdout);
 *     perma_destroy(rt);
 *
 * Every function returns a perma_status; on failure perma_errmsg(rt) says
 * what went wrong, naming the procedure, parameter, file or OpenCL call.
 * The library never calls exit() or abort().
 *
 * Threads.  Different runtimes run at once in different threads (a
 * runtime per device or sub-device; perma_run blocks its thread).  One
 * runtime takes one call at a time: a call on it while another call on it
 * has not returned (from another thread, or from a progress or build-log
 * callback inside it) fails with PERMA_ERR_STATE and changes nothing;
 * perma_errmsg in the refused call's thread names both calls, and the
 * running call goes on undisturbed.  perma_print_stats then prints that
 * message instead of the table.  The exceptions, callable from any thread
 * at any time: perma_get_progress, perma_errmsg, perma_device_summary and
 * perma_cl_context/_device/_queue.  perma_destroy must not overlap any
 * other call on the runtime.
 *
 * Device side.  A procedure is an OpenCL C function
 *
 *     void NAME(perma_ctx *ctx, __local const ITEM_TYPE *item);
 *
 * called once per work-item assigned to the item (ctx->threads =
 * threads_per_item of them; ctx->thread is 0..threads_per_item-1).  Inside it:
 *   - emit_TARGET(ctx, &child) queues one item for a procedure listed in
 *     .emits; `child` is a private variable of TARGET's item type.  Returns 1
 *     if staged, 0 if the item exceeded the declared per-item maximum (the run
 *     then fails with PERMA_ERR_EMIT_LIMIT).  Emitting into a procedure not
 *     listed in .emits is a compile error.
 *   - reduce_NAME(ctx, value) adds value to reduction NAME (sum, min or max;
 *     perma_declare_reduction), read on the host after the run: no atomic,
 *     no barrier, the same result under every schedule.
 *   - ctx->buf.NAME is the buffer bound under NAME (perma_bind_*).
 *   - ctx->scratch points to local_bytes_per_item bytes of __local memory
 *     for this item, shared by its threads.
 *   - ctx->slot is the item's index in the batch, ctx->group the work-group:
 *     0..work_groups-1 under every technique (perma_get_work_groups), and
 *     no two work-groups with the same ctx->group run at once, so an array
 *     with one entry per group needs no atomics between groups (only
 *     between the work-items of one group).
 * A procedure must not spin-wait on other work-items, must not call barrier()
 * unless it is declared .cooperative (then it is called by every work-item
 * of the group, ctx->active tells whether this one has an item, and every
 * barrier must be reached by all of them).  barrier() or a work_group_*()
 * function in the source of a procedure that is not cooperative does not
 * build: PERMA_ERR_BUILD naming the procedure, file and line.
 */
#ifndef PERMA_H
#define PERMA_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* perma uses OpenCL 1.2 calls; a program that targets a later version
 * defines CL_TARGET_OPENCL_VERSION itself before including this header. */
#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PERMA_VERSION_STRING "0.1.0"

/* Limits of a procedure description. */
#define PERMA_NAME_MAX 63        /* longest procedure or buffer name */
#define PERMA_MAX_EMITS 8        /* targets one procedure may emit into */
/* Bytes in one work item: large enough for items that carry a block of
 * data (a diced grid of vertices); a batch must still fit the device's
 * __local memory, which the layout checks. */
#define PERMA_MAX_ITEM_SIZE 65536
#define PERMA_MAX_EMIT_ITEMS 4096 /* most items one input item may emit into one target */
#define PERMA_MAX_PROCEDURES 64
#define PERMA_MAX_BUFFERS 32
#define PERMA_MAX_REDUCTIONS 32
#define PERMA_MAX_QUEUED_ITEMS ((size_t)1 << 30) /* most items one queue holds (seeds included) */
#define PERMA_MAX_LOCAL_QUEUE_ITEMS 4096 /* most perma_schedule.local_queue_items */
#define PERMA_MAX_WORK_FIRST_ITEMS 4096 /* most perma_schedule.work_first_items */
#define PERMA_WORK_FIRST_OFF 0xffffffffu /* perma_schedule.work_first_items: no stacks ("+wf0") */
#define PERMA_MESSAGE_MAX 1024

typedef enum perma_status {
    PERMA_OK = 0,
    PERMA_ERR_ARGUMENT,   /* a bad argument or descriptor field; the message names it */
    PERMA_ERR_NO_PLATFORM,/* no OpenCL platform installed (install pocl-opencl-icd) */
    PERMA_ERR_NO_DEVICE,  /* the requested platform:device does not exist */
    PERMA_ERR_OPENCL,     /* an OpenCL call failed; the message names the call */
    PERMA_ERR_BUILD,      /* the generated program did not compile; message has the log */
    PERMA_ERR_NO_MEMORY,  /* a host allocation failed */
    PERMA_ERR_CAPACITY,   /* queues cannot grow enough for the run to progress */
    PERMA_ERR_EMIT_LIMIT, /* a procedure emitted more items than it declared */
    PERMA_ERR_TIMEOUT,    /* the watchdog stopped the run: time_limit passed, or no item
                             completed for stall_limit seconds (the message says which) */
    PERMA_ERR_STATE,      /* call not valid now (e.g. register after destroy) */
    PERMA_ERR_IO,         /* a file could not be read */
    PERMA_ERR_DEVICE      /* the kernel reported an internal failure */
} perma_status;

/* Short constant name of a status, e.g. "PERMA_ERR_BUILD". */
const char *perma_status_name(perma_status status);

typedef struct perma_error {
    perma_status status;
    char message[PERMA_MESSAGE_MAX];
} perma_error;

typedef struct perma_runtime perma_runtime;
typedef int perma_proc; /* procedure handle returned by perma_register */
struct perma_progress;  /* a run's progress (below) */

/* How the work is executed.  Every technique runs the same procedure
 * sources and gives the same results. */
typedef enum perma_technique {
    PERMA_TECHNIQUE_MEGAKERNEL = 0,       /* one persistent kernel (default) */
    PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE, /* host launches one NDRange per non-empty queue,
                                             breadth-first, until all are empty */
    PERMA_TECHNIQUE_BOUNDED_BATCHES       /* host iterations taking at most batch_limit items
                                             from the end of a queue (LIFO): bounded memory */
} perma_technique;

/* Where the megakernel's queues live and how load is balanced. */
typedef enum perma_strategy {
    PERMA_STRATEGY_SHARED = 0,        /* one global queue per procedure (default) */
    PERMA_STRATEGY_STEALING,          /* a queue set per group; idle groups steal */
    PERMA_STRATEGY_DONATION,          /* a queue set per group; full groups donate */
    PERMA_STRATEGY_STEALING_DONATION  /* both */
} perma_strategy;

/* How a stealing group picks its victim. */
typedef enum perma_victim {
    PERMA_VICTIM_RANDOM = 0,
    PERMA_VICTIM_ROUND_ROBIN
} perma_victim;

/* Names used on command lines: "megakernel", "kernel-per-procedure",
 * "bounded-batches"; "shared", "stealing", "donation", "stealing-donation";
 * "random", "round-robin".  NULL for an unknown value. */
const char *perma_technique_name(perma_technique technique);
const char *perma_strategy_name(perma_strategy strategy);
const char *perma_victim_name(perma_victim victim);
/* Parse a name; PERMA_ERR_ARGUMENT for an unknown one.  `out` is set only
 * on success. */
perma_status perma_technique_parse(const char *name, perma_technique *out);
perma_status perma_strategy_parse(const char *name, perma_strategy *out);
perma_status perma_victim_parse(const char *name, perma_victim *out);

/* A schedule: how the work runs (perma_config.schedule), written as one
 * label on command lines, in tables and in reports:
 *
 *     megakernel[/STRATEGY[/VICTIM][/d=N]][+localN][+wfN]
 *     kernel-per-procedure
 *     bounded-batches[/p=N]
 *
 * e.g. "megakernel/shared", "megakernel/stealing/round-robin",
 * "megakernel/shared+local32", "megakernel/donation/d=256",
 * "megakernel/stealing-donation/random/d=64+local32", "megakernel/shared+wf32",
 * "bounded-batches/p=64".  STRATEGY and VICTIM are the names above;
 * STRATEGY defaults to shared, VICTIM (only after a stealing strategy:
 * stealing, stealing-donation) to random.  /d=N (only after a donating
 * strategy: donation, stealing-donation) sets donation_threshold, +localN
 * local_queue_items, +wfN work_first_items (+wf0: PERMA_WORK_FIRST_OFF),
 * /p=N batch_limit; N is a decimal number >= 1 (leave
 * the part out for the default).  All fields zero (what perma_config_init
 * sets) is megakernel/shared. */
typedef struct perma_schedule {
    perma_technique technique;
    perma_strategy strategy;        /* megakernel only: where the queues live */
    perma_victim victim;            /* stealing strategies only: how a thief picks */
    /* Megakernel only: items per procedure in a per-group front queue in
     * __local memory, in front of the global queues (spilling when full);
     * 0 = none, at most PERMA_MAX_LOCAL_QUEUE_ITEMS (the device's __local
     * memory may allow fewer: perma_create says so). */
    unsigned local_queue_items;
    /* Bounded batches only: most items taken per host iteration; 0 = 4096. */
    unsigned batch_limit;
    /* Donating strategies only (donation, stealing-donation): a group whose
     * queue of a procedure holds more than this many items gives up to a
     * batch of it to the emptiest group; 0 = 4 batches of that procedure. */
    unsigned donation_threshold;
    /* Megakernel only: work-first execution (docs/writing-procedures.md,
     * *What an item costs*): a work-item runs the items its procedure emits
     * into a procedure of one thread per item right away, depth first,
     * from a stack of this many items in __local memory, and only what does
     * not fit, or what it gives to an idle group, goes through the queues.
     * 0 = the default: on, with a stack the device's __local memory holds
     * (128 items on a CPU; perma_stats.stack_items says); N (at most
     * PERMA_MAX_WORK_FIRST_ITEMS; the device may allow fewer: perma_create
     * says so) = N items; PERMA_WORK_FIRST_OFF = off, every item goes
     * through the queues. */
    unsigned work_first_items;
} perma_schedule;

/* Parse a label into *out (set only on success).  PERMA_ERR_ARGUMENT for
 * a NULL, empty or malformed label; *error (if not NULL) then holds the
 * status and a message quoting the label and naming the bad part, e.g.
 * "schedule 'megakernel/stealng': unknown strategy 'stealng' (shared,
 * stealing, donation, stealing-donation)". */
perma_status perma_schedule_parse(const char *label, perma_schedule *out, perma_error *error);
/* Write the canonical label of *schedule into buf (always terminated when
 * size > 0): a megakernel's strategy is always named, and so is the victim
 * of a stealing strategy ("megakernel/stealing/random"); /d=N, +localN and
 * /p=N only when not 0.  Fields the technique or strategy does not use are
 * left out.  The label parses back to the same schedule, and formatting a
 * parsed canonical label gives the same text.  Returns the label's length like
 * snprintf (>= size: truncated), or -1 (buf "") when the technique,
 * strategy or victim has no name. */
int perma_schedule_format(const perma_schedule *schedule, char *buf, size_t size);
/* Which schedules perma_schedule_all visits. */
typedef enum perma_schedule_set {
    PERMA_SCHEDULES_ALL = 0,        /* every one */
    PERMA_SCHEDULES_VICTIMS_ONCE,   /* victims other than the default (random)
                                     * only under the first stealing strategy
                                     * (stealing): the victim policy is the
                                     * same code under every stealing strategy */
    PERMA_SCHEDULES_DEFAULT_VICTIM  /* the default victim only */
} perma_schedule_set;
/* Every schedule that differs in technique, strategy or victim, with no
 * local queue, the default batch limit and the default donation threshold,
 * in a fixed order: every technique; under megakernel every strategy; under
 * a stealing strategy every victim.  PERMA_SCHEDULES_ALL visits "megakernel/shared",
 * "megakernel/stealing/random", "megakernel/stealing/round-robin",
 * "megakernel/donation", "megakernel/stealing-donation/random",
 * "megakernel/stealing-donation/round-robin", "kernel-per-procedure",
 * "bounded-batches"; the other sets leave some victims out.  Sets *out to
 * schedule number `index` (from 0) of `set` and returns PERMA_OK;
 * PERMA_ERR_ARGUMENT, *out untouched, past the last one or for an unknown
 * set:
 *
 *     for (unsigned i = 0; perma_schedule_all(PERMA_SCHEDULES_ALL, i, &s) == PERMA_OK; ++i) ...
 *
 * Tests, benchmarks and examples iterate it rather than list schedules, so
 * that a new strategy (one row of runtime/src/schedules.def) reaches them. */
perma_status perma_schedule_all(perma_schedule_set set, unsigned index, perma_schedule *out);

typedef struct perma_config {
    /* OpenCL device.  platform_index >= 0 picks the platform by index;
     * else platform_name, if not NULL, picks the first platform whose name
     * or vendor contains it (any case: "intel", "pocl", "oclgrind"); else
     * the first device of the PERMA_DEVICE environment variable (a device
     * list, see perma_device_list: "P:D", "NAME[:D]" with NAME a platform
     * name as above, sub-devices, e.g. PERMA_DEVICE=intel or
     * PERMA_DEVICE=pocl:0) if set, else 0:0.  device_index >= 0 picks the
     * platform's device, else the one PERMA_DEVICE names (when it is
     * consulted), else 0.  platform_name is read only by perma_create.
     * `perma-info` lists the platforms and devices. */
    int platform_index;
    int device_index;
    const char *platform_name;
    /* Sub-device: with sub_devices >= 2 the device is split into that many
     * equal parts (clCreateSubDevices, CL_DEVICE_PARTITION_EQUALLY) and the
     * runtime runs on part sub_device (0..sub_devices-1); 0 (default): the
     * whole device, or the part PERMA_DEVICE names when the indexes are -1. */
    unsigned sub_devices;
    unsigned sub_device;
    /* Persistent work-groups; 0 = as many as can be co-resident: on a CPU
     * device the physical core count from hwloc (or the compute units if
     * fewer); on another device the compute units times the groups one of
     * them holds at once, by the megakernel's __local memory and registers
     * (CL_KERNEL_LOCAL_MEM_SIZE against CL_DEVICE_LOCAL_MEM_SIZE,
     * CL_KERNEL_WORK_GROUP_SIZE against group_size; at most 16), settled
     * when the program is built (perma_stats.work_groups_reason says how).
     * There, more than the device holds at once fails perma_build and
     * perma_run with PERMA_ERR_ARGUMENT under the megakernel, rather than
     * risk groups that wait forever for one that cannot start; a CPU runs
     * any number (a group that cannot start waits for one that ends). */
    unsigned work_groups;
    /* Work-items per group; 0 = 64. */
    unsigned group_size;
    /* Items one work-item runs one after another in a batch of a procedure
     * with one thread per item that is not cooperative, so such a batch
     * holds up to group_size * items_per_work_item items (fewer if its
     * items and scratch do not fit the __local memory, or staging the
     * declared maximum of its emits would pass a group's staging memory);
     * 0 = 4.  Larger batches spread the fixed cost of a batch (claiming,
     * barriers, publishing) over more items.  Procedures with several
     * threads per item and cooperative ones take group_size /
     * threads_per_item items per batch. */
    unsigned items_per_work_item;
    /* Initial capacity of each queue in items; 0 = 1024.  Rounded up to a
     * power of two; queues grow on demand (when a batch emitted more than
     * its target had room for, when no group can start anything for lack of
     * room, and when a group's batches keep being cut to a fraction by the
     * room their expected emits need, up to queue_memory_limit), and a run
     * starts each queue at the capacity the
     * last successful run of the same program grew it to, if that is more
     * and all queues fit queue_memory_limit (perma_stats.queues_kept counts
     * them; perma_forget_capacities). */
    size_t queue_capacity;
    /* Cap on the bytes of all queues together (item_size + 8 bytes per
     * slot); 0 = half the device's largest allocation
     * (CL_DEVICE_MAX_MEM_ALLOC_SIZE): growing a queue holds the old and the
     * new items at once.  Reaching it fails the run with PERMA_ERR_CAPACITY;
     * perma_seed already refuses seeds whose queue would not fit. */
    size_t queue_memory_limit;
    /* Watchdog: a run longer than this many seconds fails with
     * PERMA_ERR_TIMEOUT; 0 = 600. */
    double time_limit;
    /* Watchdog: a run in which no item completes anywhere for this many
     * seconds (a procedure that never returns, say) fails with
     * PERMA_ERR_TIMEOUT naming the procedures that had items in flight;
     * 0 = 20.  Seen only on devices that share memory with the host (CPUs,
     * integrated GPUs); elsewhere only time_limit applies.  One item taking
     * longer than this counts as stuck: raise it for such procedures.
     *
     * When either limit passes, the watchdog asks every work-group to stop
     * and gives the kernel 10 s (the grace period) to do so; a procedure
     * with a long loop sees the request through perma_stop_requested(ctx)
     * (docs/writing-procedures.md).  A procedure that never returns cannot
     * be stopped: the run then fails saying so, and the runtime can no
     * longer be used (every call that uses the device returns
     * PERMA_ERR_STATE, perma_cl_queue returns NULL; perma_destroy frees
     * what it can).  OpenCL cannot end a running kernel, so the stuck
     * kernel keeps its compute unit busy until the process exits; the
     * process exits normally (the runtime's command queue is released so
     * that Intel's OpenCL CPU runtime does not wait for it at exit). */
    double stall_limit;
    /* Cap on the __local memory one group uses; 0 = the device's size, or
     * the PERMA_LOCAL_MEMORY_LIMIT environment variable if set (bytes, or
     * with a K or M suffix KiB or MiB, e.g. PERMA_LOCAL_MEMORY_LIMIT=32K:
     * try a program under a smaller device's limit, OpenCL's minimum being
     * 32 KiB; a malformed value fails perma_create naming it).
     * perma_get_local_memory tells what a group may use. */
    size_t local_memory_limit;
    /* Extra options for clBuildProgram, e.g. "-DTHRESHOLD=8"; may be NULL. */
    const char *build_options;
    /* Where compiler messages go: after a build that succeeded, its
     * warnings ("FILE:LINE:COL: warning: TEXT", naming the procedures'
     * files and lines), and with the PERMA_BUILD_LOG environment variable
     * set the whole build log of every build, each as one text of whole
     * lines.  NULL (default): stderr.  (A failed build's errors are in
     * perma_errmsg either way.) */
    void (*build_log)(void *user, const char *text);
    void *build_log_user;
    /* How the work runs: technique, strategy, victim, local front queue,
     * batch limit, donation threshold (perma_schedule_parse fills one from
     * a label); all zero = megakernel/shared. */
    perma_schedule schedule;
    /* Trace: if set (or the PERMA_TRACE environment variable names a file),
     * every run writes its batches as Chrome trace events (JSON, viewable
     * in Perfetto or chrome://tracing): one track per work-group, one event
     * per batch with procedure, items and kind (run, steal, local,
     * donate).  Every run of the process stays in the file, one track
     * group ("process") per run, on one time line: host microseconds since
     * the process's first traced run.  Host-driven steps are timed on the
     * host; the megakernel's batches by ticks of a device-side counter
     * that the host reads against its clock while the kernel runs (within
     * about a millisecond where the device shares memory with the host).
     * runtime/tools/trace_to_svg.py summarises and draws the file. */
    const char *trace_path;
    /* Most events recorded per work-group and launch; 0 = 65536. */
    unsigned trace_events;
    /* Progress (see perma_progress below): if set, called from the thread
     * in perma_run when a run starts, at most every progress_interval
     * seconds while it runs (0 = 0.5), and once when it ends, successfully
     * or not. */
    void (*progress)(void *user, const struct perma_progress *progress);
    void *progress_user;
    double progress_interval;
} perma_config;

/* Fill *config with the defaults described above. */
void perma_config_init(perma_config *config);

/* Several devices.  One runtime drives one device; a program that uses
 * several creates a runtime per device (each in its own thread if they
 * are to run at once: perma_run blocks).  A device is named by its
 * platform and device index, or as one of N equal sub-devices of one
 * (clCreateSubDevices with CL_DEVICE_PARTITION_EQUALLY, compute units / N
 * each; PoCL and Intel's CPU runtime support it), which lets one CPU act
 * as N devices.  Written "P:D" or "P:D/N.K" (part K of N). */
typedef struct perma_device_ref {
    int platform_index;
    int device_index;
    unsigned sub_devices;   /* 0: the whole device; N >= 2: one of N equal parts */
    unsigned sub_device;    /* that part, 0..N-1 */
} perma_device_ref;

/* Most devices a list may expand to. */
#define PERMA_MAX_DEVICES 64

/* Expand a device list, comma-separated entries of
 *     P:D       device D of platform P (perma-info lists them)
 *     NAME:D    device D of the first platform whose name or vendor
 *               contains NAME, in any case ("intel", "pocl", "oclgrind");
 *               NAME alone is NAME:0, and NAME may take the /N and /N.K
 *               below; NAME starts with a letter and has letters, digits,
 *               spaces and "()._-"
 *     P:D/N     that device split into N equal sub-devices: all N parts
 *     P:D/N.K   the K-th (from 0) of those parts
 *     all       every device of every platform
 * into out[0..*count) (at most `max`), in the order given.  NULL or ""
 * means the PERMA_DEVICE environment variable, or "0:0" if it is unset.
 * The devices must exist and split as asked (OpenCL is queried; no
 * sub-device is created); a device named twice is an error.  On failure
 * *count is 0 and *error (if not NULL) names the list and the entry:
 * PERMA_ERR_ARGUMENT (malformed, duplicate, too many), PERMA_ERR_NO_DEVICE
 * (missing, a name no platform matches, or cannot be split so),
 * PERMA_ERR_NO_PLATFORM. */
perma_status perma_device_list(const char *list, perma_device_ref *out, unsigned max,
                               unsigned *count, perma_error *error);
/* Write "P:D" or "P:D/N.K"; returns the length like snprintf. */
int perma_device_ref_format(const perma_device_ref *ref, char *buf, size_t size);
/* Point config at a device (its platform, device and sub-device fields). */
void perma_config_set_device(perma_config *config, const perma_device_ref *ref);

/* Create a runtime on the configured device.  On failure *out is NULL and
 * *error (if not NULL) holds the status and message. */
perma_status perma_create(const perma_config *config, perma_runtime **out, perma_error *error);

/* Release everything; NULL is fine. */
void perma_destroy(perma_runtime *rt);

/* The message of the last call on rt that returns a perma_status: "" if it
 * succeeded.  After a run's kernel did not stop (PERMA_ERR_TIMEOUT saying
 * so) every call that uses the device fails with PERMA_ERR_STATE. */
const char *perma_errmsg(const perma_runtime *rt);

/* Whether a buffer of `bytes` for `what` (named in the message, e.g. "the
 * sample buffer") fits before it is created: not above the device's
 * largest allocation and, on a CPU device, whose buffers are the
 * process's memory, within the process's limits (ulimit -v, ulimit -d)
 * with room left for the driver.  PERMA_ERR_NO_MEMORY naming what, its
 * size and the limit otherwise.  The runtime checks its own buffers so;
 * call it before clCreateBuffer on perma_cl_context() (an OpenCL driver
 * may not survive an allocation that fails inside it). */
perma_status perma_check_memory(perma_runtime *rt, size_t bytes, const char *what);

/* The OpenCL context, device and queue the runtime uses (for user buffers). */
cl_context perma_cl_context(const perma_runtime *rt);
cl_device_id perma_cl_device(const perma_runtime *rt);
cl_command_queue perma_cl_queue(const perma_runtime *rt);

/* Add OpenCL C declarations visible to every procedure: item types, helper
 * functions.  `source` may be NULL to read `file`; `file` names the text in
 * compiler messages (may be NULL for a string: "<source N>"). */
perma_status perma_add_source(perma_runtime *rt, const char *source, const char *file);

/* One edge of the procedure graph: this procedure may emit up to
 * max_items items into `target` for each item it processes. */
typedef struct perma_emit {
    const char *target;
    unsigned max_items;
} perma_emit;

/* A procedure, in the spirit of StarPU's codelet. */
typedef struct perma_procedure {
    const char *name;         /* C identifier, unique, not reserved (Names, below); also the queue name */
    const char *item_type;    /* OpenCL C type of one item, e.g. "struct node" */
    size_t item_size;         /* sizeof(item_type) on the device: 4..65536, multiple of 4 */
    unsigned threads_per_item;/* 1..group size; 0 means 1 */
    size_t local_bytes_per_item; /* __local scratch per item (ctx->scratch) */
    const char *source;       /* OpenCL C defining `function`; NULL = read source_file */
    const char *source_file;  /* path to read, and the name in compiler messages */
    const char *function;     /* name of the function in source */
    perma_emit emits[PERMA_MAX_EMITS]; /* ends at the first target == NULL */
    int priority;             /* higher is served first; ties: deeper in the emit graph
                                 first.  Procedures that emit into each other in a
                                 cycle must differ in priority (checked at build) */
    int cooperative;          /* 1: called by all work-items, may use barrier() */
    int queue_only;           /* 1: its items always go through the queues, in the order the
                                 scheduler takes them, and never run depth first from a
                                 work-item's stack (work-first, perma_schedule.work_first_items);
                                 nor do the items of procedures that emit into it.  For searches
                                 whose work grows when items run out of breadth-first order:
                                 label-correcting BFS or shortest paths, where a vertex reached
                                 first along a long path is expanded again for each shorter one */
} perma_procedure;

/* Validate and register a procedure.  Emit targets are resolved when the
 * program is built, so procedures may emit into ones registered later. */
perma_status perma_register(perma_runtime *rt, const perma_procedure *procedure, perma_proc *out);

/* Handle of a registered procedure by name. */
perma_status perma_find(perma_runtime *rt, const char *name, perma_proc *out);

/* Buffer access flags for host memory the runtime copies. */
enum {
    PERMA_READ = 1,       /* copied to the device before each run */
    PERMA_WRITE = 2,      /* copied back to host memory after each run */
    PERMA_READ_WRITE = 3
};

/* Bind a buffer that procedures see as ctx->buf.NAME with OpenCL C type
 * `type` (e.g. "__global float *", "__global const struct patch *").
 * Bind every name before the first run; binding the same name again later
 * (same type) swaps the memory.  perma_bind_cl uses the caller's cl_mem
 * (not released by perma); perma_bind_host copies `bytes` of host memory,
 * which must be a whole number of elements when `type` points to a
 * built-in scalar or vector ("__global uint *": a multiple of 4).
 *
 * Names.  Procedure, function, buffer and reduction names are C
 * identifiers that the generated program can take: an OpenCL C keyword or
 * type ("kernel", "int", "global", "float4"), a name beginning with perma_
 * or PERMA_ (the runtime's own) or reserved for the compiler ("__x",
 * "_X") is PERMA_ERR_ARGUMENT where it is given, naming it and why.
 *
 * PERMA_CHECK_BOUNDS=1 in the environment (read by perma_create): 1024
 * guard words follow every perma_bind_host buffer on the device, set
 * before each run and compared after it; a procedure that wrote into them
 * fails the run with PERMA_ERR_DEVICE naming the buffer, before anything
 * is copied back (docs/writing-procedures.md, Debugging). */
perma_status perma_bind_cl(perma_runtime *rt, const char *name, const char *type, cl_mem buffer);
perma_status perma_bind_host(perma_runtime *rt, const char *name, const char *type,
                             void *host, size_t bytes, unsigned flags);

/* Reductions.  A reduction is a value every procedure may combine into
 * with one call, reduce_NAME(ctx, value), and the host reads after the
 * run: a count, a sum, the deepest level reached.  Each work-item keeps a
 * private partial of every reduction, which the call updates without any
 * atomic or barrier; the partials are folded once per launch per
 * work-item and combined by the host after the run (docs/design-runs.md,
 * Reductions), so a reduction costs about as much as adding to a local
 * variable, where a global atomic_inc per item on one counter adds up to
 * 13 ns per item on a CPU, as much as the runtime's own cost of the item
 * (docs/writing-procedures.md, sections 4 and 6).
 *
 * Results are exact and independent of the schedule (technique, strategy,
 * group count, run to run, OpenCL implementation):
 *   - sums of uint and int wrap modulo 2^32, of ulong and long modulo 2^64
 *     (two's complement), as a sequential loop would;
 *   - sums of float and double are the exact sum of the values rounded
 *     once to the type (to nearest, ties to even): the same bits whatever
 *     order the items ran in.  A sum that is exactly zero is +0.0; an
 *     infinity among the values gives that infinity, +inf and -inf
 *     together or a NaN give NaN; an exact sum beyond the type's range
 *     rounds to infinity;
 *   - min and max compare values as the type does, except that -0.0 is
 *     below +0.0 and NaN values are ignored; with no value at all the
 *     result is the identity: the type's largest value for min (+inf for
 *     floats), its smallest for max (-inf).
 * Cost: one 64-bit word per work-item per reduction; an exact float sum
 * keeps 10 words, a double sum 67, and each add updates two or three of
 * them (about 20 instructions). */
typedef enum perma_reduce_op {
    PERMA_REDUCE_SUM = 0,
    PERMA_REDUCE_MIN,
    PERMA_REDUCE_MAX
} perma_reduce_op;

/* The type of a reduction's values (and of reduce_NAME's argument). */
typedef enum perma_value_type {
    PERMA_TYPE_UINT = 0, /* uint32_t on the host */
    PERMA_TYPE_INT,      /* int32_t */
    PERMA_TYPE_ULONG,    /* uint64_t */
    PERMA_TYPE_LONG,     /* int64_t */
    PERMA_TYPE_FLOAT,    /* float */
    PERMA_TYPE_DOUBLE    /* double (the device must support cl_khr_fp64) */
} perma_value_type;

/* Names used in messages: "sum", "min", "max"; "uint", "int", "ulong",
 * "long", "float", "double".  NULL for an unknown value. */
const char *perma_reduce_op_name(perma_reduce_op op);
const char *perma_value_type_name(perma_value_type type);

/* Declare reduction `name` (a C identifier; procedures call
 * reduce_NAME(ctx, value) with a value of `type`).  `result`, if not NULL,
 * points to a host variable of `type` that every successful perma_run
 * sets to the result (it must stay valid as long as the runtime runs).
 * Declare before the first run (a later declaration rebuilds the
 * program).  PERMA_ERR_ARGUMENT for a bad name, a name declared twice, an
 * unknown op or type, a double on a device without cl_khr_fp64, more than
 * PERMA_MAX_REDUCTIONS; the message names the reduction and the
 * parameter. */
perma_status perma_declare_reduction(perma_runtime *rt, const char *name, perma_reduce_op op, perma_value_type type,
                                     void *result);

/* The result of reduction `name` in the last run, into *out, a variable of
 * `type`, which must be the declared type.  PERMA_ERR_ARGUMENT for an
 * unknown name, a type that is not the declared one or a NULL out;
 * PERMA_ERR_STATE when no run has finished since the reduction was
 * declared, or the last run failed. */
perma_status perma_get_reduction(perma_runtime *rt, const char *name, perma_value_type type, void *out);
/* ---- Typed host arrays --------------------------------------------------
 * Bind a host array so that the device type and the byte count come from
 * its one C declaration:
 *
 *     double weights[1024];
 *     PERMA_BIND_HOST_ARRAY(rt, "weights", weights, PERMA_READ);
 *         // = perma_bind_host(rt, "weights", "__global const double *",
 *         //                   weights, sizeof weights, PERMA_READ)
 *     struct pair *pairs = malloc(n * sizeof *pairs);
 *     PERMA_BIND_HOST_POINTER(rt, "pairs", pairs, n, PERMA_READ_WRITE);
 *
 * The element type's OpenCL C name comes from PERMA_CL_TYPE_NAME (a
 * _Generic over the C type): char (signed or unsigned as the host's char
 * is), signed/unsigned char, short, int, long and long long (by size: 4
 * bytes "int", 8 "long"), their unsigned forms, float, double (the device
 * needs fp64: perma-info), and OpenCL's host vector types cl_float2/4/8/16,
 * cl_double2/4, cl_int2/4, cl_uint2/4, cl_uchar4 (3-component ones are not
 * listed: cl_float3 is cl_float4 on the host).  So int32_t is "int",
 * uint64_t and size_t "ulong".  Struct types are named by the program:
 * define PERMA_HOST_TYPE_NAMES as `TYPE: "OPENCL C NAME",` pairs before
 * including perma.h, e.g.
 *
 *     #define PERMA_HOST_TYPE_NAMES struct pair: "struct pair",
 *     #include <perma.h>
 *
 * (declare the struct for the device with perma_add_source).  Any other
 * element type does not compile ("'_Generic' selector of type ... is not
 * compatible with any association"), nor does PERMA_BIND_HOST_ARRAY given
 * a pointer instead of an array (with GCC and Clang; elsewhere use
 * PERMA_BIND_HOST_POINTER for pointers).  The pointer type is "__global
 * const T *" for PERMA_READ alone, else "__global T *".  The generated
 * program checks sizeof(T) on the device against the host's element size:
 * a difference (a struct the device lays out otherwise) fails the build
 * with PERMA_ERR_BUILD naming the buffer and both sizes. */
perma_status perma_bind_host_array(perma_runtime *rt, const char *name, const char *element_type, void *host,
                                   size_t count, size_t element_size, unsigned flags);

#ifndef __cplusplus
#ifndef PERMA_HOST_TYPE_NAMES
#define PERMA_HOST_TYPE_NAMES
#endif
/* The OpenCL C name of the type of expression x (a string literal's
 * value); a compile error for a type without one. */
#define PERMA_CL_TYPE_NAME(x)                                                                 \
    _Generic((x), PERMA_HOST_TYPE_NAMES                                                       \
        char: (char)-1 < 0 ? "char" : "uchar", signed char: "char", unsigned char: "uchar",  \
        short: "short", unsigned short: "ushort", int: "int", unsigned int: "uint",          \
        long: sizeof(long) == 8 ? "long" : "int", unsigned long: sizeof(long) == 8 ? "ulong" : "uint", \
        long long: "long", unsigned long long: "ulong", float: "float", double: "double",    \
        cl_float2: "float2", cl_float4: "float4", cl_float8: "float8", cl_float16: "float16", \
        cl_double2: "double2", cl_double4: "double4", cl_int2: "int2", cl_int4: "int4",       \
        cl_uint2: "uint2", cl_uint4: "uint4", cl_uchar4: "uchar4")

#if defined(__GNUC__) || defined(__clang__)
/* Zero, or a compile error when `array` is a pointer rather than an array. */
#define PERMA_ASSERT_ARRAY_(array)                                                            \
    (0 * sizeof(struct {                                                                      \
        _Static_assert(!__builtin_types_compatible_p(__typeof__(array), __typeof__(&(array)[0])), \
                       "PERMA_BIND_HOST_ARRAY needs an array; use PERMA_BIND_HOST_POINTER for a pointer"); \
        int perma_unused_;                                                                    \
    }))
#else
#define PERMA_ASSERT_ARRAY_(array) 0
#endif

#define PERMA_BIND_HOST_ARRAY(rt, name, array, flags)                                         \
    perma_bind_host_array((rt), (name), PERMA_CL_TYPE_NAME((array)[0]), (array),              \
                          sizeof(array) / sizeof((array)[0]) + PERMA_ASSERT_ARRAY_(array),    \
                          sizeof((array)[0]), (flags))
#define PERMA_BIND_HOST_POINTER(rt, name, pointer, count, flags)                              \
    perma_bind_host_array((rt), (name), PERMA_CL_TYPE_NAME(*(pointer)), (pointer), (count),   \
                          sizeof(*(pointer)), (flags))
#endif

/* Generate and compile the megakernel now (perma_run does it when needed),
 * including the driver's compile at the first launch.  A compile error in a
 * procedure reports the procedure's file and line; the build also checks
 * that emit targets exist, each function is defined in its sources and
 * cycles are ordered by priority.  Item types that something emits must be
 * declared in a shared source (perma_add_source). */
perma_status perma_build(perma_runtime *rt);

/* Where the last perma_build got its program: compiled from source, or
 * loaded from the disk cache of compiled programs (PERMA_CACHE_DIR; see
 * README).  Processes that build the same program at once, e.g. the ranks
 * of a farm sharing a cache directory, compile it once: the others wait
 * for that build (wait_seconds) and load it. */
typedef enum perma_program_origin {
    PERMA_PROGRAM_NOT_BUILT = 0,
    PERMA_PROGRAM_COMPILED,    /* from source */
    PERMA_PROGRAM_CACHED       /* from the disk cache */
} perma_program_origin;

typedef struct perma_build_info {
    perma_program_origin origin;
    double seconds;            /* perma_build's time: compile or load, and the warm-up launch */
    double wait_seconds;       /* part of it spent waiting for another process's build */
    int stored;                /* the compiled program was stored in the disk cache */
} perma_build_info;

perma_status perma_get_build_info(perma_runtime *rt, perma_build_info *out);

/* Queue `count` items of procedure `proc` (item_size bytes each) for the next
 * run.  Checked before anything is copied: PERMA_ERR_ARGUMENT if the
 * procedure's seeds would pass PERMA_MAX_QUEUED_ITEMS, PERMA_ERR_CAPACITY
 * if the queue they start in would pass the queue memory limit (the message
 * says how many bytes it would need); the seeds queued before stay. */
perma_status perma_seed(perma_runtime *rt, perma_proc proc, const void *items, size_t count);

/* Let the next run start every queue from config.queue_capacity again
 * rather than from what earlier runs grew it to: e.g. after a run much
 * larger than the ones that follow, whose queue memory they need not keep
 * (the device buffers keep their size until perma_destroy either way). */
perma_status perma_forget_capacities(perma_runtime *rt);

/* Run until no work is left.  Queues grow as needed; the watchdog turns a
 * run longer than the time limit, or one in which nothing completes for
 * the stall limit, into PERMA_ERR_TIMEOUT (config.time_limit,
 * config.stall_limit).  A run consumes the
 * seeded items whether it succeeds or fails: seed again before a retry. */
perma_status perma_run(perma_runtime *rt);

/* Why a procedure's batches held fewer items than a group could run. */
typedef enum perma_batch_cut {
    PERMA_BATCH_FULL = 0,         /* nothing cut them */
    PERMA_BATCH_CUT_LOCAL_MEMORY, /* __local memory holds fewer items (their copies, scratch and emit
                                     counters): batch_size is below group_size * items_per_work_item
                                     (group_size / threads_per_item for a procedure of several threads per
                                     item or a cooperative one) */
    PERMA_BATCH_CUT_ROOM,         /* a full batch's expected emits (what its items emitted so far, per
                                     item; the declared maximum before a group's first batch of a launch)
                                     did not fit the target's queue, which may not grow further (the queue
                                     memory limit), so batches started with the few items that fit */
    PERMA_BATCH_CUT_STAGING       /* staging the declared maximum of emits of a full batch would need more
                                     than the global memory a work-group may stage in (a quarter of the
                                     device's largest allocation over all groups, at most 16 MiB each) */
} perma_batch_cut;

/* Statistics of the last run. */
typedef struct perma_procedure_stats {
    const char *name;
    uint64_t items;                     /* items executed */
    uint64_t batches;                   /* batches executed */
    uint64_t emitted[PERMA_MAX_EMITS];  /* items emitted, per entry of .emits */
    unsigned emit_count;                /* entries used in emitted[] */
    uint64_t seeded;                    /* items seeded by the host */
    uint64_t peak_queue_items;          /* most items queued at once */
    size_t initial_capacity;            /* capacity in items when the run started */
    size_t queue_capacity;              /* final capacity in items */
    unsigned regrowths;                 /* times this queue was grown */
    unsigned batch_size;                /* most items one batch holds (items / batches: the mean) */
    perma_batch_cut batch_cut;          /* why batches were smaller, if they were */
    int batch_cut_emit;                 /* the .emits entry responsible, or -1 */
    /* Work-first (perma_schedule.work_first_items): of `items`, those that
     * ran from a work-item's stack, right after the item that emitted them,
     * without a batch of their own (the others ran in `batches`). */
    uint64_t stacked_items;
} perma_procedure_stats;

/* Load-balancing counters of one persistent work-group. */
typedef struct perma_group_stats {
    uint64_t batches;          /* batches executed */
    uint64_t items;            /* items executed */
    uint64_t steals;           /* batches taken from another group's queue */
    uint64_t donations;        /* times it gave items to another group */
    uint64_t donated_items;
    uint64_t spills;           /* items its local front queue passed to global queues */
    uint64_t idle_polls;       /* scheduler polls that found nothing to run */
    /* Work-first: items its work-items ran from their stacks, items moved
     * from the stacks to the global queues (a stack too full for its top
     * item's emits, or a share for an idle group), and the most items one
     * work-item's stack held. */
    uint64_t stacked_items;
    uint64_t stack_spills;
    unsigned stack_peak;
} perma_group_stats;

typedef struct perma_stats {
    double seconds;            /* wall time of perma_run, build excluded */
    unsigned launches;         /* kernel launches (1 + relaunches after growth) */
    unsigned regrowths;        /* queue growth steps */
    unsigned work_groups;
    unsigned group_size;
    unsigned procedure_count;
    size_t peak_queue_bytes;   /* largest total queue allocation */
    size_t queue_memory_limit; /* the cap on it (config.queue_memory_limit or its default) */
    unsigned queues_kept;      /* queues that started at the capacity an earlier run of this
                                  runtime grew them to (kept while the program is not rebuilt
                                  and all queues fit the memory limit) */
    uint64_t items;            /* items executed, all procedures */
    uint64_t steals, donations, spills, idle_polls; /* sums over groups */
    /* Emitted items a megakernel batch could not queue because their target
     * had no room for more than the batch reserved (its expected emits): the
     * launch stopped, the queue grew and they were appended to it. */
    uint64_t overflowed_items;
    perma_technique technique;
    perma_strategy strategy;
    /* Work-first, sums over groups (perma_group_stats): items run from the
     * work-items' stacks and items moved from them to the global queues;
     * the most items one work-item's stack held (the stacks' memory is
     * config.group_size * work_groups * schedule.work_first_items items at
     * most, whatever the work). */
    uint64_t stacked_items, stack_spills;
    unsigned stack_peak;
    unsigned stack_items;      /* items a work-item's stack holds (0: no stacks: work-first is off, or
                                  no procedure's items can run from one) */
    /* How work_groups was chosen ("2 compute units", "configured", "132
     * compute units x 1, __local memory: 40960 of 49152 bytes each"); valid
     * until the runtime is destroyed or its program rebuilt. */
    const char *work_groups_reason;
    /* Work-groups of this program's megakernel the device holds at once
     * (config.work_groups); 0 on a CPU, which runs any number. */
    unsigned resident_groups;
    size_t kernel_local_bytes; /* __local memory of one group of the megakernel (CL_KERNEL_LOCAL_MEM_SIZE) */
} perma_stats;

perma_status perma_get_stats(perma_runtime *rt, perma_stats *out);
perma_status perma_get_procedure_stats(perma_runtime *rt, perma_proc proc, perma_procedure_stats *out);
/* The work-groups a run uses and the work-items in each, known from
 * perma_create on (config.work_groups, or the device's choice): e.g. to
 * size an array indexed by ctx->group.  On a device that is not a CPU the
 * runtime's choice is settled when the program is built and may then be
 * lower than before (never higher than at perma_create), so an array
 * sized before holds every ctx->group.  Either pointer may be NULL, not
 * both. */
perma_status perma_get_work_groups(perma_runtime *rt, unsigned *work_groups, unsigned *group_size);

/* The __local memory one work-group may use, in bytes, from perma_create
 * on: the device's CL_DEVICE_LOCAL_MEM_SIZE, or config.local_memory_limit
 * (PERMA_LOCAL_MEMORY_LIMIT) when that is lower.  A batch's items, their
 * scratch and emit counters must fit it (perma_batch_cut); emits are staged
 * in global memory. */
perma_status perma_get_local_memory(perma_runtime *rt, size_t *bytes);

/* Counters of persistent group `group` (0..work_groups-1) in the last run;
 * all zero for the host-driven techniques. */
perma_status perma_get_group_stats(perma_runtime *rt, unsigned group, perma_group_stats *out);

/* Print the statistics of the last run as a readable table, with a warning
 * for each procedure whose batches were cut (perma_batch_cut) naming the
 * declaration responsible. */
void perma_print_stats(perma_runtime *rt, FILE *out);

/* ---- Progress -------------------------------------------------------------
 * What a run has done so far, for a progress display.  Two ways to get it:
 * config.progress, a callback called from perma_run's thread (at the start
 * of a run, at most every config.progress_interval seconds while it runs,
 * and at its end), or perma_get_progress from any thread at any time.
 * Both give a copy of the same snapshot, which the runtime takes from the
 * watch page the watchdog reads (docs/design-runs.md, Progress) while a kernel
 * runs, and makes exact from the statistics after each launch: at the end
 * of a run, completed equals perma_procedure_stats.items, procedure by
 * procedure, and queued is 0.  Counts never decrease within a run.  On a
 * device that does not share memory with the host (a discrete GPU) they
 * move only between launches (`live` is 0).  A callback runs on the thread
 * that watches the kernel, while it runs: keep it short, and call no other
 * perma function on the runtime than perma_get_progress. */
typedef struct perma_procedure_progress {
    const char *name;
    uint64_t completed;     /* items executed so far in this run */
    uint64_t queued;        /* items seeded or emitted into it and not yet completed (waiting or
                               running); between launches exact, while a kernel runs an estimate */
} perma_procedure_progress;

typedef struct perma_progress {
    unsigned run;           /* runs this runtime started: 1 during and after the first */
    int running;            /* 1 from the start of perma_run (after the build) to its end */
    double elapsed;         /* seconds since the run started (its perma_stats.seconds at the end) */
    unsigned launches;      /* kernels launched so far: the megakernel's launches, or the host steps */
    int live;               /* 1: the counts move while a kernel runs; 0: only between launches */
    uint64_t completed;     /* sums over the procedures */
    uint64_t queued;
    unsigned procedure_count;
    perma_procedure_progress procedures[PERMA_MAX_PROCEDURES]; /* by perma_proc */
} perma_progress;

/* The progress of the current (or last) run of rt, from any thread.  Does
 * not change perma_errmsg.  PERMA_ERR_ARGUMENT if rt or out is NULL.
 * Before the first run everything is 0.  While a kernel runs the counts
 * are sampled at least every 50 ms, once any progress was asked for (a
 * callback, or a first call of this function). */
perma_status perma_get_progress(perma_runtime *rt, perma_progress *out);

/* Description of the device and the chosen work-group count, one line. */
const char *perma_device_summary(const perma_runtime *rt);

/* ---- Output files ----
 * Files written whole or not at all (the trace here; images, statistics
 * and CSV in the renderer and the benchmarks): the writer fills a stream
 * on a new temporary file in the target's directory, and only a complete,
 * synced file is renamed over the target.  On failure the temporary file
 * is removed, a file that was there before is unchanged, and the message
 * names the path and the reason ("No space left on device").  A symbolic
 * link to a regular file is kept (its target is replaced); a path that is
 * there and is not a regular file (/dev/null, a named pipe) is written in
 * place.  Linux (glibc or musl: fopencookie). */
typedef struct perma_output perma_output;

/* Whether `path` can be written, without writing it: not a directory, not
 * a read-only file, and its directory takes a new file (one is created and
 * removed).  For a check before long work whose result goes there. */
perma_status perma_output_check(const char *path, perma_error *error);

/* Start writing `path`; write to perma_output_stream(*out). */
perma_status perma_output_open(const char *path, perma_output **out, perma_error *error);
FILE *perma_output_stream(perma_output *out);

/* Flush, sync and close the file, which is complete but not yet in place:
 * a writer of several files finishes each before committing any.  On
 * failure (a write failed now or earlier) the output is discarded and
 * freed. */
perma_status perma_output_finish(perma_output *out, perma_error *error);

/* Finish (if not yet) and rename the file into place; frees `out`, also
 * on failure, which leaves the target as it was. */
perma_status perma_output_commit(perma_output *out, perma_error *error);

/* Give up: remove the temporary file and free `out` (NULL is fine). */
void perma_output_discard(perma_output *out);

/* A file a program reads or writes, as its command line names it. */
typedef struct perma_file_role {
    const char *path;   /* NULL or "": not used */
    const char *name;   /* the option or role, in messages: "--output", "--stats", "the model" */
    int written;        /* 1: an output; 0: an input */
} perma_file_role;

/* Refuse files that would overwrite each other: PERMA_ERR_ARGUMENT when
 * two outputs are the same file or an output is the same file as an
 * input (inputs may repeat), the message naming both, e.g. "--stats
 * 'a.png' and --output 'a.png' are the same file: one would overwrite the
 * other", "--output 'm.bpt' is the same file as the model 'm.bpt', which
 * it would overwrite".  The trace that the PERMA_TRACE environment
 * variable names counts as an output named "PERMA_TRACE".  Where a path
 * exists, the same file is the same device and inode (through symbolic
 * and hard links, "./" and ".."); where it does not, the same absolute
 * path once its directory is resolved.  A device or named pipe that is
 * there (/dev/null) is written in place and clashes with nothing.  For
 * the command line, before any work; the first clash is reported. */
perma_status perma_check_distinct_files(const perma_file_role *files, size_t count, perma_error *error);

#ifdef __cplusplus
}
#endif
#endif
