/* The pipeline workload: producer -> transform -> consumer.
 *
 * Producer item i emits pipe_fan(i) records into transform: 64 for about
 * one producer in 16, else 1 (a skewed fan-out).  Transform hashes its
 * record `rounds` times and emits one result into consumer, which adds the
 * value to a checksum.  The functions are written once and compiled as C
 * and as OpenCL C (PIPE_DEVICE_CODE), like uts.h. */
#ifndef PIPELINE_H
#define PIPELINE_H

#include <stddef.h>
#include <stdint.h>

#define PIPE_SHARED_CODE(FN)                                                           \
    FN uint pipe_mix(uint x)                                                           \
    {                                                                                  \
        x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;  \
        return x;                                                                      \
    }                                                                                  \
    FN uint pipe_fan(uint index)                                                       \
    {                                                                                  \
        return (pipe_mix(index ^ 0x2545f491u) & 15u) == 0u ? 64u : 1u;                 \
    }                                                                                  \
    FN uint pipe_value(uint source, uint k, uint rounds)                               \
    {                                                                                  \
        uint h = source * 64u + k;                                                     \
        for (uint r = 0; r < rounds; ++r)                                              \
            h = pipe_mix(h + r);                                                       \
        return h;                                                                      \
    }

typedef uint32_t uint;
PIPE_SHARED_CODE(static inline)

#define PIPE_STRINGIFY_(...) #__VA_ARGS__
#define PIPE_STRINGIFY(...) PIPE_STRINGIFY_(__VA_ARGS__)
#define PIPE_DEVICE_CODE PIPE_STRINGIFY(PIPE_SHARED_CODE())

/* Item layouts, identical on the device (see bench_pipeline.c). */
typedef struct pipe_producer { uint index, pad; } pipe_producer;            /* 8 bytes */
typedef struct pipe_record { uint source, k, payload[6]; } pipe_record;     /* 32 bytes */
typedef struct pipe_result { uint source, value, pad[2]; } pipe_result;     /* 16 bytes */

typedef struct pipe_params {
    uint producers, rounds;
} pipe_params;

typedef struct pipe_result_sum {
    uint64_t consumed, checksum;
    uint64_t items;           /* all items executed */
    size_t peak_item_bytes;   /* most bytes of items waiting at once */
} pipe_result_sum;

/* Sequential C: three queues served in priority order, one item at a time
 * (downstream_first: consumer, transform, producer; else the reverse).
 * Returns 0, or -1 when out of memory. */
int pipe_run_sequential(const pipe_params *p, int downstream_first, pipe_result_sum *out);

/* OpenMP tasks: producer tasks create transform tasks, which create
 * consumer tasks.  Peak bytes count the items of live tasks. */
void pipe_run_openmp(const pipe_params *p, unsigned threads, pipe_result_sum *out);

#endif
