/* `perma-bench plain`: workloads written the way a newcomer writes them
 * after README.md and docs/writing-procedures.md (one item = one node,
 * interval, board or range; emit_<target> for the children; results added
 * with reduce_<name>), each against sequential C and OpenMP tasks.
 *
 * bench_plain.c holds the command and the rows every workload shares;
 * plain_uts.c, plain_simpson.c, plain_queens.c, plain_sort.c and
 * plain_subset.c one workload each (host side), plain_*.cl their procedures, plain_work.h the
 * per-item work that the procedures and the baselines (plain_baselines.h)
 * share. */
#ifndef PLAIN_H
#define PLAIN_H

#include "bench.h"

#include <stdint.h>

/* The procedure sources, embedded at build time (kernels/embed.py). */
extern const char plain_work_source[], plain_uts_source[], plain_simpson_source[], plain_queens_source[],
    plain_sort_source[], plain_subset_source[];

typedef enum plain_count {
    PLAIN_COUNT_REDUCE = 1, /* reduce_<name>(ctx, value): a reduction per result */
    PLAIN_COUNT_ATOMIC = 2  /* one global atomic per result per item, on one word */
} plain_count;

typedef struct plain_options {
    const bench_options *common;
    unsigned counts;        /* plain_count bits: the ways of counting measured */
    unsigned group_size;    /* perma work-items per group */
    unsigned cutoff;        /* OpenMP spawn depth for every workload; 0: each one's default */
    unsigned weights;       /* subset sum: weights; 0: the default (30, 16 with --quick) */
} plain_options;

/* The OpenMP spawn depth: --cutoff, or the workload's default. */
unsigned plain_cutoff(const plain_options *o, unsigned workload_default);

/* ---- rows ---- */

/* The sequential C row (the ratio's baseline); note: e.g. the node count. */
void plain_sequential_row(bench_report *report, const char *title, const char *unit, double units,
                          bench_timing time, const char *note);
/* An OpenMP row, `label` after "openmp tasks ", checked by `ok`. */
void plain_openmp_row(bench_report *report, const plain_options *o, const char *title, const char *label,
                      const char *unit, double units, bench_timing time, int ok);

/* A workload's perma side.  `setup` adds its sources (plain_add_sources
 * first), registers its procedures into run.procs and declares its results
 * and binds its buffers on a new runtime; run.prepare seeds, run.verify
 * checks one run (see bench_workload). */
typedef struct plain_perma {
    perma_status (*setup)(void *state, perma_runtime *rt, plain_count count);
    bench_workload run;
    int counts_nothing; /* no results to add to: one row per variant, whatever --count says */
} plain_perma;

/* A row per selected perma variant, device and way of counting. */
void plain_perma_rows(const plain_options *o, bench_report *report, const char *title, const char *unit,
                      double units, const plain_perma *w);

/* ---- helpers of the workloads' perma side ---- */

/* plain_work.h, `#define PLAIN_COUNT_ATOMIC` when counting with atomics,
 * then `defines` (the workload's constants). */
perma_status plain_add_sources(perma_runtime *rt, plain_count count, const char *defines);

/* Register a procedure of one thread per item whose source is `source`
 * (one of the embedded plain_*.cl, named `file`: procedures of the same
 * source and file share it) and that emits at most max_emits items into
 * `target` (NULL: none). */
perma_status plain_register(perma_runtime *rt, const char *name, const char *item_type, size_t item_size,
                            const char *source, const char *file, const char *target, unsigned max_emits,
                            perma_proc *out);

/* A result the procedures add to: reduction `name` (a sum of `type`,
 * PERMA_TYPE_ULONG or PERMA_TYPE_DOUBLE) that the run writes into *value,
 * or with PLAIN_COUNT_ATOMIC a buffer of that name holding one word,
 * *value, that the procedures add to with global atomics. */
typedef struct plain_result {
    const char *name;
    perma_value_type type;
    void *value; /* uint64_t or double */
} plain_result;

/* Declare (or bind) the `n` results for counting `count`. */
perma_status plain_results_declare(perma_runtime *rt, plain_count count, const plain_result *results, unsigned n);
/* Zero them before a run (atomic counting adds to them). */
void plain_results_clear(const plain_result *results, unsigned n);

/* perma_stats.items of the run that just finished (UINT64_MAX if unknown). */
uint64_t plain_items_run(perma_runtime *rt);

/* ---- the workloads ---- */

int plain_uts_geometric(const plain_options *o, bench_report *report);
int plain_uts_binomial(const plain_options *o, bench_report *report);
int plain_simpson(const plain_options *o, bench_report *report);
int plain_queens(const plain_options *o, bench_report *report);
int plain_sort(const plain_options *o, bench_report *report);
int plain_subset(const plain_options *o, bench_report *report);

#endif
