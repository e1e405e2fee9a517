/* The settings the ranks of an MPI job compare (examples/reyes/scale/reyes_settings.h):
 * jobs that render the same image agree whatever runs them; an option or
 * a model that changes the image is found and named. */
#include <check.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "reyes_settings.h"

typedef struct made {
    reyes_cli cli;
    reyes_job job;
    reyes_setting *settings;
    size_t count;
} made;

static void make(made *m, int argc, char **argv)
{
    char message[512];
    ck_assert_msg(reyes_cli_parse(argc, argv, &m->cli, message, sizeof message) == PERMA_CLI_OK, "%s", message);
    reyes_error error;
    ck_assert_msg(reyes_job_init(&m->job, &m->cli, &error) == REYES_OK, "%s", error.message);
    m->settings = reyes_job_settings(&m->job, &m->cli, &m->count);
    ck_assert_ptr_nonnull(m->settings);
}

static void unmake(made *m)
{
    free(m->settings);
    reyes_job_free(&m->job);
    reyes_cli_free(&m->cli);
}

#define ARGS(...) ((char *[]){"reyes-render", __VA_ARGS__})
#define COUNT(...) ((int)(sizeof((char *[]){"reyes-render", __VA_ARGS__}) / sizeof(char *)))
#define MAKE(m, ...) make(m, COUNT(__VA_ARGS__), ARGS(__VA_ARGS__))

/* a and b differ first in `name`, a's value `value`, b's `other`. */
static void expect_difference(const made *a, const made *b, const char *name, const char *value,
                              const char *other, size_t differing)
{
    size_t count = 0;
    size_t first = reyes_settings_compare(a->settings, a->count, b->settings, b->count, &count);
    ck_assert_msg(first < a->count, "no difference found, expected %s", name);
    ck_assert_str_eq(a->settings[first].name, name);
    ck_assert_str_eq(a->settings[first].value, value);
    const reyes_setting *theirs = reyes_settings_find(b->settings, b->count, name);
    ck_assert_ptr_nonnull(theirs);
    ck_assert_str_eq(theirs->value, other);
    ck_assert_uint_eq(count, differing);
}

static void expect_agree(const made *a, const made *b)
{
    size_t count = 1;
    size_t first = reyes_settings_compare(a->settings, a->count, b->settings, b->count, &count);
    ck_assert_msg(first == SIZE_MAX, "differ in %s: %s", first < a->count ? a->settings[first].name : "?",
                  first < a->count ? a->settings[first].value : "");
    ck_assert_uint_eq(count, 0);
}

/* Where and how fast a job runs, and what rank 0 alone writes, are not
 * settings: such ranks agree. */
START_TEST(test_running_options_agree)
{
    made a, b;
    MAKE(&a, "--size", "64x48", "--bucket", "16x16", "-o", "a.png");
    MAKE(&b, "--size=64x48", "--bucket", "16x16", "-o", "b.png", "--stats", "s.json", "--devices", "0:0/2",
         "--schedule", "megakernel/stealing/round-robin+local32", "--groups", "3", "--rank-timeout", "9",
         "--coordinator-only");
    expect_agree(&a, &b);
    expect_agree(&b, &a);
    unmake(&b);
    /* Explicit defaults are the defaults. */
    MAKE(&b, "--size", "64x48", "--bucket", "16x16", "--spp", "4", "--crack-fix", "polyline", "--fov", "40");
    expect_agree(&a, &b);
    unmake(&b);
    unmake(&a);
}
END_TEST

/* The command line: another size and bucket on rank 1. */
START_TEST(test_image_options_differ)
{
    made a, b;
    MAKE(&a, "--size", "64x64", "--bucket", "64x64");
    MAKE(&b, "--size", "1024x1024", "--bucket", "1024x1024");
    expect_difference(&b, &a, "--size", "1024x1024", "64x64", 2);
    unmake(&b);
    const struct { int argc; char **argv; const char *name, *value, *other; } cases[] = {
        { COUNT("--size", "64x64", "--bucket", "64x64", "--crack-fix", "none"),
          ARGS("--size", "64x64", "--bucket", "64x64", "--crack-fix", "none"), "--crack-fix", "none", "polyline" },
        { COUNT("--size", "64x64", "--bucket", "64x64", "--spp", "9"),
          ARGS("--size", "64x64", "--bucket", "64x64", "--spp", "9"), "--spp", "9", "4" },
        { COUNT("--size", "64x64", "--bucket", "64x64", "--backface"),
          ARGS("--size", "64x64", "--bucket", "64x64", "--backface"), "--backface", "on", "off" },
        { COUNT("--size", "64x64", "--bucket", "64x64", "--motion", "0.5,0,0"),
          ARGS("--size", "64x64", "--bucket", "64x64", "--motion", "0.5,0,0"), "--motion", "0.5,0,0", "0,0,0" },
        { COUNT("--size", "64x64", "--bucket", "64x64", "--grid", "8"),
          ARGS("--size", "64x64", "--bucket", "64x64", "--grid", "8"), "--crack-fix", "stitch", "polyline" },
        { COUNT("--size", "64x64", "--bucket", "32x32"), ARGS("--size", "64x64", "--bucket", "32x32"), "--bucket",
          "32x32", "64x64" },
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        make(&b, cases[k].argc, cases[k].argv);
        /* --grid 8 alone also means fixed grids, which stitch: three
         * settings differ, the crack fix first. */
        expect_difference(&b, &a, cases[k].name, cases[k].value, cases[k].other,
                          strcmp(cases[k].value, "stitch") == 0 ? 3 : 1);
        unmake(&b);
    }
    /* The camera given on one rank and framed on the other. */
    MAKE(&b, "--size", "64x64", "--bucket", "64x64", "--camera", "0,-10,3,0,0,0");
    const char *framed = reyes_settings_find(a.settings, a.count, "--camera")->value;
    ck_assert_ptr_nonnull(strstr(framed, " (framed)"));
    expect_difference(&b, &a, "--camera", "0,-10,3,0,0,0", framed, 1);
    unmake(&b);
    unmake(&a);
}
END_TEST

static void write_model(const char *path, float z)
{
    FILE *f = fopen(path, "w");
    ck_assert_ptr_nonnull(f);
    fprintf(f, "1\n3 3\n");
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            fprintf(f, "%g %g %g\n", c / 3.0, r / 3.0, (double)z);
    fclose(f);
}

/* Models are compared by what they contain: a copy under another name
 * agrees, other contents under one name differ, and so do the model
 * count and the built-in scene. */
START_TEST(test_models)
{
    char dir[] = "/tmp/reyes-settings-XXXXXX", a_path[64], b_path[64], c_path[64];
    ck_assert_ptr_nonnull(mkdtemp(dir));
    snprintf(a_path, sizeof a_path, "%s/a.bpt", dir);
    snprintf(b_path, sizeof b_path, "%s/b.bpt", dir);
    snprintf(c_path, sizeof c_path, "%s/c.bpt", dir);
    write_model(a_path, 0.0f);
    write_model(b_path, 0.0f);
    write_model(c_path, 0.5f);
    made a, b;
    make(&a, 2, ARGS(a_path));
    make(&b, 2, ARGS(b_path));
    expect_agree(&a, &b);
    unmake(&b);
    char value[128], other[128];
    /* Another model: it, and the camera framed from it, differ. */
    make(&b, 2, ARGS(c_path));
    snprintf(value, sizeof value, "%s (1 patches)", c_path);
    snprintf(other, sizeof other, "%s (1 patches)", a_path);
    expect_difference(&b, &a, "model 1", value, other, 2);
    unmake(&b);
    /* Another model count: the count, the model only b has, the camera. */
    make(&b, 3, ARGS(a_path, c_path));
    expect_difference(&b, &a, "models", "2", "1", 3);
    unmake(&b);
    make(&b, 1, ARGS());
    expect_difference(&b, &a, "models", "none (the built-in scene)", "1", 3);
    unmake(&b);
    /* One name, other contents: the same value, another digest. */
    write_model(b_path, 0.25f);
    make(&b, 2, ARGS(b_path));
    write_model(b_path, 0.0f);
    made c;
    make(&c, 2, ARGS(b_path));
    expect_difference(&b, &c, "model 1", strcpy(value, reyes_settings_find(c.settings, c.count, "model 1")->value),
                      value, 2);
    unmake(&c);
    unmake(&b);
    unmake(&a);
    unlink(a_path);
    unlink(b_path);
    unlink(c_path);
    rmdir(dir);
}
END_TEST

static Suite *settings_suite(void)
{
    Suite *s = suite_create("reyes_settings");
    TCase *tc = tcase_create("settings");
    tcase_add_test(tc, test_running_options_agree);
    tcase_add_test(tc, test_image_options_differ);
    tcase_add_test(tc, test_models);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *runner = srunner_create(settings_suite());
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
