/* perma-bench: shared declarations of the scheduler microbenchmarks.
 *
 * Every subcommand measures one workload with every perma variant (see
 * variants.c), a sequential C implementation and an OpenMP-tasks
 * implementation, and reports one row per measurement through report.c. */
#ifndef BENCH_H
#define BENCH_H

#include <perma.h>
#include <perma_cli.h>

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define BENCH_MAX_DEVICES 4

/* Options common to every subcommand. */
typedef struct bench_options {
    const char *csv_path;   /* --csv FILE, or NULL */
    unsigned repeat;        /* --repeat N: timed runs, the median is reported */
    int best;               /* --best: report the fastest of the timed runs instead */
    int quick;              /* --quick: small sizes (tests) */
    unsigned groups;        /* --groups N: perma work-groups, 0 = runtime default */
    unsigned threads;       /* OpenMP threads: --threads N, 0 = online CPUs */
    const char *only;       /* --only TEXT: run only perma variants whose label contains it
                             * (=LABEL: only that label) */
    int verbose;            /* --verbose: perma_print_stats after each perma row */
    /* --devices LIST: PERMA_DEVICE values (e.g. pocl,intel); every perma
     * row is measured once per device, the rows of a variant side by side. */
    const char *devices[BENCH_MAX_DEVICES];
    unsigned device_count;
    char device_list[256];  /* the list the devices point into */
} bench_options;

/* A subcommand: one entry of the table in main.c.  `run` gets the
 * command's argv (argv[0]: its name) and parses it with bench_parse. */
typedef struct bench_command {
    const char *name;
    const char *summary;
    int (*run)(bench_options *options, int argc, char **argv);
} bench_command;

int bench_queue(bench_options *options, int argc, char **argv);
int bench_tree(bench_options *options, int argc, char **argv);
int bench_pipeline(bench_options *options, int argc, char **argv);
int bench_reyes(bench_options *options, int argc, char **argv);
int bench_plain(bench_options *options, int argc, char **argv);

/* ---- command lines (bench_cli.c) ---- */

#define BENCH_COMMON_OPTIONS 9
#define BENCH_EXIT_STATUS \
    "exit status: 0 all checks passed, 1 a result was wrong or output failed, 2 bad usage.\n" \
    "Variants the runtime does not support print as n/a."

/* The rows of the options every command takes, their targets in *o. */
void bench_common_options(bench_options *o, perma_cli_option rows[BENCH_COMMON_OPTIONS]);

/* Parse a command's argv (argv[0]: its name) with its own `rows` (listed
 * as "NAME options") and the common ones (into *options); `synopsis`
 * follows "usage: perma-bench NAME".  PERMA_CLI_OK: run; otherwise the
 * command returns perma_cli_exit_status(status) (help, version or bad
 * usage printed). */
perma_cli_status bench_parse(bench_options *options, const char *synopsis, const char *about,
                             const perma_cli_option *rows, size_t count, int argc, char **argv);

/* ---- results (report.c) ---- */

typedef enum bench_check {
    BENCH_CHECK_NONE = 0, /* nothing to compare (or the variant did not run) */
    BENCH_CHECK_PASS,
    BENCH_CHECK_FAIL
} bench_check;

typedef struct bench_row {
    char workload[64];       /* e.g. "geometric b=4 d=10" */
    char variant[64];        /* e.g. "megakernel/stealing/random", "sequential C" */
    unsigned group_size;     /* perma rows; 0 otherwise */
    unsigned work_groups;    /* perma rows: groups; baselines: threads */
    int ran;                 /* 0: "n/a", message says why */
    char message[PERMA_MESSAGE_MAX + 64];
    double seconds;          /* median of the timed runs */
    double wall_seconds;     /* perma rows: median wall time around perma_run */
    double cpu_seconds;      /* median CPU time of the process (all threads) per run; 0: not measured */
    double units;            /* items or nodes processed per run */
    const char *unit;        /* "items" or "nodes" */
    uint64_t count, expected;
    bench_check check;
    size_t peak_queue_bytes; /* perma: largest queue allocation */
    size_t peak_item_bytes;  /* sum over procedures of peak items * item size */
    uint64_t steals, donations, spills;
} bench_row;

/* One report per subcommand run: a readable table on stdout and, when
 * csv_path is set, the same rows in a CSV file. */
typedef struct bench_report bench_report;

int bench_report_open(bench_report **out, const char *benchmark, const bench_options *options);
/* Widen the variant column by `extra` characters (for longer row names). */
void bench_report_widen(bench_report *report, int extra);
/* Print a "cpu vs seq" column: the CPU time (all threads) of sequential C
 * over the row's, from bench_row.cpu_seconds. */
void bench_report_show_cpu(bench_report *report);
/* Start a new workload: its first row should be the sequential baseline. */
void bench_report_workload(bench_report *report, const char *title);
/* Print and record one row; the sequential row sets the ratio baseline. */
void bench_report_add(bench_report *report, const bench_row *row, int is_baseline);
/* Number of rows whose check failed. */
unsigned bench_report_failures(const bench_report *report);
/* Finish the table and write the CSV file; returns 0, or 1 when writing failed or
 * no perma variant was measured (every perma row n/a, or none at all). */
int bench_report_close(bench_report *report);

/* Initialise a row with a workload and variant name (and show that its
 * measurement starts: bench_status_show). */
void bench_row_init(bench_row *row, const char *workload, const char *variant, const char *unit);

/* ---- the row being measured, on a terminal (status.c) ---- */

/* When stderr is a terminal: "perma-bench: row N, T s: WORKLOAD: VARIANT"
 * on one line of it, redrawn in place. */
void bench_status_show(const char *workload, const char *variant);
/* A row was printed: clear the line (bench_report_add). */
void bench_status_row_printed(void);

/* ---- timing (timing.c) ---- */

double bench_now(void);                         /* monotonic seconds */
double bench_cpu_now(void);                     /* CPU seconds of the process, all threads */
double bench_median(double *values, unsigned count); /* sorts values */
/* The median of the timed runs, or the fastest with --best. */
double bench_summary(const bench_options *options, double *values, unsigned count);

/* ---- perma variants (variants.c) ---- */

/* A perma variant: a schedule label (perma_schedule_parse), which is also
 * the variant's name in reports and what --only matches, and the schedule
 * parsed from it. */
typedef struct bench_variant {
    const char *label;
    perma_schedule schedule;
    char name[80];          /* its rows' name: the label, plus " @DEVICE" with --devices */
} bench_variant;

/* The variants every benchmark measures: how many, and the label of
 * variant `index` (NULL past the last one). */
unsigned bench_variant_count(void);
const char *bench_variant_label(unsigned index);
/* Add `label` after the listed variants unless it is one of them (--only
 * =LABEL with a label the list does not have, e.g. another stack size). */
void bench_variant_add(const char *label);
/* The labels of every schedule of `set` (perma_schedule_all), the bounded
 * batches with their default limit named ("bounded-batches/p=4096"), at
 * most `max` of them; returns how many. */
#define BENCH_LABEL_SIZE 64
unsigned bench_schedule_labels(perma_schedule_set set, char (*labels)[BENCH_LABEL_SIZE], unsigned max);

/* Parse a label into *out (out->label points to it); the parser's status
 * and, in *error (may be NULL), its message. */
perma_status bench_variant_parse(const char *label, bench_variant *out, perma_error *error);
/* Passes over devices: the number of --devices, or 1 (the device
 * PERMA_DEVICE or the default picks). */
unsigned bench_device_passes(const bench_options *options);
/* Make device pass d the one the runtimes created next use (PERMA_DEVICE)
 * and name v's rows after it. */
void bench_variant_use_device(const bench_options *options, unsigned d, bench_variant *v);

/* Whether --only selects `label` (a substring of it, or the whole label
 * after '=': --only =megakernel/shared); if so, parse it into
 * *out.  A label that does not parse prints as n/a with the parser's
 * message and is not selected. */
int bench_variant_select(const bench_options *options, const char *label, bench_variant *out);

/* ---- running a perma workload (perma_session.c) ---- */

/* A workload plugged into bench_perma_measure: `prepare` resets the host
 * counters and seeds the queues before each run; `verify` compares the
 * results of the run that just finished with the expected ones and fills
 * row->count/expected. */
typedef struct bench_workload {
    perma_status (*prepare)(void *state, perma_runtime *rt);
    int (*verify)(void *state, perma_runtime *rt, bench_row *row);
    void *state;
    unsigned procedures;       /* registered procedures */
    const perma_proc *procs;   /* their handles */
    const size_t *item_sizes;  /* and item sizes */
} bench_workload;

/* Create a runtime for `variant` with the given group size and work-group
 * count.  On failure returns NULL and writes the message into row. */
perma_runtime *bench_perma_create(const bench_variant *variant, unsigned group_size,
                                  unsigned work_groups, bench_row *row);

/* Build, run once untimed (warm-up), then options->repeat timed runs.
 * Fills row (times: median of perma_stats.seconds and of wall time; the
 * queue statistics of the last run) and marks it ran, or sets the message
 * and leaves ran == 0 when a call failed.  Every run is verified.  A row
 * whose statistics name another technique or strategy than `variant` says
 * so in its message. */
void bench_perma_measure(perma_runtime *rt, const bench_variant *variant, const bench_options *options,
                         const bench_workload *workload, bench_row *row);

/* Print the runtime's statistics when --verbose. */
void bench_perma_verbose(perma_runtime *rt, const bench_options *options);

/* Time `repeat` runs of fn (after one warm-up run) and return the median. */
double bench_time_baseline(const bench_options *options, void (*fn)(void *), void *arg);
/* The same with prepare(arg) before every call of fn, outside the timing
 * (e.g. restoring an input that fn changes in place). */
double bench_time_prepared(const bench_options *options, void (*prepare)(void *), void (*fn)(void *), void *arg);
/* The same, with the median (or, with --best, least) CPU time of the
 * process per call too. */
typedef struct bench_timing {
    double seconds, cpu_seconds;
} bench_timing;
bench_timing bench_time_runs(const bench_options *options, void (*prepare)(void *), void (*fn)(void *), void *arg);

/* Number of OpenMP threads to use. */
unsigned bench_threads(const bench_options *options);

/* ---- what it is doing (activity.c) ---- */

/* Take SIGTERM, SIGINT and SIGHUP (blocked in every thread, waited for by
 * one thread, whatever handlers libraries install): each then ends
 * perma-bench with a line on stderr naming the benchmark, the seconds since
 * this call and the activity last set, and exit status 1. */
void bench_activity_start(const char *benchmark);
/* Set the activity, e.g. "building %s (%s)" with a variant and workload. */
void bench_activity(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif
