/* Trace mode: the Chrome trace JSON holds one event per batch, whose item
 * counts add up to the items executed; a bad path is a clear error before
 * the run, a full disk one after it that leaves the earlier trace. */
#include "perma_test.h"
#include "tree_procedure.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = calloc(1, (size_t)size + 1);
    ck_assert_uint_eq(fread(text, 1, (size_t)size, f), (size_t)size);
    fclose(f);
    return text;
}

/* Sum of the "items" of all executed batches (not donations, which move
 * items), their count, the number of donations and the highest tid. */
static void scan_events(const char *json, uint64_t *items, unsigned *events, unsigned *donations,
                        unsigned *max_tid)
{
    *items = 0;
    *events = 0;
    *donations = 0;
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
        ++*events;
    }
}

START_TEST(trace_events_cover_every_item)
{
    char path[] = "/tmp/perma-trace-XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    close(fd);
    perma_config config;
    perma_config_init(&config);
    config.trace_path = path;
    perma_runtime *rt = test_runtime_config(&config);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, 0, counts, sums);
    struct tree_node root = { 0, 11, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));

    char *json = read_file(path);
    ck_assert_contains(json, "\"traceEvents\":[");
    ck_assert_contains(json, "\"name\":\"tree\"");
    uint64_t items;
    unsigned events, donations, max_tid;
    scan_events(json, &items, &events, &donations, &max_tid);
    ck_assert_uint_eq(donations, st.donations);
    ck_assert_uint_eq(items, st.items);
    ck_assert_uint_eq(items, (2u << 11) - 1);
    if (st.technique == PERMA_TECHNIQUE_MEGAKERNEL) {
        perma_procedure_stats ps;
        ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
        ck_assert_uint_eq(events, ps.batches); /* one event per batch */
        ck_assert_uint_lt(max_tid, st.work_groups);
        ck_assert_contains(json, "\"name\":\"group 0\"");
        if (st.steals > 0)
            ck_assert_contains(json, "\"kind\":\"steal\"");
    } else {
        ck_assert_uint_eq(events, st.launches);   /* one event per host step */
        ck_assert_contains(json, "host steps");
    }
    free(json);
    remove(path);
    perma_destroy(rt);
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
    char *earlier = read_file(path);
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit = { 200, 200 };
    ck_assert_int_eq(setrlimit(RLIMIT_FSIZE, &limit), 0);
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_IO);
    char expected[256];
    snprintf(expected, sizeof expected, "cannot write the trace: writing '%s' failed: %s (the file there "
             "before is unchanged)", path, strerror(EFBIG));
    ck_assert_str_eq(perma_errmsg(rt), expected);
    char *now = read_file(path);
    ck_assert_str_eq(now, earlier);
    free(now);
    free(earlier);
    remove(path);
    ck_assert_int_eq(rmdir(dir), 0); /* empty: no temporary file left */
    perma_destroy(rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("trace");
    TCase *tc = tcase_create("trace");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, trace_events_cover_every_item);
    tcase_add_test(tc, unwritable_trace_path_is_an_error);
    tcase_add_test(tc, full_disk_keeps_the_earlier_trace);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
