/* The command-line engine of perma's programs (runtime/tools/cli/perma_cli.h):
 * each kind of value with its range, the argv walk (inline values, short
 * names, operands, "--"), what bad usage says and returns, --help and
 * --version, the help text written from the table. */
#include <check.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <perma.h>
#include <perma_cli.h>

/* Every kind of row, the targets in one struct. */
typedef struct targets {
    int flag, flag_given;
    const char *text;
    unsigned whole, size[2], choice, named;
    unsigned long long whole64;
    float low_bounded, fov;
    double between;
    const char *operands[4];
    size_t added, operand_count; /* by the operand row, and as the engine counts */
    char custom[16];
} targets;

static const char *const colours[] = { "red", "green", "blue", NULL };

static int parse_even(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    size_t n = strlen(value);
    if (n % 2 || n >= 16) {
        snprintf(complaint, size, "expected an even length below 16");
        return 1;
    }
    memcpy(option->target, value, n + 1);
    return 0;
}

static int add_operand(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    (void)complaint;
    (void)size;
    targets *t = option->target;
    t->operands[t->added++] = value;
    return 0;
}

/* The tests' command line: its rows (targets in t), quiet. */
typedef struct fixture {
    targets t;
    perma_cli_option rows[11];
    perma_cli_option operand;
    perma_cli_table tables[2];
    perma_cli cli;
    char message[PERMA_CLI_MESSAGE_MAX];
} fixture;

static fixture *fixture_new(size_t max_operands)
{
    fixture *f = calloc(1, sizeof *f);
    ck_assert_ptr_nonnull(f);
    targets *t = &f->t;
    const perma_cli_option rows[] = {
        { PERMA_CLI_FLAG("flag", &t->flag, "a flag"), .given = &t->flag_given },
        { PERMA_CLI_TEXT("output", "FILE", &t->text, "a file (default x.png)"), .short_name = 'o' },
        { PERMA_CLI_WHOLE("count", "N", &t->whole, 2, 32, "a count (default 16)") },
        { PERMA_CLI_WHOLE64("seed", "S", &t->whole64, 0, ULLONG_MAX, "a seed") },
        { PERMA_CLI_SIZE("size", "WxH", t->size, 1, 16384, "an image size") },
        { PERMA_CLI_CHOICE("colour", "NAME", &t->choice, colours, "a colour") },
        { PERMA_CLI_CHOICE_OF("technique", "NAME", &t->named, perma_cli_technique_name, "a technique") },
        { PERMA_CLI_FLOAT("bound", "PX", &t->low_bounded, 0.01, INFINITY, "a bound") },
        { PERMA_CLI_FLOAT("fov", "DEG", &t->fov, 0.5, 179, "an angle"),
          .open = PERMA_CLI_ABOVE_LOW | PERMA_CLI_BELOW_HIGH },
    };
    memcpy(f->rows, rows, sizeof rows);
    const perma_cli_option more[] = {
        { PERMA_CLI_DOUBLE("between", "X", &t->between, -1, 1e6, "a number") },
        { PERMA_CLI_CUSTOM("even", "TEXT", parse_even, t->custom, "an even text") },
    };
    memcpy(f->rows + 9, more, sizeof more);
    f->operand = (perma_cli_option){ PERMA_CLI_CUSTOM(NULL, "MODEL", add_operand, t, "a model") };
    f->tables[0] = (perma_cli_table){ "options", f->rows, 9 };
    f->tables[1] = (perma_cli_table){ "more options", f->rows + 9, 2 };
    f->cli = (perma_cli){
        .program = "perma-test",
        .synopsis = "[options] MODEL ...\n--flag",
        .about = "Tests the engine.",
        .tables = f->tables,
        .table_count = 2,
        .operand = &f->operand,
        .max_operands = max_operands,
        .operand_count = &t->operand_count,
        .notes = "exit status: 0 ok, 2 bad usage",
        .version = "9.8.7",
        .quiet = 1,
    };
    return f;
}

#define ARGV(...) ((char *[]){ "perma-test", __VA_ARGS__, NULL })
#define ARGC(...) ((int)(sizeof((char *[]){ "perma-test", __VA_ARGS__ }) / sizeof(char *)))
#define PARSE(f, ...) perma_cli_parse(&(f)->cli, ARGC(__VA_ARGS__), ARGV(__VA_ARGS__), (f)->message, sizeof (f)->message)

START_TEST(values_land_in_their_targets)
{
    fixture *f = fixture_new(0);
    perma_cli_status status = PARSE(f, "a.bpt", "--flag", "-o", "out.png", "--count=32", "--seed",
                                    "18446744073709551615", "--size", "640x480", "--colour", "blue", "--technique",
                                    "bounded-batches", "--bound", "0.01", "--fov", "178.5", "--between", "-1",
                                    "--even", "abcd", "-", "--", "-b.bpt");
    ck_assert_msg(status == PERMA_CLI_OK, "%s", f->message);
    const targets *t = &f->t;
    ck_assert_str_eq(f->message, "");
    ck_assert(t->flag && t->flag_given);
    ck_assert_str_eq(t->text, "out.png");
    ck_assert_uint_eq(t->whole, 32);
    ck_assert(t->whole64 == ULLONG_MAX);
    ck_assert_uint_eq(t->size[0], 640);
    ck_assert_uint_eq(t->size[1], 480);
    ck_assert_uint_eq(t->choice, 2);
    ck_assert_uint_eq(t->named, PERMA_TECHNIQUE_BOUNDED_BATCHES);
    ck_assert(t->low_bounded == 0.01f); /* the bound itself, compared in float */
    ck_assert(t->fov == 178.5f);
    ck_assert(t->between == -1.0);
    ck_assert_str_eq(t->custom, "abcd");
    ck_assert_uint_eq(t->operand_count, 3);
    ck_assert_uint_eq(t->added, 3);
    ck_assert_str_eq(t->operands[0], "a.bpt");
    ck_assert_str_eq(t->operands[1], "-");
    ck_assert_str_eq(t->operands[2], "-b.bpt");
    free(f);
}
END_TEST

/* Each bad value: PERMA_CLI_USAGE and exactly this message. */
static const struct {
    const char *option, *value, *message;
} bad_values[] = {
    { "--count", "1", "--count '1': expected a whole number in 2..32" },
    { "--count", "33", "--count '33': expected a whole number in 2..32" },
    { "--count", "+5", "--count '+5': expected a whole number in 2..32" },
    { "--count", " 5", "--count ' 5': expected a whole number in 2..32" },
    { "--count", "-0", "--count '-0': expected a whole number in 2..32" },
    { "--count", "5x", "--count '5x': expected a whole number in 2..32" },
    { "--count", "", "--count '': expected a whole number in 2..32" },
    { "--count", "99999999999999999999999", "--count '99999999999999999999999': expected a whole number in 2..32" },
    { "--seed", "18446744073709551616", "--seed '18446744073709551616': expected a whole number" },
    { "--size", "0x5", "--size '0x5': expected WxH with sides in 1..16384" },
    { "--size", "64", "--size '64': expected WxH with sides in 1..16384" },
    { "--size", "64x", "--size '64x': expected WxH with sides in 1..16384" },
    { "--size", "16385x1", "--size '16385x1': expected WxH with sides in 1..16384" },
    { "--colour", "Red", "--colour 'Red': expected red, green or blue" },
    { "--technique", "warp", "--technique 'warp': expected megakernel, kernel-per-procedure or bounded-batches" },
    { "--bound", "0.0099", "--bound '0.0099': expected a number >= 0.01" },
    { "--bound", "nan", "--bound 'nan': expected a number >= 0.01" },
    { "--bound", "inf", "--bound 'inf': expected a number >= 0.01" },
    { "--bound", "1e39", "--bound '1e39': expected a number >= 0.01" }, /* beyond float */
    { "--fov", "179", "--fov '179': expected a number > 0.5 and < 179" },
    { "--fov", "0.5", "--fov '0.5': expected a number > 0.5 and < 179" },
    { "--between", "1000001", "--between '1000001': expected a number in -1..1e6" },
    { "--between", "1,5", "--between '1,5': expected a number in -1..1e6" },
    { "--even", "abc", "--even 'abc': expected an even length below 16" },
};

START_TEST(bad_values_name_the_option_and_the_range)
{
    fixture *f = fixture_new(0);
    char *argv[] = { "perma-test", (char *)bad_values[_i].option, (char *)bad_values[_i].value, NULL };
    ck_assert_int_eq(perma_cli_parse(&f->cli, 3, argv, f->message, sizeof f->message), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, bad_values[_i].message);
    free(f);
}
END_TEST

START_TEST(bad_usage_of_the_line)
{
    fixture *f = fixture_new(1);
    ck_assert_int_eq(PARSE(f, "--frobnicate"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "unknown option '--frobnicate'");
    ck_assert_int_eq(PARSE(f, "-x"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "unknown option '-x'");
    ck_assert_int_eq(PARSE(f, "--count"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "--count needs a value N");
    ck_assert_int_eq(PARSE(f, "-o"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "--output needs a value FILE");
    ck_assert_int_eq(PARSE(f, "--flag=yes"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "--flag takes no value");
    ck_assert_int_eq(PARSE(f, "--help=yes"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "--help takes no value");
    /* A prefix of a name is no name. */
    ck_assert_int_eq(PARSE(f, "--coun", "3"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "unknown option '--coun'");
    /* At most one operand here. */
    ck_assert_int_eq(PARSE(f, "a", "b"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "unexpected argument 'b'");
    ck_assert_uint_eq(f->t.operand_count, 1);
    /* The walk stops at the first bad option: a later one is not taken. */
    ck_assert_int_eq(PARSE(f, "--count", "0", "--seed", "5"), PERMA_CLI_USAGE);
    ck_assert(f->t.whole64 == 0);
    /* Without an operand row, any operand is unexpected. */
    f->cli.operand = NULL;
    ck_assert_int_eq(PARSE(f, "x.bpt"), PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "unexpected argument 'x.bpt'");
    free(f);
}
END_TEST

START_TEST(help_and_version_stop_the_walk)
{
    fixture *f = fixture_new(0);
    ck_assert_int_eq(PARSE(f, "--help", "--count", "0"), PERMA_CLI_HELP);
    ck_assert_int_eq(PARSE(f, "-h"), PERMA_CLI_HELP);
    ck_assert_int_eq(PARSE(f, "--version", "--frobnicate"), PERMA_CLI_VERSION);
    ck_assert_int_eq(PARSE(f, "--count", "0", "--help"), PERMA_CLI_USAGE); /* in order */
    ck_assert_int_eq(perma_cli_exit_status(PERMA_CLI_HELP), 0);
    ck_assert_int_eq(perma_cli_exit_status(PERMA_CLI_VERSION), 0);
    ck_assert_int_eq(perma_cli_exit_status(PERMA_CLI_OK), 0);
    ck_assert_int_eq(perma_cli_exit_status(PERMA_CLI_USAGE), 2);
    ck_assert_int_eq(PERMA_CLI_EXIT_USAGE, 2);
    free(f);
}
END_TEST

/* What `run` writes to the stream `fd` (1 or 2) while it runs. */
static char *capture(int fd, perma_cli_status (*run)(fixture *), fixture *f, perma_cli_status *status)
{
    FILE *tmp = tmpfile();
    ck_assert_ptr_nonnull(tmp);
    fflush(fd == 1 ? stdout : stderr);
    int saved = dup(fd);
    dup2(fileno(tmp), fd);
    *status = run(f);
    fflush(fd == 1 ? stdout : stderr);
    dup2(saved, fd);
    close(saved);
    static char text[8192];
    rewind(tmp);
    size_t n = fread(text, 1, sizeof text - 1, tmp);
    text[n] = '\0';
    fclose(tmp);
    return text;
}

static perma_cli_status run_bad(fixture *f)
{
    return PARSE(f, "--colour", "mauve");
}

static perma_cli_status run_version(fixture *f)
{
    return PARSE(f, "--version");
}

static perma_cli_status run_fail(fixture *f)
{
    return perma_cli_fail(&f->cli, f->message, sizeof f->message, "--count %u needs --flag", 3u);
}

START_TEST(what_is_printed_and_where)
{
    fixture *f = fixture_new(0);
    perma_cli_status status;
    f->cli.quiet = 0;
    ck_assert_str_eq(capture(2, run_bad, f, &status),
                     "perma-test: --colour 'mauve': expected red, green or blue (see --help)\n");
    ck_assert_int_eq(status, PERMA_CLI_USAGE);
    ck_assert_str_eq(capture(1, run_version, f, &status), "perma-test 9.8.7\n");
    ck_assert_int_eq(status, PERMA_CLI_VERSION);
    ck_assert_str_eq(capture(2, run_fail, f, &status), "perma-test: --count 3 needs --flag (see --help)\n");
    ck_assert_int_eq(status, PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "--count 3 needs --flag");
    /* Quiet: the same statuses and message, nothing printed. */
    f->cli.quiet = 1;
    ck_assert_str_eq(capture(2, run_bad, f, &status), "");
    ck_assert_int_eq(status, PERMA_CLI_USAGE);
    ck_assert_str_eq(f->message, "--colour 'mauve': expected red, green or blue");
    ck_assert_str_eq(capture(1, run_version, f, &status), "");
    /* Without a version of its own, a program has perma's; it is named
     * without the path it was run by. */
    f->cli.quiet = 0;
    f->cli.version = NULL;
    f->cli.program = "build/bin/perma-test";
    ck_assert_str_eq(capture(1, run_version, f, &status), "perma-test " PERMA_VERSION_STRING "\n");
    free(f);
}
END_TEST

/* The help text: usage lines, about, operand and option rows with the
 * accepted values appended, --help and --version, notes; every line within
 * 79 columns. */
START_TEST(help_is_written_from_the_table)
{
    fixture *f = fixture_new(0);
    FILE *tmp = tmpfile();
    ck_assert_ptr_nonnull(tmp);
    perma_cli_help(&f->cli, tmp);
    rewind(tmp);
    char text[8192];
    size_t n = fread(text, 1, sizeof text - 1, tmp);
    text[n] = '\0';
    fclose(tmp);
    const char *expected[] = {
        "usage: perma-test [options] MODEL ...\n       perma-test --flag\n\nTests the engine.\n\n",
        "\narguments:\n  MODEL ",
        "\noptions:\n      --flag ",
        "\n  -o, --output FILE ",
        "a file (default x.png)\n",
        "a count (default 16; N in 2..32)\n",
        "a seed\n", /* the full range says nothing */
        "an image size (sides in 1..16384)\n",
        "a colour (NAME: red, green or blue)\n",
        "a bound (PX >= 0.01)\n",
        "an angle (DEG > 0.5 and < 179)\n",
        "\nmore options:\n      --between X ",
        "a number (X in -1..1e6)\n",
        "an even text\n",
        "\n  -h, --help ",
        "show this help\n      --version ",
        "show the version\n\nexit status: 0 ok, 2 bad usage\n",
    };
    for (size_t k = 0; k < sizeof expected / sizeof expected[0]; ++k)
        ck_assert_msg(strstr(text, expected[k]) != NULL, "the help lacks '%s':\n%s", expected[k], text);
    for (const char *line = text; *line; line += strcspn(line, "\n") + 1)
        ck_assert_msg(strcspn(line, "\n") <= 79, "a line is longer than 79 columns:\n%s", text);
    free(f);
}
END_TEST

START_TEST(value_text_and_find)
{
    fixture *f = fixture_new(0);
    char out[32];
    ck_assert_int_eq(PARSE(f, "--colour", "green"), PERMA_CLI_OK);
    const perma_cli_option *colour = perma_cli_find(&f->cli, "colour");
    ck_assert_ptr_eq(colour, &f->rows[5]);
    ck_assert_int_eq(perma_cli_value_text(colour, out, sizeof out), 1);
    ck_assert_str_eq(out, "green");
    ck_assert_int_eq(perma_cli_value_text(perma_cli_find(&f->cli, "flag"), out, sizeof out), 1);
    ck_assert_str_eq(out, "off");
    ck_assert_ptr_eq(perma_cli_find(&f->cli, "even"), &f->rows[10]); /* the second table */
    ck_assert_int_eq(perma_cli_value_text(perma_cli_find(&f->cli, "count"), out, sizeof out), 0);
    ck_assert_ptr_null(perma_cli_find(&f->cli, "help")); /* the engine's own rows are not the program's */
    ck_assert_ptr_null(perma_cli_find(&f->cli, "colou"));
    f->t.choice = 7;
    ck_assert_int_eq(perma_cli_value_text(colour, out, sizeof out), 1);
    ck_assert_str_eq(out, "?");
    free(f);
}
END_TEST

START_TEST(number_lists)
{
    float xyz[3];
    double four[4];
    char complaint[128];
    ck_assert_int_eq(perma_cli_floats("1,-2.5,1e1", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert(xyz[0] == 1.0f && xyz[1] == -2.5f && xyz[2] == 10.0f);
    ck_assert_int_ne(perma_cli_floats("1,2", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert_str_eq(complaint, "expected 3 numbers dx,dy,dz");
    ck_assert_int_ne(perma_cli_floats("1,2,3,4", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert_str_eq(complaint, "expected 3 numbers dx,dy,dz");
    ck_assert_int_ne(perma_cli_floats("1,,3", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert_str_eq(complaint, "expected 3 numbers dx,dy,dz");
    ck_assert_int_ne(perma_cli_floats("1,x,3", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert_str_eq(complaint, "'x' is not a number");
    ck_assert_int_ne(perma_cli_floats("1,2,1e39", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert_str_eq(complaint, "'1e39' is out of range: numbers here are at most +-3.40282e+38");
    ck_assert_int_ne(perma_cli_floats("1,2,-1e39", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert_str_eq(complaint, "'-1e39' is out of range: numbers here are at most +-3.40282e+38");
    ck_assert_int_ne(perma_cli_floats("1,2,inf", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert_str_eq(complaint, "'inf' is not a number");
    ck_assert_int_ne(perma_cli_doubles("1,2,3,1e999", four, 4, "X0,X1,Y0,Y1", complaint, sizeof complaint), 0);
    ck_assert_str_eq(complaint, "'1e999' is out of range: numbers here are at most +-1.79769e+308");
    ck_assert_int_eq(perma_cli_floats("1,2,1e-60", xyz, 3, "dx,dy,dz", complaint, sizeof complaint), 0);
    ck_assert_int_eq(perma_cli_doubles("-2.2,0.8,-1.125,1.125", four, 4, "X0,X1,Y0,Y1", complaint, sizeof complaint),
                     0);
    ck_assert(four[0] == -2.2 && four[3] == 1.125);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("cli");
    TCase *tc = tcase_create("cli");
    tcase_add_test(tc, values_land_in_their_targets);
    tcase_add_loop_test(tc, bad_values_name_the_option_and_the_range, 0,
                        (int)(sizeof bad_values / sizeof bad_values[0]));
    tcase_add_test(tc, bad_usage_of_the_line);
    tcase_add_test(tc, help_and_version_stop_the_walk);
    tcase_add_test(tc, what_is_printed_and_where);
    tcase_add_test(tc, help_is_written_from_the_table);
    tcase_add_test(tc, value_text_and_find);
    tcase_add_test(tc, number_lists);
    suite_add_tcase(s, tc);
    SRunner *runner = srunner_create(s);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
