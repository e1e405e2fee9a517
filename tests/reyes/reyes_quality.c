/*
 * reyes-quality: renders models from several views with fixed grids and
 * with a shading rate, holds each against the brute-force reference
 * (reyes_brute.h) and prints one line per render: micropolygons per
 * covered pixel and the distribution of their areas, cracks (see-through
 * samples and holes at 1 sample per pixel, at the renderer's own sample
 * positions) and the mean FLIP error (reyes_flip.h).  The numbers of
 * docs/reyes-measurements.md's quality tables; not a test (the tests check the same
 * things on fewer views).
 *
 *   reyes-quality [--size N] [--spp N] [--rate R] [--crack-fix NAME] [--no-grid] [--cracks] [--dump DIR]
 *                 [--views LIST | --random N [--seed S]] MODEL...   (options: perma_cli's table in main; --help)
 *
 * MODEL: a .bpt file, `builtin` or `subdivision[:LEVELS][:loose][:ico]`
 * (loose: boundaries that agree only to rounding; ico: the icosahedral
 * cage, base patch corners of valence 3 to 6); LIST: views
 * `azimuth,elevation,distance` separated by `/` (degrees about the
 * framed camera's target, distance in framed distances); --random: N
 * views of reyes_quality_random_view (framed, near, telephoto, grazing).
 * The last lines total the see-through samples and holes per dicing.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "perma_cli.h"
#include "reyes_brute.h"
#include "reyes_flip.h"
#include "reyes_quality_util.h"
#include "reyes_subdivision_model.h"

typedef struct settings {
    unsigned size, spp;
    float rate;
    unsigned crack_fix;
    int no_grid, cracks_only;
    const char *dump;
    reyes_quality_view views[16];
    unsigned view_count, random_views, seed;
    const char **models;
    size_t model_count;
} settings;

/* azimuth,elevation,distance views separated by '/' (at most 16). */
static int parse_views_text(const char *text, settings *s)
{
    s->view_count = 0;
    while (*text) {
        if (s->view_count == 16)
            return 0;
        reyes_quality_view *v = &s->views[s->view_count++];
        int used = 0;
        if (sscanf(text, "%f,%f,%f%n", &v->azimuth, &v->elevation, &v->distance, &used) != 3)
            return 0;
        text += used;
        if (*text == '/')
            ++text;
        else if (*text)
            return 0;
    }
    return s->view_count > 0;
}

static int parse_views(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    if (parse_views_text(value, option->target))
        return 0;
    snprintf(complaint, size, "expected 1 to 16 views azimuth,elevation,distance separated by '/'");
    return 1;
}

/* Models: every operand, into s->models (room for argc of them). */
static int add_model(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    (void)complaint;
    (void)size;
    settings *s = option->target;
    s->models[s->model_count++] = value;
    return 0;
}

static int load(const char *name, reyes_scene *scene, reyes_error *error)
{
    reyes_scene_init(scene);
    if (strcmp(name, "builtin") == 0)
        return reyes_scene_add_builtin(scene, error) == REYES_OK;
    if (strncmp(name, "subdivision", 11) == 0) {
        /* subdivision[:LEVELS][:loose] */
        unsigned levels = name[11] == ':' && name[12] >= '0' && name[12] <= '9' ? (unsigned)atoi(name + 12) : 4u;
        int glued = strstr(name, "loose") == NULL;
        unsigned cage = strstr(name, "ico") ? REYES_CAGE_ICOSAHEDRAL : REYES_CAGE_CUBE;
        return reyes_subdivision_cage_add(scene, cage, levels, glued, reyes_model_color(0), error) == REYES_OK;
    }
    return reyes_scene_load_bpt(scene, name, reyes_model_color(0), error) == REYES_OK;
}

static void print_line(const char *model, unsigned view, const char *config, const reyes_quality_result *r)
{
    printf("%-14s view %u %-8s | mp/px %6.2f (%zu px) | area mean %.3f p10 %.3f p50 %.3f p90 %.3f p99 %.3f | "
           "see-through %3zu holes %3zu | extra %zu missing %zu other %zu | FLIP %.5f (silhouettes %.5f seams %.5f) truth %.5f | mean err %.3f >32 %zu\n",
           model, view, config, r->micropolygons_per_pixel, r->covered_pixels, r->area_mean, r->area_percentile[0],
           r->area_percentile[1], r->area_percentile[2], r->area_percentile[3], r->see_through, r->holes, r->colour.extra, r->colour.missing, r->colour.other_surface, r->flip, r->flip_silhouettes, r->flip_seams, r->flip_truth,
           r->colour.mean_error, r->colour.pixels_over_32);
    fflush(stdout);
}

int main(int argc, char **argv)
{
    settings s = { 512, 4, 1.0f, REYES_CRACK_FIX_STITCH, 0, 0, NULL, {{0, 0, 0}}, 0, 0, 1, NULL, 0 };
    parse_views_text("0,25,1/60,10,0.9/140,45,1.1/220,5,0.8/300,-20,1/30,30,2.5/100,20,4", &s);
    s.models = calloc(argc > 0 ? (size_t)argc : 1, sizeof *s.models);
    if (!s.models) {
        fprintf(stderr, "reyes-quality: out of memory\n");
        return 1;
    }
    static const char *const crack_fixes[] = { "none", "stitch", "wedge", "polyline", NULL }; /* REYES_CRACK_FIX_* */
    const perma_cli_option rows[] = {
        { PERMA_CLI_WHOLE("size", "N", &s.size, 16, 4096, "image side in pixels (default 512)") },
        { PERMA_CLI_WHOLE("spp", "N", &s.spp, 1, REYES_MAX_SPP, "samples per pixel (default 4)") },
        { PERMA_CLI_FLOAT("rate", "R", &s.rate, REYES_MIN_SHADING_RATE, REYES_MAX_SHADING_RATE,
                          "the shading rate of the rate renders (default 1)") },
        { PERMA_CLI_CHOICE("crack-fix", "NAME", &s.crack_fix, crack_fixes, "crack fix (default stitch)") },
        { PERMA_CLI_FLAG("no-grid", &s.no_grid, "skip the fixed 16x16 grids' renders") },
        { PERMA_CLI_FLAG("cracks", &s.cracks_only, "count cracks only (no colour, no FLIP)") },
        { PERMA_CLI_TEXT("dump", "DIR", &s.dump, "write each render, its reference and their error as PNGs here") },
        { PERMA_CLI_CUSTOM("views", "a,e,d/...", parse_views, &s,
                           "views: azimuth,elevation (degrees about the framed camera's target), distance (in "
                           "framed distances), separated by '/' (default: docs/reyes-measurements.md's 7)") },
        { PERMA_CLI_WHOLE("random", "N", &s.random_views, 0, 100000,
                          "N random views instead: framed, near, telephoto and grazing in turn") },
        { PERMA_CLI_WHOLE("seed", "S", &s.seed, 0, 4000000000u, "the random views' seed (default 1)") },
    };
    const perma_cli_table table = { "options", rows, sizeof rows / sizeof rows[0] };
    const perma_cli_option model_row = { PERMA_CLI_CUSTOM(NULL, "MODEL", add_model, &s, NULL) };
    const perma_cli cli = {
        .program = "reyes-quality",
        .synopsis = "[options] MODEL...",
        .about = "Render each model from several views with fixed grids and with a shading rate, hold\n"
                 "each against the brute-force reference and print a line per render (docs/reyes-measurements.md's\n"
                 "quality tables).  MODEL: a .bpt file, builtin or subdivision[:LEVELS][:loose].",
        .tables = &table,
        .table_count = 1,
        .operand = &model_row,
        .notes = "exit status: 0 ok, 1 rendering or file error, 2 bad usage",
    };
    char message[PERMA_CLI_MESSAGE_MAX];
    perma_cli_status status = perma_cli_parse(&cli, argc, argv, message, sizeof message);
    if (status == PERMA_CLI_OK && s.model_count == 0)
        status = perma_cli_fail(&cli, message, sizeof message, "no MODEL given");
    if (status != PERMA_CLI_OK) {
        free(s.models);
        return perma_cli_exit_status(status);
    }
    reyes_options base;
    reyes_options_init(&base);
    base.width = base.height = s.size;
    base.spp = s.spp;
    reyes_renderer *renderer;
    reyes_error error;
    if (reyes_renderer_create(&base, &renderer, &error) != REYES_OK) {
        fprintf(stderr, "reyes-quality: %s\n", error.message);
        return 1;
    }
    size_t see_through[2] = {0, 0}, holes[2] = {0, 0};
    for (size_t m = 0; m < s.model_count; ++m) {
        reyes_scene scene;
        if (!load(s.models[m], &scene, &error)) {
            fprintf(stderr, "reyes-quality: %s\n", error.message);
            return 1;
        }
        const char *name = strrchr(s.models[m], '/') ? strrchr(s.models[m], '/') + 1 : s.models[m];
        reyes_camera framed;
        if (reyes_camera_frame(&scene, 40.0f, 1.0f, &framed, &error) != REYES_OK) {
            fprintf(stderr, "reyes-quality: %s\n", error.message);
            return 1;
        }
        unsigned views = s.random_views ? s.random_views : s.view_count;
        for (unsigned v = 0; v < views; ++v) {
            reyes_quality_shot shot = { s.views[v % 16], 1.0f, {0.0f, 0.0f, 0.0f} };
            if (s.random_views)
                shot = reyes_quality_random_shot(s.seed, v);
            reyes_camera camera = reyes_quality_shoot(&framed, shot);
            reyes_quality_reference reference;
            unsigned what = s.cracks_only ? REYES_QUALITY_CRACKS
                                           : REYES_QUALITY_CRACKS | REYES_QUALITY_SAMPLES | REYES_QUALITY_TRUTH;
            if (reyes_quality_reference_make(&scene, &camera, &base, what, &reference, &error) != REYES_OK) {
                fprintf(stderr, "reyes-quality: %s\n", error.message);
                return 1;
            }
            if (!s.cracks_only)
                printf("%-14s view %u sampling floor: FLIP of the reference at the render's samples against the "
                       "converged image %.5f\n", name, v,
                       reyes_flip_mean(reference.truth.rgb, reference.many.rgb, s.size, s.size, REYES_FLIP_DEFAULT_PPD,
                                       NULL));
            for (int config = s.no_grid ? 1 : 0; config < 2; ++config) {
                reyes_options o = base;
                o.shading_rate = config == 0 ? 0.0f : s.rate;
                /* Polylines need a rate: the fixed grids stitch then. */
                o.crack_fix = config == 0 && s.crack_fix == REYES_CRACK_FIX_POLYLINE ? REYES_CRACK_FIX_STITCH
                                                                                    : s.crack_fix;
                reyes_quality_result r = {0};
                reyes_status status = reyes_quality_cracks(renderer, &scene, &camera, &o, &reference, &r, &error);
                if (status == REYES_OK && !s.cracks_only)
                {
                    char dump[1024];
                    snprintf(dump, sizeof dump, "%s/%s-%u-%s", s.dump ? s.dump : ".", name, v,
                             config == 0 ? "grid" : "rate");
                    status = reyes_quality_colour(renderer, &scene, &camera, &o, &reference, s.dump ? dump : NULL,
                                                  &r, &error);
                }
                if (status != REYES_OK) {
                    fprintf(stderr, "reyes-quality: %s\n", error.message);
                    return 1;
                }
                print_line(name, v, config == 0 ? "grid 16" : "rate", &r);
                see_through[config] += r.see_through;
                holes[config] += r.holes;
            }
            reyes_quality_reference_free(&reference);
        }
        reyes_scene_free(&scene);
    }
    for (int config = s.no_grid ? 1 : 0; config < 2; ++config)
        printf("total %s: see-through %zu holes %zu\n", config == 0 ? "grid 16" : "rate", see_through[config],
               holes[config]);
    reyes_renderer_destroy(renderer);
    free(s.models);
    return 0;
}
