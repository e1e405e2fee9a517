/* perma-bench reyes: timing one configuration of the stage and defaults
 * workloads (the C reference, or a variant's renderer) run after run, and
 * its row in the report. */
#include "bench_reyes_timing.h"

#include <time.h>

#include "reyes_reference_parallel.h"

/* The smallest of count times: on a shared machine the best run is the
 * one least disturbed. */
double reyes_bench_best_of(const double *times, unsigned count)
{
    double best = times[0];
    for (unsigned k = 1; k < count; ++k)
        best = times[k] < best ? times[k] : best;
    return best;
}


/* CPU seconds of the whole process (every thread: OpenMP's and the
 * OpenCL runtime's workers). */
static double process_cpu_seconds(void)
{
    struct timespec now;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

/* FNV-1a of an image's colours and coverage. */
static uint64_t image_hash(const reyes_image *image)
{
    size_t pixels = (size_t)image->width * image->height;
    uint64_t h = 0xcbf29ce484222325u;
    for (size_t k = 0; k < 3 * pixels; ++k)
        h = (h ^ image->rgb[k]) * 0x100000001b3u;
    for (size_t k = 0; k < pixels; ++k)
        h = (h ^ image->coverage[k]) * 0x100000001b3u;
    return h;
}

/* One run of the C reference in mode o->stages (the full pipeline for
 * REYES_STAGES_ALL; on `threads` OpenMP threads when not 0). */
void reyes_bench_time_reference(stage_timing *t, const reyes_scene *scene, const reyes_camera *camera,
                                const reyes_options *o, unsigned threads)
{
    if (!t->ran || t->runs == MAX_RUNS)
        return;
    reyes_error error;
    reyes_status status;
    reyes_image image = { 0 };
    double cpu = process_cpu_seconds(), start = bench_now();
    if (o->stages == REYES_STAGES_ALL)
        status = threads ? reyes_reference_render_parallel(scene, camera, o, threads, &image, &t->counts, &error)
                         : reyes_reference_render(scene, camera, o, &image, &t->counts, &error);
    else
        status = reyes_reference_run(scene, camera, o, &t->counts, &error);
    double used = process_cpu_seconds() - cpu, wall = bench_now() - start;
    if (status != REYES_OK) {
        snprintf(t->message, sizeof t->message, "%s", error.message);
        t->ran = 0;
        return;
    }
    if (o->stages == REYES_STAGES_ALL) {
        uint64_t hash = image_hash(&image);
        t->image_changed |= t->runs > 0 && hash != t->image_hash;
        t->image_hash = hash;
        t->culls = o->occlusion_cull && o->shading_rate > 0.0f;
        reyes_image_free(&image);
    }
    /* seconds: the pipeline's span (as a perma_run); walls: the whole call
     * (its clear and resolve too). */
    t->seconds[t->runs] = t->counts.seconds;
    t->walls[t->runs] = wall;
    t->cpus[t->runs] = used;
    ++t->runs;
}

/* One render of a variant: perma_run's time (the statistics' seconds) and
 * the whole reyes_render call's. */
void reyes_bench_time_render(stage_timing *t, reyes_renderer *renderer, const reyes_scene *scene,
                             const reyes_camera *camera, const reyes_options *o)
{
    if (!t->ran || t->runs == MAX_RUNS)
        return;
    reyes_error error;
    reyes_image image;
    reyes_stats_free(&t->stats);
    double start = bench_now(), cpu = process_cpu_seconds();
    if (reyes_render(renderer, scene, camera, o, &image, &t->stats, &error) != REYES_OK) {
        snprintf(t->message, sizeof t->message, "%s", error.message);
        t->ran = 0;
        return;
    }
    t->walls[t->runs] = bench_now() - start;
    t->cpus[t->runs] = process_cpu_seconds() - cpu;
    t->seconds[t->runs] = t->stats.seconds;
    ++t->runs;
    reyes_image_free(&image);
}

/* The row of the C reference in one mode (the full render is the
 * workload's baseline; mode -1: the full render on `threads` OpenMP
 * threads, its image and counts checked against the single-threaded
 * one's: with occlusion culling only those that do not depend on the
 * order of dicing, every count otherwise). */
double reyes_bench_reference_row(bench_report *report, const char *workload, int mode, const stage_timing *t,
                                 unsigned threads, const stage_timing *single)
{
    const char *labels[STAGE_MODES] = { "C reference full render", "C reference bound/split/dice",
                                        "C reference bound/split" };
    bench_row row;
    bench_row_init(&row, workload, mode < 0 ? "C reference OpenMP full render" : labels[mode], "quads");
    row.work_groups = mode < 0 ? threads : 1;
    row.ran = t->ran && t->runs > 0;
    snprintf(row.message, sizeof row.message, "%s", t->message);
    if (row.ran) {
        row.seconds = reyes_bench_best_of(t->seconds, t->runs);
        row.wall_seconds = reyes_bench_best_of(t->walls, t->runs);
        row.units = (double)t->counts.micropolygons;
        row.count = row.expected = t->counts.grids;
        snprintf(row.message, sizeof row.message, "splits %llu grids %llu%s", (unsigned long long)t->counts.splits,
                 (unsigned long long)t->counts.grids, t->culls ? "" : t->image_changed ? "; the image changed" : "");
        if (t->culls)
            snprintf(row.message, sizeof row.message, "splits %llu grids %llu occluded %llu%s",
                     (unsigned long long)t->counts.splits, (unsigned long long)t->counts.grids,
                     (unsigned long long)t->counts.occluded, t->image_changed ? "; the image changed" : "");
        if (mode < 0) {
            const reyes_reference_counts *c = &t->counts, *s = &single->counts;
            int same = c->splits == s->splits && c->grids == s->grids && c->culled == s->culled
                       && c->samples_written == s->samples_written && t->image_hash == single->image_hash
                       && !t->image_changed && !single->image_changed
                       && (t->culls || (c->micropolygons == s->micropolygons && c->occluded == s->occluded));
            row.check = same ? BENCH_CHECK_PASS : BENCH_CHECK_FAIL;
        }
    }
    bench_report_add(report, &row, mode == 0);
    return row.ran ? row.seconds : 0.0;
}

static size_t peak_item_bytes(const reyes_stats *stats)
{
    size_t total = 0;
    for (int p = 0; p < REYES_PROC_COUNT; ++p) {
        size_t size = p == REYES_PROC_STITCH ? sizeof(struct reyes_stitch) : sizeof(struct reyes_subpatch);
        total += (size_t)stats->procedures[p].peak_queue_items * size;
    }
    return total;
}

/* The row of a variant in one mode, its counts checked against the C
 * reference's with fixed grids (equal).  With a shading rate they are
 * not checked: the renderer's edge-conforming dicing and sample shading
 * (issue 25 items 1-3) are not the C reference's (which dices each
 * sub-patch to the size bound chose and shades vertices, the renderer's
 * shading-rate pipeline before them), so the row's message gives both
 * micropolygon counts, the work each did. */
double reyes_bench_variant_row(bench_report *report, const char *workload, const char *label,
                               const stage_timing *t, const reyes_options *o,
                               const reyes_reference_counts *reference)
{
    bench_row row;
    bench_row_init(&row, workload, label, "quads");
    row.ran = t->ran && t->runs > 0;
    snprintf(row.message, sizeof row.message, "%s", t->message);
    if (row.ran) {
        const reyes_stats *stats = &t->stats;
        row.seconds = reyes_bench_best_of(t->seconds, t->runs);
        row.wall_seconds = reyes_bench_best_of(t->walls, t->runs);
        row.work_groups = stats->run.work_groups;
        row.group_size = stats->run.group_size;
        row.units = (double)stats->micropolygons;
        row.count = stats->grids;
        row.expected = reference->grids;
        int same = stats->splits == reference->splits && stats->grids == reference->grids
                   && (o->stages == REYES_STAGES_SUBDIVIDE || stats->micropolygons == reference->micropolygons);
        row.check = o->shading_rate > 0.0f ? BENCH_CHECK_NONE : same ? BENCH_CHECK_PASS : BENCH_CHECK_FAIL;
        row.peak_queue_bytes = stats->peak_queue_bytes;
        row.peak_item_bytes = peak_item_bytes(stats);
        row.steals = stats->run.steals;
        row.donations = stats->run.donations;
        row.spills = stats->run.spills;
        const perma_procedure_stats *p = stats->procedures;
        char rate[96] = "";
        if (o->shading_rate > 0.0f)
            snprintf(rate, sizeof rate, "micropolygons %llu (C reference %llu); ",
                     (unsigned long long)stats->micropolygons, (unsigned long long)reference->micropolygons);
        snprintf(row.message, sizeof row.message,
                 "%ssplits %llu grids %llu; items bound %llu split %llu dice %llu; launches %u", rate,
                 (unsigned long long)stats->splits, (unsigned long long)stats->grids,
                 (unsigned long long)p[REYES_PROC_BOUND].items,
                 (unsigned long long)(p[REYES_PROC_SPLIT_U].items + p[REYES_PROC_SPLIT_V].items),
                 (unsigned long long)p[REYES_PROC_DICE].items, stats->run.launches);
    }
    bench_report_add(report, &row, 0);
    return row.ran ? row.seconds : 0.0;
}
