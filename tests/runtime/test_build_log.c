/* Reading the compiler's build log (runtime/src/build_log.c): where a
 * diagnostic points in PoCL's and clang's forms, and the warnings shown
 * after a build, each once.  Host code only: no device is opened. */
#include "perma_test.h"

#include <stdlib.h>
#include <string.h>

#include "build_log.h"
#include "internal.h"

/* perma_build_log_diagnostic over all of `line`; "" in where when it is not one. */
static bool diagnostic(const char *line, const char *kind, char *where, size_t where_size, const char **text)
{
    where[0] = '\0';
    *text = NULL;
    return perma_build_log_diagnostic(line, strlen(line), kind, where, where_size, text);
}

START_TEST(pocl_and_clang_forms_give_the_same_location)
{
    char where[64];
    const char *text;
    ck_assert(diagnostic("warning: user.cl:12:7: unused variable 'x'", "warning", where, sizeof where, &text));
    ck_assert_str_eq(where, "user.cl:12:7");
    ck_assert_str_eq(text, "unused variable 'x'");
    /* PoCL's spelling location (a macro's) is not part of where it points. */
    ck_assert(diagnostic("warning: user.cl:3:1 <Spelling=lib.cl:9:2>: implicit conversion", "warning", where,
                         sizeof where, &text));
    ck_assert_str_eq(where, "user.cl:3:1");
    ck_assert_str_eq(text, "implicit conversion");
    ck_assert(diagnostic("dir/user.cl:4:15: error: expected ';' after expression", "error", where, sizeof where,
                         &text));
    ck_assert_str_eq(where, "dir/user.cl:4:15");
    ck_assert_str_eq(text, "expected ';' after expression");
}
END_TEST

START_TEST(other_lines_are_not_diagnostics)
{
    char where[64];
    const char *text;
    /* Another kind, a note, plain text, a kind without its ": ". */
    ck_assert(!diagnostic("user.cl:4:15: error: expected ';'", "warning", where, sizeof where, &text));
    ck_assert(!diagnostic("user.cl:2:1: note: previous definition is here", "warning", where, sizeof where, &text));
    ck_assert(!diagnostic("1 warning generated.", "warning", where, sizeof where, &text));
    ck_assert(!diagnostic("warning:user.cl:1:1 no space", "warning", where, sizeof where, &text));
    ck_assert(!diagnostic("warning: no location and no colon", "warning", where, sizeof where, &text));
    ck_assert(!diagnostic("", "warning", where, sizeof where, &text));
    ck_assert_str_eq(where, "");
}
END_TEST

START_TEST(only_the_given_length_is_read)
{
    char where[64];
    const char *text;
    /* The next line of the log is not part of this one. */
    const char *log = "plain line\nuser.cl:1:2: warning: later";
    ck_assert(!perma_build_log_diagnostic(log, strlen("plain line"), "warning", where, sizeof where, &text));
    ck_assert(perma_build_log_diagnostic(log + 11, strlen(log + 11), "warning", where, sizeof where, &text));
    ck_assert_str_eq(where, "user.cl:1:2");
    /* A location longer than the room is cut, still terminated. */
    char small[5];
    ck_assert(diagnostic("warning: user.cl:12:7: text", "warning", small, sizeof small, &text));
    ck_assert_str_eq(small, "user");
    ck_assert_str_eq(text, "text");
}
END_TEST

/* config.build_log's callback: the text of every call, appended. */
static void collect(void *user, const char *text)
{
    char *log = user;
    size_t used = strlen(log);
    ck_assert_uint_lt(used + strlen(text), 4096);
    strcpy(log + used, text);
}

/* A runtime that is only a configuration: perma_build_log_show reads no more. */
static perma_runtime *log_runtime(char *log)
{
    perma_runtime *rt = calloc(1, sizeof *rt);
    ck_assert_ptr_nonnull(rt);
    perma_config_init(&rt->config);
    rt->config.build_log = collect;
    rt->config.build_log_user = log;
    perma_settings_read(&rt->settings); /* as perma_create does: PERMA_BUILD_LOG */
    log[0] = '\0';
    return rt;
}

static const char *pocl_log =
    "warning: a.cl:3:5: unused variable 'x'\n"
    "a.cl:2:1: note: declared here\n"
    "warning: a.cl:3:5: unused variable 'x'\n"   /* PoCL repeats some */
    "b.cl:7:9: warning: using the result of an assignment as a condition\n"
    "2 warnings generated.";

START_TEST(warnings_are_shown_once_each_in_one_form)
{
    unsetenv("PERMA_BUILD_LOG");
    char log[4096];
    perma_runtime *rt = log_runtime(log);
    ck_assert_uint_eq(perma_build_log_show(rt, pocl_log, false), 2);
    ck_assert_str_eq(log, "perma: the program built with 2 compiler warnings:\n"
                          "a.cl:3:5: warning: unused variable 'x'\n"
                          "b.cl:7:9: warning: using the result of an assignment as a condition\n");
    /* No warning: nothing is shown. */
    log[0] = '\0';
    ck_assert_uint_eq(perma_build_log_show(rt, "a.cl:2:1: note: nothing\n", false), 0);
    ck_assert_str_eq(log, "");
    /* A failed build's warnings are the error message's business. */
    ck_assert_uint_eq(perma_build_log_show(rt, pocl_log, true), 0);
    ck_assert_str_eq(log, "");
    free(rt);
}
END_TEST

START_TEST(perma_build_log_shows_the_whole_log)
{
    setenv("PERMA_BUILD_LOG", "1", 1);
    char log[4096];
    perma_runtime *rt = log_runtime(log);
    /* The warnings are counted all the same; the log ends with a newline added. */
    ck_assert_uint_eq(perma_build_log_show(rt, pocl_log, false), 2);
    char expected[1024];
    snprintf(expected, sizeof expected, "perma: build log:\n%s\n", pocl_log);
    ck_assert_str_eq(log, expected);
    log[0] = '\0';
    perma_build_log_show(rt, "x.cl:1:1: error: bad\n", true);
    ck_assert_str_eq(log, "perma: build log (the build failed):\nx.cl:1:1: error: bad\n");
    /* PERMA_BUILD_LOG=0 is off. */
    setenv("PERMA_BUILD_LOG", "0", 1);
    perma_settings_read(&rt->settings);
    log[0] = '\0';
    perma_build_log_show(rt, "x.cl:1:1: error: bad\n", true);
    ck_assert_str_eq(log, "");
    unsetenv("PERMA_BUILD_LOG");
    free(rt);
}
END_TEST

PERMA_TEST_MAIN("build_log", pocl_and_clang_forms_give_the_same_location, other_lines_are_not_diagnostics,
                only_the_given_length_is_read, warnings_are_shown_once_each_in_one_form,
                perma_build_log_shows_the_whole_log)
