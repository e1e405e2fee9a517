/* `perma-bench plain --workload subset`: counting the nodes of a
 * branch-and-bound subset-sum search, one node per item (plain_subset.cl):
 * n weights of 1000 to 9999, the target half their sum, a node per choice
 * of the next weight (taken or not) while the weights left can still reach
 * what is needed.  About 2 ns of C per node and a tree as deep as the
 * weights: sequential C needs a stack of that depth, a queue of the
 * tree's breadth would not fit memory at 34 weights (6.7e9 nodes).
 * Against the recursion (sequential C) and OpenMP tasks.  A perma row
 * passes with the sequential node and solution counts and one item per
 * node. */
#include "plain.h"
#include "plain_baselines.h"

#include <stdlib.h>
#include <string.h>

enum { WEIGHTS_DEFAULT = 30, WEIGHTS_QUICK = 16, OPENMP_CUTOFF = 12 };

typedef struct subset_state {
    plain_subset_instance instance;
    perma_proc proc;
    size_t item_size;
    uint64_t nodes, solutions; /* the results, described by `results` */
    plain_result results[2];
    plain_subset_result expected;
} subset_state;

/* The instance as __constant arrays in front of plain_subset.cl. */
static char *subset_defines(const plain_subset_instance *s)
{
    size_t size = 128 + 24 * (2 * (size_t)s->n + 1), used = 0;
    char *text = malloc(size);
    if (!text)
        return NULL;
    used += (size_t)snprintf(text + used, size - used, "#define SUBSET_N %uu\n__constant uint SUBSET_WEIGHTS[%u] = {",
                             s->n, s->n);
    for (uint i = 0; i < s->n; ++i)
        used += (size_t)snprintf(text + used, size - used, "%s%uu", i ? ", " : " ", s->weights[i]);
    used += (size_t)snprintf(text + used, size - used, " };\n__constant uint SUBSET_SUFFIX[%u] = {", s->n + 1u);
    for (uint i = 0; i <= s->n; ++i)
        used += (size_t)snprintf(text + used, size - used, "%s%uu", i ? ", " : " ", s->suffix[i]);
    snprintf(text + used, size - used, " };\n");
    return text;
}

static perma_status subset_setup(void *state, perma_runtime *rt, plain_count count)
{
    subset_state *s = state;
    char *defines = subset_defines(&s->instance);
    if (!defines)
        return PERMA_ERR_NO_MEMORY;
    perma_status st = plain_add_sources(rt, count, defines);
    free(defines);
    if (st == PERMA_OK)
        st = plain_register(rt, "subset", "struct subset_node", sizeof(struct subset_node), plain_subset_source,
                            "plain_subset.cl", "subset", 2, &s->proc);
    if (st == PERMA_OK)
        st = plain_results_declare(rt, count, s->results, 2);
    return st;
}

static perma_status subset_prepare(void *state, perma_runtime *rt)
{
    subset_state *s = state;
    plain_results_clear(s->results, 2);
    struct subset_node root = { 0u, s->instance.target };
    return perma_seed(rt, s->proc, &root, 1);
}

static int subset_verify(void *state, perma_runtime *rt, bench_row *row)
{
    subset_state *s = state;
    row->count = s->nodes;
    row->expected = s->expected.nodes;
    return s->nodes == s->expected.nodes && s->solutions == s->expected.solutions &&
           plain_items_run(rt) == s->expected.nodes;
}

/* ---- baselines ---- */

typedef struct subset_baseline {
    const plain_subset_instance *instance;
    unsigned threads;
    uint spawn_depth;
    plain_subset_result result;
} subset_baseline;

static void subset_sequential_once(void *p)
{
    subset_baseline *b = p;
    plain_subset_sequential(b->instance, &b->result);
}

static void subset_openmp_once(void *p)
{
    subset_baseline *b = p;
    plain_subset_openmp(b->instance, b->threads, b->spawn_depth, &b->result);
}

int plain_subset(const plain_options *o, bench_report *report)
{
    subset_state *s = calloc(1, sizeof *s);
    if (!s)
        return 1;
    plain_subset_instance_init(&s->instance, o->weights ? o->weights : o->common->quick ? WEIGHTS_QUICK : WEIGHTS_DEFAULT);
    s->item_size = sizeof(struct subset_node);
    s->results[0] = (plain_result){ "subset_nodes", PERMA_TYPE_ULONG, &s->nodes };
    s->results[1] = (plain_result){ "subset_solutions", PERMA_TYPE_ULONG, &s->solutions };
    char title[96];
    snprintf(title, sizeof title, "subset sum of %u weights, a search node per item", s->instance.n);
    bench_report_workload(report, title);

    subset_baseline seq = { .instance = &s->instance };
    bench_timing time = bench_time_runs(o->common, NULL, subset_sequential_once, &seq);
    s->expected = seq.result;
    char note[96];
    snprintf(note, sizeof note, "%llu nodes, %llu solutions", (unsigned long long)s->expected.nodes,
             (unsigned long long)s->expected.solutions);
    plain_sequential_row(report, title, "nodes", (double)s->expected.nodes, time, note);

    subset_baseline omp = { .instance = &s->instance, .threads = bench_threads(o->common),
                            .spawn_depth = plain_cutoff(o, OPENMP_CUTOFF) };
    time = bench_time_runs(o->common, NULL, subset_openmp_once, &omp);
    char label[48];
    snprintf(label, sizeof label, "(tasks above depth %u)", omp.spawn_depth);
    plain_openmp_row(report, o, title, label, "nodes", (double)s->expected.nodes, time,
                     omp.result.nodes == s->expected.nodes && omp.result.solutions == s->expected.solutions);

    plain_perma w = { subset_setup, { subset_prepare, subset_verify, s, 1, &s->proc, &s->item_size }, 0 };
    plain_perma_rows(o, report, title, "nodes", (double)s->expected.nodes, &w);
    free(s);
    return 0;
}
