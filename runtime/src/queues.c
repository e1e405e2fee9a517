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

/* Words of queue_data one queue takes per slot: its item and two
 * completion marks (kernels/perma_queue.cl). */
static size_t slot_words(const perma_proc_info *p)
{
    return item_words(p) + 2;
}

static size_t memory_limit(const perma_runtime *rt)
{
    if (rt->config.queue_memory_limit)
        return rt->config.queue_memory_limit;
    return rt->max_alloc ? (size_t)rt->max_alloc : ((size_t)1 << 30);
}

/* The procedure whose items queue `qi` holds. */
static const perma_proc_info *proc_of(const perma_runtime *rt, unsigned qi)
{
    return &rt->procs[qi % rt->proc_count];
}

static size_t queue_bytes(const perma_runtime *rt, const size_t *capacities)
{
    size_t total = 0;
    for (unsigned qi = 0; qi < rt->image_count; ++qi)
        total += capacities[qi] * slot_words(proc_of(rt, qi)) * 4;
    return total;
}

/* Ensure image qi can hold `capacity` items. */
static perma_status image_reserve(perma_runtime *rt, unsigned qi, size_t capacity)
{
    perma_queue_image *img = &rt->images[qi];
    size_t words = capacity * item_words(proc_of(rt, qi));
    uint32_t *data = realloc(img->words, words ? words * 4 : 4);
    if (!data)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for queue '%s' (%zu items)",
                               proc_of(rt, qi)->name, capacity);
    img->words = data;
    return PERMA_OK;
}

void perma_queues_release(perma_runtime *rt)
{
    cl_mem *mems[] = { &rt->ctl_mem, &rt->data_mem, &rt->stats_mem, &rt->abort_mem, &rt->input_mem,
                       &rt->trace_mem };
    for (size_t i = 0; i < sizeof mems / sizeof mems[0]; ++i) {
        if (*mems[i])
            clReleaseMemObject(*mems[i]);
        *mems[i] = NULL;
    }
    rt->data_mem_words = rt->input_mem_words = rt->trace_mem_words = 0;
    for (unsigned qi = 0; qi < rt->image_count; ++qi)
        free(rt->images[qi].words);
    free(rt->images);
    rt->images = NULL;
    rt->image_count = 0;
}

/* Turn the seeds into queue images with their initial capacities.  With
 * one queue set per group the seeds are dealt out in contiguous shares. */
perma_status perma_queues_prepare(perma_runtime *rt)
{
    unsigned n = rt->proc_count, sets = rt->queue_sets;
    if (rt->image_count != sets * n) {
        perma_queues_release(rt);
        rt->images = calloc((size_t)sets * n, sizeof *rt->images);
        if (!rt->images)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for %u queues", sets * n);
        rt->image_count = sets * n;
    }
    size_t base = rt->config.queue_capacity ? rt->config.queue_capacity : DEFAULT_CAPACITY;
    size_t *capacities = calloc(rt->image_count, sizeof *capacities);
    if (!capacities)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for %u queues", rt->image_count);
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        unsigned q = qi % n;
        size_t share = (rt->procs[q].seed_count + sets - 1) / sets;
        size_t cap = base;
        if (share > cap)
            cap = share;
        /* One item of any producer must fit, or nothing could ever run. */
        for (unsigned i = 0; i < n; ++i)
            for (unsigned e = 0; e < rt->procs[i].emit_count; ++e)
                if ((unsigned)rt->procs[i].emit_target[e] == q && rt->procs[i].emit_max[e] > cap)
                    cap = rt->procs[i].emit_max[e];
        capacities[qi] = next_pow2(cap);
    }
    size_t bytes = queue_bytes(rt, capacities);
    perma_status st = PERMA_OK;
    if (bytes > memory_limit(rt))
        st = perma_set_error(rt, PERMA_ERR_CAPACITY,
                             "the initial queues need %zu bytes, more than the queue memory limit of %zu bytes",
                             bytes, memory_limit(rt));
    for (unsigned qi = 0; st == PERMA_OK && qi < rt->image_count; ++qi) {
        unsigned q = qi % n, set = qi / n;
        perma_proc_info *p = &rt->procs[q];
        st = image_reserve(rt, qi, capacities[qi]);
        if (st != PERMA_OK)
            break;
        size_t share = (p->seed_count + sets - 1) / sets;
        size_t first = (size_t)set * share;
        size_t count = first < p->seed_count ? p->seed_count - first : 0;
        if (count > share)
            count = share;
        perma_queue_image *img = &rt->images[qi];
        img->capacity = capacities[qi];
        img->count = count;
        img->regrowths = 0;
        if (count)
            memcpy(img->words, p->seeds + first * p->item_size, count * p->item_size);
    }
    free(capacities);
    if (st != PERMA_OK)
        return st;
    for (unsigned q = 0; q < n; ++q) {
        perma_proc_info *p = &rt->procs[q];
        p->stats.seeded = p->seed_count;
        p->stats.peak_queue_items = p->seed_count;
        p->seed_count = 0;
    }
    return PERMA_OK;
}

perma_status perma_ensure_buffer(perma_runtime *rt, cl_mem *mem, size_t *have_words, size_t words,
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
    size_t data_words = 0, outstanding = 0;
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        data_words += rt->images[qi].capacity * slot_words(proc_of(rt, qi));
        outstanding += rt->images[qi].count;
    }
    size_t bytes = data_words * 4;
    if (bytes > rt->stats.peak_queue_bytes)
        rt->stats.peak_queue_bytes = bytes;

    size_t ctl_words = perma_ctl_words(rt->image_count, rt->work_groups);
    size_t stats_words = (size_t)rt->work_groups * perma_stat_group_words(rt->proc_count, rt->max_edges);
    uint32_t *ctl = calloc(ctl_words, 4);
    uint32_t *data = calloc(data_words ? data_words : 1, 4);
    perma_status st = PERMA_OK;
    if (!ctl || !data) {
        st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory laying out %zu bytes of queues", bytes);
        goto done;
    }
    ctl[PERMA_CTL_OUTSTANDING] = (uint32_t)outstanding;
    ctl[PERMA_CTL_GROW_STARVED] = rt->grow_starved ? 1u : 0u;
    size_t data_off = 0;
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        const perma_queue_image *img = &rt->images[qi];
        size_t words = item_words(proc_of(rt, qi));
        uint32_t *rec = ctl + PERMA_CTL_HEADER_WORDS + qi * PERMA_QUEUE_WORDS;
        rec[PERMA_Q_HEAD] = 0;
        rec[PERMA_Q_TAIL] = (uint32_t)img->count;
        rec[PERMA_Q_ROOM] = (uint32_t)(img->capacity - img->count);
        rec[PERMA_Q_CAP] = (uint32_t)img->capacity;
        rec[PERMA_Q_DATA] = (uint32_t)data_off;
        rec[PERMA_Q_PUBLISHED] = (uint32_t)img->count;
        rec[PERMA_Q_PEAK] = (uint32_t)img->count;
        rec[PERMA_Q_RELEASED] = 0;
        memcpy(data + data_off, img->words, img->count * words * 4);
        /* Completion marks: each slot's own index, which reads as "not
         * done" for every position of it. */
        uint32_t *marks = data + data_off + img->capacity * words;
        for (size_t i = 0; i < img->capacity; ++i)
            marks[i] = marks[img->capacity + i] = (uint32_t)i;
        data_off += img->capacity * slot_words(proc_of(rt, qi));
    }

    size_t ctl_have = 0, stats_have = 0;
    if (rt->ctl_mem)
        clReleaseMemObject(rt->ctl_mem), rt->ctl_mem = NULL;
    if (rt->stats_mem)
        clReleaseMemObject(rt->stats_mem), rt->stats_mem = NULL;
    if ((st = perma_ensure_buffer(rt, &rt->ctl_mem, &ctl_have, ctl_words, "control block")) != PERMA_OK ||
        (st = perma_ensure_buffer(rt, &rt->stats_mem, &stats_have, stats_words ? stats_words : 1, "statistics")) != PERMA_OK ||
        (st = perma_ensure_buffer(rt, &rt->data_mem, &rt->data_mem_words, data_words ? data_words : 1, "queue items")) != PERMA_OK)
        goto done;
    cl_uint zero = 0;
    cl_int err = clEnqueueFillBuffer(rt->queue, rt->stats_mem, &zero, sizeof zero, 0,
                                     (stats_words ? stats_words : 1) * 4, 0, NULL, NULL);
    const char *call = "clEnqueueFillBuffer (statistics)";
    if (err == CL_SUCCESS) {
        err = clEnqueueWriteBuffer(rt->queue, rt->ctl_mem, CL_TRUE, 0, ctl_words * 4, ctl, 0, NULL, NULL);
        call = "clEnqueueWriteBuffer (control block)";
    }
    if (err == CL_SUCCESS && data_words) {
        err = clEnqueueWriteBuffer(rt->queue, rt->data_mem, CL_TRUE, 0, data_words * 4, data, 0, NULL, NULL);
        call = "clEnqueueWriteBuffer (queue items)";
    }
    if (err != CL_SUCCESS)
        st = perma_set_error(rt, PERMA_ERR_OPENCL, "%s failed: %s (%d)", call, perma_cl_error_name(err), (int)err);
done:
    free(ctl);
    free(data);
    return st;
}

/* Read the queues back after a launch stopped with no batch running. */
perma_status perma_queues_download(perma_runtime *rt)
{
    size_t ctl_words = perma_ctl_words(rt->image_count, rt->work_groups);
    size_t data_words = 0;
    for (unsigned qi = 0; qi < rt->image_count; ++qi)
        data_words += rt->images[qi].capacity * slot_words(proc_of(rt, qi));
    uint32_t *ctl = malloc(ctl_words * 4);
    uint32_t *data = malloc(data_words * 4 + 4);
    perma_status st = PERMA_OK;
    if (!ctl || !data) {
        st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory reading the queues back");
        goto done;
    }
    cl_int err = clEnqueueReadBuffer(rt->queue, rt->ctl_mem, CL_TRUE, 0, ctl_words * 4, ctl, 0, NULL, NULL);
    if (err == CL_SUCCESS && data_words)
        err = clEnqueueReadBuffer(rt->queue, rt->data_mem, CL_TRUE, 0, data_words * 4, data, 0, NULL, NULL);
    if (err != CL_SUCCESS) {
        st = perma_set_error(rt, PERMA_ERR_OPENCL, "clEnqueueReadBuffer (reading the queues back) failed: %s (%d)",
                             perma_cl_error_name(err), (int)err);
        goto done;
    }
    size_t queued = 0;
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        const uint32_t *rec = ctl + PERMA_CTL_HEADER_WORDS + qi * PERMA_QUEUE_WORDS;
        queued += (uint32_t)(rec[PERMA_Q_TAIL] - rec[PERMA_Q_HEAD]);
    }
    /* Every item the kernel counts as outstanding must be in a queue: one
     * left in a group's local memory would be lost by the next launch. */
    if (queued != (size_t)(int32_t)ctl[PERMA_CTL_OUTSTANDING]) {
        st = perma_set_error(rt, PERMA_ERR_DEVICE, "items were lost: the kernel stopped with %d items outstanding "
                             "but its queues hold %zu", (int)(int32_t)ctl[PERMA_CTL_OUTSTANDING], queued);
        goto done;
    }
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        perma_queue_image *img = &rt->images[qi];
        const uint32_t *rec = ctl + PERMA_CTL_HEADER_WORDS + qi * PERMA_QUEUE_WORDS;
        uint32_t head = rec[PERMA_Q_HEAD], tail = rec[PERMA_Q_TAIL];
        uint32_t cap = rec[PERMA_Q_CAP];
        size_t words = item_words(proc_of(rt, qi));
        size_t count = (uint32_t)(tail - head);
        if (cap != img->capacity || count > cap) {
            st = perma_set_error(rt, PERMA_ERR_DEVICE, "queue '%s' is inconsistent after the launch "
                                 "(head %u, tail %u, capacity %u)", proc_of(rt, qi)->name, head, tail, cap);
            goto done;
        }
        /* Every batch has finished: every reserved range is published and
         * every claimed one released. */
        if (rec[PERMA_Q_PUBLISHED] != tail || rec[PERMA_Q_RELEASED] != head) {
            st = perma_set_error(rt, PERMA_ERR_DEVICE,
                                 "queue '%s': positions %u to %u were never %s", proc_of(rt, qi)->name,
                                 rec[PERMA_Q_PUBLISHED] != tail ? rec[PERMA_Q_PUBLISHED] : rec[PERMA_Q_RELEASED],
                                 (rec[PERMA_Q_PUBLISHED] != tail ? tail : head) - 1,
                                 rec[PERMA_Q_PUBLISHED] != tail ? "published" : "released");
            goto done;
        }
        for (size_t i = 0; i < count; ++i) {
            uint32_t slot = (head + (uint32_t)i) & (cap - 1);
            memcpy(img->words + i * words, data + rec[PERMA_Q_DATA] + (size_t)slot * words, words * 4);
        }
        img->count = count;
    }
done:
    free(ctl);
    free(data);
    return st;
}

/* Give every queue whose entry in `capacities` differs from its capacity
 * that capacity: all checked against the memory limit first, then applied,
 * so a refusal changes nothing. */
static perma_status apply_capacities(perma_runtime *rt, const size_t *capacities)
{
    size_t bytes = queue_bytes(rt, capacities);
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        if (capacities[qi] == rt->images[qi].capacity)
            continue;
        if (bytes > memory_limit(rt))
            return perma_set_error(rt, PERMA_ERR_CAPACITY,
                                   "queue '%s' is full (%zu items of %zu bytes) and cannot grow to %zu items: "
                                   "all queues would need %zu bytes, more than the queue memory limit of %zu bytes",
                                   proc_of(rt, qi)->name, rt->images[qi].capacity, proc_of(rt, qi)->item_size,
                                   capacities[qi], bytes, memory_limit(rt));
        if (capacities[qi] > ((size_t)1 << 31))
            return perma_set_error(rt, PERMA_ERR_CAPACITY, "queue '%s' would need more than 2^31 items",
                                   proc_of(rt, qi)->name);
    }
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        if (capacities[qi] == rt->images[qi].capacity)
            continue;
        perma_status st = image_reserve(rt, qi, capacities[qi]);
        if (st != PERMA_OK)
            return st;
        rt->images[qi].capacity = capacities[qi];
        rt->images[qi].regrowths++;
    }
    rt->stats.regrowths++;
    return PERMA_OK;
}

/* Grow the queues that stopped the launch: every target without room for
 * one item's worst-case emits from a non-empty source.  `starved_queue`
 * (when below image_count) names the one queue a group starved of room
 * asked for instead: only that one doubles. */
perma_status perma_queues_grow(perma_runtime *rt, unsigned starved_queue)
{
    unsigned n = rt->proc_count;
    size_t *capacities = calloc(rt->image_count, sizeof *capacities);
    bool *grow = calloc(rt->image_count, sizeof *grow);
    perma_status st = PERMA_OK;
    if (!capacities || !grow) {
        st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory growing queues");
        goto done;
    }
    bool any = false;
    for (unsigned qi = 0; qi < rt->image_count; ++qi)
        capacities[qi] = rt->images[qi].capacity;
    if (starved_queue < rt->image_count)
        grow[starved_queue] = any = true;
    for (int relaxed = 0; relaxed < 2 && !any; ++relaxed) {
        for (unsigned qi = 0; qi < rt->image_count; ++qi) {
            if (rt->images[qi].count == 0)
                continue;
            const perma_proc_info *p = proc_of(rt, qi);
            /* A stolen batch emits into the thief's set: consider every set. */
            for (unsigned set = 0; set < rt->queue_sets; ++set) {
                for (unsigned e = 0; e < p->emit_count; ++e) {
                    unsigned ti = set * n + (unsigned)p->emit_target[e];
                    size_t room = rt->images[ti].capacity - rt->images[ti].count;
                    /* relaxed: the kernel saw no room where we see some (a
                     * race between groups); grow the targets of all waiting work. */
                    if (relaxed || room < p->emit_max[e]) {
                        grow[ti] = true;
                        any = true;
                    }
                }
            }
        }
    }
    if (!any) {
        st = perma_set_error(rt, PERMA_ERR_DEVICE, "the kernel reported no room, but no queued item emits anything");
        goto done;
    }
    /* capacity >= any emit_max (perma_queues_prepare), so doubling leaves
     * room for at least one item's emits. */
    for (unsigned qi = 0; qi < rt->image_count; ++qi)
        if (grow[qi])
            capacities[qi] = rt->images[qi].capacity * 2;
    st = apply_capacities(rt, capacities);
done:
    free(capacities);
    free(grow);
    return st;
}

/* Between launches of the host-driven techniques: grow every queue qi with
 * needed[qi] > free slots to a capacity that fits, and relay the queues out. */
perma_status perma_queues_make_room(perma_runtime *rt, const size_t *needed)
{
    perma_status st = perma_queues_download(rt);
    if (st != PERMA_OK)
        return st;
    size_t *capacities = calloc(rt->image_count, sizeof *capacities);
    if (!capacities)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory growing queues");
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        capacities[qi] = rt->images[qi].capacity;
        while (capacities[qi] - rt->images[qi].count < needed[qi])
            capacities[qi] *= 2;
    }
    st = apply_capacities(rt, capacities);
    free(capacities);
    if (st != PERMA_OK)
        return st;
    return perma_queues_upload(rt);
}
