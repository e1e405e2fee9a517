/* perma-bench reyes: the arguments (bench_reyes_args.c) shared by the
 * stage workload (bench_reyes.c) and the effect workloads
 * (bench_reyes_effects.c). */
#ifndef BENCH_REYES_H
#define BENCH_REYES_H

#include "bench.h"
#include "reyes.h"

#define REYES_BENCH_MAX_SIZES 4

/* Workloads, selected with --workload (a comma-separated list). */
enum {
    REYES_BENCH_STAGES = 1,   /* every variant, stages by difference, vs the C reference */
    REYES_BENCH_DISPLACE = 2, /* plain vs --displace bumps */
    REYES_BENCH_BLUR = 4,     /* each blur algorithm vs unblurred, killeroo 800x600, 16/25/64 spp */
    REYES_BENCH_BUCKETS = 8,  /* peak queue memory and time per bucket size */
    REYES_BENCH_DEFAULTS = 16, /* shading rate 1 (no crack fix, stitched) vs the C reference at rate 1 */
};

/* The models of the stages and defaults workloads, in --models DIR as NAME.bpt. */
#define REYES_BENCH_MODEL_COUNT 2
extern const char *const reyes_bench_models[REYES_BENCH_MODEL_COUNT];

typedef struct reyes_bench_args {
    const char *models_dir;
    unsigned widths[REYES_BENCH_MAX_SIZES], heights[REYES_BENCH_MAX_SIZES];
    unsigned size_count;
    int sizes_given;          /* --size was given (else the workload's default sizes) */
    float bound_px;
    unsigned workloads;       /* REYES_BENCH_* bits */
    unsigned occlusion_cull;  /* --occlusion: reyes_options.occlusion_cull of every render */
} reyes_bench_args;

/* Parse perma-bench reyes's arguments into *a (the common ones into
 * *options): PERMA_CLI_OK, or what the command returns
 * perma_cli_exit_status of. */
perma_cli_status reyes_bench_parse_args(int argc, char **argv, bench_options *options, reyes_bench_args *a);
/* 1 if the file can be read. */
int reyes_bench_file_exists(const char *path);
/* Render options for a variant (its scheduling fields) at an image size,
 * with the arguments' bound and the common options' work-groups. */
reyes_options reyes_bench_render_options(const reyes_bench_args *a, const bench_options *options,
                                         const bench_variant *v, unsigned width, unsigned height);

/* The displace, blur and buckets workloads selected in a->workloads, rows
 * into report.  Returns 0, or 1 when a model could not be loaded. */
int reyes_bench_effects(bench_report *report, const reyes_bench_args *a, const bench_options *options);

#endif
