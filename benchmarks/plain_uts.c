/* `perma-bench plain --workload uts-geometric,uts-binomial`: the UTS geometric and binomial trees
 * with one node per item and a splitmix64 hash per child (plain_uts.cl),
 * against plain_uts_sequential and plain_uts_openmp.  A perma row passes
 * if the node count and the sum of the node hashes equal the sequential
 * ones and the runtime ran one item per node. */
#include "plain.h"
#include "plain_baselines.h"

#include <stdlib.h>
#include <string.h>

/* p = 0.8: 4 children expected per node; q * m = 0.999 (0.99 quick).  Root
 * hashes picked for trees of the intended size (2.6 and 3.0 million nodes;
 * about 13,000 quick): most give much smaller or larger ones. */
#define UTS_P64_08 0xccccccccccccccccUL
static const plain_uts_tree geometric_default = { .root_hash = 8, .max_depth = 10, .p64 = UTS_P64_08 };
static const plain_uts_tree geometric_quick = { .root_hash = 12, .max_depth = 7, .p64 = UTS_P64_08 };
static const plain_uts_tree binomial_default = { .binomial = 1, .root_hash = 2, .b0 = 2000, .m = 8,
                                                 .q64 = 0x1ff7ced916872b00UL /* 0.124875 */ };
static const plain_uts_tree binomial_quick = { .binomial = 1, .root_hash = 7, .b0 = 200, .m = 8,
                                               .q64 = 0x1fae147ae147ae00UL /* 0.12375 */ };
/* OpenMP spawns tasks above this depth (--cutoff overrides). */
enum { GEOMETRIC_CUTOFF = 3, BINOMIAL_CUTOFF = 64 };

typedef struct uts_state {
    const plain_uts_tree *tree;
    perma_proc procs[2];       /* geometric: the node; binomial: the root, the node */
    size_t item_sizes[2];
    uint64_t nodes, hash_sum; /* the results, described by `results` */
    plain_result results[2];
    plain_uts_result expected;
} uts_state;

static perma_status uts_setup(void *state, perma_runtime *rt, plain_count count)
{
    uts_state *s = state;
    const plain_uts_tree *t = s->tree;
    char defines[256];
    if (!t->binomial)
        snprintf(defines, sizeof defines, "#define UTS_GEOMETRIC 1\n#define UTS_MAX_DEPTH %uu\n#define UTS_P64 %#lxUL\n",
                 t->max_depth, (unsigned long)t->p64);
    else
        snprintf(defines, sizeof defines, "#define UTS_B0 %uu\n#define UTS_M %uu\n#define UTS_Q64 %#lxUL\n", t->b0,
                 t->m, (unsigned long)t->q64);
    perma_status st = plain_add_sources(rt, count, defines);
    if (st == PERMA_OK && !t->binomial)
        st = plain_register(rt, "uts_geometric", "struct uts_node", sizeof(struct uts_node), plain_uts_source,
                            "plain_uts.cl", "uts_geometric", UTS_MAX_CHILDREN, &s->procs[0]);
    if (st == PERMA_OK && t->binomial)
        st = plain_register(rt, "uts_binomial_root", "struct uts_node", sizeof(struct uts_node), plain_uts_source,
                            "plain_uts.cl", "uts_binomial", t->b0, &s->procs[0]);
    if (st == PERMA_OK && t->binomial)
        st = plain_register(rt, "uts_binomial", "struct uts_node", sizeof(struct uts_node), plain_uts_source,
                            "plain_uts.cl", "uts_binomial", t->m, &s->procs[1]);
    if (st == PERMA_OK)
        st = plain_results_declare(rt, count, s->results, 2);
    return st;
}

static perma_status uts_prepare(void *state, perma_runtime *rt)
{
    uts_state *s = state;
    plain_results_clear(s->results, 2);
    struct uts_node root = { s->tree->root_hash, 0u, 0u };
    return perma_seed(rt, s->procs[0], &root, 1);
}

/* The results of a run: where the counting of plain_uts.cl ends up. */
static plain_uts_result uts_results(const uts_state *s)
{
    plain_uts_result r = { s->nodes, s->hash_sum };
    return r;
}

static int uts_verify(void *state, perma_runtime *rt, bench_row *row)
{
    uts_state *s = state;
    plain_uts_result r = uts_results(s);
    row->count = r.nodes;
    row->expected = s->expected.nodes;
    return r.nodes == s->expected.nodes && r.hash_sum == s->expected.hash_sum &&
           plain_items_run(rt) == s->expected.nodes;
}

/* ---- baselines ---- */

typedef struct uts_baseline {
    const plain_uts_tree *tree;
    unsigned threads;
    uint spawn_depth;
    plain_uts_result result;
    int failed;
} uts_baseline;

static void uts_sequential_once(void *p)
{
    uts_baseline *b = p;
    b->failed |= plain_uts_sequential(b->tree, &b->result) != 0;
}

static void uts_openmp_once(void *p)
{
    uts_baseline *b = p;
    plain_uts_openmp(b->tree, b->threads, b->spawn_depth, &b->result);
}

static void uts_openmp_row(const plain_options *o, bench_report *report, const char *title, const uts_state *s,
                           uint spawn_depth)
{
    uts_baseline b = { .tree = s->tree, .threads = bench_threads(o->common), .spawn_depth = spawn_depth };
    bench_timing time = bench_time_runs(o->common, NULL, uts_openmp_once, &b);
    char label[48];
    if (spawn_depth == UINT32_MAX)
        snprintf(label, sizeof label, "(task per node)");
    else
        snprintf(label, sizeof label, "(tasks above depth %u)", spawn_depth);
    int ok = b.result.nodes == s->expected.nodes && b.result.hash_sum == s->expected.hash_sum;
    plain_openmp_row(report, o, title, label, "nodes", (double)s->expected.nodes, time, ok);
}

static int uts_tree(const plain_options *o, bench_report *report, const plain_uts_tree *t)
{
    char title[96];
    if (!t->binomial)
        snprintf(title, sizeof title, "uts geometric b=4 d=%u, splitmix64, a node per item", t->max_depth);
    else
        snprintf(title, sizeof title, "uts binomial b0=%u m=%u q=%.6f, splitmix64, a node per item", t->b0, t->m,
                 (double)t->q64 / 18446744073709551616.0);
    bench_report_workload(report, title);

    uts_baseline seq = { .tree = t };
    bench_timing time = bench_time_runs(o->common, NULL, uts_sequential_once, &seq);
    if (seq.failed) {
        fprintf(stderr, "perma-bench plain: out of memory in the sequential tree count\n");
        return 1;
    }
    char note[64];
    snprintf(note, sizeof note, "%llu nodes", (unsigned long long)seq.result.nodes);
    plain_sequential_row(report, title, "nodes", (double)seq.result.nodes, time, note);

    uts_state s = { .tree = t, .expected = seq.result };
    s.item_sizes[0] = s.item_sizes[1] = sizeof(struct uts_node);
    s.results[0] = (plain_result){ "uts_nodes", PERMA_TYPE_ULONG, &s.nodes };
    s.results[1] = (plain_result){ "uts_hash_sum", PERMA_TYPE_ULONG, &s.hash_sum };
    uts_openmp_row(o, report, title, &s, UINT32_MAX);
    uts_openmp_row(o, report, title, &s, plain_cutoff(o, t->binomial ? BINOMIAL_CUTOFF : GEOMETRIC_CUTOFF));

    plain_perma w = { uts_setup, { uts_prepare, uts_verify, &s, t->binomial ? 2u : 1u, s.procs, s.item_sizes }, 0 };
    plain_perma_rows(o, report, title, "nodes", (double)s.expected.nodes, &w);
    return 0;
}

int plain_uts_geometric(const plain_options *o, bench_report *report)
{
    return uts_tree(o, report, o->common->quick ? &geometric_quick : &geometric_default);
}

int plain_uts_binomial(const plain_options *o, bench_report *report)
{
    return uts_tree(o, report, o->common->quick ? &binomial_quick : &binomial_default);
}
