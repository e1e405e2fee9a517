/* `perma-bench tree`: UTS-style unbalanced tree search (see uts.h).
 *
 * For each tree: the sequential C count (the baseline, and the expected
 * node count and hash sum), OpenMP tasks, then every perma variant with one
 * procedure `uts_visit` that counts its node and emits its children.  A perma
 * row passes its check only if the node count and the hash sum equal the
 * sequential ones.  The procedure counts with two reductions
 * (perma_declare_reduction): no atomic, no counter array. */
#include "bench.h"
#include "uts.h"

#include <stdlib.h>
#include <string.h>

static const char *device_types =
    "#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable\n"
    "#define UTS_GEO_CAP_VALUE 32u\n"
    "#define UTS_LANES 8u\n"
    "struct uts_node { uint hash; uint depth; };\n"
    UTS_DEVICE_CODE "\n";

typedef struct tree_case {
    const char *title_format;
    uts_tree tree;
} tree_case;

/* Default sizes aim at 1-4 million nodes; --quick at ~10^4. */
/* Root hashes picked for a tree of the intended size (most roots give a
 * much smaller or, for the binomial tree, a much larger one). */
static const uts_tree geometric_default = { .shape = UTS_GEOMETRIC, .root_hash = 5, .rounds = 16,
                                            .max_depth = 10, .p16 = 52429 /* p = 0.8, b = 4 */ };
static const uts_tree binomial_default = { .shape = UTS_BINOMIAL, .root_hash = 7, .rounds = 16, .b0 = 2000,
                                           .m = 8, .q32 = 536334541 /* q = 0.124875, qm = 0.999 */ };
static const uts_tree geometric_quick = { .shape = UTS_GEOMETRIC, .root_hash = 5, .rounds = 16,
                                          .max_depth = 7, .p16 = 52429 };
static const uts_tree binomial_quick = { .shape = UTS_BINOMIAL, .root_hash = 42, .rounds = 16, .b0 = 200,
                                         .m = 8, .q32 = 531502203 /* q = 0.12375, qm = 0.99 */ };

static void tree_title(const uts_tree *t, char *out, size_t size)
{
    if (t->shape == UTS_GEOMETRIC)
        snprintf(out, size, "geometric b=%.1f d=%u r=%u", (double)t->p16 / (65536.0 - t->p16), t->max_depth,
                 t->rounds);
    else
        snprintf(out, size, "binomial b0=%u m=%u q=%.6f r=%u", t->b0, t->m, (double)t->q32 / 4294967296.0,
                 t->rounds);
}

/* ---- the perma workload ---- */

typedef struct tree_state {
    const uts_tree *tree;
    perma_proc proc;
    uint64_t nodes, hash_sum; /* the reductions of the last run */
    uts_node *seeds;
    size_t seed_count;
    uts_result host_part; /* nodes counted on the host (the expanded binomial root) */
    uts_result expected;
} tree_state;

static perma_status tree_prepare(void *state, perma_runtime *rt)
{
    tree_state *s = state;
    return perma_seed(rt, s->proc, s->seeds, s->seed_count);
}

static int tree_verify(void *state, perma_runtime *rt, bench_row *row)
{
    tree_state *s = state;
    uint64_t nodes = s->host_part.nodes + s->nodes, sum = s->host_part.hash_sum + s->hash_sum;
    perma_stats st;
    int items_ok = perma_get_stats(rt, &st) == PERMA_OK && st.items + s->host_part.nodes == nodes;
    row->count = nodes;
    row->expected = s->expected.nodes;
    return nodes == s->expected.nodes && sum == s->expected.hash_sum && items_ok;
}

/* The procedure: counts its node with two reductions and emits its
 * children, their hashes computed UTS_LANES at a time (uts_child_hashes:
 * eight independent chains in a fixed-length loop, which the compiler runs
 * in SIMD lanes), or with `lanes` 1 one child after another as plain code
 * would (the same hashes: each lane is its own chain). */
static char *procedure_source(const uts_tree *t, unsigned lanes)
{
    char children[160];
    if (t->shape == UTS_GEOMETRIC)
        snprintf(children, sizeof children, "uts_geometric_children(n->hash, n->depth, %uu, %uu)", t->max_depth,
                 t->p16);
    else
        snprintf(children, sizeof children, "uts_binomial_children(n->hash, n->depth, %uu, %uu, %uu)", t->b0,
                 t->m, t->q32);
    const char *format = lanes == 1
        ? "void uts_visit(perma_ctx *ctx, __local const struct uts_node *n)\n"
          "{\n"
          "    reduce_nodes(ctx, 1ul);\n"
          "    reduce_hash_sum(ctx, (ulong)n->hash);\n"
          "    uint k = %s;\n"
          "    struct uts_node child;\n"
          "    child.depth = n->depth + 1u;\n"
          "    for (uint i = 0; i < k; ++i) {\n"
          "        uint h = n->hash ^ (i * 0x9e3779b9u + 0x632be5abu);\n"
          "        for (uint r = 0; r < %uu; ++r)\n"
          "            h = uts_mix(h + r);\n"
          "        child.hash = h;\n"
          "        emit_uts_visit(ctx, &child);\n"
          "    }\n"
          "}\n"
        : "void uts_visit(perma_ctx *ctx, __local const struct uts_node *n)\n"
          "{\n"
          "    reduce_nodes(ctx, 1ul);\n"
          "    reduce_hash_sum(ctx, (ulong)n->hash);\n"
          "    uint k = %s;\n"
          "    struct uts_node child;\n"
          "    child.depth = n->depth + 1u;\n"
          "    for (uint base = 0; base < k; base += UTS_LANES) {\n"
          "        uint hashes[UTS_LANES];\n"
          "        uts_child_hashes(n->hash, base, %uu, hashes);\n"
          "        for (uint j = 0; j < UTS_LANES && base + j < k; ++j) {\n"
          "            child.hash = hashes[j];\n"
          "            emit_uts_visit(ctx, &child);\n"
          "        }\n"
          "    }\n"
          "}\n";
    size_t size = strlen(format) + strlen(children) + 64;
    char *text = malloc(size);
    if (text)
        snprintf(text, size, format, children, t->rounds);
    return text;
}

/* The binomial root has b0 children, far more than any other node: the
 * benchmark keeps the declared maximum m (as it did when the runtime
 * reserved the worst case per batch), so the
 * host expands the root, counts it and seeds its children. */
static int make_seeds(tree_state *s)
{
    const uts_tree *t = s->tree;
    uts_node root = { t->root_hash, 0 };
    memset(&s->host_part, 0, sizeof s->host_part);
    if (t->shape == UTS_GEOMETRIC) {
        s->seed_count = 1;
        s->seeds = malloc(sizeof *s->seeds);
        if (!s->seeds)
            return -1;
        s->seeds[0] = root;
        return 0;
    }
    s->seed_count = uts_children(t, root);
    s->seeds = malloc((s->seed_count ? s->seed_count : 1) * sizeof *s->seeds);
    if (!s->seeds)
        return -1;
    uts_child_nodes(root, s->seed_count, t->rounds, s->seeds);
    s->host_part.nodes = 1;
    s->host_part.hash_sum = root.hash;
    return 0;
}

static void run_perma_variant(const bench_options *o, const bench_variant *v, tree_state *s, const char *source,
                              unsigned group_size, const char *title, bench_report *report)
{
    bench_row row;
    bench_row_init(&row, title, v->name, "nodes");
    row.group_size = group_size;
    row.work_groups = o->groups;
    perma_runtime *rt = bench_perma_create(o, v, group_size, o->groups, &row);
    if (rt) {
        const uts_tree *t = s->tree;
        perma_procedure visit = {
            .name = "uts_visit", .item_type = "struct uts_node", .item_size = sizeof(uts_node),
            .source = source, .source_file = "uts_visit.cl", .function = "uts_visit",
            .emits = { { "uts_visit", t->shape == UTS_GEOMETRIC ? UTS_GEO_CAP : t->m } },
        };
        size_t item_size = sizeof(uts_node);
        bench_workload w = { tree_prepare, tree_verify, s, 1, &s->proc, &item_size };
        if (perma_add_source(rt, device_types, "uts_types.cl") != PERMA_OK ||
            perma_register(rt, &visit, &s->proc) != PERMA_OK ||
            perma_declare_reduction(rt, "nodes", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &s->nodes) != PERMA_OK ||
            perma_declare_reduction(rt, "hash_sum", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &s->hash_sum) != PERMA_OK)
            snprintf(row.message, sizeof row.message, "setup: %s", perma_errmsg(rt));
        else
            bench_perma_measure(rt, v, o, &w, &row);
        bench_perma_verbose(rt, o);
        perma_destroy(rt);
    }
    row.units = (double)s->expected.nodes;
    bench_report_add(report, &row, 0);
}

/* ---- baselines ---- */

typedef struct baseline_arg {
    const uts_tree *tree;
    unsigned threads;
    uint spawn_depth;
    uts_result result;
    int failed;
} baseline_arg;

static void sequential_once(void *p)
{
    baseline_arg *a = p;
    if (uts_count_sequential(a->tree, &a->result) != 0)
        a->failed = 1;
}

static void openmp_once(void *p)
{
    baseline_arg *a = p;
    uts_count_openmp(a->tree, a->threads, a->spawn_depth, &a->result);
}

static void add_openmp_row(const bench_options *o, const uts_tree *t, const uts_result *expected, uint spawn_depth,
                           const char *title, bench_report *report)
{
    baseline_arg a = { .tree = t, .threads = bench_threads(o), .spawn_depth = spawn_depth };
    bench_row row;
    char label[64];
    if (spawn_depth == UINT32_MAX)
        snprintf(label, sizeof label, "openmp tasks (task per node)");
    else
        snprintf(label, sizeof label, "openmp tasks (tasks above depth %u)", spawn_depth);
    bench_row_init(&row, title, label, "nodes");
    row.work_groups = a.threads;
    row.seconds = bench_time_baseline(o, openmp_once, &a);
    row.ran = 1;
    row.units = (double)expected->nodes;
    row.count = a.result.nodes;
    row.expected = expected->nodes;
    row.check = a.result.nodes == expected->nodes && a.result.hash_sum == expected->hash_sum ? BENCH_CHECK_PASS
                                                                                             : BENCH_CHECK_FAIL;
    bench_report_add(report, &row, 0);
}

static int run_tree(const bench_options *o, const uts_tree *t, unsigned group_size, uint cutoff, unsigned lanes,
                    bench_report *report)
{
    char title[96];
    tree_title(t, title, sizeof title);
    bench_report_workload(report, title);

    baseline_arg seq = { .tree = t };
    bench_row row;
    bench_row_init(&row, title, "sequential C", "nodes");
    row.seconds = bench_time_baseline(o, sequential_once, &seq);
    if (seq.failed) {
        fprintf(stderr, "perma-bench: out of memory in the sequential tree count\n");
        return 1;
    }
    row.ran = 1;
    row.units = (double)seq.result.nodes;
    row.count = row.expected = seq.result.nodes;
    snprintf(row.message, sizeof row.message, "%llu nodes, depth %u", (unsigned long long)seq.result.nodes,
             seq.result.max_depth);
    bench_report_add(report, &row, 1);

    add_openmp_row(o, t, &seq.result, UINT32_MAX, title, report);
    add_openmp_row(o, t, &seq.result, cutoff, title, report);

    tree_state *s = calloc(1, sizeof *s);
    char *source = procedure_source(t, lanes);
    if (s) {
        s->tree = t;
        s->expected = seq.result;
    }
    if (!s || !source || make_seeds(s) != 0) {
        free(s);
        free(source);
        fprintf(stderr, "perma-bench: out of memory\n");
        return 1;
    }
    for (unsigned i = 0; i < bench_variant_count(); ++i) {
        bench_variant v;
        if (!bench_variant_select(o, bench_variant_label(i), &v))
            continue;
        for (unsigned d = 0; d < bench_device_passes(o); ++d) {
            bench_variant_use_device(o, d, &v);
            run_perma_variant(o, &v, s, source, group_size, title, report);
        }
    }
    free(s->seeds);
    free(s);
    free(source);
    return 0;
}

int bench_tree(bench_options *o, int argc, char **argv)
{
    static const char *const shapes[] = { "both", "geometric", "binomial", NULL };
    static const char *const lane_counts[] = { "8", "1", NULL }; /* UTS_LANES or 1 */
    unsigned shape = 0, rounds = 0, depth = 0, group_size = 64, cutoff = 3, lane_choice = 0;
    const perma_cli_option rows[] = {
        { PERMA_CLI_CHOICE("shape", "NAME", &shape, shapes, "which tree (default both)") },
        { PERMA_CLI_WHOLE("rounds", "N", &rounds, 0, 4096, "hash rounds per child: the work per node (default 16)") },
        { PERMA_CLI_WHOLE("depth", "D", &depth, 0, 40,
                          "depth limit of the geometric tree (default 10, quick 7; deeper would not finish)") },
        { PERMA_CLI_WHOLE("group-size", "N", &group_size, 0, 4096, "perma work-items per group (default 64)") },
        { PERMA_CLI_WHOLE("cutoff", "D", &cutoff, 0, 4096, "OpenMP: nodes above depth D spawn tasks (default 3)") },
        { PERMA_CLI_CHOICE("lanes", "8|1", &lane_choice, lane_counts,
                           "perma: hash a node's children 8 at a time (default) or one after another, as plain "
                           "code does (the baselines hash 8 at a time)") },
    };
    perma_cli_status parsed = bench_parse(o, "[options]",
                                          NULL, rows, sizeof rows / sizeof rows[0], argc, argv);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    int geometric = shape != 2, binomial = shape != 1;
    unsigned lanes = lane_choice == 1 ? 1 : UTS_LANES;

    uts_tree trees[2];
    unsigned count = 0;
    if (geometric)
        trees[count++] = o->quick ? geometric_quick : geometric_default;
    if (binomial)
        trees[count++] = o->quick ? binomial_quick : binomial_default;

    bench_report *report;
    if (bench_report_open(&report, "tree", o))
        return 1;
    int failed = 0;
    for (unsigned i = 0; i < count && !failed; ++i) {
        if (rounds)
            trees[i].rounds = rounds;
        if (depth && trees[i].shape == UTS_GEOMETRIC)
            trees[i].max_depth = depth;
        failed = run_tree(o, &trees[i], group_size, cutoff, lanes, report);
    }
    unsigned wrong = bench_report_failures(report);
    failed |= bench_report_close(report);
    return failed || wrong ? 1 : 0;
}
