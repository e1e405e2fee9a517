/*
 * Command-line parsing of reyes-render: the engine (perma_cli.h) walks
 * argv with the table (reyes_cli_options.c); then the options that depend
 * on each other are checked.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_cli_internal.h"

/* --epsilon and --lambda belong to the tiered criterion: a value the
 * bound criterion would ignore is an error. */
static perma_cli_status check_subdivision_options(reyes_cli *cli, const perma_cli *line, char *message,
                                                  size_t size)
{
    int tiered = cli->render.subdivision == REYES_SUBDIVISION_TIERED;
    /* Tiered: --bound is the largest sub-patch to dice (else grid - 1). */
    if (tiered && cli->bound_given)
        cli->render.flat_bound_px = cli->render.bound_px;
    if (!tiered && cli->render.crack_fix == REYES_CRACK_FIX_WEDGE)
        return perma_cli_fail(line, message, size, "--crack-fix wedge needs --subdivision tiered");
    if (!tiered && cli->flatness_given)
        return perma_cli_fail(line, message, size, "--epsilon and --lambda apply to --subdivision tiered");
    /* Dicing: to a shading rate of 1 by default; fixed grids with --grid
     * alone, and for the wedges and the C reference, which need them. */
    int fixed = cli->render.crack_fix == REYES_CRACK_FIX_WEDGE || cli->reference;
    if (cli->shading_rate_given && fixed)
        return perma_cli_fail(line, message, size, "--shading-rate cannot be combined with %s (fixed grids only)",
                              cli->reference ? "--reference" : "--crack-fix wedge");
    if (!cli->shading_rate_given)
        cli->render.shading_rate = cli->grid_given || fixed ? 0.0f : 1.0f;
    /* One pass at a rate; fixed grids and displaced surfaces stitch. */
    int displaced = cli->render.displace_mode != REYES_DISPLACE_NONE && cli->render.displace_amplitude != 0.0f;
    if (!cli->crack_fix_given)
        cli->render.crack_fix = cli->render.shading_rate > 0.0f && !displaced ? REYES_CRACK_FIX_POLYLINE
                                                                              : REYES_CRACK_FIX_STITCH;
    return PERMA_CLI_OK;
}

perma_cli_status reyes_cli_parse(int argc, char **argv, reyes_cli *cli, char *message, size_t size)
{
    memset(cli, 0, sizeof *cli);
    reyes_options_init(&cli->render);
    cli->output = "reyes.png";
    cli->fov_deg = 40.0f;
    cli->size[0] = cli->render.width;
    cli->size[1] = cli->render.height;
    message[0] = '\0';
    reyes_cli_description d;
    reyes_cli_describe(cli, argc > 0 ? argv[0] : "reyes-render", &d);
    cli->models = calloc(argc > 0 ? (size_t)argc : 1, sizeof *cli->models);
    if (!cli->models)
        return perma_cli_fail(&d.cli, message, size, "out of memory");
    perma_cli_status status = perma_cli_parse(&d.cli, argc, argv, message, size);
    if (status != PERMA_CLI_OK)
        return status;
    cli->render.width = cli->size[0];
    cli->render.height = cli->size[1];
    cli->render.bucket_width = cli->bucket[0];
    cli->render.bucket_height = cli->bucket[1];
    cli->render.area_stats = cli->stats_path != NULL; /* the JSON reports the micropolygons' areas */
    if (cli->orbit_given && !cli->frames)
        return perma_cli_fail(&d.cli, message, size, "--orbit needs --frames");
    if (cli->progress && cli->quiet)
        return perma_cli_fail(&d.cli, message, size, "--progress and --quiet contradict each other");
    return check_subdivision_options(cli, &d.cli, message, size);
}

void reyes_cli_frame_path(const char *output, unsigned frame, char *path, size_t size)
{
    const char *slash = strrchr(output, '/');
    const char *dot = strrchr(output, '.');
    if (!dot || (slash && dot < slash) || dot == output || (slash && dot == slash + 1))
        dot = output + strlen(output);
    snprintf(path, size, "%.*s-%04u%s", (int)(dot - output), output, frame + 1, dot);
}

perma_cli_status reyes_cli_check_files(const reyes_cli *cli, char *message, size_t size)
{
    /* The models, the displacement map, then the image or every frame,
     * the statistics and the trace (the runtime's check adds PERMA_TRACE). */
    size_t images = cli->frames ? cli->frames : 1, count = cli->model_count + 3 + images, n = 0;
    perma_file_role *files = calloc(count, sizeof *files);
    int ok = files != NULL;
    for (size_t m = 0; ok && m < cli->model_count; ++m)
        files[n++] = (perma_file_role){ cli->models[m], "the model", 0 };
    if (ok)
        files[n++] = (perma_file_role){ cli->render.displace_map, "--displace", 0 };
    size_t first_frame = n;
    for (unsigned f = 0; ok && f < cli->frames; ++f) {
        char path[REYES_CLI_PATH_MAX];
        reyes_cli_frame_path(cli->output, f, path, sizeof path);
        files[n].path = strdup(path);
        files[n].name = "--frames";
        files[n].written = 1;
        ok = files[n++].path != NULL;
    }
    if (ok && !cli->frames)
        files[n++] = (perma_file_role){ cli->output, "--output", 1 };
    if (ok)
        files[n++] = (perma_file_role){ cli->stats_path, "--stats", 1 };
    if (ok)
        files[n++] = (perma_file_role){ cli->render.trace_path, "--trace", 1 };
    perma_error error;
    perma_status status = ok ? perma_check_distinct_files(files, n, &error) : PERMA_ERR_NO_MEMORY;
    if (status == PERMA_ERR_NO_MEMORY)
        snprintf(error.message, sizeof error.message, "out of memory checking the names of %zu files", count);
    for (size_t k = first_frame; files && k < first_frame + cli->frames && k < n; ++k)
        free((char *)files[k].path);
    free(files);
    if (status == PERMA_OK)
        return PERMA_CLI_OK;
    snprintf(message, size, "%s", error.message);
    return PERMA_CLI_USAGE;
}

void reyes_cli_free(reyes_cli *cli)
{
    free(cli->models);
    cli->models = NULL;
}

int reyes_cli_field_text(const reyes_cli *cli, const char *name, char *out, size_t size)
{
    reyes_cli_description d;
    /* Only read: the table's targets are where the values are. */
    reyes_cli_describe((reyes_cli *)cli, "reyes-render", &d);
    const perma_cli_option *row = perma_cli_find(&d.cli, name);
    return row && perma_cli_value_text(row, out, size);
}

void reyes_cli_usage(FILE *out, const char *program)
{
    reyes_cli unused;
    reyes_cli_description d;
    memset(&unused, 0, sizeof unused);
    reyes_cli_describe(&unused, program, &d);
    perma_cli_help(&d.cli, out);
}
