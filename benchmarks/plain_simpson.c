/* `perma-bench plain --workload simpson`: adaptive Simpson integration in
 * double with one interval per item (plain_simpson.cl), against the
 * textbook recursion (plain_simpson_sequential) and OpenMP tasks.
 *
 * The interval tree is exact: host and device do the same correctly
 * rounded operations, so a perma row passes only with the sequential
 * number of accepted intervals, the same sum of their areas' bit patterns
 * (every accepted area bit for bit the sequential one) and one item per
 * interval.  The integral itself is the sum of the accepted areas.  As a
 * reduction (the default) it is their exact sum rounded once: the same
 * bits under every schedule and run, which every reduction row must give,
 * though not the sequential sum's bits (that one rounds at every add).
 * With --count atomic perma adds in the order the groups happen to accept
 * the intervals: the last bits change from run to run.  Both are checked
 * against the bound of any summation order, accepted * DBL_EPSILON
 * relative (the areas are positive), and the difference is in the note.
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
    uint64_t accepted, area_bits; /* the results, described by `results` */
    double area;
    plain_result results[3];
    plain_count count;       /* of the runtime being measured */
    double reduced_area;     /* the integral of the first reduction run */
    int reduced;             /* and whether there was one */
    plain_simpson_result expected;
} simpson_state;

static perma_status simpson_setup(void *state, perma_runtime *rt, plain_count count)
{
    simpson_state *s = state;
    s->count = count;
    char defines[64];
    snprintf(defines, sizeof defines, "#define SIMPSON_MAX_DEPTH %uu\n", (unsigned)MAX_DEPTH);
    perma_status st = plain_add_sources(rt, count, defines);
    if (st == PERMA_OK)
        st = plain_register(rt, "simpson", "struct simpson_interval", sizeof(struct simpson_interval),
                            plain_simpson_source, "plain_simpson.cl", "simpson", 2, &s->proc);
    if (st == PERMA_OK)
        st = plain_results_declare(rt, count, s->results, 3);
    return st;
}

static perma_status simpson_prepare(void *state, perma_runtime *rt)
{
    simpson_state *s = state;
    plain_results_clear(s->results, 3);
    return perma_seed(rt, s->proc, &s->root, 1);
}

/* The results of a run: where the counting of plain_simpson.cl ends up. */
static plain_simpson_result simpson_results(const simpson_state *s)
{
    plain_simpson_result r = { s->accepted, s->area_bits, s->area };
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
    int same_reduction = 1;
    if (s->count == PLAIN_COUNT_REDUCE) {
        if (!s->reduced)
            s->reduced_area = r.area;
        s->reduced = 1;
        same_reduction = memcmp(&r.area, &s->reduced_area, sizeof r.area) == 0;
        if (!same_reduction)
            snprintf(row->message, sizeof row->message, "integral %.17g, not the %.17g of the first reduction",
                     r.area, s->reduced_area);
    }
    return same_reduction && simpson_same(&r, &s->expected) && plain_items_run(rt) == 2 * s->expected.accepted - 1;
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
    s.results[0] = (plain_result){ "simpson_accepted", PERMA_TYPE_ULONG, &s.accepted };
    s.results[1] = (plain_result){ "simpson_area", PERMA_TYPE_DOUBLE, &s.area };
    s.results[2] = (plain_result){ "simpson_area_bits", PERMA_TYPE_ULONG, &s.area_bits };
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

    plain_perma w = { simpson_setup, { simpson_prepare, simpson_verify, &s, 1, &s.proc, &s.item_size }, 0 };
    plain_perma_rows(o, report, title, "intervals", intervals, &w);
    return 0;
}
