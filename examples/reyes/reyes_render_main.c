/*
 * reyes-render: parse the command line, build the scene (models or the
 * built-in one), render it with the Reyes procedures, write PNG and stats.
 * With --devices or --frames the buckets or frames are spread over
 * devices (reyes_farm.h); under mpirun over ranks (reyes_mpi.h).  A
 * progress line on stderr when it is a terminal (or --progress), nothing
 * but errors with --quiet (reyes_progress.h).
 * Exit status: 0 ok, 1 rendering or file failure, 2 bad usage.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "reyes_cli.h"
#include "reyes_farm.h"
#include "reyes_interrupt.h"
#include "reyes_mpi.h"
#include "reyes_progress.h"
#include "reyes_reference.h"
#include "reyes_report.h"

static reyes_status run_reference(const reyes_cli *cli, const reyes_scene *scene,
                                  const reyes_camera *camera, reyes_error *error)
{
    reyes_reference_counts counts;
    reyes_status status = reyes_reference_run(scene, camera, &cli->render, &counts, error);
    if (status == REYES_OK && !cli->quiet)
        printf("reference (C, 1 thread, no shading or sampling): %llu splits, %llu grids, "
               "%llu culled, %llu micropolygons, %.3f s\n",
               (unsigned long long)counts.splits, (unsigned long long)counts.grids,
               (unsigned long long)counts.culled, (unsigned long long)counts.micropolygons,
               counts.seconds);
    return status;
}

/* The buckets of one image in order, each counted on the progress line
 * when it is done. */
typedef struct progress_source {
    reyes_progress *progress;
    unsigned next, count;
} progress_source;

static int progress_next(void *user, unsigned *bucket)
{
    progress_source *s = user;
    if (s->next >= s->count)
        return 0;
    *bucket = s->next++;
    return 1;
}

static reyes_status progress_done(void *user, unsigned bucket, const reyes_image *image, unsigned x0,
                                  unsigned y0, unsigned x1, unsigned y1, reyes_error *error)
{
    (void)bucket, (void)image, (void)x0, (void)y0, (void)x1, (void)y1, (void)error;
    reyes_progress_item_done(((progress_source *)user)->progress, 0);
    return REYES_OK;
}

/* The files an interrupt finds written: the image (or, with frames, the
 * frames the pool names) and the statistics. */
typedef struct written_files {
    const char *image, *stats;
    reyes_pool *pool;
} written_files;

static void describe_written(void *user, char *out, size_t size)
{
    const written_files *w = user;
    char frames[512] = "";
    if (w->pool)
        reyes_pool_describe_written(w->pool, frames, sizeof frames);
    if (w->image)
        snprintf(out, size, "%s%s%s %s written", w->image, w->stats ? " and " : "", w->stats ? w->stats : "",
                 w->stats ? "were" : "was");
    else
        snprintf(out, size, "%s%s%s%s", frames, w->stats ? "; " : "", w->stats ? w->stats : "",
                 w->stats ? " was written" : "");
}

static void describe_text(void *user, char *out, size_t size)
{
    snprintf(out, size, "%s", (const char *)user);
}

/* One image on one device: the full statistics. */
static reyes_status run(const reyes_cli *cli, const char *program, reyes_error *error)
{
    reyes_job job;
    reyes_scene scene = {0};
    reyes_camera camera;
    reyes_renderer *renderer = NULL;
    reyes_image image = {0};
    reyes_stats stats = {0};
    reyes_options options = cli->render;
    reyes_progress progress;
    reyes_progress_slot slot = { &progress, 0 };
    progress_source buckets = { &progress, 0, 0 };
    reyes_bucket_source source = { progress_next, progress_done, &buckets };
    int terminal, shown = reyes_progress_wanted(cli->progress, cli->quiet, &terminal);
    reyes_status status = reyes_job_init(&job, cli, error);
    scene = job.scene;
    camera = job.camera;
    if (status == REYES_OK && shown) {
        buckets.count = job.items;
        reyes_progress_start(&progress, stderr, terminal, program, "buckets", job.items);
        options.bucket_source = &source;
        options.progress = reyes_progress_runtime;
        options.progress_user = &slot;
        options.progress_interval = REYES_PROGRESS_INTERVAL;
    }
    if (status == REYES_OK)
        status = reyes_job_check_outputs(&job, cli->stats_path, error);
    if (status == REYES_OK) {
        if (!cli->quiet)
            reyes_job_print_notes(&job, stderr);
        status = reyes_renderer_create(&options, &renderer, error);
    }
    if (status == REYES_OK)
        status = reyes_render(renderer, &scene, &camera, &options, &image, &stats, error);
    if (status == REYES_OK) {
        /* The image and its statistics: both or neither. */
        const reyes_stats_output stats_output = { &stats, &cli->render };
        const reyes_output_file files[] = { { cli->output, reyes_png_writer, &image },
                                            { cli->stats_path, reyes_stats_writer, &stats_output } };
        static written_files written;
        written = (written_files){ cli->output, cli->stats_path, NULL };
        reyes_interrupt_outputs_begin();
        status = reyes_write_outputs(files, cli->stats_path ? 2 : 1, error);
        reyes_interrupt_outputs_end(status == REYES_OK ? describe_written : NULL, &written);
    }
    if (shown && buckets.count) {
        reyes_progress_finish(&progress, status == REYES_OK);
        reyes_progress_free(&progress);
    }
    if (status == REYES_OK && !cli->quiet)
        printf("%s: %ux%u, %zu patches, %llu splits, %llu grids, %llu micropolygons, %.3f s, "
               "%s/%s (%s)\n",
               cli->output, image.width, image.height, scene.patch_count,
               (unsigned long long)stats.splits, (unsigned long long)stats.grids,
               (unsigned long long)stats.micropolygons, stats.seconds,
               perma_technique_name(cli->render.schedule.technique), perma_strategy_name(cli->render.schedule.strategy),
               reyes_renderer_device(renderer));
    if (status == REYES_OK && cli->reference)
        status = run_reference(cli, &scene, &camera, error);
    reyes_image_free(&image);
    reyes_stats_free(&stats);
    reyes_renderer_destroy(renderer);
    reyes_job_free(&job);
    return status;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The devices of --devices (or PERMA_DEVICE): a bad list is bad usage, a
 * missing device a failure. */
static reyes_status list_devices(const char *list, perma_device_ref *devices, unsigned *count,
                                 reyes_error *error)
{
    perma_error perr;
    perma_status st = perma_device_list(list, devices, PERMA_MAX_DEVICES, count, &perr);
    if (st == PERMA_OK)
        return REYES_OK;
    return reyes_fail(error, st == PERMA_ERR_ARGUMENT ? REYES_ERR_ARGUMENT : REYES_ERR_RUNTIME,
                      "--devices: %s", perr.message);
}

/* Buckets or frames spread over the devices of --devices (docs/scale-out.md). */
static reyes_status run_farm(const reyes_cli *cli, const char *program, reyes_error *error)
{
    perma_device_ref devices[PERMA_MAX_DEVICES];
    unsigned count = 0;
    reyes_job job;
    reyes_pool pool;
    reyes_farm_worker workers[PERMA_MAX_DEVICES];
    reyes_status status = list_devices(cli->devices, devices, &count, error);
    if (status != REYES_OK)
        return status;
    double start = now();
    status = reyes_job_init(&job, cli, error);
    if (status == REYES_OK)
        status = reyes_job_check_outputs(&job, cli->stats_path, error);
    if (status == REYES_OK) {
        if (!cli->quiet)
            reyes_job_print_notes(&job, stderr);
        status = reyes_pool_init(&pool, &job, error);
    }
    else
        reyes_job_free(&job);
    if (status != REYES_OK)
        return status;
    reyes_progress progress;
    int terminal, shown = reyes_progress_wanted(cli->progress, cli->quiet, &terminal);
    if (shown) {
        reyes_progress_start(&progress, stderr, terminal, program, job.frames ? "frames" : "buckets", job.items);
        pool.progress = &progress;
    }
    static written_files before, after;
    before = (written_files){ NULL, NULL, job.frames ? &pool : NULL };
    after = (written_files){ job.frames ? NULL : cli->output, cli->stats_path, before.pool };
    reyes_interrupt_describe_with(job.frames ? describe_written : NULL, &before);
    status = reyes_farm_run(&pool, devices, count, workers, error);
    double seconds = now() - start;
    reyes_work_report reports[PERMA_MAX_DEVICES];
    for (unsigned k = 0; k < count; ++k)
        reports[k] = workers[k].report;
    if (status == REYES_OK) {
        reyes_interrupt_outputs_begin();
        status = reyes_report_write_outputs(&pool, reports, count, seconds, cli->stats_path, error);
        reyes_interrupt_outputs_end(status == REYES_OK ? describe_written : NULL, &after);
    }
    if (shown) {
        reyes_progress_finish(&progress, status == REYES_OK);
        reyes_progress_free(&progress);
    }
    if (status == REYES_OK && !cli->quiet)
        reyes_report_print(stdout, &job, reports, count, "device", seconds);
    if (status == REYES_OK && cli->reference && !job.frames)
        status = run_reference(cli, &job.scene, &job.camera, error);
    if (status != REYES_OK && job.frames) {
        /* Say which frames are there (the message is the failure's). */
        char written[480], message[REYES_MESSAGE_MAX];
        reyes_pool_describe_written(&pool, written, sizeof written);
        snprintf(message, sizeof message, "%s", error->message);
        snprintf(error->message, sizeof error->message, "%.500s; %s", message, written);
    }
    if (job.frames) {
        /* The pool is going: what it says now stays true. */
        static char final[1024];
        describe_written(&after, final, sizeof final);
        reyes_interrupt_describe_with(describe_text, final);
    }
    reyes_pool_free(&pool);
    reyes_job_free(&job);
    return status;
}

int main(int argc, char **argv)
{
    const char *program = argc > 0 ? argv[0] : "reyes-render";
    reyes_cli cli;
    char message[512];
    /* Under mpirun every rank parses the same line; rank 0 speaks. */
    int quiet = reyes_mpi_launched() && reyes_mpi_launched_rank() != 0;
    perma_cli_status parsed = reyes_cli_parse(argc, argv, &cli, message, sizeof message);
    if (parsed == PERMA_CLI_OK)
        parsed = reyes_cli_check_files(&cli, message, sizeof message);
    int code = EXIT_SUCCESS;
    if (parsed == PERMA_CLI_USAGE) {
        if (!quiet)
            perma_cli_print_error(program, message);
        code = PERMA_CLI_EXIT_USAGE;
    } else if (parsed == PERMA_CLI_HELP) {
        if (!quiet)
            reyes_cli_usage(stdout, program);
    } else if (parsed == PERMA_CLI_VERSION) {
        if (!quiet)
            printf("reyes-render %s (perma %s%s)\n", REYES_VERSION_STRING, PERMA_VERSION_STRING,
                   reyes_mpi_available() ? ", MPI" : "");
    } else if (reyes_mpi_launched()) {
        code = reyes_mpi_main(&cli, program);
    } else if (cli.coordinator_only || cli.rank_timeout > 0.0f) {
        /* Options of an MPI job would be silently ignored in one process. */
        snprintf(message, sizeof message, "%s applies only to a job started by mpirun (docs/scale-out.md); without "
                                          "it reyes-render runs in one process",
                 cli.coordinator_only ? "--coordinator-only" : "--rank-timeout");
        perma_cli_print_error(program, message);
        code = PERMA_CLI_EXIT_USAGE;
    } else {
        reyes_error error;
        reyes_interrupt_watch(program);
        reyes_status status = cli.devices || cli.frames ? run_farm(&cli, program, &error) : run(&cli, program, &error);
        /* Options that parse but do not fit together are bad usage too. */
        if (status == REYES_ERR_ARGUMENT)
            perma_cli_print_error(program, error.message);
        else if (status != REYES_OK)
            fprintf(stderr, "%s: %s\n", program, error.message);
        code = status == REYES_OK ? EXIT_SUCCESS : status == REYES_ERR_ARGUMENT ? PERMA_CLI_EXIT_USAGE : EXIT_FAILURE;
    }
    reyes_cli_free(&cli);
    return code;
}
