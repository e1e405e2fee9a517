/* Command-line parsing of the bfs program: its rows and the examples'
 * shared ones (example_options.h) for the engine (perma_cli.h). */
#include "bfs_options.h"

#include <limits.h>

perma_cli_status bfs_parse_options(int argc, char **argv, bfs_options *o, char *message, size_t size)
{
    perma_cli_option shared[EXAMPLE_OPTION_ROWS];
    perma_cli_table tables[2];
    *o = (bfs_options){ .degree = 4, .seed = 1 };
    example_options_init(&o->common, shared, &tables[1]);
    const perma_cli_option rows[] = {
        { PERMA_CLI_WHOLE("generate", "N", &o->generate, 2, BFS_MAX_VERTICES,
                          "a preferential-attachment (power-law) graph of N vertices") },
        { PERMA_CLI_WHOLE("degree", "M", &o->degree, 1, 1000, "edges per new vertex when generating (default 4)") },
        { PERMA_CLI_WHOLE64("seed", "S", &o->seed, 0, ULLONG_MAX, "generator seed (default 1)") },
        { PERMA_CLI_WHOLE("source", "V", &o->source, 0, BFS_MAX_VERTICES - 1, "start vertex (default 0)") },
        { PERMA_CLI_FLAG("directed", &o->directed, "edges go from u to v only (default: both ways)") },
        { PERMA_CLI_TEXT("output", "FILE", &o->output, "write 'vertex level' lines (-1: unreached)"),
          .short_name = 'o' },
    };
    tables[0] = (perma_cli_table){ "options", rows, sizeof rows / sizeof rows[0] };
    const perma_cli_option edge_file = {
        PERMA_CLI_TEXT(NULL, "EDGE_FILE", &o->edge_file,
                       "one edge 'u v' per line (vertex ids from 0); '#' starts a comment"),
    };
    const perma_cli cli = {
        .program = "perma-bfs",
        .synopsis = "[options] EDGE_FILE\n[options] --generate N",
        .about = "Breadth-first levels from a source vertex with perma procedures.",
        .tables = tables,
        .table_count = 2,
        .operand = &edge_file,
        .max_operands = 1,
        .notes = "exit status: 0 ok, 1 runtime or file failure (a bad edge file), 2 bad usage",
    };
    perma_cli_status status = perma_cli_parse(&cli, argc, argv, message, size);
    if (status != PERMA_CLI_OK)
        return status;
    if (!o->edge_file == !o->generate)
        return perma_cli_fail(&cli, message, size, "give either an edge file or --generate N");
    if (o->generate && o->degree >= o->generate)
        return perma_cli_fail(&cli, message, size, "--degree %u must be below --generate %u", o->degree,
                              o->generate);
    const perma_file_role files[] = { { o->edge_file, "the edge file", 0 }, { o->output, "--output", 1 } };
    return perma_cli_check_files(&cli, files, 2, message, size);
}
