/* perma-bench's command lines (perma_cli.h): the options every command
 * takes and the parse of one command's argv. */
#include "bench.h"

#include <string.h>

/* --devices LIST: up to BENCH_MAX_DEVICES comma-separated PERMA_DEVICE values. */
static int parse_devices(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    bench_options *o = option->target;
    size_t length = strlen(value);
    if (!length || length >= sizeof o->device_list) {
        snprintf(complaint, size, "expected a comma-separated list, e.g. pocl,intel");
        return 1;
    }
    memcpy(o->device_list, value, length + 1);
    o->device_count = 0;
    for (char *item = strtok(o->device_list, ","); item; item = strtok(NULL, ",")) {
        if (o->device_count == BENCH_MAX_DEVICES) {
            snprintf(complaint, size, "expected at most %d devices", BENCH_MAX_DEVICES);
            return 1;
        }
        o->devices[o->device_count++] = item;
    }
    return 0;
}

void bench_common_options(bench_options *o, perma_cli_option rows[BENCH_COMMON_OPTIONS])
{
    const perma_cli_option common[BENCH_COMMON_OPTIONS] = {
        { PERMA_CLI_TEXT("csv", "FILE", &o->csv_path, "also write the rows to FILE as CSV") },
        { PERMA_CLI_WHOLE("repeat", "N", &o->repeat, 1, 1000,
                          "timed runs per variant, the median is reported (default 3)") },
        { PERMA_CLI_FLAG("best", &o->best, "report the fastest of the --repeat runs instead of the median (on a "
                                           "shared, noisy machine: the time least disturbed)") },
        { PERMA_CLI_FLAG("quick", &o->quick, "small sizes (for tests)") },
        { PERMA_CLI_WHOLE("groups", "N", &o->groups, 1, 1024, "perma work-groups (default: the runtime's choice)") },
        { PERMA_CLI_WHOLE("threads", "N", &o->threads, 1, 1024, "OpenMP threads (default: online CPUs)") },
        { PERMA_CLI_TEXT("only", "TEXT", &o->only, "run only perma variants whose label contains TEXT (--only =LABEL: only the variant of "
                                           "exactly that label; several, separated by commas: the variants of "
                                           "any)") },
        { PERMA_CLI_CUSTOM("devices", "LIST", parse_devices, o,
                           "measure every perma variant on each device of LIST, side by side (PERMA_DEVICE "
                           "values: pocl,intel or 0:0,1:0; the reyes effect workloads use the first)") },
        { PERMA_CLI_FLAG("verbose", &o->verbose, "print perma's statistics after each perma run") },
        { PERMA_CLI_TEXT("trace", "FILE", &o->trace_path, "write every perma run's batches (warm-up and timed runs of "
                                                          "every row) to FILE as a Chrome trace (perma-trace-to-svg "
                                                          "reads it)") },
    };
    memcpy(rows, common, sizeof common);
}

perma_cli_status bench_parse(bench_options *options, const char *synopsis, const char *about,
                             const perma_cli_option *rows, size_t count, int argc, char **argv)
{
    perma_cli_option common[BENCH_COMMON_OPTIONS];
    bench_common_options(options, common);
    char heading[64], program[64], message[PERMA_CLI_MESSAGE_MAX];
    snprintf(heading, sizeof heading, "%s options", argv[0]);
    snprintf(program, sizeof program, "perma-bench %s", argv[0]);
    const perma_cli_table tables[] = { { heading, rows, count }, { "common options", common, BENCH_COMMON_OPTIONS } };
    const perma_cli cli = {
        .program = program,
        .synopsis = synopsis,
        .about = about,
        .tables = count ? tables : tables + 1,
        .table_count = count ? 2 : 1,
        .notes = BENCH_EXIT_STATUS,
    };
    perma_cli_status status = perma_cli_parse(&cli, argc, argv, message, sizeof message);
    /* --only =LABEL names any schedule, listed or not: it becomes a row
     * (each such entry of a list). */
    for (const char *entry = status == PERMA_CLI_OK ? options->only : NULL; entry;) {
        const char *comma = strchr(entry, ',');
        size_t length = comma ? (size_t)(comma - entry) : strlen(entry);
        char label[BENCH_LABEL_SIZE];
        if (entry[0] == '=' && length > 1 && length <= sizeof label) {
            memcpy(label, entry + 1, length - 1);
            label[length - 1] = '\0';
            bench_variant_add(label);
        }
        entry = comma ? comma + 1 : NULL;
    }
    const perma_file_role outputs[] = { { options->csv_path, "--csv", 1 }, { options->trace_path, "--trace", 1 } };
    return status == PERMA_CLI_OK ? perma_cli_check_files(&cli, outputs, 2, message, sizeof message) : status;
}

perma_cli_status bench_check_inputs(const bench_options *options, const char *command, const perma_file_role *inputs,
                                    size_t count)
{
    perma_file_role files[8];
    char program[64], message[PERMA_CLI_MESSAGE_MAX];
    if (count + 2 > sizeof files / sizeof files[0])
        count = sizeof files / sizeof files[0] - 2;
    memcpy(files, inputs, count * sizeof *inputs);
    files[count] = (perma_file_role){ options->csv_path, "--csv", 1 };
    files[count + 1] = (perma_file_role){ options->trace_path, "--trace", 1 };
    snprintf(program, sizeof program, "perma-bench %s", command);
    const perma_cli cli = { .program = program };
    return perma_cli_check_files(&cli, files, count + 2, message, sizeof message);
}
