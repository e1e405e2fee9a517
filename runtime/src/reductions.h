#ifndef PERMA_REDUCTIONS_H
#define PERMA_REDUCTIONS_H

#include "perma.h"
#include "perma_abi.h"
#include "strbuf.h"

#include <stddef.h>
#include <stdint.h>

/* reductions.c: the declared reductions, its state (opaque outside it;
 * made at perma_create, freed at perma_destroy).  At build, the lane layout and the reductions' two parts
 * of the generated program (`constants`, which go before perma_ctx; after
 * it `helpers`, the reduce_NAME() functions and the lane's initialisation
 * and fold); before a run the slots' identities, after one the results. */
typedef struct perma_reductions_state perma_reductions_state;
perma_status perma_reductions_open(perma_runtime *rt);
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

#endif
