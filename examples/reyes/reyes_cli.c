/*
 * Command-line parsing of reyes-render: walk argv, find each option in the
 * table (reyes_cli_options.c) and apply its value, then check the options
 * that depend on each other.
 */
#include <stdlib.h>
#include <string.h>

#include "reyes_cli_internal.h"

/* The option an argument names ("--name", "--name=value" or "-c"), or NULL. */
static const cli_option *find_option(const char *arg, const char **inline_value)
{
    *inline_value = NULL;
    if (arg[0] == '-' && arg[1] != '-' && arg[1] && !arg[2]) {
        for (size_t i = 0; i < cli_option_count; ++i)
            if (cli_options[i].short_name == arg[1])
                return &cli_options[i];
        return NULL;
    }
    if (strncmp(arg, "--", 2) != 0)
        return NULL;
    const char *name = arg + 2;
    size_t length = strcspn(name, "=");
    for (size_t i = 0; i < cli_option_count; ++i) {
        if (strlen(cli_options[i].name) == length && strncmp(cli_options[i].name, name, length) == 0) {
            if (name[length] == '=')
                *inline_value = name + length + 1;
            return &cli_options[i];
        }
    }
    return NULL;
}

/* --epsilon and --lambda belong to the tiered criterion: a value the
 * bound criterion would ignore is an error. */
static int check_subdivision_options(reyes_cli *cli, char *message, size_t size)
{
    int tiered = cli->render.subdivision == REYES_SUBDIVISION_TIERED;
    /* Tiered: --bound is the largest sub-patch to dice (else grid - 1). */
    if (tiered && cli->bound_given)
        cli->render.flat_bound_px = cli->render.bound_px;
    if (!tiered && cli->render.crack_fix == REYES_CRACK_FIX_WEDGE)
        return cli_usage_error(message, size, "--crack-fix wedge needs --subdivision tiered%s%s", "", "");
    if (!tiered && cli->flatness_given)
        return cli_usage_error(message, size, "--epsilon and --lambda apply to --subdivision tiered%s%s",
                               "", "");
    /* Dicing: to a shading rate of 1 by default; fixed grids with --grid
     * alone, and for the wedges and the C reference, which need them. */
    int fixed = cli->render.crack_fix == REYES_CRACK_FIX_WEDGE || cli->reference;
    if (cli->shading_rate_given && fixed)
        return cli_usage_error(message, size, "--shading-rate cannot be combined with %s (fixed grids only)%s",
                               cli->reference ? "--reference" : "--crack-fix wedge", "");
    if (!cli->shading_rate_given)
        cli->render.shading_rate = cli->grid_given || fixed ? 0.0f : 1.0f;
    return REYES_CLI_OK;
}

int reyes_cli_parse(int argc, char **argv, reyes_cli *cli, char *message, size_t size)
{
    memset(cli, 0, sizeof *cli);
    reyes_options_init(&cli->render);
    cli->output = "reyes.png";
    cli->fov_deg = 40.0f;
    message[0] = '\0';
    cli->models = calloc(argc > 0 ? (size_t)argc : 1, sizeof *cli->models);
    if (!cli->models)
        return cli_usage_error(message, size, "out of memory%s%s", "", "");
    int only_models = 0;
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (only_models || arg[0] != '-' || strcmp(arg, "-") == 0) {
            cli->models[cli->model_count++] = arg;
            continue;
        }
        if (strcmp(arg, "--") == 0) {
            only_models = 1;
            continue;
        }
        const char *value;
        const cli_option *option = find_option(arg, &value);
        if (!option)
            return cli_usage_error(message, size, "unknown option '%s' (see --help)%s", arg, "");
        if (option->argument && !value) {
            if (i + 1 >= argc)
                return cli_usage_error(message, size, "option '%s' needs a value %s", arg,
                                       option->argument);
            value = argv[++i];
        } else if (!option->argument && value) {
            return cli_usage_error(message, size, "option '--%s' takes no value%s", option->name, "");
        }
        int result = cli_option_apply(option, cli, value, message, size);
        if (result != REYES_CLI_OK)
            return result;
    }
    if (cli->orbit_given && !cli->frames)
        return cli_usage_error(message, size, "--orbit needs --frames%s%s", "", "");
    if (cli->progress && cli->quiet)
        return cli_usage_error(message, size, "--progress and --quiet contradict each other%s%s", "", "");
    return check_subdivision_options(cli, message, size);
}

void reyes_cli_free(reyes_cli *cli)
{
    free(cli->models);
    cli->models = NULL;
}
