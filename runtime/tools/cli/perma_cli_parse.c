/*
 * The argv walk of the command-line engine: find each option's row,
 * take its value, parse it (perma_cli_values.c), and say bad usage one
 * way: "PROGRAM: --NAME 'VALUE': expected ... (see --help)".
 */
#include <stdarg.h>
#include <string.h>

#include <perma.h>

#include "perma_cli_internal.h"

/* Every program's own rows, after its tables. */
static const perma_cli_option own_rows[] = {
    { .name = "help", .short_name = 'h', .help = "show this help" },
    { .name = "version", .help = "show the version" },
};
#define HELP_ROW (&own_rows[0])

const perma_cli_option *perma_cli_own_rows(size_t *count)
{
    *count = sizeof own_rows / sizeof own_rows[0];
    return own_rows;
}

/* The row of `rows` an argument names: "-c" (is_short), or "--name" whose
 * name is `length` characters at `name`. */
static const perma_cli_option *match(const perma_cli_option *rows, size_t count, int is_short, char c,
                                     const char *name, size_t length)
{
    for (size_t i = 0; i < count; ++i) {
        if (is_short ? rows[i].short_name == c
                     : strlen(rows[i].name) == length && strncmp(rows[i].name, name, length) == 0)
            return &rows[i];
    }
    return NULL;
}

const perma_cli_option *perma_cli_find(const perma_cli *cli, const char *name)
{
    const perma_cli_option *found = NULL;
    for (size_t t = 0; t < cli->table_count && !found; ++t)
        found = match(cli->tables[t].options, cli->tables[t].count, 0, 0, name, strlen(name));
    return found;
}

/* The row an argument names ("--name", "--name=value" or "-c"), or NULL;
 * *inline_value: the text after '=', or NULL. */
static const perma_cli_option *find_row(const perma_cli *cli, const char *arg, const char **inline_value)
{
    *inline_value = NULL;
    int is_short = arg[0] == '-' && arg[1] != '-' && arg[1] && !arg[2];
    if (!is_short && strncmp(arg, "--", 2) != 0)
        return NULL;
    const char *name = arg + 2;
    size_t length = strcspn(name, "=");
    const perma_cli_option *found = NULL;
    for (size_t t = 0; t < cli->table_count && !found; ++t)
        found = match(cli->tables[t].options, cli->tables[t].count, is_short, arg[1], name, length);
    if (!found)
        found = match(own_rows, sizeof own_rows / sizeof own_rows[0], is_short, arg[1], name, length);
    if (found && !is_short && name[length] == '=')
        *inline_value = name + length + 1;
    return found;
}

void perma_cli_print_error(const char *program, const char *message)
{
    fprintf(stderr, "%s: %s (see --help)\n", program, message);
}

perma_cli_status perma_cli_fail(const perma_cli *cli, char *message, size_t size, const char *format, ...)
{
    va_list ap;
    va_start(ap, format);
    vsnprintf(message, size, format, ap);
    va_end(ap);
    if (!cli->quiet)
        perma_cli_print_error(cli->program, message);
    return PERMA_CLI_USAGE;
}

perma_cli_status perma_cli_check_files(const perma_cli *cli, const perma_file_role *files, size_t count,
                                       char *message, size_t size)
{
    perma_error error;
    if (perma_check_distinct_files(files, count, &error) == PERMA_OK)
        return PERMA_CLI_OK;
    return perma_cli_fail(cli, message, size, "%s", error.message);
}

int perma_cli_exit_status(perma_cli_status status)
{
    return status == PERMA_CLI_USAGE ? PERMA_CLI_EXIT_USAGE : 0;
}

/* --help and --version: print (unless quiet) and stop. */
static perma_cli_status answer(const perma_cli *cli, const perma_cli_option *row)
{
    if (!cli->quiet && row == HELP_ROW)
        perma_cli_help(cli, stdout);
    else if (!cli->quiet) /* the program's name, not the path it was run by */
        printf("%s %s\n", strrchr(cli->program, '/') ? strrchr(cli->program, '/') + 1 : cli->program,
               cli->version ? cli->version : PERMA_VERSION_STRING);
    return row == HELP_ROW ? PERMA_CLI_HELP : PERMA_CLI_VERSION;
}

/* Parse `value` by `row`; `what` names it in the complaint ("--grid", "N"). */
static perma_cli_status take(const perma_cli *cli, const perma_cli_option *row, const char *what, const char *value,
                             char *message, size_t size)
{
    char complaint[PERMA_CLI_MESSAGE_MAX];
    complaint[0] = '\0';
    if (perma_cli_apply(row, value, complaint, sizeof complaint) != 0)
        return perma_cli_fail(cli, message, size, "%s '%s': %s", what, value, complaint);
    if (row->given)
        *row->given = 1;
    return PERMA_CLI_OK;
}

static perma_cli_status take_operand(const perma_cli *cli, const char *arg, size_t *count, char *message,
                                     size_t size)
{
    if (!cli->operand || (cli->max_operands && *count == cli->max_operands))
        return perma_cli_fail(cli, message, size, "unexpected argument '%s'", arg);
    ++*count;
    if (cli->operand_count)
        *cli->operand_count = *count;
    return take(cli, cli->operand, cli->operand->argument ? cli->operand->argument : "argument", arg, message, size);
}

perma_cli_status perma_cli_parse(const perma_cli *cli, int argc, char **argv, char *message, size_t size)
{
    size_t operands = 0;
    int only_operands = 0;
    message[0] = '\0';
    if (cli->operand_count)
        *cli->operand_count = 0;
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        perma_cli_status status = PERMA_CLI_OK;
        if (only_operands || arg[0] != '-' || strcmp(arg, "-") == 0) {
            status = take_operand(cli, arg, &operands, message, size);
        } else if (strcmp(arg, "--") == 0) {
            only_operands = 1;
        } else {
            const char *value;
            const perma_cli_option *row = find_row(cli, arg, &value);
            char what[80];
            snprintf(what, sizeof what, "--%s", row ? row->name : "");
            if (!row)
                status = perma_cli_fail(cli, message, size, "unknown option '%s'", arg);
            else if (row->argument && !value && i + 1 >= argc)
                status = perma_cli_fail(cli, message, size, "%s needs a value %s", what, row->argument);
            else if (!row->argument && value)
                status = perma_cli_fail(cli, message, size, "%s takes no value", what);
            else if (row == &own_rows[0] || row == &own_rows[1])
                status = answer(cli, row);
            else
                status = take(cli, row, what, row->argument && !value ? argv[++i] : value, message, size);
        }
        if (status != PERMA_CLI_OK)
            return status;
    }
    return PERMA_CLI_OK;
}
