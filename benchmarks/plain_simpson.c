/* `perma-bench plain --workload simpson`: adaptive Simpson integration in
 * double with one interval per item (plain_simpson.cl), against the
 * textbook recursion (plain_simpson_sequential) and OpenMP tasks.
 *
 * The interval tree is exact: host and device do the same correctly
 * rounded operations, so a perma row passes only with the sequential
 * number of accepted intervals, the same sum of their areas' bit patterns
 * (every accepted area bit for bit the sequential one) and one item per
 * interval.  The integral itself is the sum of the accepted areas, which
 * perma adds in the order the groups happen to accept them: it differs
 * from the sequential sum in the last bits, from run to run.  It is
 * checked against the bound of any summation order, accepted * DBL_EPSILON
 * relative (the areas are positive), and its difference is in the note.
 * The OpenMP tasks add the two halves' sums after a taskwait, which is the
 * sequential order: bit-identical. */
#include "plain.h"
#include "plain_baselines.h"

#include <float.h>
#include <math.h>
#include <string.h>

enum { MAX_DEPTH = 40, OPENMP_CUTOFF = 10 };
static const double eps_default = 1e-9, eps_quick = 1e-4;

typedef struct simpson_state {
    struct simpson_interval root;
    perma_proc proc;
    size_t item_size;
    plain_lines accepted, area, area_bits;
    plain_simpson_result expected;
} simpson_state;

static perma_status simpson_setup(void *state, perma_runtime *rt, unsigned groups, plain_count count)
{
    simpson_state *s = state;
    char defines[64];
    snprintf(defines, sizeof defines, "#define SIMPSON_MAX_DEPTH %uu\n", (unsigned)MAX_DEPTH);
    perma_status st = plain_add_sources(rt, count, defines);
    if (st == PERMA_OK)
        st = plain_register(rt, "simpson", "struct simpson_interval", sizeof(struct simpson_interval),
                            plain_simpson_source, "plain_simpson.cl", "simpson", 2, &s->proc);
    if (st == PERMA_OK)
        st = plain_lines_bind(rt, &s->accepted, groups, "simpson_accepted", "__global uint *");
    if (st == PERMA_OK)
        st = plain_lines_bind(rt, &s->area, groups, "simpson_area", "__global double *");
    if (st == PERMA_OK)
        st = plain_lines_bind(rt, &s->area_bits, groups, "simpson_area_bits", "__global ulong *");
    return st;
}

static perma_status simpson_prepare(void *state, perma_runtime *rt)
{
    simpson_state *s = state;
    plain_lines_clear(&s->accepted);
    plain_lines_clear(&s->area);
    plain_lines_clear(&s->area_bits);
    return perma_seed(rt, s->proc, &s->root, 1);
}

/* The results of a run: where the counting of plain_simpson.cl ends up. */
static plain_simpson_result simpson_results(const simpson_state *s)
{
    plain_simpson_result r = { plain_lines_sum_u32(&s->accepted), plain_lines_sum_u64(&s->area_bits),
                               plain_lines_sum_double(&s->area) };
    return r;
}

static int simpson_same(const plain_simpson_result *r, const plain_simpson_result *expected)
{
    double bound = (double)expected->accepted * DBL_EPSILON * fabs(expected->area);
    return r->accepted == expected->accepted && r->area_bits == expected->area_bits &&
           fabs(r->area - expected->area) <= bound;
}

static int simpson_verify(void *state, perma_runtime *rt, bench_row *row)
{
    simpson_state *s = state;
    plain_simpson_result r = simpson_results(s);
    row->count = r.accepted;
    row->expected = s->expected.accepted;
    snprintf(row->message, sizeof row->message, "integral %.17g, %+.1e relative to sequential", r.area,
             (r.area - s->expected.area) / s->expected.area);
    return simpson_same(&r, &s->expected) && plain_items_run(rt) == 2 * s->expected.accepted - 1;
}

/* ---- baselines ---- */

typedef struct simpson_baseline {
    const struct simpson_interval *root;
    unsigned threads;
    uint spawn_depth;
    plain_simpson_result result;
} simpson_baseline;

static void simpson_sequential_once(void *p)
{
    simpson_baseline *b = p;
    plain_simpson_sequential(b->root, MAX_DEPTH, &b->result);
}

static void simpson_openmp_once(void *p)
{
    simpson_baseline *b = p;
    plain_simpson_openmp(b->root, MAX_DEPTH, b->threads, b->spawn_depth, &b->result);
}

static void simpson_openmp_row(const plain_options *o, bench_report *report, const char *title,
                               const simpson_state *s, uint spawn_depth)
{
    simpson_baseline b = { .root = &s->root, .threads = bench_threads(o->common), .spawn_depth = spawn_depth };
    bench_timing time = bench_time_runs(o->common, NULL, simpson_openmp_once, &b);
    char label[48];
    if (spawn_depth == UINT32_MAX)
        snprintf(label, sizeof label, "(task per interval)");
    else
        snprintf(label, sizeof label, "(tasks above depth %u)", spawn_depth);
    int ok = b.result.accepted == s->expected.accepted && b.result.area_bits == s->expected.area_bits &&
             b.result.area == s->expected.area;
    plain_openmp_row(report, o, title, label, "intervals", 2.0 * (double)s->expected.accepted - 1.0, time, ok);
}

int plain_simpson(const plain_options *o, bench_report *report)
{
    double eps = o->common->quick ? eps_quick : eps_default;
    char title[96];
    snprintf(title, sizeof title, "adaptive simpson eps=%g, double, an interval per item", eps);
    bench_report_workload(report, title);

    simpson_state s = { .root = simpson_root(0.0, 1.0, eps), .item_size = sizeof(struct simpson_interval) };
    simpson_baseline seq = { .root = &s.root };
    bench_timing time = bench_time_runs(o->common, NULL, simpson_sequential_once, &seq);
    s.expected = seq.result;
    double intervals = 2.0 * (double)s.expected.accepted - 1.0;
    char note[96];
    snprintf(note, sizeof note, "%llu accepted, integral %.17g", (unsigned long long)s.expected.accepted,
             s.expected.area);
    plain_sequential_row(report, title, "intervals", intervals, time, note);

    simpson_openmp_row(o, report, title, &s, UINT32_MAX);
    simpson_openmp_row(o, report, title, &s, plain_cutoff(o, OPENMP_CUTOFF));

    plain_perma w = { simpson_setup, { simpson_prepare, simpson_verify, &s, 1, &s.proc, &s.item_size } };
    plain_perma_rows(o, report, title, "intervals", intervals, &w);
    plain_lines_free(&s.accepted);
    plain_lines_free(&s.area);
    plain_lines_free(&s.area_bits);
    return 0;
}
