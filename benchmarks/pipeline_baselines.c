/* The pipeline in sequential C and with OpenMP tasks (see pipeline.h). */
#include "pipeline.h"

#include <omp.h>
#include <stdatomic.h>
#include <stdlib.h>

/* A growable LIFO of fixed-size items. */
typedef struct stack {
    unsigned char *data;
    size_t count, capacity, item_size;
} stack;

static int stack_push(stack *s, const void *item)
{
    if (s->count == s->capacity) {
        size_t capacity = s->capacity ? s->capacity * 2 : 1024;
        unsigned char *grown = realloc(s->data, capacity * s->item_size);
        if (!grown)
            return -1;
        s->data = grown;
        s->capacity = capacity;
    }
    unsigned char *slot = s->data + s->count++ * s->item_size;
    for (size_t i = 0; i < s->item_size; ++i)
        slot[i] = ((const unsigned char *)item)[i];
    return 0;
}

static void *stack_pop(stack *s)
{
    return s->data + --s->count * s->item_size;
}

int pipe_run_sequential(const pipe_params *p, int downstream_first, pipe_result_sum *out)
{
    stack producers = { .item_size = sizeof(pipe_producer) };
    stack records = { .item_size = sizeof(pipe_record) };
    stack results = { .item_size = sizeof(pipe_result) };
    pipe_result_sum r = { 0, 0, 0, 0 };
    int failed = 0;
    for (uint i = p->producers; i-- > 0 && !failed;)
        failed = stack_push(&producers, &(pipe_producer){ i, 0 });
    while (!failed) {
        size_t bytes = producers.count * producers.item_size + records.count * records.item_size +
                       results.count * results.item_size;
        if (bytes > r.peak_item_bytes)
            r.peak_item_bytes = bytes;
        stack *order[3] = { &results, &records, &producers };
        if (!downstream_first) {
            order[0] = &producers;
            order[2] = &results;
        }
        stack *next = order[0]->count ? order[0] : order[1]->count ? order[1] : order[2]->count ? order[2] : NULL;
        if (!next)
            break;
        r.items++;
        if (next == &producers) {
            pipe_producer item = *(pipe_producer *)stack_pop(next);
            uint fan = pipe_fan(item.index);
            for (uint k = 0; k < fan && !failed; ++k) {
                pipe_record rec = { item.index, k, { item.index, k, 0, 0, 0, 0 } };
                failed = stack_push(&records, &rec);
            }
        } else if (next == &records) {
            pipe_record rec = *(pipe_record *)stack_pop(next);
            pipe_result res = { rec.source, pipe_value(rec.source, rec.k, p->rounds), { 0, 0 } };
            failed = stack_push(&results, &res);
        } else {
            pipe_result res = *(pipe_result *)stack_pop(next);
            r.consumed++;
            r.checksum += res.value;
        }
    }
    free(producers.data);
    free(records.data);
    free(results.data);
    if (failed)
        return -1;
    *out = r;
    return 0;
}

/* ---- OpenMP ---- */

enum { MAX_THREADS = 256 };
struct thread_sum {
    uint64_t consumed, checksum, items;
    char pad[64 - 3 * sizeof(uint64_t)];
};
static struct thread_sum sums[MAX_THREADS];
static atomic_size_t live_bytes, peak_bytes;

static void live_add(size_t bytes)
{
    size_t now = atomic_fetch_add(&live_bytes, bytes) + bytes;
    size_t peak = atomic_load(&peak_bytes);
    while (now > peak && !atomic_compare_exchange_weak(&peak_bytes, &peak, now)) {
    }
}

static void consume(pipe_result res)
{
    struct thread_sum *s = &sums[omp_get_thread_num()];
    s->items++;
    s->consumed++;
    s->checksum += res.value;
    atomic_fetch_sub(&live_bytes, sizeof(pipe_result));
}

static void transform(pipe_record rec, uint rounds)
{
    sums[omp_get_thread_num()].items++;
    pipe_result res = { rec.source, pipe_value(rec.source, rec.k, rounds), { 0, 0 } };
    live_add(sizeof res);
    atomic_fetch_sub(&live_bytes, sizeof(pipe_record));
#pragma omp task firstprivate(res)
    consume(res);
}

static void produce(pipe_producer item, uint rounds)
{
    sums[omp_get_thread_num()].items++;
    uint fan = pipe_fan(item.index);
    for (uint k = 0; k < fan; ++k) {
        pipe_record rec = { item.index, k, { item.index, k, 0, 0, 0, 0 } };
        live_add(sizeof rec);
#pragma omp task firstprivate(rec)
        transform(rec, rounds);
    }
    atomic_fetch_sub(&live_bytes, sizeof(pipe_producer));
}

void pipe_run_openmp(const pipe_params *p, unsigned threads, pipe_result_sum *out)
{
    if (threads > MAX_THREADS)
        threads = MAX_THREADS;
    for (unsigned t = 0; t < MAX_THREADS; ++t)
        sums[t] = (struct thread_sum){ 0, 0, 0, { 0 } };
    atomic_store(&live_bytes, 0);
    atomic_store(&peak_bytes, 0);
    uint rounds = p->rounds, producers = p->producers;
#pragma omp parallel num_threads(threads)
#pragma omp single
    for (uint i = 0; i < producers; ++i) {
        pipe_producer item = { i, 0 };
        live_add(sizeof item);
#pragma omp task firstprivate(item)
        produce(item, rounds);
    }
    pipe_result_sum r = { 0, 0, 0, atomic_load(&peak_bytes) };
    for (unsigned t = 0; t < threads; ++t) {
        r.consumed += sums[t].consumed;
        r.checksum += sums[t].checksum;
        r.items += sums[t].items;
    }
    *out = r;
}
