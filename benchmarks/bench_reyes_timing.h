/* perma-bench reyes: the timings of the stage and defaults workloads
 * (bench_reyes_timing.c), kept run after run for the best of --repeat. */
#ifndef BENCH_REYES_TIMING_H
#define BENCH_REYES_TIMING_H

#include "bench_reyes.h"
#include "reyes_reference.h"

/* The stage modes a workload is timed in (full, geometry, subdivide). */
#define STAGE_MODES 3

/* The timings of one configuration (the C reference or a variant) in one
 * stage mode, run after run, and the last run's counts. */
#define MAX_RUNS 1000
typedef struct stage_timing {
    int ran;
    unsigned runs;
    double seconds[MAX_RUNS], walls[MAX_RUNS];
    double cpus[MAX_RUNS]; /* the process's CPU seconds over the whole call */
    reyes_stats stats;
    reyes_reference_counts counts;
    /* The C reference's full render: a hash of its image (rgb and
     * coverage), 1 when one run's differed from another's, and 1 when it
     * culls hidden grids (its dicing counts then depend on the order the
     * threads dice in). */
    uint64_t image_hash;
    int image_changed, culls;
    char message[REYES_MESSAGE_MAX];
} stage_timing;

/* The smallest of count times. */
double reyes_bench_best_of(const double *times, unsigned count);
/* One more run of the C reference into t; one more render of a variant
 * (nothing once t has failed: t->ran 0, t->message says why). */
void reyes_bench_time_reference(stage_timing *t, const reyes_scene *scene, const reyes_camera *camera,
                                const reyes_options *o, unsigned threads);
void reyes_bench_time_render(stage_timing *t, reyes_renderer *renderer, const reyes_scene *scene,
                             const reyes_camera *camera, const reyes_options *o);
/* The report's rows of the C reference and of a variant in one mode:
 * they return the row's seconds, 0 when it did not run. */
double reyes_bench_reference_row(bench_report *report, const char *workload, int mode, const stage_timing *t,
                                 unsigned threads, const stage_timing *single);
double reyes_bench_variant_row(bench_report *report, const char *workload, const char *label,
                               const stage_timing *t, const reyes_options *o,
                               const reyes_reference_counts *reference);

#endif
