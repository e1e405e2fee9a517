/* perma-bench reyes: the command line (models, sizes, bound, workloads)
 * and what the stage and effect workloads derive from it. */
#include "bench_reyes.h"

#include <string.h>
#include <unistd.h>

#ifndef REYES_BENCH_MODELS_DIR
#define REYES_BENCH_MODELS_DIR "../shared/models"
#endif

#define MAX_SIZES REYES_BENCH_MAX_SIZES

static const char *const off_on_names[] = { "off", "on", NULL };

/* The workloads, for --help. */
static const char workloads_help[] =
    "workloads (--workload, comma-separated; default stages,defaults; all = every one):\n"
    "  stages    teapot.bpt and killeroo.bpt from DIR (default " REYES_BENCH_MODELS_DIR ")\n"
    "            at 512x512 and 1280x1024 (--size replaces them; --quick: teapot at\n"
    "            256x256) with every technique and the main strategies, in full and\n"
    "            stopped after dice's geometry and after subdivision, the\n"
    "            single-threaded C reference of the same pipeline (shading and\n"
    "            sampling included) timed the same way, and its full render on\n"
    "            --threads OpenMP threads.  No crack fix (the C reference has none);\n"
    "            fixed cameras (docs/reyes-measurements.md).\n"
    "            Rows: seconds are the best perma_run time of --repeat runs, the\n"
    "            configurations interleaved run by run; 'vs seq' is the C reference's\n"
    "            full render / row.\n"
    "  defaults  the same models and sizes at the command's default dicing, a shading\n"
    "            rate of 1: the C reference at that rate on one thread and on --threads\n"
    "            OpenMP threads, megakernel/shared without a crack fix and stitched\n"
    "            (the command's default), interleaved run by run; the renderer and the C\n"
    "            reference both cull hidden grids (--occlusion off: neither does).\n"
    "  displace  the same models and sizes plain and with bumps displacement.\n"
    "  blur      killeroo at 800x600 (or --size) at 16, 25 and 64 spp, unblurred and\n"
    "            with each blur algorithm (simple, interleaved, bbox) under a\n"
    "            moderate motion and aperture.\n"
    "  buckets   the models and sizes without buckets and with 256, 128, 64 and 32\n"
    "            pixel buckets: peak queue memory and time (megakernel/shared and\n"
    "            kernel-per-procedure).\n"
    "The effect workloads use the first variant --only selects (buckets: those of\n"
    "megakernel/shared and kernel-per-procedure), run the configurations of a\n"
    "comparison in turn --repeat times and report the best time of each; their\n"
    "'vs seq' column is the first row's time / row (1/cost).  With --quick they\n"
    "render the built-in scene at small sizes (no model files needed).";

/* --size WxH, up to MAX_SIZES times: one size more. */
static int parse_size(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    reyes_bench_args *a = option->target;
    unsigned wxh[2];
    const perma_cli_option side = { PERMA_CLI_SIZE("size", "WxH", wxh, 1, REYES_MAX_SIZE, NULL) };
    if (a->size_count == MAX_SIZES) {
        snprintf(complaint, size, "expected at most %d sizes", MAX_SIZES);
        return 1;
    }
    if (perma_cli_apply(&side, value, complaint, size) != 0)
        return 1;
    a->widths[a->size_count] = wxh[0];
    a->heights[a->size_count++] = wxh[1];
    return 0;
}

/* --workload LIST: the REYES_BENCH_* bits of comma-separated names. */
static int parse_workloads(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    static const struct { const char *name; unsigned bits; } names[] = {
        { "stages", REYES_BENCH_STAGES }, { "defaults", REYES_BENCH_DEFAULTS }, { "displace", REYES_BENCH_DISPLACE },
        { "blur", REYES_BENCH_BLUR }, { "buckets", REYES_BENCH_BUCKETS },
        { "all", REYES_BENCH_STAGES | REYES_BENCH_DEFAULTS | REYES_BENCH_DISPLACE | REYES_BENCH_BLUR
                     | REYES_BENCH_BUCKETS },
    };
    unsigned bits = 0, found = 1;
    for (const char *at = value; *at && found;) {
        size_t n = strcspn(at, ",");
        found = 0;
        for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
            if (strlen(names[k].name) == n && strncmp(names[k].name, at, n) == 0)
                found = names[k].bits;
        bits |= found;
        at += n + (at[n] == ',');
    }
    if (!found || !bits) {
        snprintf(complaint, size, "expected a comma-separated list of stages, defaults, displace, blur, buckets or all");
        return 1;
    }
    *(unsigned *)option->target = bits;
    return 0;
}

const char *const reyes_bench_models[REYES_BENCH_MODEL_COUNT] = { "teapot", "killeroo" };

/* PERMA_CLI_OK, or what the command returns perma_cli_exit_status of. */
perma_cli_status reyes_bench_parse_args(int argc, char **argv, bench_options *options, reyes_bench_args *a)
{
    memset(a, 0, sizeof *a);
    a->models_dir = REYES_BENCH_MODELS_DIR;
    a->bound_px = 8.0f;
    a->workloads = REYES_BENCH_STAGES | REYES_BENCH_DEFAULTS;
    a->occlusion_cull = 1;
    const perma_cli_option rows[] = {
        { PERMA_CLI_TEXT("models", "DIR", &a->models_dir, "where teapot.bpt and killeroo.bpt are") },
        { PERMA_CLI_CUSTOM("size", "WxH", parse_size, a,
                           "an image size (up to 4 times; default: the workload's sizes)") },
        { PERMA_CLI_FLOAT("bound", "PX", &a->bound_px, 0.5, INFINITY, "dice patches of at most PX pixels (default 8)") },
        { PERMA_CLI_CUSTOM("workload", "LIST", parse_workloads, &a->workloads, "the workloads below (default stages,defaults)") },
        { PERMA_CLI_CHOICE("occlusion", "on|off", &a->occlusion_cull, off_on_names,
                           "cull hidden grids at a shading rate, renderer and C reference (default on)") },
    };
    perma_cli_status parsed = bench_parse(options, "[options]", workloads_help, rows, sizeof rows / sizeof rows[0],
                                          argc, argv);
    if (parsed != PERMA_CLI_OK)
        return parsed;
    /* --csv must not overwrite a model. */
    char paths[REYES_BENCH_MODEL_COUNT][4200];
    perma_file_role models[REYES_BENCH_MODEL_COUNT];
    for (unsigned m = 0; m < REYES_BENCH_MODEL_COUNT; ++m) {
        snprintf(paths[m], sizeof paths[m], "%s/%s.bpt", a->models_dir, reyes_bench_models[m]);
        models[m] = (perma_file_role){ paths[m], "the model", 0 };
    }
    parsed = bench_check_inputs(options, argv[0], models, REYES_BENCH_MODEL_COUNT);
    if (parsed != PERMA_CLI_OK)
        return parsed;
    a->sizes_given = a->size_count > 0;
    if (a->size_count == 0) {
        const unsigned w[2] = {512, 1280}, h[2] = {512, 1024};
        a->size_count = options->quick ? 1 : 2;
        for (unsigned s = 0; s < a->size_count; ++s) {
            a->widths[s] = options->quick ? 256 : w[s];
            a->heights[s] = options->quick ? 256 : h[s];
        }
    }
    return PERMA_CLI_OK;
}

reyes_options reyes_bench_render_options(const reyes_bench_args *a, const bench_options *options,
                                         const bench_variant *v, unsigned width, unsigned height)
{
    reyes_options o;
    reyes_options_init(&o);
    o.width = width;
    o.height = height;
    o.bound_px = a->bound_px;
    o.occlusion_cull = a->occlusion_cull;
    o.work_groups = options->groups;
    o.schedule = v->schedule;
    o.trace_path = options->trace_path;
    return o;
}

int reyes_bench_file_exists(const char *path)
{
    return access(path, R_OK) == 0;
}
