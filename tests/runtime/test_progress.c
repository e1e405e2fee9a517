/* Progress (perma_get_progress, config.progress): the callback is called at
 * the start and end of a run and in between, its counts never decrease and
 * end at the statistics' exact totals, a kernel's progress is seen while
 * it runs, and another thread may ask at any time.
 *
 * The program: `split` items {depth, width} emit `width` children of depth
 * - 1; a chain (width 1) ends in one `gate` item, which waits until the
 * host opens the gate (a word of host memory the kernel sees).  The test's
 * callback opens it once it has seen, while the kernel runs, every split
 * item completed and the gate item queued (and a second thread polling
 * perma_get_progress has seen the run): so the live counts are checked
 * exactly, under every technique, whatever the timing. */
#include "perma_test.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

static const char *types_source = "struct shape { uint depth; uint width; };\n";

static const char *split_source =
    "void split(perma_ctx *ctx, __local const struct shape *s)\n"
    "{\n"
    "    if (s->depth == 0) {\n"
    "        uint gate = 0;\n"
    "        if (s->width == 1)\n"
    "            emit_gate(ctx, &gate);\n"
    "        return;\n"
    "    }\n"
    "    struct shape child = { s->depth - 1, s->width };\n"
    "    for (uint k = 0; k < s->width; ++k)\n"
    "        emit_split(ctx, &child);\n"
    "}\n";

/* Bounded, so that a test that never opens the gate fails rather than hangs
 * (the watchdog's stall limit would stop it too). */
static const char *gate_source =
    "void gate(perma_ctx *ctx, __local const uint *g)\n"
    "{\n"
    "    (void)g;\n"
    "    for (ulong i = 0; i < (1ul << 36) && ctx->buf.open[0] == 0; ++i)\n"
    "        ;\n"
    "    ctx->buf.passed[0] = ctx->buf.open[0];\n"
    "}\n";

#define CHAIN 40u       /* split items of the chain: depth CHAIN - 1 .. 0 */
#define MAX_SEEN 4096

typedef struct recorder {
    perma_progress seen[MAX_SEEN];
    unsigned count;
    volatile uint32_t *open;    /* the gate */
    perma_proc split, gate;
    int opened_live;            /* the gate was opened on a snapshot of a running kernel */
    perma_progress at_open;
    unsigned *also_seen;        /* and not before this is nonzero (the other thread saw the run) */
} recorder;

static void record(void *user, const perma_progress *p)
{
    recorder *r = user;
    if (r->count < MAX_SEEN)
        r->seen[r->count++] = *p;
    if (r->open && !*r->open && p->running && p->procedures[r->split].completed == CHAIN &&
        p->procedures[r->gate].queued == 1 && (!r->also_seen || __atomic_load_n(r->also_seen, __ATOMIC_SEQ_CST))) {
        r->at_open = *p;
        r->opened_live = 1;
        __atomic_store_n(r->open, 1u, __ATOMIC_SEQ_CST);
    }
}

typedef struct fixture {
    perma_runtime *rt;
    perma_proc split, gate;
    cl_mem open_mem;
    uint32_t *open;             /* page-aligned host memory behind open_mem */
    uint32_t passed[1];
} fixture;

static void setup(fixture *f, perma_config *config)
{
    memset(f, 0, sizeof *f);
    f->rt = test_runtime_config(config);
    ck_assert_perma_ok(f->rt, perma_add_source(f->rt, types_source, "shape.cl"));
    perma_procedure split = { .name = "split", .item_type = "struct shape", .item_size = 8,
                              .source = split_source, .source_file = "split.cl", .function = "split",
                              .emits = { { "split", 2 }, { "gate", 1 } } };
    perma_procedure gate = { .name = "gate", .item_type = "uint", .item_size = 4, .source = gate_source,
                             .source_file = "gate.cl", .function = "gate" };
    ck_assert_perma_ok(f->rt, perma_register(f->rt, &split, &f->split));
    ck_assert_perma_ok(f->rt, perma_register(f->rt, &gate, &f->gate));
    f->open = aligned_alloc(4096, 4096);
    ck_assert_ptr_nonnull(f->open);
    memset(f->open, 0, 4096);
    cl_int err;
    f->open_mem = clCreateBuffer(perma_cl_context(f->rt), CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, 4096, f->open,
                                 &err);
    ck_assert_int_eq(err, CL_SUCCESS);
    ck_assert_perma_ok(f->rt, perma_bind_cl(f->rt, "open", "volatile __global uint *", f->open_mem));
    ck_assert_perma_ok(f->rt, perma_bind_host(f->rt, "passed", "__global uint *", f->passed, sizeof f->passed,
                                              PERMA_WRITE));
}

static void teardown(fixture *f)
{
    perma_destroy(f->rt);
    clReleaseMemObject(f->open_mem);
    free(f->open);
}

/* Successive snapshots of one run never go back. */
static void expect_monotone(const perma_progress *a, const perma_progress *b)
{
    ck_assert_uint_eq(a->run, b->run);
    ck_assert_uint_le(a->launches, b->launches);
    ck_assert_uint_le(a->completed, b->completed);
    ck_assert_msg(a->elapsed <= b->elapsed, "elapsed %g then %g", a->elapsed, b->elapsed);
    ck_assert_int_ge(a->running, b->running);
    for (unsigned q = 0; q < a->procedure_count; ++q)
        ck_assert_uint_le(a->procedures[q].completed, b->procedures[q].completed);
}

/* The last snapshot: the run's statistics, exactly. */
static void expect_final(perma_runtime *rt, const perma_progress *last)
{
    perma_stats stats;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &stats));
    ck_assert_int_eq(last->running, 0);
    ck_assert_uint_eq(last->completed, stats.items);
    ck_assert_uint_eq(last->queued, 0);
    ck_assert_uint_eq(last->launches, stats.launches);
    ck_assert_msg(last->elapsed == stats.seconds, "elapsed %g, run %g s", last->elapsed, stats.seconds);
    ck_assert_uint_eq(last->procedure_count, stats.procedure_count);
    for (unsigned q = 0; q < last->procedure_count; ++q) {
        perma_procedure_stats ps;
        ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, (perma_proc)q, &ps));
        ck_assert_str_eq(last->procedures[q].name, ps.name);
        ck_assert_uint_eq(last->procedures[q].completed, ps.items);
        ck_assert_uint_eq(last->procedures[q].queued, 0);
    }
}

/* Another thread asks while the run goes on. */
typedef struct poller {
    perma_runtime *rt;
    int stop;                   /* atomic */
    unsigned count;
    unsigned running_seen;      /* atomic */
    perma_progress first, last;
    int went_back;
    char why[256];
} poller;

static void *poll_progress(void *arg)
{
    poller *p = arg;
    while (!__atomic_load_n(&p->stop, __ATOMIC_SEQ_CST)) {
        perma_progress now;
        if (perma_get_progress(p->rt, &now) != PERMA_OK) {
            snprintf(p->why, sizeof p->why, "perma_get_progress failed");
            p->went_back = 1;
            return NULL;
        }
        if (p->count++ == 0)
            p->first = now;
        else if (now.run == p->last.run &&
                 (now.completed < p->last.completed || now.launches < p->last.launches ||
                  now.elapsed < p->last.elapsed)) {
            snprintf(p->why, sizeof p->why, "completed %llu -> %llu, launches %u -> %u, elapsed %g -> %g",
                     (unsigned long long)p->last.completed, (unsigned long long)now.completed,
                     p->last.launches, now.launches, p->last.elapsed, now.elapsed);
            p->went_back = 1;
        }
        if (now.running)
            __atomic_add_fetch(&p->running_seen, 1, __ATOMIC_SEQ_CST);
        p->last = now;
    }
    return NULL;
}

/* A configuration whose progress callback records into *r (emptied),
 * every millisecond. */
static perma_config recording_config(recorder *r)
{
    memset(r, 0, sizeof *r);
    perma_config config;
    perma_config_init(&config);
    config.progress = record;
    config.progress_user = r;
    config.progress_interval = 0.001;
    /* Live counts move once per batch, and work-first would run the whole
     * chain and its gate item in one batch on one work-item (the gate then
     * waits for counts that only its batch's end publishes); and a tree
     * run depth first never fills the 16-item queues these tests grow.
     * So the queues carry every item here. */
    config.schedule.work_first_items = PERMA_WORK_FIRST_OFF;
    return config;
}

START_TEST(progress_is_seen_live_and_ends_exact)
{
    static recorder r;
    perma_config config = recording_config(&r);
    config.time_limit = 120;
    fixture f;
    setup(&f, &config);
    r.split = f.split;
    r.gate = f.gate;

    perma_progress before;
    ck_assert_perma_ok(f.rt, perma_get_progress(f.rt, &before));
    ck_assert_uint_eq(before.run, 0);
    ck_assert_int_eq(before.running, 0);
    ck_assert_uint_eq(before.completed, 0);
    if (!before.live) {
        /* A device that does not share memory with the host: the gate
         * could not be opened while the kernel runs. */
        fprintf(stderr, "progress is not live on this device: the live part is not tested\n");
        teardown(&f);
        return;
    }
    r.open = f.open;
    poller poll = { .rt = f.rt };
    r.also_seen = &poll.running_seen;
    pthread_t thread;
    ck_assert_int_eq(pthread_create(&thread, NULL, poll_progress, &poll), 0);

    struct { uint32_t depth, width; } chain = { CHAIN - 1, 1 };
    ck_assert_perma_ok(f.rt, perma_seed(f.rt, f.split, &chain, 1));
    ck_assert_perma_ok(f.rt, perma_run(f.rt));
    __atomic_store_n(&poll.stop, 1, __ATOMIC_SEQ_CST);
    pthread_join(thread, NULL);

    /* The gate opened on what the kernel showed while it ran. */
    ck_assert_int_eq(r.opened_live, 1);
    ck_assert_uint_eq(f.passed[0], 1);
    ck_assert_uint_eq(r.at_open.procedures[f.split].completed, CHAIN);
    ck_assert_uint_eq(r.at_open.procedures[f.split].queued, 0);
    ck_assert_uint_eq(r.at_open.procedures[f.gate].completed, 0);
    ck_assert_uint_eq(r.at_open.completed, CHAIN);
    ck_assert_uint_eq(r.at_open.queued, 1);
    ck_assert_uint_ge(r.at_open.launches, 1);

    /* Called at the start (nothing done, the seed queued), in between and
     * at the end; never going back; ending at the statistics. */
    ck_assert_uint_ge(r.count, 3);
    ck_assert_uint_eq(r.seen[0].run, 1);
    ck_assert_int_eq(r.seen[0].running, 1);
    ck_assert_uint_eq(r.seen[0].completed, 0);
    ck_assert_uint_eq(r.seen[0].queued, 1);
    ck_assert_uint_eq(r.seen[0].procedures[f.split].queued, 1);
    for (unsigned i = 1; i < r.count; ++i)
        expect_monotone(&r.seen[i - 1], &r.seen[i]);
    expect_final(f.rt, &r.seen[r.count - 1]);
    ck_assert_uint_eq(r.seen[r.count - 1].completed, CHAIN + 1);

    /* The other thread: never going back, and it saw the run. */
    ck_assert_msg(!poll.went_back, "perma_get_progress went back: %s", poll.why);
    ck_assert_uint_gt(poll.running_seen, 0);
    perma_progress after;
    ck_assert_perma_ok(f.rt, perma_get_progress(f.rt, &after));
    expect_final(f.rt, &after);
    teardown(&f);
}
END_TEST

/* A tree in queues of 16 items: several launches (queue growth), and the
 * counts stay exact across them; a second run starts again from 0. */
START_TEST(progress_is_exact_across_launches_and_runs)
{
    static recorder r;
    perma_config config = recording_config(&r);
    config.queue_capacity = 16;
    config.time_limit = 120;
    fixture f;
    setup(&f, &config);
    struct { uint32_t depth, width; } tree = { 12, 2 };
    for (unsigned run = 1; run <= 2; ++run) {
        r.count = 0;
        ck_assert_perma_ok(f.rt, perma_forget_capacities(f.rt)); /* grow again: several launches */
        ck_assert_perma_ok(f.rt, perma_seed(f.rt, f.split, &tree, 1));
        ck_assert_perma_ok(f.rt, perma_run(f.rt));
        ck_assert_uint_ge(r.count, 2);
        ck_assert_uint_eq(r.seen[0].run, run);
        ck_assert_uint_eq(r.seen[0].completed, 0);
        for (unsigned i = 1; i < r.count; ++i)
            expect_monotone(&r.seen[i - 1], &r.seen[i]);
        expect_final(f.rt, &r.seen[r.count - 1]);
        ck_assert_uint_eq(r.seen[r.count - 1].procedures[f.split].completed, (2u << 12) - 1);
        ck_assert_uint_eq(r.seen[r.count - 1].procedures[f.gate].completed, 0);
        perma_stats stats;
        ck_assert_perma_ok(f.rt, perma_get_stats(f.rt, &stats));
        if (stats.technique == PERMA_TECHNIQUE_MEGAKERNEL)
            ck_assert_uint_gt(stats.regrowths, 0);
        ck_assert_uint_gt(stats.launches, 1);
    }
    teardown(&f);
}
END_TEST

START_TEST(bad_progress_arguments_are_refused)
{
    perma_config config;
    perma_config_init(&config);
    config.progress_interval = -1;
    perma_runtime *rt = NULL;
    perma_error error;
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_ERR_ARGUMENT);
    ck_assert_contains(error.message, "config.progress_interval -1 is not a number of seconds in 0..1e6");
    ck_assert_ptr_null(rt);
    perma_progress p;
    ck_assert_int_eq(perma_get_progress(NULL, &p), PERMA_ERR_ARGUMENT);
    rt = test_runtime(0, 0, 0);
    ck_assert_int_eq(perma_get_progress(rt, NULL), PERMA_ERR_ARGUMENT);
    perma_destroy(rt);
}
END_TEST

PERMA_TEST_MAIN("progress", progress_is_seen_live_and_ends_exact, progress_is_exact_across_launches_and_runs, bad_progress_arguments_are_refused)
