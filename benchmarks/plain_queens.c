/* `perma-bench plain --workload queens`: N-Queens with one partial board
 * per item (plain_queens.cl): boards with fewer than `cutoff` queens emit
 * a child per free column, boards with `cutoff` queens are solved inside
 * their item.  Against queens_solve on the empty board (sequential C) and
 * OpenMP tasks.  A perma row passes with the sequential number of
 * solutions and one item per board of up to `cutoff` queens. */
#include "plain.h"
#include "plain_baselines.h"

#include <string.h>

typedef struct queens_size {
    uint n, cutoff;   /* perma: boards of `cutoff` queens are solved inside the item */
} queens_size;

static const queens_size size_default = { 13, 4 }, size_quick = { 10, 3 };
enum { OPENMP_CUTOFF = 3 };

typedef struct queens_state {
    queens_size size;
    perma_proc proc;
    size_t item_size;
    uint64_t solutions; /* the result, described by `result` */
    plain_result result;
    uint64_t expected, boards;
} queens_state;

/* Boards of at most `cutoff` queens below b, b included: perma's items. */
static uint64_t boards_above(uint n, uint cutoff, struct queens_board b)
{
    uint64_t count = 1;
    if (b.row >= cutoff)
        return count;
    for (uint free = queens_free(n, b.columns, b.left, b.right); free; free &= free - 1u)
        count += boards_above(n, cutoff, queens_place(n, b.row, b.columns, b.left, b.right, free & (0u - free)));
    return count;
}

static perma_status queens_setup(void *state, perma_runtime *rt, plain_count count)
{
    queens_state *s = state;
    char defines[96];
    snprintf(defines, sizeof defines, "#define QUEENS_N %uu\n#define QUEENS_CUTOFF %uu\n", s->size.n,
             s->size.cutoff);
    perma_status st = plain_add_sources(rt, count, defines);
    if (st == PERMA_OK)
        st = plain_register(rt, "queens", "struct queens_board", sizeof(struct queens_board), plain_queens_source,
                            "plain_queens.cl", "queens", s->size.n, &s->proc);
    if (st == PERMA_OK)
        st = plain_results_declare(rt, count, &s->result, 1);
    return st;
}

static perma_status queens_prepare(void *state, perma_runtime *rt)
{
    queens_state *s = state;
    plain_results_clear(&s->result, 1);
    struct queens_board empty = { 0u, 0u, 0u, 0u };
    return perma_seed(rt, s->proc, &empty, 1);
}

/* The result of a run: where the counting of plain_queens.cl ends up. */
static uint64_t queens_results(const queens_state *s)
{
    return s->solutions;
}

static int queens_verify(void *state, perma_runtime *rt, bench_row *row)
{
    queens_state *s = state;
    row->count = queens_results(s);
    row->expected = s->expected;
    return row->count == s->expected && plain_items_run(rt) == s->boards;
}

/* ---- baselines ---- */

typedef struct queens_baseline {
    uint n;
    unsigned threads;
    uint spawn_depth;
    uint64_t solutions;
} queens_baseline;

static void queens_sequential_once(void *p)
{
    queens_baseline *b = p;
    b->solutions = plain_queens_sequential(b->n);
}

static void queens_openmp_once(void *p)
{
    queens_baseline *b = p;
    b->solutions = plain_queens_openmp(b->n, b->threads, b->spawn_depth);
}

static void queens_openmp_row(const plain_options *o, bench_report *report, const char *title,
                              const queens_state *s, uint spawn_depth)
{
    queens_baseline b = { .n = s->size.n, .threads = bench_threads(o->common), .spawn_depth = spawn_depth };
    bench_timing time = bench_time_runs(o->common, NULL, queens_openmp_once, &b);
    char label[48];
    /* At perma's cutoff a task is what perma makes an item of. */
    if (spawn_depth == s->size.cutoff)
        snprintf(label, sizeof label, "(task per board)");
    else
        snprintf(label, sizeof label, "(tasks above depth %u)", spawn_depth);
    plain_openmp_row(report, o, title, label, "boards", (double)s->boards, time, b.solutions == s->expected);
}

int plain_queens(const plain_options *o, bench_report *report)
{
    queens_state s = { .size = o->common->quick ? size_quick : size_default, .item_size = sizeof(struct queens_board) };
    s.result = (plain_result){ "queens_solutions", PERMA_TYPE_ULONG, &s.solutions };
    char title[96];
    snprintf(title, sizeof title, "n-queens n=%u, a board per item, solved inside from %u queens", s.size.n,
             s.size.cutoff);
    bench_report_workload(report, title);

    s.boards = boards_above(s.size.n, s.size.cutoff, (struct queens_board){ 0u, 0u, 0u, 0u });
    queens_baseline seq = { .n = s.size.n };
    bench_timing time = bench_time_runs(o->common, NULL, queens_sequential_once, &seq);
    s.expected = seq.solutions;
    char note[96];
    snprintf(note, sizeof note, "%llu solutions; perma: %llu boards", (unsigned long long)s.expected,
             (unsigned long long)s.boards);
    plain_sequential_row(report, title, "boards", (double)s.boards, time, note);

    queens_openmp_row(o, report, title, &s, s.size.cutoff);
    uint cutoff = plain_cutoff(o, OPENMP_CUTOFF);
    if (cutoff != s.size.cutoff)
        queens_openmp_row(o, report, title, &s, cutoff);

    plain_perma w = { queens_setup, { queens_prepare, queens_verify, &s, 1, &s.proc, &s.item_size }, 0 };
    plain_perma_rows(o, report, title, "boards", (double)s.boards, &w);
    return 0;
}
