/*
 * perma_cli: the command-line engine of perma's programs (perma-info,
 * perma-bench, reyes-render and the examples).  A program describes its
 * options as a table of rows (name, value, what the value goes into, its
 * range, help); the engine walks argv, parses every value into its target
 * or says what it expected, and writes --help from the table.  Every
 * program so answers --help and --version the same way, exits with status
 * 2 on bad usage, and words its complaints alike:
 *
 *     perma-bfs: --groups '0': expected a whole number in 1..4096 (see --help)
 *
 * A table is an array built where its targets are (a function's locals, a
 * struct of options), e.g.
 *
 *     unsigned n = 10;
 *     const char *output = "out.png";
 *     const perma_cli_option rows[] = {
 *         { PERMA_CLI_WHOLE("n", "N", &n, 1, 16, "board size (default 10)") },
 *         { PERMA_CLI_TEXT("output", "FILE", &output, "PNG to write"), .short_name = 'o' },
 *     };
 *     const perma_cli_table table = { "options", rows, sizeof rows / sizeof rows[0] };
 *     const perma_cli cli = { .program = "perma-x", .synopsis = "[options]", .tables = &table,
 *                             .table_count = 1, .notes = "exit status: 0 ok, 1 failure, 2 bad usage" };
 *     char message[PERMA_CLI_MESSAGE_MAX];
 *     perma_cli_status status = perma_cli_parse(&cli, argc, argv, message, sizeof message);
 *     if (status != PERMA_CLI_OK)
 *         return perma_cli_exit_status(status);
 *
 * The row macros set a row's fields; a row adds others after them
 * (.short_name, .given, .open).  Accepted forms: --name VALUE,
 * --name=VALUE, -c VALUE, flags without a value, and "--" before operands
 * that start with '-'.  --help (-h) and --version are every program's.
 *
 * Not part of libperma: a static library (libperma-cli.a, pkg-config
 * perma-cli) that perma's programs and the first example link.
 */
#ifndef PERMA_CLI_H
#define PERMA_CLI_H

#include <math.h> /* INFINITY, the bound of a FLOAT or DOUBLE row without one */
#include <stddef.h>
#include <stdio.h>
#include <perma.h> /* perma_file_role */

#define PERMA_CLI_MESSAGE_MAX 512 /* room for any message of the engine */
#define PERMA_CLI_EXIT_USAGE 2    /* the exit status of bad usage */

typedef enum perma_cli_status {
    PERMA_CLI_OK = 0,  /* parsed: run the program */
    PERMA_CLI_HELP,    /* --help was given and printed: exit 0 */
    PERMA_CLI_VERSION, /* --version was given and printed: exit 0 */
    PERMA_CLI_USAGE    /* bad usage, said on stderr and in the message: exit 2 */
} perma_cli_status;

/* What a row's value is and where it goes (`target`). */
typedef enum perma_cli_kind {
    PERMA_CLI_KIND_FLAG,    /* int: 1 when given; the option takes no value */
    PERMA_CLI_KIND_TEXT,    /* const char *: the value as given */
    PERMA_CLI_KIND_WHOLE,   /* unsigned: a decimal number in least..most */
    PERMA_CLI_KIND_WHOLE64, /* unsigned long long: the same */
    PERMA_CLI_KIND_FLOAT,   /* float: a finite number from low to high */
    PERMA_CLI_KIND_DOUBLE,  /* double: the same */
    PERMA_CLI_KIND_SIZE,    /* unsigned[2]: WxH, each side in least..most */
    PERMA_CLI_KIND_CHOICE,  /* unsigned (or an enum of its size): the index of the name given */
    PERMA_CLI_KIND_CUSTOM   /* the row's own `parse` */
} perma_cli_kind;

/* .open of a FLOAT or DOUBLE row: its bounds themselves are refused. */
#define PERMA_CLI_ABOVE_LOW 1u
#define PERMA_CLI_BELOW_HIGH 2u

typedef struct perma_cli_option perma_cli_option;

/* A CUSTOM row's parser: store `value` into option->target and return 0,
 * or return nonzero with what is wrong in `complaint` ("expected ...");
 * the engine prefixes "--NAME 'VALUE': ". */
typedef int (*perma_cli_parser)(const perma_cli_option *option, const char *value, char *complaint,
                                size_t size);

struct perma_cli_option {
    const char *name;     /* long name without dashes ("output"); an operand row: NULL */
    char short_name;      /* 'o' for -o; 0: none */
    const char *argument; /* the value in --help and messages ("FILE"); NULL: a flag */
    const char *help;     /* one sentence; the engine appends the range of a number */
    perma_cli_kind kind;
    void *target;
    unsigned long long least, most; /* WHOLE, WHOLE64, SIZE */
    double low, high;               /* FLOAT, DOUBLE (-INFINITY, INFINITY: unbounded) */
    unsigned open;                  /* FLOAT, DOUBLE: PERMA_CLI_ABOVE_LOW | PERMA_CLI_BELOW_HIGH */
    const char *const *names;       /* CHOICE: NULL-terminated; or */
    const char *(*name_of)(unsigned value); /* CHOICE: value's name, NULL past the last */
    perma_cli_parser parse;         /* CUSTOM */
    int *given;                     /* set to 1 when the option is given (NULL: not kept) */
};

#define PERMA_CLI_FLAG(n, t, h) .name = (n), .kind = PERMA_CLI_KIND_FLAG, .target = (t), .help = (h)
#define PERMA_CLI_TEXT(n, a, t, h) .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_TEXT, .target = (t), .help = (h)
#define PERMA_CLI_WHOLE(n, a, t, lo, hi, h) \
    .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_WHOLE, .target = (t), .least = (lo), .most = (hi), .help = (h)
#define PERMA_CLI_WHOLE64(n, a, t, lo, hi, h) \
    .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_WHOLE64, .target = (t), .least = (lo), .most = (hi), .help = (h)
#define PERMA_CLI_FLOAT(n, a, t, lo, hi, h) \
    .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_FLOAT, .target = (t), .low = (lo), .high = (hi), .help = (h)
#define PERMA_CLI_DOUBLE(n, a, t, lo, hi, h) \
    .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_DOUBLE, .target = (t), .low = (lo), .high = (hi), .help = (h)
#define PERMA_CLI_SIZE(n, a, t, lo, hi, h) \
    .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_SIZE, .target = (t), .least = (lo), .most = (hi), .help = (h)
#define PERMA_CLI_CHOICE(n, a, t, list, h) \
    .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_CHOICE, .target = (t), .names = (list), .help = (h)
#define PERMA_CLI_CHOICE_OF(n, a, t, fn, h) \
    .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_CHOICE, .target = (t), .name_of = (fn), .help = (h)
#define PERMA_CLI_CUSTOM(n, a, p, t, h) \
    .name = (n), .argument = (a), .kind = PERMA_CLI_KIND_CUSTOM, .parse = (p), .target = (t), .help = (h)

/* The names of perma's techniques, strategies and victims for CHOICE rows
 * (perma_*_name), so that a new one is accepted without a change. */
const char *perma_cli_technique_name(unsigned value);
const char *perma_cli_strategy_name(unsigned value);
const char *perma_cli_victim_name(unsigned value);

/* A heading ("options") and its rows, listed under it in --help. */
typedef struct perma_cli_table {
    const char *heading;
    const perma_cli_option *options;
    size_t count;
} perma_cli_table;

typedef struct perma_cli {
    const char *program;  /* in messages, --help and --version */
    const char *synopsis; /* after "usage: PROGRAM "; each '\n' starts another usage line */
    const char *about;    /* what the program does (lines of text after the usage; may be NULL) */
    const perma_cli_table *tables;
    size_t table_count;
    /* Operands (arguments that are not options): each is parsed by this
     * row (its argument names it, e.g. "N"); NULL: none are taken. */
    const perma_cli_option *operand;
    size_t max_operands; /* 0: any number */
    size_t *operand_count; /* how many were given (may be NULL) */
    const char *notes;    /* text after the options, e.g. "exit status: 0 ok, 1 failure, 2 bad usage" */
    const char *version;  /* after "PROGRAM " in --version; NULL: perma's version */
    int quiet;            /* print nothing (e.g. an MPI rank other than 0); the message is still set */
} perma_cli;

/* Walk argv: every option's value into its target, in order.  --help and
 * --version print the help or "PROGRAM VERSION" on stdout and stop the
 * walk (PERMA_CLI_HELP, PERMA_CLI_VERSION); bad usage stops it too, with
 * the complaint in `message` and "PROGRAM: MESSAGE (see --help)" on stderr
 * (PERMA_CLI_USAGE).  Nothing is printed when cli->quiet. */
perma_cli_status perma_cli_parse(const perma_cli *cli, int argc, char **argv, char *message, size_t size);

/* Bad usage found after the walk (options that do not fit together):
 * the message from `format`, said as perma_cli_parse says it; returns
 * PERMA_CLI_USAGE. */
perma_cli_status perma_cli_fail(const perma_cli *cli, char *message, size_t size, const char *format, ...)
    __attribute__((format(printf, 4, 5)));

/* The files of a parsed command line (perma_check_distinct_files): two
 * outputs that are one file, or an output that is an input, are bad
 * usage, said as perma_cli_fail says it; else PERMA_CLI_OK. */
perma_cli_status perma_cli_check_files(const perma_cli *cli, const perma_file_role *files, size_t count,
                                       char *message, size_t size);

/* "PROGRAM: MESSAGE (see --help)" on stderr: how bad usage is said. */
void perma_cli_print_error(const char *program, const char *message);

/* The exit status a status ends the program with: 0 after --help or
 * --version, PERMA_CLI_EXIT_USAGE after bad usage (0 for PERMA_CLI_OK). */
int perma_cli_exit_status(perma_cli_status status);

/* Stop signals.  A program that runs OpenCL work takes SIGINT, SIGTERM
 * and SIGHUP in a thread of its own ("stop-signals") with sigwait(),
 * blocked in every other thread: PoCL's LLVM installs handlers for them at
 * its first compile, so a handler of the program's may not be the one that
 * runs.  Call before any thread starts.  stopped(number) runs in that
 * thread when one comes (to say what was going on); when it returns, the
 * process ends by the signal, as it would have without it.  0, or -1 when
 * the thread could not start (the signals keep their default actions). */
int perma_cli_take_stop_signals(void (*stopped)(int number));
/* "SIGINT", "SIGTERM", "SIGHUP" ("a signal" for another). */
const char *perma_cli_signal_name(int number);

/* The --help text: usage lines, about, operands and options (with their
 * ranges), --help and --version, notes. */
void perma_cli_help(const perma_cli *cli, FILE *out);

/* The row of option `name` (without dashes), or NULL. */
const perma_cli_option *perma_cli_find(const perma_cli *cli, const char *name);

/* The value in the target of a FLAG ("on", "off") or CHOICE (its name, "?"
 * if out of range) row into out: 1; 0 for other kinds. */
int perma_cli_value_text(const perma_cli_option *option, char *out, size_t size);

/* Parse `value` as `option`'s kind into its target (a CUSTOM row's parser
 * may parse a part so): 0, or nonzero with the complaint. */
int perma_cli_apply(const perma_cli_option *option, const char *value, char *complaint, size_t size);

/* For CUSTOM parsers: exactly `count` comma-separated finite numbers; 0,
 * or nonzero with the complaint ("expected 3 numbers dx,dy,dz", the shape
 * being `shape`, or "'x' is not a number"). */
int perma_cli_floats(const char *text, float *out, size_t count, const char *shape, char *complaint,
                     size_t size);
int perma_cli_doubles(const char *text, double *out, size_t count, const char *shape, char *complaint,
                      size_t size);

#endif
