/* perma-bench: command line and the table of subcommands.
 *
 * To add a benchmark, write bench_NAME.c with an entry function of type
 * bench_command.run and add one line to `commands` below. */
#include "bench.h"

#include <stdlib.h>
#include <string.h>

static const bench_command commands[] = {
    { "queue", "throughput of empty tasks per strategy, batch size and work-group count", bench_queue },
    { "tree", "unbalanced tree search (UTS-style geometric and binomial trees)", bench_tree },
    { "pipeline", "producer -> transform -> consumer with skewed fan-out: peak queue memory", bench_pipeline },
    { "plain", "newcomer-style workloads (trees, integration, queens, sort) vs C and OpenMP", bench_plain },
    { "reyes", "Reyes renderer on teapot and killeroo: stages, counts, vs the C reference", bench_reyes },
};
static const unsigned command_count = sizeof commands / sizeof commands[0];

static void usage(FILE *out)
{
    fprintf(out,
            "usage: perma-bench COMMAND [options] [command options]\n"
            "\n"
            "commands:\n");
    for (unsigned i = 0; i < command_count; ++i)
        fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(out,
            "\n"
            "options:\n"
            "  --csv FILE     also write the rows to FILE as CSV\n"
            "  --repeat N     timed runs per variant, the median is reported (default 3)\n"
            "  --best         report the fastest of the --repeat runs instead of the median\n"
            "                 (on a shared, noisy machine: the time least disturbed)\n"
            "  --quick        small sizes (for tests)\n"
            "  --groups N     perma work-groups (default: the runtime's choice)\n"
            "  --threads N    OpenMP threads (default: online CPUs)\n"
            "  --only TEXT    run only perma variants whose label contains TEXT\n"
            "                 (--only =LABEL: only the variant of exactly that label)\n"
            "  --devices LIST measure every perma variant on each device of LIST, side by side\n"
            "                 (PERMA_DEVICE values: pocl,intel or 0:0,1:0; the reyes effect\n"
            "                 workloads use the first)\n"
            "  --verbose      print perma's statistics after each perma run\n"
            "  --help         this text; `perma-bench COMMAND --help` for command options\n"
            "\n"
            "Exit status: 0 all checks passed, 1 a result was wrong or output failed,\n"
            "2 bad usage.  Variants the runtime does not support print as n/a.\n");
}

static int parse_unsigned(const char *option, const char *text, unsigned min, unsigned max, unsigned *out)
{
    char *end;
    unsigned long value = text ? strtoul(text, &end, 10) : 0;
    if (!text || !*text || *end || value < min || value > max) {
        fprintf(stderr, "perma-bench: %s needs a number in %u..%u, got '%s'\n", option, min, max,
                text ? text : "");
        return -1;
    }
    *out = (unsigned)value;
    return 0;
}

/* Take the common options out of argv (the rest stays for the command).
 * Returns the new argc, or -1 on a usage error. */
static int parse_common(int argc, char **argv, bench_options *o)
{
    int kept = 1;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--csv") == 0) {
            if (!next) {
                fprintf(stderr, "perma-bench: --csv needs a file name\n");
                return -1;
            }
            o->csv_path = next;
            ++i;
        } else if (strcmp(a, "--repeat") == 0) {
            if (parse_unsigned(a, next, 1, 1000, &o->repeat))
                return -1;
            ++i;
        } else if (strcmp(a, "--groups") == 0) {
            if (parse_unsigned(a, next, 1, 1024, &o->groups))
                return -1;
            ++i;
        } else if (strcmp(a, "--threads") == 0) {
            if (parse_unsigned(a, next, 1, 1024, &o->threads))
                return -1;
            ++i;
        } else if (strcmp(a, "--only") == 0) {
            if (!next) {
                fprintf(stderr, "perma-bench: --only needs a text\n");
                return -1;
            }
            o->only = next;
            ++i;
        } else if (strcmp(a, "--devices") == 0) {
            if (!next || !*next) {
                fprintf(stderr, "perma-bench: --devices needs a comma-separated list, e.g. pocl,intel\n");
                return -1;
            }
            static char list[256];
            snprintf(list, sizeof list, "%s", next);
            o->device_count = 0;
            for (char *item = strtok(list, ","); item; item = strtok(NULL, ",")) {
                if (o->device_count == BENCH_MAX_DEVICES) {
                    fprintf(stderr, "perma-bench: --devices takes at most %d devices\n", BENCH_MAX_DEVICES);
                    return -1;
                }
                o->devices[o->device_count++] = item;
            }
            ++i;
        } else if (strcmp(a, "--best") == 0) {
            o->best = 1;
        } else if (strcmp(a, "--quick") == 0) {
            o->quick = 1;
        } else if (strcmp(a, "--verbose") == 0) {
            o->verbose = 1;
        } else {
            argv[kept++] = argv[i];
        }
    }
    return kept;
}

int main(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const bench_command *command = NULL;
    for (unsigned i = 0; i < command_count; ++i)
        if (strcmp(argv[1], commands[i].name) == 0)
            command = &commands[i];
    if (!command) {
        fprintf(stderr, "perma-bench: unknown command '%s'\n", argv[1]);
        usage(stderr);
        return 2;
    }
    bench_options options = { .repeat = 3 };
    /* The command sees argv[0] = its name and its own options. */
    int rest = parse_common(argc - 1, argv + 1, &options);
    if (rest < 0)
        return 2;
    return command->run(&options, rest, argv + 1);
}
