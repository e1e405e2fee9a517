/* The device state: every buffer the kernels use (control block, queue
 * items and completion marks, statistics, trace, step input, watchdog flag),
 * with its size.  A buffer is created when first needed and replaced only
 * when it must grow; the queues grow on the device, so after the seeds'
 * upload no queued item passes through the host. */
#include "internal.h"
#include "state.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The watch page (kernels/perma_abi.h) is host memory the kernels use
 * through a CL_MEM_USE_HOST_PTR buffer: whole aligned pages, so an
 * implementation can map it without copying. */
#define PAGE_BYTES 4096

/* A device buffer and its size. */
typedef struct perma_device_buffer {
    cl_mem mem;
    size_t bytes;
} perma_device_buffer;

/* Everything the kernels use on the device, owned by state.c: each buffer
 * is created when first needed and replaced only by a bigger one. */
struct perma_device_state {
    perma_device_buffer ctl;      /* control block (kernels/perma_abi.h) */
    perma_device_buffer data;     /* queue items */
    perma_device_buffer seq;      /* queue completion marks (kernels/perma_queue.cl) */
    perma_device_buffer stats;    /* a statistics record per group */
    perma_device_buffer trace;    /* trace records per group */
    perma_device_buffer input;    /* the items a step kernel consumes */
    perma_device_buffer relayout; /* a regrowth's perma_relayout_records, then its overflow segments */
    perma_device_buffer emit_areas; /* a group's emit area each: staging, overflow (kernels/perma_abi.h) */
    perma_device_buffer reductions; /* a slot of reduce_words words per work-item (kernels/perma_reduce.cl) */
    uint32_t *overflow_headers;   /* the areas' headers as the last launch left them (perma_state_read_overflow) */
    bool overflow_known;          /* overflow_headers were read for the growth to come */
    perma_ctl_block *stopped;     /* the control block as a launch that stopped for room left it
                                     (perma_state_read_queues), for the growth to come */
    cl_mem abort_mem;             /* the watch page (kernels/perma_abi.h): the abort */
    uint32_t *abort_flag;         /* flag, each group's progress; page-aligned host memory */
    size_t watch_bytes;           /* its size (whole pages) */
    perma_queue_state *queues;    /* queue_count entries, index set * procs + proc */
    unsigned queue_count;
};

/* The watch page of this build: a record per group, sized for its
 * procedures. */
static size_t watch_bytes(const perma_runtime *rt)
{
    size_t bytes = 4 * (size_t)PERMA_WATCH_WORDS_FOR(rt->work_groups, rt->proc_count);
    return (bytes + PAGE_BYTES - 1) / PAGE_BYTES * PAGE_BYTES;
}

static size_t item_words(const perma_runtime *rt, unsigned qi)
{
    return rt->procs[qi % rt->proc_count].item_size / 4;
}

static void release(perma_device_buffer *b)
{
    if (b->mem)
        clReleaseMemObject(b->mem);
    b->mem = NULL;
    b->bytes = 0;
}

/* A new buffer of `bytes` (at least 4) in *b, which must be empty. */
static perma_status create(perma_runtime *rt, perma_device_buffer *b, size_t bytes, const char *what)
{
    if (bytes < 4)
        bytes = 4;
    char name[64];
    snprintf(name, sizeof name, "the %s", what);
    perma_status st = perma_check_memory(rt, bytes, name);
    if (st != PERMA_OK)
        return st;
    cl_int err;
    b->mem = clCreateBuffer(rt->context, CL_MEM_READ_WRITE, bytes, NULL, &err);
    if (err != CL_SUCCESS) {
        b->mem = NULL;
        return perma_set_error(rt, PERMA_ERR_OPENCL, "clCreateBuffer (%s, %zu bytes) failed: %s (%d)", what, bytes,
                               perma_cl_error_name(err), (int)err);
    }
    b->bytes = bytes;
    return PERMA_OK;
}

/* *b holds at least `bytes`; a buffer that must grow loses its contents. */
static perma_status ensure(perma_runtime *rt, perma_device_buffer *b, size_t bytes, const char *what)
{
    if (b->mem && b->bytes >= bytes)
        return PERMA_OK;
    release(b);
    return create(rt, b, bytes, what);
}

static perma_status write_buffer(perma_runtime *rt, perma_device_buffer *b, const void *host, size_t bytes,
                                 const char *what)
{
    cl_int err = clEnqueueWriteBuffer(rt->queue, b->mem, CL_TRUE, 0, bytes, host, 0, NULL, NULL);
    if (err != CL_SUCCESS)
        return perma_set_error(rt, PERMA_ERR_OPENCL, "clEnqueueWriteBuffer (%s) failed: %s (%d)", what,
                               perma_cl_error_name(err), (int)err);
    return PERMA_OK;
}

static perma_status read_buffer(perma_runtime *rt, perma_device_buffer *b, void *host, size_t bytes, const char *what)
{
    cl_int err = clEnqueueReadBuffer(rt->queue, b->mem, CL_TRUE, 0, bytes, host, 0, NULL, NULL);
    if (err != CL_SUCCESS)
        return perma_set_error(rt, PERMA_ERR_OPENCL, "clEnqueueReadBuffer (%s) failed: %s (%d)", what,
                               perma_cl_error_name(err), (int)err);
    return PERMA_OK;
}

static perma_status zero(perma_runtime *rt, perma_device_buffer *b, size_t bytes, const char *what)
{
    cl_uint pattern = 0;
    cl_int err = clEnqueueFillBuffer(rt->queue, b->mem, &pattern, sizeof pattern, 0, bytes, 0, NULL, NULL);
    if (err != CL_SUCCESS)
        return perma_set_error(rt, PERMA_ERR_OPENCL, "clEnqueueFillBuffer (%s) failed: %s (%d)", what,
                               perma_cl_error_name(err), (int)err);
    return PERMA_OK;
}

static size_t ctl_bytes(const perma_runtime *rt)
{
    return 4 * (size_t)PERMA_CTL_WORDS_FOR(rt->build.queue_layout.count, rt->work_groups);
}

size_t perma_ctl_block_bytes(size_t queues)
{
    return sizeof(perma_ctl_block) + queues * sizeof(perma_queue_record);
}

/* The statistics buffer: one record per group. */
static size_t stats_bytes(const perma_runtime *rt)
{
    return 4 * (size_t)rt->work_groups * PERMA_STAT_GROUP_WORDS_FOR(rt->proc_count, rt->build.max_edges);
}

/* Words of one group's emit area (kernels/perma_abi.h). */
static size_t emit_area_words(const perma_runtime *rt)
{
    return PERMA_EMIT_AREA_WORDS_FOR((size_t)rt->build.stage_words);
}

static size_t emit_areas_bytes(const perma_runtime *rt)
{
    return 4 * (size_t)rt->work_groups * emit_area_words(rt);
}

static size_t trace_bytes(const perma_runtime *rt)
{
    return 4 * (size_t)rt->work_groups * PERMA_TRACE_GROUP_WORDS_FOR((size_t)rt->build.device_trace_events);
}

perma_status perma_state_open(perma_runtime *rt)
{
    /* Every buffer is made when a launch first needs it. */
    rt->state = calloc(1, sizeof *rt->state);
    if (!rt->state)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the device state");
    return PERMA_OK;
}

static void release_watch_page(perma_device_state *s)
{
    if (s->abort_mem)
        clReleaseMemObject(s->abort_mem);
    s->abort_mem = NULL;
    free(s->abort_flag);
    s->abort_flag = NULL;
    s->watch_bytes = 0;
}

/* The watch page, replaced by a bigger one when a build has more
 * procedures (no kernel runs between launches). */
static perma_status ensure_watch_page(perma_runtime *rt)
{
    perma_device_state *s = rt->state;
    size_t bytes = watch_bytes(rt);
    if (s->abort_mem && s->watch_bytes >= bytes)
        return PERMA_OK;
    release_watch_page(s);
    s->abort_flag = aligned_alloc(PAGE_BYTES, bytes);
    if (!s->abort_flag)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the watch page");
    memset(s->abort_flag, 0, bytes);
    cl_int err;
    s->abort_mem = clCreateBuffer(rt->context, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, bytes, s->abort_flag, &err);
    if (err != CL_SUCCESS) {
        release_watch_page(s);
        if (err != CL_SUCCESS)
            return perma_cl_error(rt, "clCreateBuffer (watch page)", err);
    }
    s->watch_bytes = bytes;
    return PERMA_OK;
}

void perma_state_close(perma_runtime *rt)
{
    perma_device_state *s = rt->state;
    if (!s)
        return;
    perma_device_buffer *buffers[] = { &s->ctl, &s->data, &s->seq, &s->stats, &s->trace, &s->input, &s->relayout,
                                       &s->emit_areas, &s->reductions };
    for (size_t i = 0; i < sizeof buffers / sizeof buffers[0]; ++i)
        release(buffers[i]);
    release_watch_page(s);
    free(s->queues);
    s->queues = NULL;
    s->queue_count = 0;
    free(s->overflow_headers);
    s->overflow_headers = NULL;
    free(s->stopped);
    free(s);
    rt->state = NULL;
}

/* The buffers every launch needs, at the sizes of this build. */
static perma_status ensure_launch_buffers(perma_runtime *rt)
{
    perma_device_state *s = rt->state;
    perma_status st = ensure(rt, &s->ctl, ctl_bytes(rt), "control block");
    if (st == PERMA_OK)
        st = ensure(rt, &s->stats, stats_bytes(rt), "statistics");
    if (st == PERMA_OK)
        st = ensure(rt, &s->trace, trace_bytes(rt), "trace");
    if (st == PERMA_OK)
        st = ensure(rt, &s->emit_areas, emit_areas_bytes(rt), "emit areas");
    if (st == PERMA_OK)
        st = ensure(rt, &s->reductions,
                    8 * (size_t)rt->work_groups * rt->group_size * (rt->build.reduce_words ? rt->build.reduce_words : 1),
                    "reductions");
    if (st == PERMA_OK)
        st = ensure_watch_page(rt);
    return st;
}

perma_status perma_state_empty(perma_runtime *rt)
{
    perma_device_state *s = rt->state;
    perma_status st = ensure_launch_buffers(rt);
    if (st == PERMA_OK)
        __atomic_store_n(s->abort_flag + PERMA_WATCH_ABORT, 0u, __ATOMIC_SEQ_CST);
    if (st == PERMA_OK)
        st = ensure(rt, &s->data, 4, "queue items");
    if (st == PERMA_OK)
        st = ensure(rt, &s->seq, 4, "queue completion marks");
    if (st == PERMA_OK)
        st = ensure(rt, &s->input, 4, "step input");
    if (st == PERMA_OK)
        st = zero(rt, &s->ctl, ctl_bytes(rt), "warm-up control block");
    return st;
}

/* Record the queues' capacities, `bytes` in all (and reset their
 * regrowths when `fresh`). */
static perma_status set_queues(perma_runtime *rt, const size_t *capacities, size_t bytes, bool fresh)
{
    perma_device_state *s = rt->state;
    unsigned count = rt->build.queue_layout.count;
    if (s->queue_count != count) {
        perma_queue_state *queues = calloc(count, sizeof *queues);
        if (!queues)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for %u queues", count);
        free(s->queues);
        s->queues = queues;
        s->queue_count = count;
    }
    for (unsigned qi = 0; qi < count; ++qi) {
        if (fresh) {
            s->queues[qi].regrowths = 0;
            s->queues[qi].initial = capacities[qi];
        } else if (capacities[qi] != s->queues[qi].capacity)
            s->queues[qi].regrowths++;
        s->queues[qi].capacity = capacities[qi];
    }
    if (bytes > rt->stats.peak_queue_bytes)
        rt->stats.peak_queue_bytes = bytes;
    return PERMA_OK;
}

/* The queues' capacities on the device now. */
static void capacities_now(const perma_device_state *s, size_t *out)
{
    for (unsigned qi = 0; qi < s->queue_count; ++qi)
        out[qi] = s->queues[qi].capacity;
}

perma_status perma_state_upload(perma_runtime *rt, const size_t *capacities, size_t bytes, const size_t *seed_first,
                                const size_t *seed_count)
{
    perma_device_state *s = rt->state;
    unsigned count = rt->build.queue_layout.count;
    size_t data_words = 0, seq_words = 0, outstanding = 0;
    for (unsigned qi = 0; qi < count; ++qi) {
        data_words += capacities[qi] * item_words(rt, qi);
        seq_words += 2 * capacities[qi];
    }
    perma_ctl_block *ctl = calloc(ctl_bytes(rt), 1);
    uint32_t *data = calloc(data_words ? data_words : 1, 4);
    uint32_t *seq = calloc(seq_words ? seq_words : 1, 4);
    perma_status st = PERMA_OK;
    if (!ctl || !data || !seq) {
        st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory laying out %zu bytes of queues", bytes);
        goto done;
    }
    size_t data_off = 0, seq_off = 0;
    for (unsigned qi = 0; qi < count; ++qi) {
        const perma_proc_info *p = &rt->procs[qi % rt->proc_count];
        size_t first = seed_first[qi], items = seed_count[qi], cap = capacities[qi];
        ctl->queues[qi] = (perma_queue_record){ .head = 0, .tail = (uint32_t)items, .room = (uint32_t)(cap - items),
                                                .cap = (uint32_t)cap, .data = (uint32_t)data_off,
                                                .seq = (uint32_t)seq_off, .peak = (uint32_t)items,
                                                .published = (uint32_t)items, .released = 0 };
        if (items) /* a procedure without seeds has no seed array */
            memcpy(data + data_off, p->seeds + first * p->item_size, items * p->item_size);
        /* Completion marks: each slot's own index, which reads as "not
         * done" for every position (kernels/perma_queue.cl). */
        for (size_t i = 0; i < cap; ++i)
            seq[seq_off + i] = seq[seq_off + cap + i] = (uint32_t)i;
        data_off += cap * item_words(rt, qi);
        seq_off += 2 * cap;
        outstanding += items;
    }
    ctl->header.outstanding = (uint32_t)outstanding;
    ctl->header.grow_starved = rt->grow_starved;
    s->overflow_known = false;
    if ((st = ensure_launch_buffers(rt)) != PERMA_OK ||
        (st = ensure(rt, &s->data, data_words * 4, "queue items")) != PERMA_OK ||
        (st = ensure(rt, &s->seq, seq_words * 4, "queue completion marks")) != PERMA_OK ||
        (st = write_buffer(rt, &s->ctl, ctl, ctl_bytes(rt), "control block")) != PERMA_OK ||
        (st = write_buffer(rt, &s->data, data, data_words * 4, "queue items")) != PERMA_OK ||
        (st = write_buffer(rt, &s->seq, seq, seq_words * 4, "queue completion marks")) != PERMA_OK)
        goto done;
    st = set_queues(rt, capacities, bytes, true);
done:
    free(ctl);
    free(data);
    free(seq);
    return st;
}

perma_status perma_state_begin_launch(perma_runtime *rt)
{
    perma_status st = ensure_launch_buffers(rt);
    if (st != PERMA_OK)
        return st;
    memset(rt->state->abort_flag, 0, rt->state->watch_bytes); /* no kernel is running */
    __atomic_thread_fence(__ATOMIC_SEQ_CST);
    return zero(rt, &rt->state->stats, stats_bytes(rt), "statistics");
}

void perma_state_raise_abort(perma_runtime *rt)
{
    __atomic_store_n(rt->state->abort_flag + PERMA_WATCH_ABORT, 1u, __ATOMIC_SEQ_CST);
}

const uint32_t *perma_state_watch_record(const perma_runtime *rt, unsigned group)
{
    return rt->state->abort_flag + PERMA_WATCH_RECORDS + (size_t)group * PERMA_WATCH_RECORD_WORDS_FOR(rt->proc_count);
}

bool perma_state_abort_raised(const perma_runtime *rt)
{
    return __atomic_load_n(rt->state->abort_flag + PERMA_WATCH_ABORT, __ATOMIC_SEQ_CST) != 0;
}

uint64_t perma_state_watch(const perma_runtime *rt, unsigned *running, unsigned procs)
{
    uint64_t done = 0;
    memset(running, 0, procs * sizeof *running);
    for (unsigned g = 0; g < rt->work_groups; ++g) {
        const uint32_t *record = perma_state_watch_record(rt, g);
        done += __atomic_load_n(record + PERMA_WATCH_DONE, __ATOMIC_RELAXED);
        uint32_t proc = __atomic_load_n(record + PERMA_WATCH_RUNNING, __ATOMIC_RELAXED);
        if (proc >= 1 && proc <= procs)
            running[proc - 1]++;
    }
    return done;
}

perma_status perma_state_read_control(perma_runtime *rt, perma_ctl_block *out, unsigned queues)
{
    return read_buffer(rt, &rt->state->ctl, out, perma_ctl_block_bytes(queues), "control block");
}

perma_status perma_state_read_header(perma_runtime *rt, perma_ctl_header *out)
{
    return read_buffer(rt, &rt->state->ctl, out, sizeof *out, "control block");
}

perma_status perma_state_write_queue_counters(perma_runtime *rt, unsigned q, const perma_queue_record *record)
{
    cl_int err = clEnqueueWriteBuffer(rt->queue, rt->state->ctl.mem, CL_FALSE, perma_ctl_block_bytes(q),
                                      sizeof *record, record, 0, NULL, NULL);
    if (err != CL_SUCCESS)
        return perma_cl_error(rt, "clEnqueueWriteBuffer (queue record)", err);
    return PERMA_OK;
}

/* The header of group g's overflow area (as last read). */
static const uint32_t *overflow_header(const perma_device_state *s, unsigned g)
{
    return s->overflow_headers + (size_t)g * PERMA_EMIT_AREA_HEADER;
}

/* The items each queue's groups left in their overflow areas (per_queue[qi]). */
static perma_status read_overflow(perma_runtime *rt, size_t *per_queue)
{
    perma_device_state *s = rt->state;
    if (!s->overflow_headers) {
        s->overflow_headers = calloc((size_t)rt->work_groups * PERMA_EMIT_AREA_HEADER, 4);
        if (!s->overflow_headers)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the overflow records");
    }
    /* The headers only: one row of PERMA_EMIT_AREA_HEADER words per group. */
    size_t origin[3] = { 0, 0, 0 }, region[3] = { 4 * PERMA_EMIT_AREA_HEADER, rt->work_groups, 1 };
    cl_int err = clEnqueueReadBufferRect(rt->queue, s->emit_areas.mem, CL_TRUE, origin, origin, region,
                                         4 * emit_area_words(rt), 0, 4 * PERMA_EMIT_AREA_HEADER, 0,
                                         s->overflow_headers, 0, NULL, NULL);
    if (err != CL_SUCCESS)
        return perma_cl_error(rt, "clEnqueueReadBufferRect (overflow records)", err);
    memset(per_queue, 0, s->queue_count * sizeof *per_queue);
    for (unsigned g = 0; g < rt->work_groups; ++g) {
        const uint32_t *h = overflow_header(s, g);
        if (h[PERMA_OVERFLOW_RECORDS] > PERMA_OVERFLOW_MAX_RECORDS)
            return perma_set_error(rt, PERMA_ERR_DEVICE, "work-group %u reports %u overflow records (at most %d)", g,
                                   h[PERMA_OVERFLOW_RECORDS], PERMA_OVERFLOW_MAX_RECORDS);
        for (uint32_t r = 0; r < h[PERMA_OVERFLOW_RECORDS]; ++r) {
            const uint32_t *rec = h + PERMA_OVERFLOW_RECORD(r);
            if (rec[PERMA_OVERFLOW_QUEUE] >= s->queue_count ||
                rec[PERMA_OVERFLOW_AT] + (size_t)rec[PERMA_OVERFLOW_COUNT] * item_words(rt, rec[PERMA_OVERFLOW_QUEUE]) >
                    rt->build.stage_words)
                return perma_set_error(rt, PERMA_ERR_DEVICE, "work-group %u reports an overflow record out of range "
                                       "(queue %u, %u items at word %u)", g, rec[PERMA_OVERFLOW_QUEUE],
                                       rec[PERMA_OVERFLOW_COUNT], rec[PERMA_OVERFLOW_AT]);
            per_queue[rec[PERMA_OVERFLOW_QUEUE]] += rec[PERMA_OVERFLOW_COUNT];
        }
    }
    s->overflow_known = true;
    return PERMA_OK;
}

perma_status perma_state_read_queues(perma_runtime *rt, bool with_overflow, size_t *capacities, size_t *queued,
                                     size_t *overflow)
{
    perma_device_state *s = rt->state;
    unsigned queues = s->queue_count;
    perma_ctl_block *ctl = realloc(s->stopped, perma_ctl_block_bytes(queues));
    if (!ctl)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory growing queues");
    s->stopped = ctl;
    perma_status st = perma_state_read_control(rt, ctl, queues);
    memset(overflow, 0, queues * sizeof *overflow);
    if (st == PERMA_OK && with_overflow)
        st = read_overflow(rt, overflow);
    capacities_now(s, capacities);
    for (unsigned qi = 0; st == PERMA_OK && qi < queues; ++qi)
        queued[qi] = (uint32_t)(ctl->queues[qi].tail - ctl->queues[qi].head);
    return st;
}

/* Items queue qi gets from the overflow areas (0 unless read). */
static size_t overflowed(const perma_device_state *s, unsigned qi, unsigned groups)
{
    size_t items = 0;
    for (unsigned g = 0; s->overflow_known && g < groups; ++g) {
        const uint32_t *h = overflow_header(s, g);
        for (uint32_t r = 0; r < h[PERMA_OVERFLOW_RECORDS]; ++r)
            if (h[PERMA_OVERFLOW_RECORD(r) + PERMA_OVERFLOW_QUEUE] == qi)
                items += h[PERMA_OVERFLOW_RECORD(r) + PERMA_OVERFLOW_COUNT];
    }
    return items;
}

/* A launch that stopped with no batch running left every outstanding item
 * in a queue or an overflow area, each queue at the capacity it was given. */
static perma_status check_stopped(perma_runtime *rt, const perma_ctl_block *ctl)
{
    const perma_device_state *s = rt->state;
    size_t queued = 0;
    for (unsigned qi = 0; qi < s->queue_count; ++qi)
        queued += (uint32_t)(ctl->queues[qi].tail - ctl->queues[qi].head) + overflowed(s, qi, rt->work_groups);
    /* An item left in a group's local memory would be lost by the next launch. */
    if (queued != (size_t)(int32_t)ctl->header.outstanding)
        return perma_set_error(rt, PERMA_ERR_DEVICE, "items were lost: the kernel stopped with %d items outstanding "
                               "but its queues and overflow areas hold %zu", (int)(int32_t)ctl->header.outstanding,
                               queued);
    for (unsigned qi = 0; qi < s->queue_count; ++qi) {
        const perma_queue_record *rec = &ctl->queues[qi];
        const char *name = rt->procs[qi % rt->proc_count].name;
        if (rec->cap != s->queues[qi].capacity || (uint32_t)(rec->tail - rec->head) > rec->cap)
            return perma_set_error(rt, PERMA_ERR_DEVICE, "queue '%s' is inconsistent after the launch "
                                   "(head %u, tail %u, capacity %u)", name, rec->head, rec->tail, rec->cap);
        /* No batch runs: every reserved range is published, every claimed
         * one released, or an item would be moved unwritten or a slot lost. */
        if (rec->published != rec->tail)
            return perma_set_error(rt, PERMA_ERR_DEVICE, "queue '%s' (queue set %u): positions %u to %u were "
                                   "never published", name, qi / rt->proc_count, rec->published, rec->tail - 1);
        if (rec->released != rec->head)
            return perma_set_error(rt, PERMA_ERR_DEVICE, "queue '%s' (queue set %u): positions %u to %u were "
                                   "never released", name, qi / rt->proc_count, rec->released, rec->head - 1);
    }
    return PERMA_OK;
}

/* Segments of overflowed items the relayout appends (at most one per
 * overflow record of each group). */
static size_t max_segments(const perma_runtime *rt)
{
    return (size_t)rt->work_groups * PERMA_OVERFLOW_MAX_RECORDS;
}

/* Append queue qi's overflow segments to `segments` (at *used words) and
 * describe them in *rec. */
static void plan_overflow(const perma_runtime *rt, unsigned qi, perma_relayout_record *rec, uint32_t *segments,
                          size_t *used, size_t segments_at)
{
    const perma_device_state *s = rt->state;
    size_t group_words = emit_area_words(rt);
    rec->overflow_first = (uint32_t)(segments_at + *used);
    for (unsigned g = 0; s->overflow_known && g < rt->work_groups; ++g) {
        const uint32_t *h = overflow_header(s, g);
        for (uint32_t r = 0; r < h[PERMA_OVERFLOW_RECORDS]; ++r) {
            const uint32_t *o = h + PERMA_OVERFLOW_RECORD(r);
            if (o[PERMA_OVERFLOW_QUEUE] != qi)
                continue;
            segments[(*used)++] =
                (uint32_t)(g * group_words + PERMA_EMIT_AREA_OVERFLOW_FOR((size_t)rt->build.stage_words) + o[PERMA_OVERFLOW_AT]);
            segments[(*used)++] = o[PERMA_OVERFLOW_COUNT];
            rec->overflow += o[PERMA_OVERFLOW_COUNT];
            rec->overflow_segments++;
        }
    }
}

/* The new layout: each queue's items from position 0 in fresh buffers
 * (next, the control block to write), the items of the overflow areas
 * after them, and where they all come from (map, then the segments). */
static void plan_relayout(const perma_runtime *rt, const perma_ctl_block *ctl, const size_t *capacities,
                          perma_ctl_block *next, perma_relayout_record *map, size_t *map_bytes, size_t *data_words,
                          size_t *slots)
{
    *data_words = *slots = 0;
    next->header.outstanding = ctl->header.outstanding;
    next->header.grow_starved = rt->grow_starved;
    uint32_t *segments = (uint32_t *)(map + rt->state->queue_count);
    size_t used = 0, segments_at = rt->state->queue_count * (size_t)PERMA_RELAYOUT_RECORD_WORDS;
    for (unsigned qi = 0; qi < rt->state->queue_count; ++qi) {
        const perma_queue_record *old = &ctl->queues[qi];
        uint32_t count = old->tail - old->head, cap = (uint32_t)capacities[qi];
        map[qi] = (perma_relayout_record){ .head = old->head, .count = count, .old_cap = old->cap,
                                           .old_data = old->data, .new_cap = cap,
                                           .new_data = (uint32_t)*data_words, .new_seq = (uint32_t)(2 * *slots),
                                           .words = (uint32_t)item_words(rt, qi) };
        plan_overflow(rt, qi, &map[qi], segments, &used, segments_at);
        count += map[qi].overflow; /* fits: the host grew the queue for it (run.c) */
        next->queues[qi] = (perma_queue_record){ .head = 0, .tail = count, .room = cap - count, .cap = cap,
                                                 .data = (uint32_t)*data_words, .seq = (uint32_t)(2 * *slots),
                                                 .peak = count, .published = count, .released = 0 };
        *data_words += capacities[qi] * item_words(rt, qi);
        *slots += capacities[qi];
    }
    *map_bytes = 4 * (segments_at + used);
}

static perma_status run_relayout(perma_runtime *rt, unsigned queues, size_t slots, perma_device_buffer *data,
                                 perma_device_buffer *seq)
{
    perma_device_state *s = rt->state;
    cl_uint queue_count = queues, slot_count = (cl_uint)slots;
    const struct {
        cl_uint index;
        size_t size;
        const void *value;
    } args[] = {
        { PERMA_RELAYOUT_ARG_MAP, sizeof(cl_mem), &s->relayout.mem },
        { PERMA_RELAYOUT_ARG_QUEUES, sizeof queue_count, &queue_count },
        { PERMA_RELAYOUT_ARG_SLOTS, sizeof slot_count, &slot_count },
        { PERMA_RELAYOUT_ARG_OLD_DATA, sizeof(cl_mem), &s->data.mem },
        { PERMA_RELAYOUT_ARG_NEW_DATA, sizeof(cl_mem), &data->mem },
        { PERMA_RELAYOUT_ARG_NEW_SEQ, sizeof(cl_mem), &seq->mem },
        { PERMA_RELAYOUT_ARG_SEGMENTS, sizeof(cl_mem), &s->relayout.mem },
        { PERMA_RELAYOUT_ARG_EMIT_AREAS, sizeof(cl_mem), &s->emit_areas.mem },
    };
    _Static_assert(sizeof args / sizeof args[0] == PERMA_RELAYOUT_ARG_TOTAL, "every argument of perma_relayout_kernel");
    cl_int err = CL_SUCCESS;
    for (size_t i = 0; i < sizeof args / sizeof args[0] && err == CL_SUCCESS; ++i)
        err = clSetKernelArg(rt->build.relayout_kernel, args[i].index, args[i].size, args[i].value);
    if (err != CL_SUCCESS)
        return perma_cl_error(rt, "clSetKernelArg (relayout)", err);
    size_t local = 64, global = (slots + local - 1) / local * local;
    err = clEnqueueNDRangeKernel(rt->queue, rt->build.relayout_kernel, 1, NULL, &global, &local, 0, NULL, NULL);
    if (err != CL_SUCCESS)
        return perma_cl_error(rt, "clEnqueueNDRangeKernel (relayout)", err);
    return PERMA_OK;
}

perma_status perma_state_grow(perma_runtime *rt, const size_t *capacities, size_t bytes)
{
    perma_device_state *s = rt->state;
    unsigned queues = s->queue_count;
    const perma_ctl_block *ctl = s->stopped;
    perma_status st = check_stopped(rt, ctl);
    if (st != PERMA_OK)
        return st;
    perma_ctl_block *next = calloc(ctl_bytes(rt), 1);
    size_t map_bytes = queues * sizeof(perma_relayout_record) + max_segments(rt) * PERMA_RELAYOUT_SEGMENT_WORDS * 4;
    perma_relayout_record *map = calloc(map_bytes, 1);
    perma_device_buffer data = { NULL, 0 }, seq = { NULL, 0 };
    if (!next || !map) {
        st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory growing queues");
        goto done;
    }
    size_t data_words, slots;
    plan_relayout(rt, ctl, capacities, next, map, &map_bytes, &data_words, &slots);
    if ((st = create(rt, &data, data_words * 4, "queue items")) != PERMA_OK ||
        (st = create(rt, &seq, 2 * slots * 4, "queue completion marks")) != PERMA_OK ||
        (st = ensure(rt, &s->relayout, map_bytes, "queue relayout")) != PERMA_OK ||
        (st = write_buffer(rt, &s->relayout, map, map_bytes, "queue relayout")) != PERMA_OK ||
        (st = write_buffer(rt, &s->ctl, next, ctl_bytes(rt), "control block")) != PERMA_OK ||
        (st = run_relayout(rt, queues, slots, &data, &seq)) != PERMA_OK)
        goto done;
    /* The old items are no longer needed: the new buffers take their place. */
    release(&s->data);
    release(&s->seq);
    s->data = data;
    s->seq = seq;
    data.mem = seq.mem = NULL;
    st = set_queues(rt, capacities, bytes, false);
done:
    s->overflow_known = false; /* appended (or the run failed) */
    release(&data);
    release(&seq);
    free(next);
    free(map);
    return st;
}

perma_status perma_state_read_stats(perma_runtime *rt, uint32_t *words, size_t count)
{
    return read_buffer(rt, &rt->state->stats, words, count * 4, "statistics");
}

perma_status perma_state_read_trace(perma_runtime *rt, uint32_t *words, size_t count)
{
    return read_buffer(rt, &rt->state->trace, words, count * 4, "trace");
}

perma_status perma_state_ensure_input(perma_runtime *rt, size_t words)
{
    return ensure(rt, &rt->state->input, words * 4, "step input");
}

perma_status perma_state_bind(perma_runtime *rt, cl_kernel kernel, cl_uint first_user_arg)
{
    perma_device_state *s = rt->state;
    perma_status st = ensure_launch_buffers(rt);
    if (st != PERMA_OK)
        return st;
    cl_mem common[PERMA_MEGAKERNEL_USER_ARGS];
    common[PERMA_ARG_CTL] = s->ctl.mem;
    common[PERMA_ARG_QUEUE_DATA] = s->data.mem;
    common[PERMA_ARG_QUEUE_SEQ] = s->seq.mem;
    common[PERMA_ARG_GROUP_STATS] = s->stats.mem;
    common[PERMA_ARG_ABORT_FLAG] = s->abort_mem;
    common[PERMA_ARG_TRACE] = s->trace.mem;
    common[PERMA_ARG_EMIT_AREAS] = s->emit_areas.mem;
    common[PERMA_ARG_REDUCTIONS] = s->reductions.mem;
    cl_int err = CL_SUCCESS;
    for (cl_uint i = 0; i < PERMA_MEGAKERNEL_USER_ARGS && err == CL_SUCCESS; ++i)
        err = clSetKernelArg(kernel, i, sizeof(cl_mem), &common[i]);
    if (err != CL_SUCCESS)
        return perma_cl_error(rt, "clSetKernelArg", err);
    for (unsigned b = 0; b < rt->buffer_count; ++b) {
        if (!rt->buffers[b].mem)
            return perma_set_error(rt, PERMA_ERR_STATE, "buffer '%s' has no memory bound", rt->buffers[b].name);
        err = clSetKernelArg(kernel, first_user_arg + b, sizeof(cl_mem), &rt->buffers[b].mem);
        if (err != CL_SUCCESS)
            return perma_set_error(rt, PERMA_ERR_OPENCL, "clSetKernelArg (buffer '%s') failed: %s (%d)",
                                   rt->buffers[b].name, perma_cl_error_name(err), (int)err);
    }
    return PERMA_OK;
}

const perma_queue_state *perma_state_queues(const perma_runtime *rt, unsigned *count)
{
    *count = rt->state->queue_count;
    return rt->state->queues;
}

perma_status perma_state_write_reductions(perma_runtime *rt, const uint64_t *slots, size_t words)
{
    cl_int err = clEnqueueWriteBuffer(rt->queue, rt->state->reductions.mem, CL_TRUE, 0, words * sizeof *slots, slots,
                                      0, NULL, NULL);
    return err == CL_SUCCESS ? PERMA_OK : perma_cl_error(rt, "clEnqueueWriteBuffer (reductions)", err);
}

perma_status perma_state_read_reductions(perma_runtime *rt, uint64_t *slots, size_t words)
{
    cl_int err = clEnqueueReadBuffer(rt->queue, rt->state->reductions.mem, CL_TRUE, 0, words * sizeof *slots, slots, 0,
                                     NULL, NULL);
    return err == CL_SUCCESS ? PERMA_OK : perma_cl_error(rt, "clEnqueueReadBuffer (reductions)", err);
}

perma_status perma_state_bind_take(perma_runtime *rt)
{
    const perma_device_state *s = rt->state;
    const struct {
        cl_uint index;
        const cl_mem *mem;
    } args[] = {
        { PERMA_TAKE_ARG_CTL, &s->ctl.mem },
        { PERMA_TAKE_ARG_QUEUE_DATA, &s->data.mem },
        { PERMA_TAKE_ARG_QUEUE_SEQ, &s->seq.mem },
        { PERMA_TAKE_ARG_INPUT, &s->input.mem },
    };
    cl_int err = CL_SUCCESS;
    for (size_t i = 0; i < sizeof args / sizeof args[0] && err == CL_SUCCESS; ++i)
        err = clSetKernelArg(rt->build.take_kernel, args[i].index, sizeof(cl_mem), args[i].mem);
    return err == CL_SUCCESS ? PERMA_OK : perma_cl_error(rt, "clSetKernelArg (take)", err);
}

perma_status perma_state_bind_step(perma_runtime *rt)
{
    perma_status st = perma_state_bind(rt, rt->build.step_kernel, PERMA_STEP_USER_ARGS);
    if (st != PERMA_OK)
        return st;
    cl_int err = clSetKernelArg(rt->build.step_kernel, PERMA_STEP_ARG_INPUT, sizeof(cl_mem), &rt->state->input.mem);
    return err == CL_SUCCESS ? PERMA_OK : perma_cl_error(rt, "clSetKernelArg (step)", err);
}

uint32_t perma_state_watch_clock(const perma_runtime *rt)
{
    return __atomic_load_n(rt->state->abort_flag + PERMA_WATCH_CLOCK, __ATOMIC_RELAXED);
}
