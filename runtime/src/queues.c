/* Host side of the queues: laying them out in device memory, reading them
 * back after a launch that ran out of room, and growing them. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

#define DEFAULT_CAPACITY 1024

static size_t next_pow2(size_t v)
{
    size_t p = 1;
    while (p < v)
        p <<= 1;
    return p;
}

static size_t item_words(const perma_proc_info *p)
{
    return p->item_size / 4;
}

static size_t memory_limit(const perma_runtime *rt)
{
    if (rt->config.queue_memory_limit)
        return rt->config.queue_memory_limit;
    return rt->max_alloc ? (size_t)rt->max_alloc : ((size_t)1 << 30);
}

static size_t queue_bytes(const perma_runtime *rt, const size_t *capacities)
{
    size_t total = 0;
    for (unsigned q = 0; q < rt->proc_count; ++q)
        total += capacities[q] * (rt->procs[q].item_size + 4);
    return total;
}

/* Ensure image q can hold `capacity` items. */
static perma_status image_reserve(perma_runtime *rt, unsigned q, size_t capacity)
{
    perma_queue_image *img = &rt->images[q];
    size_t words = capacity * item_words(&rt->procs[q]);
    uint32_t *data = realloc(img->words, words ? words * 4 : 4);
    if (!data)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for queue '%s' (%zu items)",
                               rt->procs[q].name, capacity);
    img->words = data;
    return PERMA_OK;
}

void perma_queues_release(perma_runtime *rt)
{
    cl_mem *mems[] = { &rt->ctl_mem, &rt->data_mem, &rt->seq_mem, &rt->stats_mem, &rt->abort_mem };
    for (size_t i = 0; i < sizeof mems / sizeof mems[0]; ++i) {
        if (*mems[i])
            clReleaseMemObject(*mems[i]);
        *mems[i] = NULL;
    }
    rt->data_mem_words = rt->seq_mem_words = 0;
    for (unsigned q = 0; q < PERMA_MAX_PROCEDURES; ++q) {
        free(rt->images[q].words);
        memset(&rt->images[q], 0, sizeof rt->images[q]);
    }
}

/* Turn the seeds into queue images with their initial capacities. */
perma_status perma_queues_prepare(perma_runtime *rt)
{
    size_t base = rt->config.queue_capacity ? rt->config.queue_capacity : DEFAULT_CAPACITY;
    size_t capacities[PERMA_MAX_PROCEDURES];
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        size_t cap = base;
        if (rt->procs[q].seed_count > cap)
            cap = rt->procs[q].seed_count;
        /* One item of any producer must fit, or nothing could ever run. */
        for (unsigned i = 0; i < rt->proc_count; ++i)
            for (unsigned e = 0; e < rt->procs[i].emit_count; ++e)
                if ((unsigned)rt->procs[i].emit_target[e] == q && rt->procs[i].emit_max[e] > cap)
                    cap = rt->procs[i].emit_max[e];
        capacities[q] = next_pow2(cap);
    }
    size_t bytes = queue_bytes(rt, capacities);
    if (bytes > memory_limit(rt))
        return perma_set_error(rt, PERMA_ERR_CAPACITY,
                               "the initial queues need %zu bytes, more than the queue memory limit of %zu bytes",
                               bytes, memory_limit(rt));
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        perma_proc_info *p = &rt->procs[q];
        perma_status st = image_reserve(rt, q, capacities[q]);
        if (st != PERMA_OK)
            return st;
        perma_queue_image *img = &rt->images[q];
        img->capacity = capacities[q];
        img->count = p->seed_count;
        img->regrowths = 0;
        if (p->seed_count)
            memcpy(img->words, p->seeds, p->seed_count * p->item_size);
        p->stats.seeded = p->seed_count;
        p->stats.peak_queue_items = p->seed_count;
        p->seed_count = 0;
    }
    return PERMA_OK;
}

static perma_status ensure_buffer(perma_runtime *rt, cl_mem *mem, size_t *have_words, size_t words,
                                  const char *what)
{
    if (*mem && *have_words >= words)
        return PERMA_OK;
    if (*mem)
        clReleaseMemObject(*mem);
    cl_int err;
    *mem = clCreateBuffer(rt->context, CL_MEM_READ_WRITE, words * 4, NULL, &err);
    if (err != CL_SUCCESS) {
        *mem = NULL;
        *have_words = 0;
        return perma_set_error(rt, PERMA_ERR_OPENCL, "clCreateBuffer (%s, %zu bytes) failed: %s (%d)", what,
                               words * 4, perma_cl_error_name(err), (int)err);
    }
    *have_words = words;
    return PERMA_OK;
}

/* Write the queue images to the device as a fresh launch state. */
perma_status perma_queues_upload(perma_runtime *rt)
{
    unsigned n = rt->proc_count;
    size_t data_words = 0, seq_words = 0, outstanding = 0;
    size_t capacities[PERMA_MAX_PROCEDURES];
    for (unsigned q = 0; q < n; ++q) {
        capacities[q] = rt->images[q].capacity;
        data_words += rt->images[q].capacity * item_words(&rt->procs[q]);
        seq_words += rt->images[q].capacity;
        outstanding += rt->images[q].count;
    }
    size_t bytes = queue_bytes(rt, capacities);
    if (bytes > rt->stats.peak_queue_bytes)
        rt->stats.peak_queue_bytes = bytes;

    size_t ctl_words = perma_ctl_words(n, rt->work_groups);
    size_t stats_words = (size_t)rt->work_groups * n * PERMA_STAT_PROC_WORDS(rt->max_edges);
    uint32_t *ctl = calloc(ctl_words, 4);
    uint32_t *data = calloc(data_words ? data_words : 1, 4);
    uint32_t *seq = calloc(seq_words ? seq_words : 1, 4);
    perma_status st = PERMA_OK;
    if (!ctl || !data || !seq) {
        st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory laying out %zu bytes of queues", bytes);
        goto done;
    }
    ctl[PERMA_CTL_OUTSTANDING] = (uint32_t)outstanding;
    size_t data_off = 0, seq_off = 0;
    for (unsigned q = 0; q < n; ++q) {
        const perma_queue_image *img = &rt->images[q];
        size_t words = item_words(&rt->procs[q]);
        uint32_t *rec = ctl + PERMA_CTL_HEADER_WORDS + q * PERMA_QUEUE_WORDS;
        rec[PERMA_Q_HEAD] = 0;
        rec[PERMA_Q_TAIL] = (uint32_t)img->count;
        rec[PERMA_Q_ROOM] = (uint32_t)(img->capacity - img->count);
        rec[PERMA_Q_CAP] = (uint32_t)img->capacity;
        rec[PERMA_Q_DATA] = (uint32_t)data_off;
        rec[PERMA_Q_SEQ] = (uint32_t)seq_off;
        rec[PERMA_Q_PEAK] = (uint32_t)img->count;
        memcpy(data + data_off, img->words, img->count * words * 4);
        for (size_t i = 0; i < img->capacity; ++i)
            seq[seq_off + i] = (uint32_t)(i < img->count ? i + 1 : i); /* published : free */
        data_off += img->capacity * words;
        seq_off += img->capacity;
    }

    size_t ctl_have = 0, stats_have = 0;
    if (rt->ctl_mem)
        clReleaseMemObject(rt->ctl_mem), rt->ctl_mem = NULL;
    if (rt->stats_mem)
        clReleaseMemObject(rt->stats_mem), rt->stats_mem = NULL;
    if ((st = ensure_buffer(rt, &rt->ctl_mem, &ctl_have, ctl_words, "control block")) != PERMA_OK ||
        (st = ensure_buffer(rt, &rt->stats_mem, &stats_have, stats_words ? stats_words : 1, "statistics")) != PERMA_OK ||
        (st = ensure_buffer(rt, &rt->data_mem, &rt->data_mem_words, data_words ? data_words : 1, "queue items")) != PERMA_OK ||
        (st = ensure_buffer(rt, &rt->seq_mem, &rt->seq_mem_words, seq_words ? seq_words : 1, "queue sequence words")) != PERMA_OK)
        goto done;
    cl_int err = clEnqueueWriteBuffer(rt->queue, rt->ctl_mem, CL_TRUE, 0, ctl_words * 4, ctl, 0, NULL, NULL);
    if (err == CL_SUCCESS && data_words)
        err = clEnqueueWriteBuffer(rt->queue, rt->data_mem, CL_TRUE, 0, data_words * 4, data, 0, NULL, NULL);
    if (err == CL_SUCCESS && seq_words)
        err = clEnqueueWriteBuffer(rt->queue, rt->seq_mem, CL_TRUE, 0, seq_words * 4, seq, 0, NULL, NULL);
    if (err != CL_SUCCESS)
        st = perma_set_error(rt, PERMA_ERR_OPENCL, "clEnqueueWriteBuffer (queues) failed: %s (%d)",
                             perma_cl_error_name(err), (int)err);
done:
    free(ctl);
    free(data);
    free(seq);
    return st;
}

/* Read the queues back after a launch stopped with no batch running. */
perma_status perma_queues_download(perma_runtime *rt)
{
    unsigned n = rt->proc_count;
    size_t ctl_words = perma_ctl_words(n, rt->work_groups);
    size_t data_words = 0, seq_words = 0;
    for (unsigned q = 0; q < n; ++q) {
        data_words += rt->images[q].capacity * item_words(&rt->procs[q]);
        seq_words += rt->images[q].capacity;
    }
    uint32_t *ctl = malloc(ctl_words * 4);
    uint32_t *data = malloc(data_words * 4 + 4);
    uint32_t *seq = malloc(seq_words * 4 + 4);
    perma_status st = PERMA_OK;
    if (!ctl || !data || !seq) {
        st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory reading the queues back");
        goto done;
    }
    cl_int err = clEnqueueReadBuffer(rt->queue, rt->ctl_mem, CL_TRUE, 0, ctl_words * 4, ctl, 0, NULL, NULL);
    if (err == CL_SUCCESS && data_words)
        err = clEnqueueReadBuffer(rt->queue, rt->data_mem, CL_TRUE, 0, data_words * 4, data, 0, NULL, NULL);
    if (err == CL_SUCCESS && seq_words)
        err = clEnqueueReadBuffer(rt->queue, rt->seq_mem, CL_TRUE, 0, seq_words * 4, seq, 0, NULL, NULL);
    if (err != CL_SUCCESS) {
        st = perma_set_error(rt, PERMA_ERR_OPENCL, "clEnqueueReadBuffer (queues) failed: %s (%d)",
                             perma_cl_error_name(err), (int)err);
        goto done;
    }
    for (unsigned q = 0; q < n; ++q) {
        perma_queue_image *img = &rt->images[q];
        const uint32_t *rec = ctl + PERMA_CTL_HEADER_WORDS + q * PERMA_QUEUE_WORDS;
        uint32_t head = rec[PERMA_Q_HEAD], tail = rec[PERMA_Q_TAIL];
        uint32_t cap = rec[PERMA_Q_CAP];
        size_t words = item_words(&rt->procs[q]);
        size_t count = (uint32_t)(tail - head);
        if (cap != img->capacity || count > cap) {
            st = perma_set_error(rt, PERMA_ERR_DEVICE, "queue '%s' is inconsistent after the launch "
                                 "(head %u, tail %u, capacity %u)", rt->procs[q].name, head, tail, cap);
            goto done;
        }
        for (size_t i = 0; i < count; ++i) {
            uint32_t pos = head + (uint32_t)i;
            uint32_t slot = pos & (cap - 1);
            if (seq[rec[PERMA_Q_SEQ] + slot] != pos + 1) {
                st = perma_set_error(rt, PERMA_ERR_DEVICE,
                                     "queue '%s': item at position %u was never published", rt->procs[q].name, pos);
                goto done;
            }
            memcpy(img->words + i * words, data + rec[PERMA_Q_DATA] + (size_t)slot * words, words * 4);
        }
        img->count = count;
    }
done:
    free(ctl);
    free(data);
    free(seq);
    return st;
}

/* Grow the queues that stopped the launch: every target without room for
 * one item's worst-case emits from a non-empty source. */
perma_status perma_queues_grow(perma_runtime *rt)
{
    unsigned n = rt->proc_count;
    size_t capacities[PERMA_MAX_PROCEDURES];
    bool grow[PERMA_MAX_PROCEDURES] = { false };
    bool any = false;
    for (unsigned q = 0; q < n; ++q)
        capacities[q] = rt->images[q].capacity;
    for (int relaxed = 0; relaxed < 2 && !any; ++relaxed) {
        for (unsigned q = 0; q < n; ++q) {
            if (rt->images[q].count == 0)
                continue;
            const perma_proc_info *p = &rt->procs[q];
            for (unsigned e = 0; e < p->emit_count; ++e) {
                unsigned t = (unsigned)p->emit_target[e];
                size_t room = rt->images[t].capacity - rt->images[t].count;
                /* relaxed: the kernel saw no room where we see some (a race
                 * between groups); grow the targets of all waiting work. */
                if (relaxed || room < p->emit_max[e]) {
                    grow[t] = true;
                    any = true;
                }
            }
        }
    }
    if (!any)
        return perma_set_error(rt, PERMA_ERR_DEVICE,
                               "the kernel reported no room, but no queued item emits anything");
    for (unsigned t = 0; t < n; ++t) {
        if (!grow[t])
            continue;
        /* capacity >= any emit_max (perma_queues_prepare), so doubling
         * leaves room for at least one item's emits. */
        capacities[t] = rt->images[t].capacity * 2;
    }
    size_t bytes = queue_bytes(rt, capacities);
    if (bytes > memory_limit(rt) || bytes / 2 > ((size_t)1 << 40)) {
        for (unsigned t = 0; t < n; ++t) {
            if (!grow[t])
                continue;
            return perma_set_error(rt, PERMA_ERR_CAPACITY,
                                   "queue '%s' is full (%zu items of %zu bytes) and cannot grow to %zu items: "
                                   "all queues would need %zu bytes, more than the queue memory limit of %zu bytes",
                                   rt->procs[t].name, rt->images[t].capacity, rt->procs[t].item_size,
                                   capacities[t], bytes, memory_limit(rt));
        }
    }
    for (unsigned t = 0; t < n; ++t) {
        if (!grow[t])
            continue;
        if (capacities[t] > ((size_t)1 << 31))
            return perma_set_error(rt, PERMA_ERR_CAPACITY,
                                   "queue '%s' would need more than 2^31 items", rt->procs[t].name);
        perma_status st = image_reserve(rt, t, capacities[t]);
        if (st != PERMA_OK)
            return st;
        rt->images[t].capacity = capacities[t];
        rt->images[t].regrowths++;
    }
    rt->stats.regrowths++;
    return PERMA_OK;
}
