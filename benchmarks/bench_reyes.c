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
 * --workload (bench_reyes_args.c) selects this (stages, the default) and
 * the effect workloads of bench_reyes_effects.c: displacement, motion blur
 * and depth of field, buckets.  One configuration's runs are timed and
 * reported in bench_reyes_timing.c. */
#include "bench_reyes.h"

#include <stdlib.h>
#include <string.h>

#include "bench_reyes_timing.h"
#include "reyes.h"
#include "reyes_shared.h"

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
    double c = reyes_bench_best_of(openmp->cpus, openmp->runs), m = reyes_bench_best_of(render->cpus, render->runs);
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

/* The camera of a workload: a fixed one for the two models (docs/reyes-measurements.md,
 * *Measured*); other models are framed.  0 (the reason printed) when the
 * scene cannot be framed. */
static int workload_camera(const char *workload, const char *model, const reyes_scene *scene, unsigned width,
                           unsigned height, reyes_camera *camera)
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
    reyes_error error;
    if (reyes_camera_frame(scene, 40.0f, (float)width / (float)height, camera, &error) == REYES_OK)
        return 1;
    printf("reyes: %s: %s\n", workload, error.message);
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
    if (!workload_camera(workload, model, scene, width, height, &camera))
        return;
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
            reyes_bench_time_reference(&reference[m], scene, &camera, &base, 0);
            if (stage_modes[m] == REYES_STAGES_ALL)
                reyes_bench_time_reference(&parallel, scene, &camera, &base, threads);
            for (unsigned i = 0; i < SLOTS; ++i) {
                if (!usable[i])
                    continue;
                options_of[i].stages = stage_modes[m];
                reyes_bench_time_render(&timings[i][m], renderers[i], scene, &camera, &options_of[i]);
            }
        }
    }
    double reference_seconds[STAGE_MODES];
    for (int m = 0; m < STAGE_MODES; ++m)
        reference_seconds[m] = reyes_bench_reference_row(report, workload, m, &reference[m], 1, NULL);
    double parallel_seconds = reyes_bench_reference_row(report, workload, -1, &parallel, threads, &reference[0]);
    for (unsigned i = 0; i < SLOTS; ++i) {
        if (!usable[i])
            continue;
        times[i].ran = 1;
        for (int m = 0; m < STAGE_MODES; ++m) {
            char label[128];
            options_of[i].stages = stage_modes[m];
            snprintf(label, sizeof label, "%s %s", times[i].name, stage_names[m]);
            times[i].seconds[m] = reyes_bench_variant_row(report, workload, label, &timings[i][m],
                                                          &options_of[i], &reference[1].counts);
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

/* The defaults workload of one model and size: the command's default
 * dicing, a shading rate of 1, against the C reference at the same rate
 * on one thread and on --threads (no crack fix: it has none),
 * interleaved run by run, best of --repeat.  megakernel/shared renders it
 * with the command's default crack fix (polylines: one pass), without one
 * (the same dicing, the fix's cost) and stitched (two passes with the
 * host's planning between them).  The main figure is the whole render a
 * user waits for (reyes_render: planning, clear, runs and resolve) against
 * the C reference's whole call (its clear and resolve too); beside it the
 * megakernel's part (perma_run) against the reference's pipeline span. */
static void run_defaults(bench_report *report, const char *model, const reyes_scene *scene, unsigned width,
                         unsigned height, const reyes_bench_args *a, const bench_options *options,
                         reyes_renderer *renderers[SLOTS])
{
    char workload[64];
    snprintf(workload, sizeof workload, "%s %ux%u shading rate 1", model, width, height);
    bench_report_workload(report, workload);
    reyes_camera camera;
    if (!workload_camera(workload, model, scene, width, height, &camera))
        return;
    enum { FIXES = 3 };
    static const unsigned fixes[FIXES] = { REYES_CRACK_FIX_POLYLINE, REYES_CRACK_FIX_NONE, REYES_CRACK_FIX_STITCH };
    static const char *const fix_labels[FIXES] = { "polylines (defaults)", "no crack fix", "stitched" };
    static stage_timing single, parallel, timed[FIXES][BENCH_MAX_DEVICES];
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
        for (unsigned f = 0; f < FIXES; ++f) {
            reyes_stats_free(&timed[f][d].stats);
            memset(&timed[f][d], 0, sizeof timed[f][d]);
            timed[f][d].ran = renderers[SLOT(0, d)] != NULL;
        }
        bench_variant_use_device(options, d, &variant);
        snprintf(names[d], sizeof names[d], "%s", variant.name);
        o[d] = reyes_bench_render_options(a, options, &variant, width, height);
        o[d].shading_rate = 1.0f;
    }
    unsigned runs = options->repeat < MAX_RUNS ? options->repeat : MAX_RUNS;
    for (unsigned r = 0; r < runs; ++r) {
        reyes_bench_time_reference(&single, scene, &camera, &base, 0);
        reyes_bench_time_reference(&parallel, scene, &camera, &base, threads);
        for (unsigned d = 0; d < devices; ++d)
            for (unsigned f = 0; f < FIXES; ++f) {
                o[d].crack_fix = fixes[f];
                reyes_bench_time_render(&timed[f][d], renderers[SLOT(0, d)], scene, &camera, &o[d]);
            }
    }
    reyes_bench_reference_row(report, workload, 0, &single, 1, NULL);
    double openmp = reyes_bench_reference_row(report, workload, -1, &parallel, threads, &single);
    double openmp_whole = parallel.runs ? reyes_bench_best_of(parallel.walls, parallel.runs) : 0.0;
    for (unsigned d = 0; d < devices; ++d) {
        double part[FIXES], whole[FIXES];
        for (unsigned f = 0; f < FIXES; ++f) {
            char label[128];
            o[d].crack_fix = fixes[f];
            snprintf(label, sizeof label, "%.80s full, %s", names[d], fix_labels[f]);
            part[f] = reyes_bench_variant_row(report, workload, label, &timed[f][d], &o[d], &single.counts);
            whole[f] = timed[f][d].runs ? reyes_bench_best_of(timed[f][d].walls, timed[f][d].runs) : 0.0;
        }
        if (whole[0] > 0.0 && openmp_whole > 0.0)
            printf("  %s vs C reference OpenMP (%u threads), shading rate 1, the whole render (planning, clear and "
                   "resolve included): polylines (the default) %.4f s against %.4f s: %.2fx (target >= 1.0x: %s); "
                   "no crack fix %.4f s: %.2fx; stitched %.4f s: %.2fx; the crack fix costs %+.1f %% over none "
                   "(target <= 10 %%: %s)\n",
                   names[d], threads, whole[0], openmp_whole, ratio(openmp_whole, whole[0]),
                   ratio(openmp_whole, whole[0]) >= 1.0 ? "met" : "NOT met", whole[1], ratio(openmp_whole, whole[1]),
                   whole[2], ratio(openmp_whole, whole[2]), 100.0 * (whole[0] / whole[1] - 1.0),
                   whole[0] <= 1.1 * whole[1] ? "met" : "NOT met");
        if (part[0] > 0.0 && openmp > 0.0)
            printf("  %s: the megakernel's part (perma_run) against the C reference's pipeline span %.4f s: "
                   "polylines %.4f s %.2fx, no crack fix %.4f s %.2fx, stitched (two runs) %.4f s %.2fx\n",
                   names[d], openmp, part[0], ratio(openmp, part[0]), part[1], ratio(openmp, part[1]), part[2],
                   ratio(openmp, part[2]));
        for (unsigned f = 0; f < FIXES; ++f)
            print_cpu_ratio(fix_labels[f], &parallel, &timed[f][d]);
    }
}

int bench_reyes(bench_options *options, int argc, char **argv)
{
    reyes_bench_args a;
    perma_cli_status parsed = reyes_bench_parse_args(argc, argv, options, &a);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    const char *const *models = reyes_bench_models;
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
