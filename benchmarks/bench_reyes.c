/* perma-bench reyes: the Reyes renderer (procedures/) on the teapot and
 * killeroo models, per technique and main strategy, against the C
 * reference of the same pipeline (reyes_reference.c) on one thread and on
 * every core with OpenMP (reyes_reference_parallel.c).
 *
 * Per-procedure times cannot be measured inside one megakernel, so stages
 * are timed by difference: every variant renders each workload three times,
 * stopping after subdivision (bound + split; dice only counts the grid),
 * after dice's geometry (positions and visibility of every quad, no
 * shading or sampling), and in full (shading and rasterization too).  The
 * C reference is timed the same way.
 *
 * --workload selects this (stages, the default) and the effect workloads
 * of bench_reyes_effects.c: displacement, motion blur and depth of field,
 * buckets. */
#include "bench_reyes.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "reyes.h"
#include "reyes_reference.h"
#include "reyes_reference_parallel.h"
#include "reyes_shared.h"

#ifndef REYES_BENCH_MODELS_DIR
#define REYES_BENCH_MODELS_DIR "../shared/models"
#endif

#define STAGE_MODES 3
#define MAX_SIZES REYES_BENCH_MAX_SIZES

/* The variants measured: every technique and strategy with the default
 * victim (perma_schedule_all), as schedule labels.  print_summary compares
 * entry 0 (megakernel/shared) with kernel-per-procedure. */
#define VARIANT_MAX 16
static char reyes_variants[VARIANT_MAX][BENCH_LABEL_SIZE];

static unsigned variant_count(void)
{
    static unsigned count;
    if (!count)
        count = bench_schedule_labels(PERMA_SCHEDULES_DEFAULT_VICTIM, reyes_variants, VARIANT_MAX);
    return count;
}

/* The label of entry v ("" past the last one). */
static const char *reyes_variant(unsigned v)
{
    return v < variant_count() ? reyes_variants[v] : "";
}

/* The entry of kernel-per-procedure (VARIANT_MAX: none). */
static unsigned kernel_per_procedure_variant(void)
{
    for (unsigned v = 0; v < variant_count(); ++v)
        if (strcmp(reyes_variant(v), perma_technique_name(PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE)) == 0)
            return v;
    return VARIANT_MAX;
}
/* A renderer per variant and device (--devices): slot v * BENCH_MAX_DEVICES + d. */
#define SLOTS (VARIANT_MAX * BENCH_MAX_DEVICES)
#define SLOT(v, d) ((v) * BENCH_MAX_DEVICES + (d))

/* Stage modes in the order the rows are printed. */
static const unsigned stage_modes[STAGE_MODES] = { REYES_STAGES_ALL, REYES_STAGES_GEOMETRY,
                                                   REYES_STAGES_SUBDIVIDE };
static const char *const stage_names[STAGE_MODES] = { "full", "geometry", "subdivide" };

/* Best seconds of one variant and workload, per stage mode, and the
 * variant's name on its device (bench_variant_use_device). */
typedef struct variant_times {
    int ran;
    char name[96];
    double seconds[STAGE_MODES];
} variant_times;

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
    "            the cameras of issue 13 (docs/reyes.md).\n"
    "            Rows: seconds are the best perma_run time of --repeat runs, the\n"
    "            configurations interleaved run by run; 'vs seq' is the C reference's\n"
    "            full render / row.\n"
    "  defaults  the same models and sizes at the command's default dicing, a shading\n"
    "            rate of 1: the C reference at that rate on one thread and on --threads\n"
    "            OpenMP threads, megakernel/shared without a crack fix and stitched\n"
    "            (the command's default), interleaved run by run.\n"
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

/* PERMA_CLI_OK, or what the command returns perma_cli_exit_status of. */
static perma_cli_status parse_args(int argc, char **argv, bench_options *options, reyes_bench_args *a)
{
    memset(a, 0, sizeof *a);
    a->models_dir = REYES_BENCH_MODELS_DIR;
    a->bound_px = 8.0f;
    a->workloads = REYES_BENCH_STAGES | REYES_BENCH_DEFAULTS;
    const perma_cli_option rows[] = {
        { PERMA_CLI_TEXT("models", "DIR", &a->models_dir, "where teapot.bpt and killeroo.bpt are") },
        { PERMA_CLI_CUSTOM("size", "WxH", parse_size, a,
                           "an image size (up to 4 times; default: the workload's sizes)") },
        { PERMA_CLI_FLOAT("bound", "PX", &a->bound_px, 0.5, INFINITY, "dice patches of at most PX pixels (default 8)") },
        { PERMA_CLI_CUSTOM("workload", "LIST", parse_workloads, &a->workloads, "the workloads below (default stages,defaults)") },
    };
    perma_cli_status parsed = bench_parse(options, "[options]", workloads_help, rows, sizeof rows / sizeof rows[0],
                                          argc, argv);
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
    o.work_groups = options->groups;
    o.schedule = v->schedule;
    return o;
}

/* The smallest of count times: on a shared machine the best run is the
 * one least disturbed. */
static double best_of(const double *times, unsigned count)
{
    double best = times[0];
    for (unsigned k = 1; k < count; ++k)
        best = times[k] < best ? times[k] : best;
    return best;
}

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
    char message[REYES_MESSAGE_MAX];
} stage_timing;

/* CPU seconds of the whole process (every thread: OpenMP's and the
 * OpenCL runtime's workers). */
static double process_cpu_seconds(void)
{
    struct timespec now;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

/* One run of the C reference in mode o->stages (the full pipeline for
 * REYES_STAGES_ALL; on `threads` OpenMP threads when not 0). */
static void time_reference(stage_timing *t, const reyes_scene *scene, const reyes_camera *camera,
                           const reyes_options *o, unsigned threads)
{
    if (!t->ran || t->runs == MAX_RUNS)
        return;
    reyes_error error;
    reyes_status status;
    double cpu = process_cpu_seconds();
    if (o->stages == REYES_STAGES_ALL) {
        reyes_image image;
        status = threads ? reyes_reference_render_parallel(scene, camera, o, threads, &image, &t->counts, &error)
                         : reyes_reference_render(scene, camera, o, &image, &t->counts, &error);
        reyes_image_free(&image);
    } else {
        status = reyes_reference_run(scene, camera, o, &t->counts, &error);
    }
    if (status != REYES_OK) {
        snprintf(t->message, sizeof t->message, "%s", error.message);
        t->ran = 0;
        return;
    }
    t->seconds[t->runs] = t->walls[t->runs] = t->counts.seconds;
    t->cpus[t->runs] = process_cpu_seconds() - cpu;
    ++t->runs;
}

/* One render of a variant: perma_run's time (the statistics' seconds) and
 * the whole reyes_render call's. */
static void time_render(stage_timing *t, reyes_renderer *renderer, const reyes_scene *scene,
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
 * threads, its counts checked against the single-threaded one's). */
static double reference_row(bench_report *report, const char *workload, int mode, const stage_timing *t,
                            unsigned threads, const reyes_reference_counts *single)
{
    const char *labels[STAGE_MODES] = { "C reference full render", "C reference bound/split/dice",
                                        "C reference bound/split" };
    bench_row row;
    bench_row_init(&row, workload, mode < 0 ? "C reference OpenMP full render" : labels[mode], "quads");
    row.work_groups = mode < 0 ? threads : 1;
    row.ran = t->ran && t->runs > 0;
    snprintf(row.message, sizeof row.message, "%s", t->message);
    if (row.ran) {
        row.seconds = row.wall_seconds = best_of(t->seconds, t->runs);
        row.units = (double)t->counts.micropolygons;
        row.count = row.expected = t->counts.grids;
        snprintf(row.message, sizeof row.message, "splits %llu grids %llu", (unsigned long long)t->counts.splits,
                 (unsigned long long)t->counts.grids);
        if (mode < 0) {
            const reyes_reference_counts *c = &t->counts;
            int same = c->splits == single->splits && c->grids == single->grids && c->culled == single->culled
                       && c->micropolygons == single->micropolygons && c->samples_written == single->samples_written;
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
static double variant_row(bench_report *report, const char *workload, const char *label, const stage_timing *t,
                          const reyes_options *o, const reyes_reference_counts *reference)
{
    bench_row row;
    bench_row_init(&row, workload, label, "quads");
    row.ran = t->ran && t->runs > 0;
    snprintf(row.message, sizeof row.message, "%s", t->message);
    if (row.ran) {
        const reyes_stats *stats = &t->stats;
        row.seconds = best_of(t->seconds, t->runs);
        row.wall_seconds = best_of(t->walls, t->runs);
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

static double ratio(double numerator, double denominator)
{
    return numerator > 0.0 && denominator > 0.0 ? numerator / denominator : 0.0;
}

/* The least CPU time of a full render's runs against the OpenMP C
 * reference's: on a shared machine the CPU a render takes moves less with
 * the load than its wall time, and on an idle machine a render that keeps
 * every core busy takes its CPU time / cores (run with
 * OMP_WAIT_POLICY=passive, or OpenMP's spinning threads bill their wait). */
static void print_cpu_ratio(const char *label, const stage_timing *openmp, const stage_timing *render)
{
    if (!openmp->ran || !render->ran || !openmp->runs || !render->runs)
        return;
    double c = best_of(openmp->cpus, openmp->runs), m = best_of(render->cpus, render->runs);
    printf("  %s: CPU per render (least of %u runs, the whole call): C reference OpenMP %.4f s, megakernel %.4f s: "
           "%.2fx\n", label, render->runs, c, m, ratio(c, m));
}

/* The stage times by difference and the ratios against the targets, per
 * device: issue 13's (megakernel/shared against the single-threaded C
 * reference and against kernel-per-procedure) and issue 25's (against the
 * C reference on every core). */
static void print_summary(const bench_options *options, const double reference[STAGE_MODES], double parallel,
                          unsigned threads, const variant_times times[SLOTS])
{
    printf("\n  stages (by difference, seconds):     subdivide   dice geometry   shade+sample   total\n");
    printf("  %-34s %9.4f %15.4f %14.4f %7.4f\n", "C reference (1 thread)", reference[2],
           reference[1] - reference[2], reference[0] - reference[1], reference[0]);
    for (unsigned v = 0; v < variant_count(); ++v) {
        for (unsigned d = 0; d < bench_device_passes(options); ++d) {
            const variant_times *t = &times[SLOT(v, d)];
            if (!t->ran)
                continue;
            const double *s = t->seconds;
            printf("  %-34s %9.4f %15.4f %14.4f %7.4f\n", t->name, s[2], s[1] - s[2], s[0] - s[1], s[0]);
        }
    }
    for (unsigned d = 0; d < bench_device_passes(options); ++d) {
        unsigned kpp_variant = kernel_per_procedure_variant();
        const variant_times *mk = &times[SLOT(0, d)];
        const variant_times *kpp = kpp_variant < VARIANT_MAX ? &times[SLOT(kpp_variant, d)] : NULL;
        const char *on = options->device_count ? options->devices[d] : "";
        if (!mk->ran)
            continue;
        double geometry = ratio(reference[1], mk->seconds[1]), full = ratio(reference[0], mk->seconds[0]);
        printf("  %s%smegakernel/shared vs C reference: full render %.2fx (target >= 1.6x: %s), geometry only "
               "(bound/split/dice) %.2fx\n", on, *on ? ": " : "", full, full >= 1.6 ? "met" : "NOT met", geometry);
        double vs_openmp = ratio(parallel, mk->seconds[0]);
        if (vs_openmp > 0.0)
            printf("  %s%smegakernel/shared vs C reference OpenMP (%u threads): full render %.2fx (target >= 1.5x: "
                   "%s)\n", on, *on ? ": " : "", threads, vs_openmp, vs_openmp >= 1.5 ? "met" : "NOT met");
        if (kpp && kpp->ran) {
            double vs_kpp = ratio(kpp->seconds[0], mk->seconds[0]);
            printf("  %s%smegakernel/shared vs kernel-per-procedure: full render %.2fx (target >= 2x: %s), "
                   "geometry only %.2fx\n", on, *on ? ": " : "", vs_kpp, vs_kpp >= 2.0 ? "met" : "NOT met",
                   ratio(kpp->seconds[1], mk->seconds[1]));
        }
    }
}

int reyes_bench_file_exists(const char *path)
{
    return access(path, R_OK) == 0;
}

/* One renderer per variant and device, kept for every workload; NULL
 * (with the message printed) when the runtime refuses it. */
static void create_renderers(const reyes_bench_args *a, const bench_options *options,
                             reyes_renderer *renderers[SLOTS])
{
    for (unsigned i = 0; i < variant_count(); ++i) {
        bench_variant v;
        if (!bench_variant_select(options, reyes_variant(i), &v))
            continue;
        for (unsigned d = 0; d < bench_device_passes(options); ++d) {
            bench_variant_use_device(options, d, &v);
            reyes_options o = reyes_bench_render_options(a, options, &v, 64, 64);
            reyes_error error;
            if (reyes_renderer_create(&o, &renderers[SLOT(i, d)], &error) != REYES_OK)
                printf("reyes: %s: n/a: %s\n", v.name, error.message);
        }
    }
}

/* A small render per renderer compiles the program and its kernels
 * outside the timed runs. */
static void warm_up(const reyes_scene *scene, const reyes_bench_args *a, const bench_options *options,
                    reyes_renderer *renderers[SLOTS])
{
    for (unsigned i = 0; i < SLOTS; ++i) {
        bench_variant v;
        if (!renderers[i] || bench_variant_parse(reyes_variant(i / BENCH_MAX_DEVICES), &v, NULL) != PERMA_OK)
            continue;
        reyes_options o = reyes_bench_render_options(a, options, &v, 64, 64);
        reyes_camera camera;
        reyes_image image;
        reyes_error error;
        if (reyes_camera_frame(scene, 40.0f, 1.0f, &camera, &error) == REYES_OK
            && reyes_render(renderers[i], scene, &camera, &o, &image, NULL, &error) == REYES_OK)
            reyes_image_free(&image);
    }
}

/* The cameras for the two models (docs/reyes.md, *Measured*);
 * other models are framed. */
static int model_camera(const char *model, reyes_camera *camera)
{
    static const struct { const char *model; float eye[3], at[3], fov; } cameras[] = {
        { "teapot", { 8.0f, -8.0f, 6.0f }, { 0.0f, 0.0f, 1.5f }, 40.0f },
        { "killeroo", { 8.0f, 0.0f, 2.0f }, { 0.0f, 0.0f, 0.0f }, 45.0f },
    };
    for (size_t k = 0; k < sizeof cameras / sizeof cameras[0]; ++k) {
        if (strcmp(model, cameras[k].model) != 0)
            continue;
        for (int d = 0; d < 3; ++d) {
            camera->eye[d] = cameras[k].eye[d];
            camera->at[d] = cameras[k].at[d];
        }
        camera->fov_deg = cameras[k].fov;
        return 1;
    }
    return 0;
}

/* The stage workload of one model and size: the C reference and every
 * variant in every stage mode, interleaved run by run (so that a change in
 * the machine's load hits them alike), best of --repeat.  No crack fix:
 * the C reference has none, and both sides do the same work. */
static void run_workload(bench_report *report, const char *model, const reyes_scene *scene,
                         unsigned width, unsigned height, const reyes_bench_args *a,
                         const bench_options *options, reyes_renderer *renderers[SLOTS])
{
    char workload[64];
    snprintf(workload, sizeof workload, "%s %ux%u bound %g", model, width, height, (double)a->bound_px);
    bench_report_workload(report, workload);
    reyes_camera camera;
    reyes_error error;
    if (!model_camera(model, &camera)
        && reyes_camera_frame(scene, 40.0f, (float)width / (float)height, &camera, &error) != REYES_OK) {
        printf("reyes: %s: %s\n", workload, error.message);
        return;
    }
    static stage_timing reference[STAGE_MODES], parallel, timings[SLOTS][STAGE_MODES];
    unsigned threads = bench_threads(options);
    variant_times times[SLOTS];
    memset(times, 0, sizeof times);
    reyes_options options_of[SLOTS];
    int usable[SLOTS] = {0};
    memset(&parallel, 0, sizeof parallel);
    parallel.ran = 1;
    for (int m = 0; m < STAGE_MODES; ++m) {
        memset(&reference[m], 0, sizeof reference[m]);
        reference[m].ran = 1;
        for (unsigned i = 0; i < SLOTS; ++i) {
            reyes_stats_free(&timings[i][m].stats);
            memset(&timings[i][m], 0, sizeof timings[i][m]);
            timings[i][m].ran = 1;
        }
    }
    for (unsigned i = 0; i < SLOTS; ++i) {
        unsigned v = i / BENCH_MAX_DEVICES, d = i % BENCH_MAX_DEVICES;
        bench_variant variant;
        if (!renderers[i] || bench_variant_parse(reyes_variant(v), &variant, NULL) != PERMA_OK)
            continue;
        bench_variant_use_device(options, d, &variant);
        snprintf(times[i].name, sizeof times[i].name, "%s", variant.name);
        options_of[i] = reyes_bench_render_options(a, options, &variant, width, height);
        options_of[i].crack_fix = REYES_CRACK_FIX_NONE;
        usable[i] = 1;
    }
    bench_variant first;
    perma_error parse_error;
    if (bench_variant_parse(reyes_variant(0), &first, &parse_error) != PERMA_OK) {
        printf("reyes: %s\n", parse_error.message);
        return;
    }
    reyes_options base = reyes_bench_render_options(a, options, &first, width, height);
    base.crack_fix = REYES_CRACK_FIX_NONE;
    unsigned runs = options->repeat < MAX_RUNS ? options->repeat : MAX_RUNS;
    for (unsigned r = 0; r < runs; ++r) {
        for (int m = 0; m < STAGE_MODES; ++m) {
            base.stages = stage_modes[m];
            time_reference(&reference[m], scene, &camera, &base, 0);
            if (stage_modes[m] == REYES_STAGES_ALL)
                time_reference(&parallel, scene, &camera, &base, threads);
            for (unsigned i = 0; i < SLOTS; ++i) {
                if (!usable[i])
                    continue;
                options_of[i].stages = stage_modes[m];
                time_render(&timings[i][m], renderers[i], scene, &camera, &options_of[i]);
            }
        }
    }
    double reference_seconds[STAGE_MODES];
    for (int m = 0; m < STAGE_MODES; ++m)
        reference_seconds[m] = reference_row(report, workload, m, &reference[m], 1, NULL);
    double parallel_seconds = reference_row(report, workload, -1, &parallel, threads, &reference[0].counts);
    for (unsigned i = 0; i < SLOTS; ++i) {
        if (!usable[i])
            continue;
        times[i].ran = 1;
        for (int m = 0; m < STAGE_MODES; ++m) {
            char label[128];
            options_of[i].stages = stage_modes[m];
            snprintf(label, sizeof label, "%s %s", times[i].name, stage_names[m]);
            times[i].seconds[m] = variant_row(report, workload, label, &timings[i][m], &options_of[i],
                                              &reference[1].counts);
            times[i].ran &= times[i].seconds[m] > 0.0;
        }
        if (options->verbose)
            printf("  (%s)\n", reyes_renderer_device(renderers[i]));
    }
    print_summary(options, reference_seconds, parallel_seconds, threads, times);
    for (unsigned d = 0; d < bench_device_passes(options); ++d)
        if (usable[SLOT(0, d)])
            print_cpu_ratio(times[SLOT(0, d)].name, &parallel, &timings[SLOT(0, d)][0]);
}

/* The defaults workload of one model and size (issue 25): the command's
 * default dicing, a shading rate of 1, against the C reference at the
 * same rate on one thread and on --threads (no crack fix: it has none),
 * interleaved run by run, best of --repeat.  megakernel/shared renders it
 * without a crack fix (the same work) and with the command's default
 * stitching (more work: two passes and the fillers; its time is the two
 * perma_runs, and the row's message gives the whole render's, with the
 * host's planning between them and the clear and resolve). */
static void run_defaults(bench_report *report, const char *model, const reyes_scene *scene, unsigned width,
                         unsigned height, const reyes_bench_args *a, const bench_options *options,
                         reyes_renderer *renderers[SLOTS])
{
    char workload[64];
    snprintf(workload, sizeof workload, "%s %ux%u shading rate 1", model, width, height);
    bench_report_workload(report, workload);
    reyes_camera camera;
    reyes_error error;
    if (!model_camera(model, &camera)
        && reyes_camera_frame(scene, 40.0f, (float)width / (float)height, &camera, &error) != REYES_OK) {
        printf("reyes: %s: %s\n", workload, error.message);
        return;
    }
    static stage_timing single, parallel, plain[BENCH_MAX_DEVICES], stitched[BENCH_MAX_DEVICES];
    unsigned threads = bench_threads(options), devices = bench_device_passes(options);
    bench_variant variant;
    if (bench_variant_parse(reyes_variant(0), &variant, NULL) != PERMA_OK)
        return;
    reyes_options o[BENCH_MAX_DEVICES], base = reyes_bench_render_options(a, options, &variant, width, height);
    base.shading_rate = 1.0f;
    base.crack_fix = REYES_CRACK_FIX_NONE;
    memset(&single, 0, sizeof single);
    memset(&parallel, 0, sizeof parallel);
    single.ran = parallel.ran = 1;
    char names[BENCH_MAX_DEVICES][96];
    for (unsigned d = 0; d < devices; ++d) {
        reyes_stats_free(&plain[d].stats);
        reyes_stats_free(&stitched[d].stats);
        memset(&plain[d], 0, sizeof plain[d]);
        memset(&stitched[d], 0, sizeof stitched[d]);
        plain[d].ran = stitched[d].ran = renderers[SLOT(0, d)] != NULL;
        bench_variant_use_device(options, d, &variant);
        snprintf(names[d], sizeof names[d], "%s", variant.name);
        o[d] = reyes_bench_render_options(a, options, &variant, width, height);
        o[d].shading_rate = 1.0f;
    }
    unsigned runs = options->repeat < MAX_RUNS ? options->repeat : MAX_RUNS;
    for (unsigned r = 0; r < runs; ++r) {
        time_reference(&single, scene, &camera, &base, 0);
        time_reference(&parallel, scene, &camera, &base, threads);
        for (unsigned d = 0; d < devices; ++d) {
            o[d].crack_fix = REYES_CRACK_FIX_NONE;
            time_render(&plain[d], renderers[SLOT(0, d)], scene, &camera, &o[d]);
            o[d].crack_fix = REYES_CRACK_FIX_STITCH;
            time_render(&stitched[d], renderers[SLOT(0, d)], scene, &camera, &o[d]);
        }
    }
    reference_row(report, workload, 0, &single, 1, NULL);
    double openmp = reference_row(report, workload, -1, &parallel, threads, &single.counts);
    for (unsigned d = 0; d < devices; ++d) {
        char label[128];
        o[d].crack_fix = REYES_CRACK_FIX_NONE;
        snprintf(label, sizeof label, "%.80s full, no crack fix", names[d]);
        double none = variant_row(report, workload, label, &plain[d], &o[d], &single.counts);
        o[d].crack_fix = REYES_CRACK_FIX_STITCH;
        snprintf(label, sizeof label, "%.80s full, stitched (defaults)", names[d]);
        double stitch = variant_row(report, workload, label, &stitched[d], &o[d], &single.counts);
        double whole = stitched[d].runs ? best_of(stitched[d].walls, stitched[d].runs) : 0.0;
        if (none > 0.0 && stitch > 0.0)
            printf("  %s vs C reference OpenMP (%u threads), shading rate 1: no crack fix %.2fx, stitched %.2fx "
                   "(the whole stitched render, planning, clear and resolve included: %.4f s, %.2fx) (target >= "
                   "1.5x: %s)\n", names[d], threads, ratio(openmp, none), ratio(openmp, stitch), whole,
                   ratio(openmp, whole), ratio(openmp, stitch) >= 1.5 ? "met" : "NOT met");
        print_cpu_ratio("no crack fix", &parallel, &plain[d]);
        print_cpu_ratio("stitched", &parallel, &stitched[d]);
    }
}

int bench_reyes(bench_options *options, int argc, char **argv)
{
    reyes_bench_args a;
    perma_cli_status parsed = parse_args(argc, argv, options, &a);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    const char *models[] = { "teapot", "killeroo" };
    unsigned model_count = a.workloads & (REYES_BENCH_STAGES | REYES_BENCH_DEFAULTS) ? (options->quick ? 1 : 2) : 0;
    bench_report *report;
    if (bench_report_open(&report, "reyes", options))
        return 1;
    reyes_renderer *renderers[SLOTS] = { NULL };
    int created = 0, status = 0;
    for (unsigned m = 0; m < model_count && status == 0; ++m) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s.bpt", a.models_dir, models[m]);
        if (!reyes_bench_file_exists(path)) {
            printf("reyes: skipping %s: %s is missing (the models are in ../shared/models; "
                   "pass --models DIR)\n", models[m], path);
            continue;
        }
        reyes_scene scene;
        reyes_error error;
        reyes_scene_init(&scene);
        if (reyes_scene_load_bpt(&scene, path, reyes_model_color(0), &error) != REYES_OK) {
            fprintf(stderr, "perma-bench reyes: %s\n", error.message);
            status = 1;
        } else {
            if (!created++)
                create_renderers(&a, options, renderers);
            warm_up(&scene, &a, options, renderers);
            for (unsigned s = 0; s < a.size_count; ++s) {
                if (a.workloads & REYES_BENCH_STAGES)
                    run_workload(report, models[m], &scene, a.widths[s], a.heights[s], &a, options, renderers);
                if (a.workloads & REYES_BENCH_DEFAULTS)
                    run_defaults(report, models[m], &scene, a.widths[s], a.heights[s], &a, options, renderers);
            }
        }
        reyes_scene_free(&scene);
    }
    for (unsigned v = 0; v < SLOTS; ++v)
        reyes_renderer_destroy(renderers[v]);
    if (status == 0 && reyes_bench_effects(report, &a, options))
        status = 1;
    if (bench_report_failures(report))
        status = 1;
    if (bench_report_close(report))
        status = 1;
    return status;
}
