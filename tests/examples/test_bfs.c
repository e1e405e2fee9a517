/* BFS levels from perma equal the sequential BFS, for a small edge-list
 * file and a generated power-law graph, under the technique and strategy of
 * the test's variant; the edge-list reader reports malformed lines by file
 * and line; the generator is deterministic. */
#include "example_test.h"

#include <stdlib.h>
#include <string.h>

#include "bfs.h"
#include "bfs_options.h"

static char *data_path(const char *name)
{
    const char *dir = getenv("EXAMPLE_DATA_DIR");
    static char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir && *dir ? dir : "tests/examples/data", name);
    return path;
}

static void load(bfs_graph *g, const bfs_edges *e, int undirected)
{
    char message[512];
    ck_assert_msg(bfs_build_csr(e, undirected, g, message, sizeof message) == BFS_OK, "%s", message);
}

/* perma levels from `source` equal the sequential ones. */
static void assert_perma_levels(const bfs_graph *g, uint32_t source)
{
    uint32_t *want = malloc((size_t)g->vertices * sizeof *want);
    uint32_t *got = malloc((size_t)g->vertices * sizeof *got);
    ck_assert(want && got);
    ck_assert_int_eq(bfs_sequential(g, source, want), 0);
    example_run_options run = { .work_groups = 0 };
    example_test_variant(&run.schedule);
    char message[2048];
    bfs_status st = bfs_perma(g, &run, source, got, message, sizeof message);
    ck_assert_msg(st == BFS_OK, "%s", message);
    size_t differ = 0, first = 0;
    for (uint32_t v = 0; v < g->vertices; ++v)
        if (got[v] != want[v] && differ++ == 0)
            first = v;
    ck_assert_msg(differ == 0, "%zu of %u levels differ; first: vertex %zu perma %d, sequential %d",
                  differ, g->vertices, first, (int)got[first], (int)want[first]);
    free(want);
    free(got);
}

START_TEST(small_file_levels)
{
    bfs_edges e;
    char message[512];
    ck_assert_msg(bfs_read_edges(data_path("small.edges"), &e, message, sizeof message) == BFS_OK, "%s", message);
    ck_assert_uint_eq(e.count, 24);
    ck_assert_uint_eq(e.vertices, 23);
    bfs_graph g;
    load(&g, &e, 1);
    /* The sequential BFS itself, on levels worked out by hand. */
    uint32_t levels[23];
    ck_assert_int_eq(bfs_sequential(&g, 0, levels), 0);
    static const int want[23] = { 0, 1, 1, 2, 3, 3, 3, 3, 3, 3, 3, 3, 1, 3, 3, 3,
                                  -1, -1, -1, -1, -1, -1, -1 };
    for (int v = 0; v < 23; ++v)
        ck_assert_msg((int)levels[v] == want[v], "vertex %d: level %d, want %d", v, (int)levels[v], want[v]);
    static const uint32_t sources[] = { 0, 3, 9, 21, 17 };
    for (size_t i = 0; i < sizeof sources / sizeof sources[0]; ++i)
        assert_perma_levels(&g, sources[i]);
    bfs_graph_free(&g);
    load(&g, &e, 0); /* directed */
    assert_perma_levels(&g, 0);
    bfs_graph_free(&g);
    bfs_edges_free(&e);
}
END_TEST

START_TEST(generated_graph_levels)
{
    bfs_edges e;
    char message[512];
    ck_assert_msg(bfs_generate(30000, 3, 7, &e, message, sizeof message) == BFS_OK, "%s", message);
    bfs_graph g;
    load(&g, &e, 1);
    assert_perma_levels(&g, 0);
    assert_perma_levels(&g, 29999);
    bfs_graph_free(&g);
    load(&g, &e, 0); /* directed: new vertices point at old ones, so few are reached */
    assert_perma_levels(&g, 29999);
    bfs_graph_free(&g);
    bfs_edges_free(&e);
}
END_TEST

START_TEST(generator_is_deterministic_and_skewed)
{
    bfs_edges a, b, c;
    char message[512];
    ck_assert(bfs_generate(5000, 4, 42, &a, message, sizeof message) == BFS_OK);
    ck_assert(bfs_generate(5000, 4, 42, &b, message, sizeof message) == BFS_OK);
    ck_assert(bfs_generate(5000, 4, 43, &c, message, sizeof message) == BFS_OK);
    ck_assert_uint_eq(a.count, b.count);
    ck_assert(memcmp(a.pairs, b.pairs, a.count * sizeof *a.pairs) == 0);
    ck_assert(memcmp(a.pairs, c.pairs, a.count * sizeof *a.pairs) != 0);
    /* Preferential attachment: the largest degree is far above the mean (8). */
    bfs_graph g;
    load(&g, &a, 1);
    uint32_t largest = 0;
    for (uint32_t v = 0; v < g.vertices; ++v)
        if (g.offsets[v + 1] - g.offsets[v] > largest)
            largest = g.offsets[v + 1] - g.offsets[v];
    ck_assert_msg(largest > 100, "largest degree %u", largest);
    bfs_graph_free(&g);
    bfs_edges_free(&a);
    bfs_edges_free(&b);
    bfs_edges_free(&c);
}
END_TEST

START_TEST(malformed_file_names_file_and_line)
{
    bfs_edges e;
    char message[512], expected[4200];
    bfs_status st = bfs_read_edges(data_path("malformed.edges"), &e, message, sizeof message);
    ck_assert_int_eq(st, BFS_ERR_RUNTIME);
    snprintf(expected, sizeof expected, "%s:4: ", data_path("malformed.edges"));
    ck_assert_msg(strstr(message, expected) == message, "message %s", message);
    ck_assert_msg(strstr(message, "'2 x'") != NULL, "message %s", message);
}
END_TEST

/* Each malformed line, written to a file after two good lines: the error names line 3. */
START_TEST(malformed_lines)
{
    static const char *const bad[] = { "1 2 3", "7", "-1 2", "a b", "1,2", "5 100000000", "12x 3" };
    char path[] = "/tmp/perma-bfs-test-XXXXXX";
    int fd = mkstemp(path);
    ck_assert(fd >= 0);
    FILE *f = fdopen(fd, "w");
    fprintf(f, "0 1\n# comment\n%s\n4 5\n", bad[_i]);
    fclose(f);
    bfs_edges e;
    char message[512], expected[64];
    bfs_status st = bfs_read_edges(path, &e, message, sizeof message);
    remove(path);
    ck_assert_int_eq(st, BFS_ERR_RUNTIME);
    snprintf(expected, sizeof expected, "%s:3: ", path);
    ck_assert_msg(strstr(message, expected) == message, "for '%s': %s", bad[_i], message);
}
END_TEST

START_TEST(missing_and_empty_files)
{
    bfs_edges e;
    char message[512];
    ck_assert_int_eq(bfs_read_edges("/nonexistent/graph.edges", &e, message, sizeof message), BFS_ERR_RUNTIME);
    ck_assert_msg(strstr(message, "/nonexistent/graph.edges: cannot open") == message, "%s", message);
    char path[] = "/tmp/perma-bfs-test-XXXXXX";
    int fd = mkstemp(path);
    ck_assert(fd >= 0);
    FILE *f = fdopen(fd, "w");
    fprintf(f, "# nothing\n\n");
    fclose(f);
    bfs_status st = bfs_read_edges(path, &e, message, sizeof message);
    remove(path);
    ck_assert_int_eq(st, BFS_ERR_RUNTIME);
    ck_assert_msg(strstr(message, "no edges") != NULL, "%s", message);
}
END_TEST

START_TEST(bad_options_are_usage_errors)
{
    static const char *const bad[][3] = {
        { "bfs", "--generate", "1" }, { "bfs", "--technique", "warp" }, { "bfs", "--strategy", "x" },
        { "bfs", "--groups", "0" }, { "bfs", "--bogus", "1" }, { "bfs", "--source", "-3" },
    };
    bfs_options o;
    char message[512];
    ck_assert_int_eq(bfs_parse_options(3, (char **)bad[_i], &o, message, sizeof message), PERMA_CLI_USAGE);
    ck_assert_msg(strstr(message, bad[_i][1]) != NULL, "message does not name %s: %s", bad[_i][1], message);
    char *none[] = { "bfs", NULL };
    ck_assert_int_eq(bfs_parse_options(1, none, &o, message, sizeof message), PERMA_CLI_USAGE);
    ck_assert_str_eq(message, "give either an edge file or --generate N");
}
END_TEST

int main(void)
{
    Suite *s = suite_create("bfs");
    TCase *tc = tcase_create("bfs");
    tcase_set_timeout(tc, EXAMPLE_TEST_TIMEOUT);
    tcase_add_test(tc, small_file_levels);
    tcase_add_test(tc, generated_graph_levels);
    tcase_add_test(tc, generator_is_deterministic_and_skewed);
    tcase_add_test(tc, malformed_file_names_file_and_line);
    tcase_add_loop_test(tc, malformed_lines, 0, 7);
    tcase_add_test(tc, missing_and_empty_files);
    tcase_add_loop_test(tc, bad_options_are_usage_errors, 0, 6);
    suite_add_tcase(s, tc);
    return example_test_run(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
