/* `perma-bench plain --workload sort`: quicksort with one range of the key
 * array per item (plain_sort.cl): a range longer than `cutoff` keys is
 * partitioned and its sides emitted, a shorter one sorted inside the item.
 * Against the same quicksort on one core (sort_range_sequential on the
 * whole array) and OpenMP tasks.  The keys are a host array bound with
 * perma_bind_host, as a newcomer binds it: each perma run copies them to
 * the device and back (inside the row's time).  A row passes if the array
 * equals the sequentially sorted one and perma ran one item per range. */
#include "plain.h"
#include "plain_baselines.h"

#include <stdlib.h>
#include <string.h>

typedef struct sort_size {
    uint keys, cutoff;
} sort_size;

static const sort_size size_default = { 1u << 21, 2048 }, size_quick = { 1u << 16, 2048 };
enum { OPENMP_CUTOFF = 8, KEY_SEED = 2026 };

typedef struct sort_state {
    sort_size size;
    uint *input, *keys, *expected;
    perma_proc proc;
    size_t item_size;
    uint64_t ranges;    /* perma's items */
} sort_state;

/* Sort keys [lo, hi) the way the procedure does, counting its items. */
static uint64_t sort_items(uint *keys, uint lo, uint hi, uint cutoff)
{
    if (hi - lo <= cutoff) {
        sort_range_sequential(keys, lo, hi);
        return 1;
    }
    uint p = sort_partition(keys, lo, hi);
    return 1 + sort_items(keys, lo, p, cutoff) + sort_items(keys, p, hi, cutoff);
}

static perma_status sort_setup(void *state, perma_runtime *rt, plain_count count)
{
    sort_state *s = state;
    char defines[64];
    snprintf(defines, sizeof defines, "#define SORT_CUTOFF %uu\n", s->size.cutoff);
    perma_status st = plain_add_sources(rt, count, defines);
    if (st == PERMA_OK)
        st = plain_register(rt, "sort", "struct sort_range", sizeof(struct sort_range), plain_sort_source,
                            "plain_sort.cl", "sort", 2, &s->proc);
    if (st == PERMA_OK)
        st = perma_bind_host(rt, "sort_keys", "__global uint *", s->keys, (size_t)s->size.keys * sizeof *s->keys,
                             PERMA_READ_WRITE);
    return st;
}

static perma_status sort_prepare(void *state, perma_runtime *rt)
{
    sort_state *s = state;
    memcpy(s->keys, s->input, (size_t)s->size.keys * sizeof *s->keys);
    struct sort_range all = { 0u, s->size.keys };
    return perma_seed(rt, s->proc, &all, 1);
}

/* Keys in their sorted place. */
static uint64_t sorted_keys(const sort_state *s)
{
    uint64_t same = 0;
    for (uint i = 0; i < s->size.keys; ++i)
        same += s->keys[i] == s->expected[i];
    return same;
}

static int sort_verify(void *state, perma_runtime *rt, bench_row *row)
{
    sort_state *s = state;
    row->count = sorted_keys(s);
    row->expected = s->size.keys;
    return row->count == row->expected && plain_items_run(rt) == s->ranges;
}

/* ---- baselines ---- */

typedef struct sort_baseline {
    sort_state *s;
    unsigned threads;
    uint spawn_depth;
} sort_baseline;

static void sort_restore(void *p)
{
    sort_baseline *b = p;
    memcpy(b->s->keys, b->s->input, (size_t)b->s->size.keys * sizeof *b->s->keys);
}

static void sort_sequential_once(void *p)
{
    sort_baseline *b = p;
    plain_sort_sequential(b->s->keys, b->s->size.keys);
}

static void sort_openmp_once(void *p)
{
    sort_baseline *b = p;
    plain_sort_openmp(b->s->keys, b->s->size.keys, b->s->size.cutoff, b->threads, b->spawn_depth);
}

static void sort_openmp_row(const plain_options *o, bench_report *report, const char *title, sort_state *s,
                            uint spawn_depth)
{
    sort_baseline b = { .s = s, .threads = bench_threads(o->common), .spawn_depth = spawn_depth };
    bench_timing time = bench_time_runs(o->common, sort_restore, sort_openmp_once, &b);
    char label[48];
    if (spawn_depth == UINT32_MAX)
        snprintf(label, sizeof label, "(task per range)");
    else
        snprintf(label, sizeof label, "(tasks above depth %u)", spawn_depth);
    plain_openmp_row(report, o, title, label, "keys", (double)s->size.keys, time,
                     sorted_keys(s) == s->size.keys);
}

int plain_sort(const plain_options *o, bench_report *report)
{
    sort_state s = { .size = o->common->quick ? size_quick : size_default, .item_size = sizeof(struct sort_range) };
    size_t bytes = (size_t)s.size.keys * sizeof(uint);
    s.input = malloc(bytes);
    s.keys = malloc(bytes);
    s.expected = malloc(bytes);
    if (!s.input || !s.keys || !s.expected) {
        free(s.input);
        free(s.keys);
        free(s.expected);
        fprintf(stderr, "perma-bench plain: out of memory for %u keys\n", s.size.keys);
        return 1;
    }
    for (uint i = 0; i < s.size.keys; ++i)
        s.input[i] = sort_key(KEY_SEED, i);
    memcpy(s.expected, s.input, bytes);
    s.ranges = sort_items(s.expected, 0u, s.size.keys, s.size.cutoff);

    char title[96];
    snprintf(title, sizeof title, "quicksort %u keys, a range per item, sorted inside at %u keys", s.size.keys,
             s.size.cutoff);
    bench_report_workload(report, title);
    sort_baseline seq = { .s = &s };
    bench_timing time = bench_time_runs(o->common, sort_restore, sort_sequential_once, &seq);
    char note[96];
    snprintf(note, sizeof note, "%s; perma: %llu ranges", sorted_keys(&s) == s.size.keys ? "sorted" : "NOT SORTED",
             (unsigned long long)s.ranges);
    plain_sequential_row(report, title, "keys", (double)s.size.keys, time, note);
    int failed = sorted_keys(&s) != s.size.keys;

    sort_openmp_row(o, report, title, &s, UINT32_MAX);
    sort_openmp_row(o, report, title, &s, plain_cutoff(o, OPENMP_CUTOFF));

    plain_perma w = { sort_setup, { sort_prepare, sort_verify, &s, 1, &s.proc, &s.item_size }, .counts_nothing = 1 };
    plain_perma_rows(o, report, title, "keys", (double)s.size.keys, &w);
    free(s.input);
    free(s.keys);
    free(s.expected);
    return failed;
}
