/* .bpt loader: valid files and every kind of malformed input. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "reyes.h"

/* A valid one-patch file: the unit square in z = 0, on lines 3..18. */
static char *one_patch_text(void)
{
    static char text[4096];
    int n = snprintf(text, sizeof text, "1\n3 3\n");
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            n += snprintf(text + n, sizeof text - (size_t)n, "%g %g 0\n", c / 3.0, r / 3.0);
    return text;
}

static reyes_status parse(const char *text, reyes_error *error, size_t *patches)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    reyes_status status = reyes_scene_parse_bpt(&scene, text, "model.bpt", 0xffffffffu, error);
    *patches = scene.patch_count;
    reyes_scene_free(&scene);
    return status;
}

/* The message must name the file and the line. */
static void expect_error(const char *text, const char *where, const char *what)
{
    reyes_error error;
    size_t patches;
    ck_assert_int_eq(parse(text, &error, &patches), REYES_ERR_FORMAT);
    ck_assert_uint_eq(patches, 0);
    ck_assert_msg(strstr(error.message, where) != NULL, "'%s' lacks '%s'", error.message, where);
    ck_assert_msg(strstr(error.message, what) != NULL, "'%s' lacks '%s'", error.message, what);
}

START_TEST(test_valid_patch)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_parse_bpt(&scene, one_patch_text(), "m", 7, &error), REYES_OK);
    ck_assert_uint_eq(scene.patch_count, 1);
    ck_assert_uint_eq(scene.colors[0], 7);
    /* Row 1, column 2 is point 6: x = 2/3, y = 1/3, w = 1. */
    ck_assert_float_eq_tol(scene.points[6 * 4 + 0], 2.0f / 3.0f, 1e-5f);
    ck_assert_float_eq_tol(scene.points[6 * 4 + 1], 1.0f / 3.0f, 1e-5f);
    ck_assert_float_eq(scene.points[6 * 4 + 3], 1.0f);
    float lo[3], hi[3];
    ck_assert(reyes_scene_bounds(&scene, lo, hi));
    ck_assert_float_eq(lo[0], 0.0f);
    ck_assert_float_eq_tol(hi[1], 1.0f, 1e-6f);
    reyes_scene_free(&scene);
}
END_TEST

START_TEST(test_truncated)
{
    char text[4096];
    strcpy(text, one_patch_text());
    /* Cut the file in the middle of line 10 (control point 8). */
    char *line = text;
    for (int k = 1; k < 10; ++k)
        line = strchr(line, '\n') + 1;
    line[2] = '\0';
    expect_error(text, "model.bpt:10:", "ends inside patch 1");
}
END_TEST

START_TEST(test_missing_patch)
{
    char text[4096];
    snprintf(text, sizeof text, "2\n%s", one_patch_text() + 2);
    expect_error(text, "model.bpt:18:", "ends before patch 2");
}
END_TEST

/* One patch whose first point's z ("0" at the end of line 3) is `z`. */
static void patch_with_z(char text[4096], const char *z)
{
    strcpy(text, one_patch_text());
    char *third = strchr(strchr(text, '\n') + 1, '\n') + 1;
    char *end = strchr(third, '\n');
    char rest[4096];
    strcpy(rest, end);
    snprintf(end - 1, 4096 - (size_t)(end - 1 - text), "%s%s", z, rest);
}

START_TEST(test_not_finite)
{
    const char *bad[] = {"nan", "inf", "-Infinity", "1e999", "1.5x", "--1"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        char text[4096];
        patch_with_z(text, bad[i]);
        expect_error(text, "model.bpt:3:", "not a finite number");
    }
}
END_TEST

/* Coordinates whose squared distances overflow single precision are
 * refused (a patch with one once vanished from the image); up to 1e18 is
 * accepted. */
START_TEST(test_too_far)
{
    const char *bad[] = {"1.1e18", "-1e20", "3e38"};
    char text[4096];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        patch_with_z(text, bad[i]);
        char what[128];
        snprintf(what, sizeof what, "patch 1, control point 1: %s is beyond +-1e+18, where the renderer's "
                 "single-precision arithmetic overflows", bad[i]);
        expect_error(text, "model.bpt:3:", what);
    }
    patch_with_z(text, "-1e18");
    reyes_error error;
    size_t patches;
    ck_assert_int_eq(parse(text, &error, &patches), REYES_OK);
    ck_assert_uint_eq(patches, 1);
}
END_TEST

/* Tiny coordinates underflow (strtof sets ERANGE) but are finite: accepted. */
START_TEST(test_tiny_numbers)
{
    char text[4096];
    int n = snprintf(text, sizeof text, "1\n3 3\n1e-40 1e-50 0\n");
    for (int k = 1; k < 16; ++k)
        n += snprintf(text + n, sizeof text - (size_t)n, "%d %d 0\n", k % 4, k / 4);
    reyes_error error;
    size_t patches;
    ck_assert_msg(parse(text, &error, &patches) == REYES_OK, "%s", error.message);
    ck_assert_uint_eq(patches, 1);
}
END_TEST

START_TEST(test_bad_counts)
{
    expect_error("", "model.bpt:1:", "empty file");
    expect_error("\n\n  -4\n", "model.bpt:3:", "not a positive integer");
    expect_error("0\n", "model.bpt:1:", "not a positive integer");
    expect_error("2.5\n", "model.bpt:1:", "not a positive integer");
    expect_error("99999999999999999999999\n", "model.bpt:1:", "not a positive integer");
    expect_error("4000000000\n3 3\n", "model.bpt:1:", "exceeds the limit");
    /* A huge but allowed count with no data fails at the first patch. */
    expect_error("5000000\n", "model.bpt:1:", "ends before patch 1");
}
END_TEST

START_TEST(test_bad_degree_and_trailing)
{
    char text[4096];
    snprintf(text, sizeof text, "1\n3 2\n%s", one_patch_text() + 6);
    expect_error(text, "model.bpt:2:", "only bicubic");
    snprintf(text, sizeof text, "%s\n\nextra\n", one_patch_text());
    expect_error(text, "model.bpt:21:", "unexpected 'extra'");
}
END_TEST

START_TEST(test_long_token)
{
    char text[8192];
    int n = snprintf(text, sizeof text, "1\n3 3\n");
    for (int k = 0; k < 300; ++k)
        text[n++] = '7';
    text[n] = '\0';
    expect_error(text, "model.bpt:3:", "not a finite number");
}
END_TEST

START_TEST(test_load_file)
{
    char path[] = "/tmp/reyes-loader-XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    FILE *f = fdopen(fd, "w");
    fputs(one_patch_text(), f);
    fputs("1 2\n", f);
    fclose(f);
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_load_bpt(&scene, path, 1, &error), REYES_ERR_FORMAT);
    char where[64];
    snprintf(where, sizeof where, "%s:19:", path);
    ck_assert_msg(strstr(error.message, where) != NULL, "%s", error.message);
    unlink(path);
    ck_assert_int_eq(reyes_scene_load_bpt(&scene, path, 1, &error), REYES_ERR_IO);
    ck_assert_msg(strstr(error.message, path) != NULL, "%s", error.message);
    reyes_scene_free(&scene);
}
END_TEST

START_TEST(test_binary_file)
{
    char path[] = "/tmp/reyes-loader-XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    ck_assert_int_eq(write(fd, "1\0\x01\x02", 4), 4);
    close(fd);
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_load_bpt(&scene, path, 1, &error), REYES_ERR_FORMAT);
    ck_assert_msg(strstr(error.message, path) != NULL, "%s", error.message);
    unlink(path);
    reyes_scene_free(&scene);
}
END_TEST

/* A UTF-8 byte order mark before the count is skipped; anywhere else it
 * is an error that shows its bytes (not an invisible character). */
START_TEST(test_byte_order_mark)
{
    char text[4096];
    size_t patches;
    reyes_error error;
    snprintf(text, sizeof text, "\xEF\xBB\xBF%s", one_patch_text());
    ck_assert_msg(parse(text, &error, &patches) == REYES_OK, "%s", error.message);
    ck_assert_uint_eq(patches, 1);
    snprintf(text, sizeof text, "\xEF\xBB\xBF\xEF\xBB\xBF%s", one_patch_text());
    expect_error(text, "model.bpt:1:", "patch count '\\xEF\\xBB\\xBF1' is not a positive integer");
    snprintf(text, sizeof text, "1\n3 3\n\x01%s", one_patch_text() + 6);
    expect_error(text, "model.bpt:3:", "control point 1: '\\x010' is not a finite number");
}
END_TEST

static Suite *loader_suite(void)
{
    Suite *s = suite_create("reyes_loader");
    TCase *tc = tcase_create("bpt");
    tcase_add_test(tc, test_valid_patch);
    tcase_add_test(tc, test_truncated);
    tcase_add_test(tc, test_missing_patch);
    tcase_add_test(tc, test_not_finite);
    tcase_add_test(tc, test_too_far);
    tcase_add_test(tc, test_tiny_numbers);
    tcase_add_test(tc, test_bad_counts);
    tcase_add_test(tc, test_bad_degree_and_trailing);
    tcase_add_test(tc, test_long_token);
    tcase_add_test(tc, test_load_file);
    tcase_add_test(tc, test_binary_file);
    tcase_add_test(tc, test_byte_order_mark);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *runner = srunner_create(loader_suite());
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
