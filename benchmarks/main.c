/* perma-bench: command line and the table of subcommands.
 *
 * To add a benchmark, write bench_NAME.c with an entry function of type
 * bench_command.run and add one line to `commands` below. */
#include "bench.h"

#include <string.h>

static const bench_command commands[] = {
    { "queue", "throughput of empty tasks per strategy, batch size and work-group count", bench_queue },
    { "tree", "unbalanced tree search (UTS-style geometric and binomial trees)", bench_tree },
    { "pipeline", "producer -> transform -> consumer with skewed fan-out: peak queue memory", bench_pipeline },
    { "plain", "newcomer-style workloads (trees, integration, queens, sort) vs C and OpenMP", bench_plain },
    { "reyes", "Reyes renderer on teapot and killeroo: stages, counts, vs the C reference", bench_reyes },
};
static const unsigned command_count = sizeof commands / sizeof commands[0];

static const char *command_name(unsigned k)
{
    return k < command_count ? commands[k].name : NULL;
}

/* The command line without a command first: --help, --version, or bad
 * usage (no command, an unknown one, options before it). */
static int without_command(int argc, char **argv)
{
    bench_options options = { .repeat = 3 };
    perma_cli_option common[BENCH_COMMON_OPTIONS];
    bench_common_options(&options, common);
    unsigned command = 0;
    size_t given = 0;
    const perma_cli_option operand = { PERMA_CLI_CHOICE_OF(NULL, "COMMAND", &command, command_name, NULL) };
    char about[2048], message[PERMA_CLI_MESSAGE_MAX];
    int used = snprintf(about, sizeof about,
                        "The scheduler microbenchmarks: each command measures its workload with every perma\n"
                        "variant (schedule), sequential C and OpenMP tasks, and checks every result.\n\n"
                        "commands:\n");
    for (unsigned i = 0; i < command_count && used > 0 && (size_t)used < sizeof about; ++i)
        used += snprintf(about + used, sizeof about - (size_t)used, "  %-10s %s\n", commands[i].name,
                         commands[i].summary);
    if (used > 0 && (size_t)used < sizeof about)
        snprintf(about + used, sizeof about - (size_t)used, "\n`perma-bench COMMAND --help` lists a command's own options.");
    const perma_cli_table table = { "common options", common, BENCH_COMMON_OPTIONS };
    const perma_cli cli = {
        .program = "perma-bench",
        .synopsis = "COMMAND [options]",
        .about = about,
        .tables = &table,
        .table_count = 1,
        .operand = &operand,
        .max_operands = 1,
        .operand_count = &given,
        .notes = BENCH_EXIT_STATUS,
    };
    perma_cli_status status = perma_cli_parse(&cli, argc, argv, message, sizeof message);
    if (status == PERMA_CLI_OK)
        status = given ? perma_cli_fail(&cli, message, sizeof message, "the command comes first: perma-bench %s "
                                                                        "[options]", commands[command].name)
                       : perma_cli_fail(&cli, message, sizeof message, "no command given");
    return perma_cli_exit_status(status);
}

int main(int argc, char **argv)
{
    for (unsigned i = 0; argc > 1 && i < command_count; ++i) {
        if (strcmp(argv[1], commands[i].name) == 0) {
            bench_options options = { .repeat = 3 };
            bench_activity_start(commands[i].name);
            /* The command sees argv[0] = its name and the rest. */
            return commands[i].run(&options, argc - 1, argv + 1);
        }
    }
    return without_command(argc, argv);
}
