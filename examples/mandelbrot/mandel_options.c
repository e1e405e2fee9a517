/* Command-line parsing of the mandelbrot program: its rows and the
 * examples' shared ones (example_options.h) for the engine (perma_cli.h). */
#include "mandel_options.h"

/* --region X0,X1,Y0,Y1: four numbers, X0 < X1 and Y0 < Y1. */
static int parse_region(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    double *r = option->target;
    if (perma_cli_doubles(value, r, 4, option->argument, complaint, size) != 0)
        return 1;
    if (r[0] < r[1] && r[2] < r[3])
        return 0;
    snprintf(complaint, size, "expected X0 < X1 and Y0 < Y1");
    return 1;
}

perma_cli_status mandel_parse_options(int argc, char **argv, mandel_options *o, char *message, size_t size)
{
    perma_cli_option shared[EXAMPLE_OPTION_ROWS];
    perma_cli_table tables[2];
    *o = (mandel_options){
        .size = { 1024, 768 }, .region = { -2.2, 0.8, -1.125, 1.125 },
        .max_iter = 1000, .min_size = MANDEL_DEFAULT_MIN_SIZE, .output = "mandelbrot.png",
    };
    example_options_init(&o->common, shared, &tables[1]);
    const perma_cli_option rows[] = {
        { PERMA_CLI_SIZE("size", "WxH", o->size, 1, MANDEL_MAX_SIZE, "image size (default 1024x768)") },
        { PERMA_CLI_CUSTOM("region", "X0,X1,Y0,Y1", parse_region, o->region,
                           "part of the complex plane (default -2.2,0.8,-1.125,1.125)") },
        { PERMA_CLI_WHOLE("max-iter", "N", &o->max_iter, 1, MANDEL_MAX_ITER, "iteration limit (default 1000)") },
        { PERMA_CLI_WHOLE("min-size", "N", &o->min_size, 2, 4096,
                          "compute interiors of at most N pixels per pixel (default 16)") },
        { PERMA_CLI_TEXT("output", "FILE", &o->output, "output PNG (default mandelbrot.png)"), .short_name = 'o' },
        { PERMA_CLI_FLAG("reference", &o->reference, "render with the host brute-force loop instead of perma") },
    };
    tables[0] = (perma_cli_table){ "options", rows, sizeof rows / sizeof rows[0] };
    const perma_cli cli = {
        .program = "perma-mandelbrot",
        .synopsis = "[options]",
        .about = "Adaptive (Mariani-Silver) Mandelbrot image with perma procedures; with --compare\n"
                 "a timing table instead of the image.",
        .tables = tables,
        .table_count = 2,
        .notes = "exit status: 0 ok, 1 runtime failure, 2 bad usage",
    };
    perma_cli_status status = perma_cli_parse(&cli, argc, argv, message, size);
    const perma_file_role image = { o->output, "--output", 1 };
    return status == PERMA_CLI_OK ? perma_cli_check_files(&cli, &image, 1, message, size) : status;
}
