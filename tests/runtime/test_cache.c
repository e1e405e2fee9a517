/* The disk cache of compiled programs (runtime/src/program_cache.c): a
 * second build of the same program loads the stored binary, a refused or
 * damaged entry is rebuilt from source, another program gets its own
 * entry, PERMA_CACHE_DIR=off writes nothing.  PERMA_CACHE_MIN_SECONDS=0
 * stores even PoCL's fast builds. */
#include "perma_test.h"
#include "tree_procedure.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <utime.h>

static char dir[64];

/* Paths in the cache directory. */
#define PATH_MAX_LENGTH 512

/* Build and run a depth-8 tree; build_options makes another program. */
static void run_tree(const char *build_options)
{
    perma_config config;
    perma_config_init(&config);
    config.build_options = build_options;
    config.time_limit = 120;
    perma_runtime *rt = test_runtime_config(&config);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, 1, counts, sums);
    struct tree_node root = { 0, 8, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(counts[0], 256);
    ck_assert_uint_eq(counts[1], 255);
    perma_destroy(rt);
}

/* The entries in the cache directory; the path of the last in *path. */
static unsigned entries(char *path, size_t size)
{
    unsigned n = 0;
    DIR *d = opendir(dir);
    ck_assert_ptr_nonnull(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        ck_assert_msg(strstr(e->d_name, ".bin") != NULL, "stray file %s in the cache", e->d_name);
        ck_assert_int_lt(snprintf(path, size, "%s/%s", dir, e->d_name), (int)size);
        ++n;
    }
    closedir(d);
    return n;
}

static void setup(void)
{
    snprintf(dir, sizeof dir, "/tmp/perma-cache-test.XXXXXX");
    ck_assert_ptr_nonnull(mkdtemp(dir));
    setenv("PERMA_CACHE_DIR", dir, 1);
    setenv("PERMA_CACHE_MIN_SECONDS", "0", 1);
}

static void teardown(void)
{
    char path[PATH_MAX_LENGTH];
    while (entries(path, sizeof path) > 0)
        unlink(path);
    rmdir(dir);
    unsetenv("PERMA_CACHE_DIR");
    unsetenv("PERMA_CACHE_MIN_SECONDS");
}

START_TEST(second_build_loads_the_binary)
{
    char path[PATH_MAX_LENGTH];
    run_tree(NULL);
    ck_assert_uint_eq(entries(path, sizeof path), 1);
    /* Loading marks the entry used (its time) but does not rewrite it (its
     * inode); a rebuild from source would store a new file. */
    struct utimbuf old = { 1000, 1000 };
    ck_assert_int_eq(utime(path, &old), 0);
    struct stat before, after;
    ck_assert_int_eq(stat(path, &before), 0);
    run_tree(NULL);
    ck_assert_uint_eq(entries(path, sizeof path), 1);
    ck_assert_int_eq(stat(path, &after), 0);
    ck_assert_uint_eq(after.st_ino, before.st_ino);
    ck_assert_int_gt(after.st_mtime, 1000);

    /* Other build options: another program, another entry. */
    run_tree("-DUNUSED_MACRO=1");
    ck_assert_uint_eq(entries(path, sizeof path), 2);
}
END_TEST

START_TEST(damaged_entry_is_rebuilt)
{
    char path[PATH_MAX_LENGTH];
    run_tree(NULL);
    ck_assert_uint_eq(entries(path, sizeof path), 1);
    struct stat before, after;
    ck_assert_int_eq(stat(path, &before), 0);
    /* Cut the entry where its binary starts (after the magic line, the
     * key's length and the key): the key still matches, there is nothing
     * to load. */
    FILE *f = fopen(path, "rb");
    ck_assert_ptr_nonnull(f);
    char magic[64];
    ck_assert_ptr_nonnull(fgets(magic, sizeof magic, f));
    uint64_t key_length = 0;
    ck_assert_uint_eq(fread(&key_length, 8, 1, f), 1);
    ck_assert_int_eq(fclose(f), 0);
    ck_assert_uint_lt(strlen(magic) + 8 + key_length, (uint64_t)before.st_size);
    ck_assert_int_eq(truncate(path, (off_t)(strlen(magic) + 8 + key_length)), 0);
    run_tree(NULL);
    ck_assert_uint_eq(entries(path, sizeof path), 1);
    ck_assert_int_eq(stat(path, &after), 0);
    /* Stored again (an implementation's binaries may differ by a few
     * bytes from build to build). */
    ck_assert_int_gt(after.st_size, (off_t)(strlen(magic) + 8 + key_length));
}
END_TEST

START_TEST(off_writes_nothing)
{
    char path[PATH_MAX_LENGTH];
    setenv("PERMA_CACHE_DIR", "off", 1);
    run_tree(NULL);
    setenv("PERMA_CACHE_DIR", dir, 1);
    ck_assert_uint_eq(entries(path, sizeof path), 0);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("cache");
    TCase *tc = tcase_create("cache");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, second_build_loads_the_binary);
    tcase_add_test(tc, damaged_entry_is_rebuilt);
    tcase_add_test(tc, off_writes_nothing);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
