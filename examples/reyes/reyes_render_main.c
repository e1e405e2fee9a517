/*
 * reyes-render: parse the command line, build the scene (models or the
 * built-in one), render it with the Reyes procedures, write PNG and stats.
 * Exit status: 0 ok, 1 rendering or file failure, 2 bad usage.
 */
#include <stdio.h>
#include <stdlib.h>

#include "reyes_cli.h"
#include "reyes_reference.h"

#define EXIT_USAGE 2

static reyes_status build_scene(const reyes_cli *cli, reyes_scene *scene, reyes_error *error)
{
    if (cli->model_count == 0)
        return reyes_scene_add_builtin(scene, error);
    for (size_t m = 0; m < cli->model_count; ++m) {
        reyes_status status = reyes_scene_load_bpt(scene, cli->models[m],
                                                   reyes_model_color((unsigned)m), error);
        if (status != REYES_OK)
            return status;
    }
    return REYES_OK;
}

static reyes_status choose_camera(const reyes_cli *cli, const reyes_scene *scene,
                                  reyes_camera *camera, reyes_error *error)
{
    float aspect = (float)cli->render.width / (float)cli->render.height;
    if (!cli->has_camera)
        return reyes_camera_frame(scene, cli->fov_deg, aspect, camera, error);
    for (int k = 0; k < 3; ++k) {
        camera->eye[k] = cli->camera[k];
        camera->at[k] = cli->camera[3 + k];
    }
    camera->fov_deg = cli->fov_deg;
    return REYES_OK;
}

static reyes_status run_reference(const reyes_cli *cli, const reyes_scene *scene,
                                  const reyes_camera *camera, reyes_error *error)
{
    reyes_reference_counts counts;
    reyes_status status = reyes_reference_run(scene, camera, &cli->render, &counts, error);
    if (status == REYES_OK)
        printf("reference (C, 1 thread, no shading or sampling): %llu splits, %llu grids, "
               "%llu culled, %llu micropolygons, %.3f s\n",
               (unsigned long long)counts.splits, (unsigned long long)counts.grids,
               (unsigned long long)counts.culled, (unsigned long long)counts.micropolygons,
               counts.seconds);
    return status;
}

static reyes_status run(const reyes_cli *cli, reyes_error *error)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    reyes_camera camera;
    reyes_renderer *renderer = NULL;
    reyes_image image = {0};
    reyes_stats stats = {0};
    reyes_status status = build_scene(cli, &scene, error);
    if (status == REYES_OK)
        status = choose_camera(cli, &scene, &camera, error);
    if (status == REYES_OK)
        status = reyes_renderer_create(&cli->render, &renderer, error);
    if (status == REYES_OK)
        status = reyes_render(renderer, &scene, &camera, &cli->render, &image, &stats, error);
    if (status == REYES_OK)
        status = reyes_write_png(cli->output, &image, error);
    if (status == REYES_OK && cli->stats_path)
        status = reyes_save_stats_json(cli->stats_path, &stats, &cli->render, error);
    if (status == REYES_OK)
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
    reyes_scene_free(&scene);
    return status;
}

int main(int argc, char **argv)
{
    const char *program = argc > 0 ? argv[0] : "reyes-render";
    reyes_cli cli;
    char message[512];
    if (reyes_cli_parse(argc, argv, &cli, message, sizeof message) != REYES_CLI_OK) {
        fprintf(stderr, "%s: %s\n", program, message);
        reyes_cli_free(&cli);
        return EXIT_USAGE;
    }
    int code = EXIT_SUCCESS;
    if (cli.help) {
        reyes_cli_usage(stdout, program);
    } else if (cli.version) {
        printf("reyes-render %s (perma %s)\n", REYES_VERSION_STRING, PERMA_VERSION_STRING);
    } else {
        reyes_error error;
        reyes_status status = run(&cli, &error);
        if (status != REYES_OK) {
            fprintf(stderr, "%s: %s\n", program, error.message);
            /* Options that parse but do not fit together are bad usage too. */
            code = status == REYES_ERR_ARGUMENT ? EXIT_USAGE : EXIT_FAILURE;
        }
    }
    reyes_cli_free(&cli);
    return code;
}
