/* Trace mode: the Chrome trace JSON holds one event per batch, whose item
 * counts add up to the items executed; every run of the process stays in
 * the file, its events in host time within the run, never overlapping on
 * a track; the converter's summary (runtime/tools/trace_to_svg.py) counts
 * the same items as the statistics; a bad path is a clear error before the
 * run, a full disk one after it that leaves the earlier trace. */
#include "perma_test.h"
#include "tree_procedure.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

/* Sum of the "items" of all executed batches (not donations, which move
 * items), their count, the number of donations, of batches that ran only
 * work-first stacks ("stack") and the highest tid. */
static void scan_events(const char *json, uint64_t *items, unsigned *events, unsigned *donations,
                        unsigned *stacks, unsigned *max_tid)
{
    *items = 0;
    *events = 0;
    *donations = 0;
    *stacks = 0;
    *max_tid = 0;
    for (const char *p = json; (p = strstr(p, "\"ph\":\"X\"")) != NULL; ++p) {
        const char *tid = strstr(p, "\"tid\":");
        const char *n = strstr(p, "\"items\":");
        const char *kind = strstr(p, "\"kind\":\"");
        ck_assert_ptr_nonnull(tid);
        ck_assert_ptr_nonnull(n);
        ck_assert_ptr_nonnull(kind);
        unsigned t = (unsigned)strtoul(tid + 6, NULL, 10);
        if (t > *max_tid)
            *max_tid = t;
        if (strncmp(kind + 8, "donate\"", 7) == 0) {
            ++*donations;
            continue;
        }
        *items += strtoull(n + 8, NULL, 10);
        *stacks += strncmp(kind + 8, "stack\"", 6) == 0;
        ++*events;
    }
}

/* A configuration tracing into a new temporary file `path` (a
 * "/tmp/perma-trace-XXXXXX" template, filled in). */
static perma_config trace_config(char *path)
{
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    close(fd);
    perma_config config;
    perma_config_init(&config);
    config.trace_path = path;
    return config;
}

START_TEST(trace_events_cover_every_item)
{
    char path[] = "/tmp/perma-trace-XXXXXX";
    perma_config config = trace_config(path);
    perma_runtime *rt = test_runtime_config(&config);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, 0, counts, sums);
    struct tree_node root = { 0, 11, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));

    char *json = test_read_file(path);
    ck_assert_contains(json, "\"traceEvents\":[");
    ck_assert_contains(json, "\"name\":\"tree\"");
    uint64_t items;
    unsigned events, donations, stacks, max_tid;
    scan_events(json, &items, &events, &donations, &stacks, &max_tid);
    ck_assert_uint_eq(donations, st.donations);
    ck_assert_uint_eq(items, st.items);
    ck_assert_uint_eq(items, (2u << 11) - 1);
    if (st.technique == PERMA_TECHNIQUE_MEGAKERNEL) {
        perma_procedure_stats ps;
        ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
        /* One event per batch, and per batch that only ran stacks (the
         * items of a batch's event include what it ran from stacks). */
        ck_assert_uint_eq(events, ps.batches + stacks);
        ck_assert(stacks == 0 || ps.stacked_items > 0);
        /* The run's metadata says what the stacks did. */
        char expected[160];
        snprintf(expected, sizeof expected, "\"stack_items\":%u,\"stacked_items\":%llu,\"stack_peak\":%u,"
                 "\"stack_spills\":%llu}", st.stack_items, (unsigned long long)st.stacked_items, st.stack_peak,
                 (unsigned long long)st.stack_spills);
        ck_assert_contains(json, expected);
        ck_assert_uint_lt(max_tid, st.work_groups);
        ck_assert_contains(json, "\"name\":\"group 0\"");
        if (st.steals > 0)
            ck_assert_contains(json, "\"kind\":\"steal\"");
        /* A batch that only ran stacks runs items of any procedure: it is
         * the stacks' event, as are the items they gave another group. */
        ck_assert_uint_eq(test_occurrences(json, "{\"name\":\"(stacks)\",\"cat\":\"stack\""), stacks);
    } else {
        ck_assert_uint_eq(events, st.launches);   /* one event per host step */
        ck_assert_contains(json, "host steps");
    }
    free(json);
    remove(path);
    perma_destroy(rt);
}
END_TEST

/* One line of the file: an event ("ph":"X") or a run's process_name. */
typedef struct trace_line {
    int event;                  /* 1: a batch, 0: a run's metadata */
    unsigned pid, tid, items;
    double ts, dur;             /* events */
    double start_us, seconds;   /* runs */
    int donate;
} trace_line;

static double number_after(const char *line, const char *key)
{
    const char *at = strstr(line, key);
    ck_assert_msg(at != NULL, "no %s in %s", key, line);
    return strtod(at + strlen(key), NULL);
}

/* Parse the file's lines; returns how many (at most max). */
static unsigned parse_lines(const char *json, trace_line *out, unsigned max)
{
    unsigned n = 0;
    for (const char *line = json; line && *line && n < max; line = strchr(line, '\n'), line = line ? line + 1 : NULL) {
        const char *end = strchr(line, '\n');
        char text[1024];
        size_t length = end ? (size_t)(end - line) : strlen(line);
        if (length >= sizeof text)
            continue;
        memcpy(text, line, length);
        text[length] = '\0';
        trace_line *t = &out[n];
        memset(t, 0, sizeof *t);
        if (strstr(text, "\"ph\":\"X\"")) {
            t->event = 1;
            t->pid = (unsigned)number_after(text, "\"pid\":");
            t->tid = (unsigned)number_after(text, "\"tid\":");
            t->items = (unsigned)number_after(text, "\"items\":");
            t->ts = number_after(text, "\"ts\":");
            t->dur = number_after(text, "\"dur\":");
            t->donate = strstr(text, "\"kind\":\"donate\"") != NULL;
            ++n;
        } else if (strstr(text, "\"name\":\"process_name\"")) {
            t->pid = (unsigned)number_after(text, "\"pid\":");
            t->start_us = number_after(text, "\"start_us\":");
            t->seconds = number_after(text, "\"seconds\":");
            ++n;
        }
    }
    return n;
}

#define RUNS 4          /* three runs of one runtime, one of another */
#define MAX_LINES 200000

START_TEST(every_run_stays_in_the_file_in_real_time)
{
    char path[] = "/tmp/perma-trace-XXXXXX";
    perma_config config = trace_config(path);
    perma_runtime *rts[2] = { test_runtime_config(&config), test_runtime_config(&config) };
    uint32_t counts[2][2] = { { 0, 0 }, { 0, 0 } };
    uint64_t sums[2][1] = { { 0 }, { 0 } };
    perma_proc ids[2] = { tree_add(rts[0], 0, counts[0], sums[0]), tree_add(rts[1], 0, counts[1], sums[1]) };
    uint64_t items[RUNS];
    double seconds[RUNS];
    for (unsigned run = 0; run < RUNS; ++run) {
        perma_runtime *rt = rts[run == RUNS - 1];
        struct tree_node root = { 0, 8 + run, 1, 0 };
        ck_assert_perma_ok(rt, perma_seed(rt, ids[run == RUNS - 1], &root, 1));
        ck_assert_perma_ok(rt, perma_run(rt));
        perma_stats st;
        ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
        items[run] = st.items;
        seconds[run] = st.seconds;
        ck_assert_uint_eq(items[run], (2u << (8 + run)) - 1);
    }

    char *json = test_read_file(path);
    static trace_line lines[MAX_LINES];
    unsigned n = parse_lines(json, lines, MAX_LINES);
    free(json);
    double start_us[RUNS + 1] = { 0 };
    unsigned runs = 0;
    for (unsigned i = 0; i < n; ++i)
        if (!lines[i].event) {
            ck_assert_uint_eq(lines[i].pid, runs + 1); /* runs numbered in order */
            start_us[runs] = lines[i].start_us;
            ck_assert_msg(lines[i].seconds == seconds[runs] || fabs(lines[i].seconds - seconds[runs]) < 1e-6,
                          "run %u: %g s in the file, %g s run", runs + 1, lines[i].seconds, seconds[runs]);
            if (runs > 0) /* the runs follow each other on the time line */
                ck_assert_double_ge(start_us[runs], start_us[runs - 1] + seconds[runs - 1] * 1e6 - 0.01);
            ++runs;
        }
    ck_assert_uint_eq(runs, RUNS);
    for (unsigned run = 0; run < RUNS; ++run) {
        double lo = start_us[run], hi = start_us[run] + seconds[run] * 1e6;
        uint64_t sum = 0;
        /* Per track: sorted by start, each event ends before the next one
         * starts (0.01 us for the 3 printed decimals). */
        for (unsigned i = 0; i < n; ++i) {
            const trace_line *e = &lines[i];
            if (!e->event || e->pid != run + 1)
                continue;
            ck_assert_msg(e->ts >= lo - 0.01 && e->ts + e->dur <= hi + 0.01,
                          "run %u: event at %.3f+%.3f us outside the run's %.3f..%.3f us", run + 1, e->ts, e->dur, lo,
                          hi);
            ck_assert_double_ge(e->dur, 0.0);
            if (!e->donate)
                sum += e->items;
            for (unsigned j = 0; j < n; ++j) {
                const trace_line *f = &lines[j];
                if (j == i || !f->event || f->pid != e->pid || f->tid != e->tid || f->ts < e->ts)
                    continue;
                if (f->ts == e->ts && j < i)
                    continue;
                ck_assert_msg(f->ts >= e->ts + e->dur - 0.01, "run %u track %u: an event at %.3f us starts before the "
                              "one at %.3f us ends (%.3f us)", run + 1, e->tid, f->ts, e->ts, e->ts + e->dur);
            }
        }
        ck_assert_uint_eq(sum, items[run]);
    }

    /* The converter's summary: the same items, run by run (the tree's
     * batches and the batches that only ran stacks, "(stacks)"). */
    char command[512];
    snprintf(command, sizeof command, "python3 runtime/tools/trace_to_svg.py %s --json", path);
    FILE *pipe = popen(command, "r");
    ck_assert_ptr_nonnull(pipe);
    static char summary[1 << 16];
    size_t got = fread(summary, 1, sizeof summary - 1, pipe);
    summary[got] = '\0';
    ck_assert_int_eq(pclose(pipe), 0);
    const char *at = summary;
    for (unsigned run = 0; run < RUNS; ++run) {
        char key[32];
        snprintf(key, sizeof key, "\"run\": %u,", run + 1);
        at = strstr(at, key);
        ck_assert_msg(at != NULL, "no %s in the summary: %s", key, summary);
        const char *tree = strstr(at, "\"tree\""), *stacks = strstr(at, "\"(stacks)\"");
        snprintf(key, sizeof key, "\"run\": %u,", run + 2);
        const char *next = strstr(at, key);
        ck_assert_ptr_nonnull(tree);
        ck_assert(!next || tree < next);
        uint64_t summed = (uint64_t)number_after(tree, "\"items\": ");
        if (stacks && (!next || stacks < next))
            summed += (uint64_t)number_after(stacks, "\"items\": ");
        ck_assert_uint_eq(summed, items[run]);
        double idle = number_after(at, "\"idle_share\": ");
        ck_assert_msg(idle >= 0.0 && idle <= 1.0, "idle share %g", idle);
    }
    remove(path);
    perma_destroy(rts[0]);
    perma_destroy(rts[1]);
}
END_TEST

START_TEST(unwritable_trace_path_is_an_error)
{
    perma_config config;
    perma_config_init(&config);
    config.trace_path = "/nonexistent-dir/trace.json";
    perma_runtime *rt = test_runtime_config(&config);
    perma_procedure p = { .name = "noop", .item_type = "uint", .item_size = 4,
                          .source = "void noop(perma_ctx *c, __local const uint *x) { (void)c; (void)x; }\n",
                          .function = "noop" };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    uint32_t one = 1;
    ck_assert_perma_ok(rt, perma_seed(rt, id, &one, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_IO);
    ck_assert_str_eq(perma_errmsg(rt), "cannot write the trace: cannot create '/nonexistent-dir/trace.json': "
                                       "No such file or directory");
    /* Checked before the run, not after its work. */
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_eq(st.launches, 0);
    perma_destroy(rt);
}
END_TEST

/* A trace that does not fit the disk (a file size limit, SIGXFSZ ignored)
 * fails the run naming the reason and leaves the earlier trace as it was. */
START_TEST(full_disk_keeps_the_earlier_trace)
{
    char dir[] = "/tmp/perma-trace-XXXXXX", path[64];
    ck_assert_ptr_nonnull(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/trace.json", dir);
    perma_config config;
    perma_config_init(&config);
    config.trace_path = path;
    perma_runtime *rt = test_runtime_config(&config);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, 0, counts, sums);
    struct tree_node root = { 0, 6, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt)); /* builds the program, unlimited */
    char *earlier = test_read_file(path);
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit = { 200, 200 };
    ck_assert_int_eq(setrlimit(RLIMIT_FSIZE, &limit), 0);
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_IO);
    char expected[256];
    snprintf(expected, sizeof expected, "cannot write the trace: writing '%s' failed: %s (the file there "
             "before is unchanged)", path, strerror(EFBIG));
    ck_assert_str_eq(perma_errmsg(rt), expected);
    char *now = test_read_file(path);
    ck_assert_str_eq(now, earlier);
    free(now);
    free(earlier);
    remove(path);
    ck_assert_int_eq(rmdir(dir), 0); /* empty: no temporary file left */
    perma_destroy(rt);
}
END_TEST

PERMA_TEST_MAIN("trace", trace_events_cover_every_item, every_run_stays_in_the_file_in_real_time, unwritable_trace_path_is_an_error, full_disk_keeps_the_earlier_trace)
