/* The procedures of the chain tests:
 *   produce --(1..4)--> transform --(1)--> consume
 *   produce --(1)-----------------------> consume
 * Each counts the ids it sees in a buffer (seen_produce, seen_transform,
 * seen_consume0 for items from produce, seen_consume1 from transform), so
 * the host can check that every item was processed exactly once.  Item:
 * struct chain_item, 8 bytes. */
#ifndef CHAIN_PROCEDURE_H
#define CHAIN_PROCEDURE_H

#include <stdint.h>

#include "perma.h"

enum { CHAIN_MAX_PRODUCERS = 2000, CHAIN_FANOUT = 4 };

#define CHAIN_TYPES "struct chain_item { uint id; uint tag; };\n"

#define CHAIN_SOURCE                                                       \
    "void produce(perma_ctx *ctx, __local const struct chain_item *it)\n" \
    "{\n"                                                                 \
    "    atomic_inc(&ctx->buf.seen_produce[it->id]);\n"                   \
    "    uint fan = it->id % 4u + 1u;\n"                                  \
    "    for (uint j = 0; j < fan; ++j) {\n"                              \
    "        struct chain_item t = { it->id * 4u + j, 0 };\n"             \
    "        emit_transform(ctx, &t);\n"                                  \
    "    }\n"                                                             \
    "    struct chain_item c = { it->id, 0 };\n"                          \
    "    emit_consume(ctx, &c);\n"                                        \
    "}\n"                                                                 \
    "void transform(perma_ctx *ctx, __local const struct chain_item *it)\n" \
    "{\n"                                                                 \
    "    atomic_inc(&ctx->buf.seen_transform[it->id]);\n"                 \
    "    struct chain_item c = { it->id, 1 };\n"                          \
    "    emit_consume(ctx, &c);\n"                                        \
    "}\n"                                                                 \
    "void consume(perma_ctx *ctx, __local const struct chain_item *it)\n" \
    "{\n"                                                                 \
    "    if (it->tag == 0)\n"                                             \
    "        atomic_inc(&ctx->buf.seen_consume0[it->id]);\n"              \
    "    else\n"                                                          \
    "        atomic_inc(&ctx->buf.seen_consume1[it->id]);\n"              \
    "}\n"

/* One run of the chain: its procedures and what each saw per id. */
typedef struct chain_run {
    unsigned producers;
    perma_proc produce, transform, consume;
    uint32_t seen_produce[CHAIN_MAX_PRODUCERS], seen_transform[CHAIN_MAX_PRODUCERS * CHAIN_FANOUT];
    uint32_t seen_consume0[CHAIN_MAX_PRODUCERS], seen_consume1[CHAIN_MAX_PRODUCERS * CHAIN_FANOUT];
} chain_run;

/* Add the chain to rt (which has nothing else registered), bind its
 * counters and seed `producers` (1..CHAIN_MAX_PRODUCERS) items into
 * produce.  Fails the test on any error. */
void chain_prepare(perma_runtime *rt, chain_run *run, unsigned producers);

/* After perma_run: every item was processed exactly once and the
 * procedures' statistics agree. */
void chain_check(perma_runtime *rt, const chain_run *run);

#endif
