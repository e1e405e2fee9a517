/* Output files (perma_output_*): whole or not at all.  A full disk is a
 * file size limit here (RLIMIT_FSIZE with SIGXFSZ ignored: a write fails
 * with EFBIG), which needs no privileges; Check runs each test in its own
 * process, so the limit ends with the test. */
#include "perma_test.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[64];

static void make_dir(void)
{
    snprintf(dir, sizeof dir, "/tmp/perma-output-XXXXXX");
    ck_assert_ptr_nonnull(mkdtemp(dir));
}

static void remove_dir(void)
{
    char command[128];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    ck_assert_int_eq(system(command), 0);
}

static void path_in_dir(char *path, size_t size, const char *name)
{
    snprintf(path, size, "%s/%s", dir, name);
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    ck_assert_ptr_nonnull(f);
    fputs(text, f);
    ck_assert_int_eq(fclose(f), 0);
}

static char *read_text(const char *path)
{
    static char text[4096];
    FILE *f = fopen(path, "r");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    return text;
}

/* Files in the directory (the output and any temporary left beside it). */
static unsigned files_in_dir(void)
{
    char command[128];
    snprintf(command, sizeof command, "ls -A '%s' | wc -l", dir);
    FILE *p = popen(command, "r");
    unsigned count = 0;
    ck_assert_int_eq(fscanf(p, "%u", &count), 1);
    pclose(p);
    return count;
}

static void limit_file_size(rlim_t bytes)
{
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit limit = { bytes, bytes };
    ck_assert_int_eq(setrlimit(RLIMIT_FSIZE, &limit), 0);
}

START_TEST(a_complete_file_replaces_the_old_one)
{
    make_dir();
    char path[128];
    path_in_dir(path, sizeof path, "out.txt");
    write_text(path, "old\n");
    chmod(path, 0640);
    perma_output *out;
    perma_error error;
    ck_assert_int_eq(perma_output_open(path, &out, &error), PERMA_OK);
    fputs("new\n", perma_output_stream(out));
    /* Until the commit the old file is in place. */
    ck_assert_str_eq(read_text(path), "old\n");
    ck_assert_uint_eq(files_in_dir(), 2);
    ck_assert_int_eq(perma_output_commit(out, &error), PERMA_OK);
    ck_assert_str_eq(read_text(path), "new\n");
    ck_assert_uint_eq(files_in_dir(), 1);
    struct stat st;
    ck_assert_int_eq(stat(path, &st), 0);
    ck_assert_uint_eq(st.st_mode & 0777, 0640); /* the permissions stay */
    remove_dir();
}
END_TEST

START_TEST(a_full_disk_leaves_the_old_file)
{
    make_dir();
    char path[128];
    path_in_dir(path, sizeof path, "out.txt");
    write_text(path, "old\n");
    limit_file_size(1000);
    perma_output *out;
    perma_error error;
    ck_assert_int_eq(perma_output_open(path, &out, &error), PERMA_OK);
    for (int i = 0; i < 1000; ++i)
        fprintf(perma_output_stream(out), "line %d\n", i);
    ck_assert_int_eq(perma_output_commit(out, &error), PERMA_ERR_IO);
    char expected[256];
    snprintf(expected, sizeof expected, "writing '%s' failed: %s (the file there before is unchanged)", path,
             strerror(EFBIG));
    ck_assert_str_eq(error.message, expected);
    ck_assert_str_eq(read_text(path), "old\n");
    ck_assert_uint_eq(files_in_dir(), 1); /* no temporary file left */
    remove_dir();
}
END_TEST

/* A writer of several files finishes each before committing any: the
 * second one failing leaves the first one's target untouched. */
START_TEST(finish_then_discard_writes_nothing)
{
    make_dir();
    char first[128], second[128];
    path_in_dir(first, sizeof first, "a.txt");
    path_in_dir(second, sizeof second, "b.txt");
    limit_file_size(100);
    perma_output *a, *b;
    perma_error error;
    ck_assert_int_eq(perma_output_open(first, &a, &error), PERMA_OK);
    fputs("short\n", perma_output_stream(a));
    ck_assert_int_eq(perma_output_finish(a, &error), PERMA_OK);
    ck_assert_int_eq(perma_output_open(second, &b, &error), PERMA_OK);
    for (int i = 0; i < 100; ++i)
        fputs("a longer line\n", perma_output_stream(b));
    ck_assert_int_eq(perma_output_finish(b, &error), PERMA_ERR_IO);
    ck_assert_contains(error.message, "(no file was written)");
    perma_output_discard(a);
    ck_assert_uint_eq(files_in_dir(), 0);
    remove_dir();
}
END_TEST

START_TEST(bad_paths_are_named)
{
    perma_error error;
    perma_output *out = (perma_output *)&error;
    ck_assert_int_eq(perma_output_check("/nonexistent-dir/x.png", &error), PERMA_ERR_IO);
    ck_assert_str_eq(error.message, "cannot create '/nonexistent-dir/x.png': No such file or directory");
    ck_assert_int_eq(perma_output_open("/nonexistent-dir/x.png", &out, &error), PERMA_ERR_IO);
    ck_assert_ptr_null(out);
    ck_assert_int_eq(perma_output_check("/tmp", &error), PERMA_ERR_IO);
    ck_assert_str_eq(error.message, "cannot write '/tmp': it is a directory");
    ck_assert_int_eq(perma_output_check("", &error), PERMA_ERR_ARGUMENT);
    /* A file that is there and not regular is written in place. */
    ck_assert_int_eq(perma_output_open("/dev/null", &out, &error), PERMA_OK);
    fputs("gone\n", perma_output_stream(out));
    ck_assert_int_eq(perma_output_commit(out, &error), PERMA_OK);
    struct stat st;
    ck_assert_int_eq(stat("/dev/null", &st), 0);
    ck_assert(S_ISCHR(st.st_mode));
}
END_TEST

/* A symbolic link stays a link; the file it points to is replaced. */
START_TEST(a_link_keeps_pointing_to_the_new_file)
{
    make_dir();
    char target[128], link[128];
    path_in_dir(target, sizeof target, "target.txt");
    path_in_dir(link, sizeof link, "link.txt");
    write_text(target, "old\n");
    ck_assert_int_eq(symlink(target, link), 0);
    perma_output *out;
    perma_error error;
    ck_assert_int_eq(perma_output_open(link, &out, &error), PERMA_OK);
    fputs("new\n", perma_output_stream(out));
    ck_assert_int_eq(perma_output_commit(out, &error), PERMA_OK);
    struct stat st;
    ck_assert_int_eq(lstat(link, &st), 0);
    ck_assert(S_ISLNK(st.st_mode));
    ck_assert_str_eq(read_text(target), "new\n");
    ck_assert_uint_eq(files_in_dir(), 2);
    remove_dir();
}
END_TEST

/* Outputs that are one file, or an output that is an input, are refused
 * naming both; through "./", "..", a symbolic link and a hard link; a
 * file not there yet by its path; devices never clash. */
START_TEST(outputs_that_overwrite_each_other_are_refused)
{
    make_dir();
    unsetenv("PERMA_TRACE");
    char model[128], image[128], other[128], dotted[128], soft[128], hard[128], fresh[128], fresh_dotted[256];
    path_in_dir(model, sizeof model, "m.bpt");
    path_in_dir(image, sizeof image, "a.png");
    path_in_dir(other, sizeof other, "b.json");
    snprintf(dotted, sizeof dotted, "%s/./../%s/a.png", dir, strrchr(dir, '/') + 1);
    path_in_dir(soft, sizeof soft, "link.png");
    path_in_dir(hard, sizeof hard, "hard.bpt");
    path_in_dir(fresh, sizeof fresh, "new.png");
    snprintf(fresh_dotted, sizeof fresh_dotted, "%s/../%s/./new.png", dir, strrchr(dir, '/') + 1);
    write_text(model, "1\n");
    write_text(image, "png\n");
    ck_assert_int_eq(symlink(image, soft), 0);
    ck_assert_int_eq(link(model, hard), 0);
    perma_error error;
    perma_file_role fine[] = { { model, "the model", 0 }, { model, "the model", 0 }, { image, "--output", 1 },
                               { other, "--stats", 1 }, { "/dev/null", "--a", 1 }, { "/dev/null", "--b", 1 },
                               { NULL, "--unused", 1 } };
    ck_assert_int_eq(perma_check_distinct_files(fine, 7, &error), PERMA_OK);
    perma_file_role two[] = { { model, "the model", 0 }, { image, "--output", 1 }, { dotted, "--stats", 1 } };
    ck_assert_int_eq(perma_check_distinct_files(two, 3, &error), PERMA_ERR_ARGUMENT);
    char expected[1024];
    snprintf(expected, sizeof expected, "--output '%s' and --stats '%s' are the same file: one would overwrite the other",
             image, dotted);
    ck_assert_str_eq(error.message, expected);
    perma_file_role linked[] = { { soft, "--stats", 1 }, { image, "--output", 1 } };
    ck_assert_int_eq(perma_check_distinct_files(linked, 2, &error), PERMA_ERR_ARGUMENT);
    ck_assert_ptr_nonnull(strstr(error.message, "--stats '"));
    perma_file_role input[] = { { hard, "the model", 0 }, { model, "--output", 1 } };
    ck_assert_int_eq(perma_check_distinct_files(input, 2, &error), PERMA_ERR_ARGUMENT);
    snprintf(expected, sizeof expected, "--output '%s' is the same file as the model '%s', which it would overwrite",
             model, hard);
    ck_assert_str_eq(error.message, expected);
    perma_file_role not_there[] = { { fresh, "--output", 1 }, { fresh_dotted, "--stats", 1 } };
    ck_assert_int_eq(perma_check_distinct_files(not_there, 2, &error), PERMA_ERR_ARGUMENT);
    ck_assert_ptr_nonnull(strstr(error.message, "are the same file"));
    /* The trace counts as an output. */
    setenv("PERMA_TRACE", dotted, 1);
    perma_file_role traced[] = { { image, "--output", 1 } };
    ck_assert_int_eq(perma_check_distinct_files(traced, 1, &error), PERMA_ERR_ARGUMENT);
    snprintf(expected, sizeof expected, "--output '%s' and PERMA_TRACE '%s' are the same file: one would overwrite the other",
             image, dotted);
    ck_assert_str_eq(error.message, expected);
    unsetenv("PERMA_TRACE");
    ck_assert_str_eq(read_text(image), "png\n");
    remove_dir();
}
END_TEST

int main(void)
{
    Suite *s = suite_create("output");
    TCase *tc = tcase_create("output");
    tcase_add_test(tc, a_complete_file_replaces_the_old_one);
    tcase_add_test(tc, a_full_disk_leaves_the_old_file);
    tcase_add_test(tc, finish_then_discard_writes_nothing);
    tcase_add_test(tc, bad_paths_are_named);
    tcase_add_test(tc, a_link_keeps_pointing_to_the_new_file);
    tcase_add_test(tc, outputs_that_overwrite_each_other_are_refused);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
