/*
 * reyes-quality: renders models from several views with fixed grids and
 * with a shading rate, holds each against the brute-force reference
 * (reyes_brute.h) and prints one line per render: micropolygons per
 * covered pixel and the distribution of their areas, cracks (see-through
 * samples and holes at 1 sample per pixel, at the renderer's own sample
 * positions) and the mean FLIP error (reyes_flip.h).  The numbers of
 * docs/reyes.md's quality tables; not a test (the tests check the same
 * things on fewer views).
 *
 *   reyes-quality [--size N] [--spp N] [--rate R] [--crack-fix NAME] [--no-grid] [--views LIST] MODEL...
 *
 * MODEL: a .bpt file, `builtin` or `subdivision[:LEVELS][:loose]` (loose:
 * boundaries that agree only to rounding); LIST: views
 * `azimuth,elevation,distance` separated by `/` (degrees about the
 * framed camera's target, distance in framed distances).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_brute.h"
#include "reyes_flip.h"
#include "reyes_quality_util.h"
#include "reyes_subdivision_model.h"

typedef struct settings {
    unsigned size, spp;
    float rate;
    unsigned crack_fix;
    int grid, cracks_only;
    const char *dump;
    reyes_quality_view views[16];
    unsigned view_count;
} settings;

static int parse_views(const char *text, settings *s)
{
    s->view_count = 0;
    while (*text && s->view_count < 16) {
        reyes_quality_view *v = &s->views[s->view_count++];
        int used = 0;
        if (sscanf(text, "%f,%f,%f%n", &v->azimuth, &v->elevation, &v->distance, &used) != 3)
            return 0;
        text += used;
        if (*text == '/')
            ++text;
    }
    return s->view_count > 0;
}

static int load(const char *name, reyes_scene *scene, reyes_error *error)
{
    reyes_scene_init(scene);
    if (strcmp(name, "builtin") == 0)
        return reyes_scene_add_builtin(scene, error) == REYES_OK;
    if (strncmp(name, "subdivision", 11) == 0) {
        /* subdivision[:LEVELS][:loose] */
        unsigned levels = name[11] == ':' ? (unsigned)atoi(name + 12) : 4u;
        int glued = strstr(name, "loose") == NULL;
        return reyes_subdivision_model_add(scene, levels, glued, reyes_model_color(0), error) == REYES_OK;
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
    settings s = { 512, 4, 1.0f, REYES_CRACK_FIX_STITCH, 1, 0, NULL, {{0, 0, 0}}, 0 };
    parse_views("0,25,1/60,10,0.9/140,45,1.1/220,5,0.8/300,-20,1/30,30,2.5/100,20,4", &s);
    int first_model = argc;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--size") == 0 && i + 1 < argc)
            s.size = (unsigned)atoi(argv[++i]);
        else if (strcmp(argv[i], "--spp") == 0 && i + 1 < argc)
            s.spp = (unsigned)atoi(argv[++i]);
        else if (strcmp(argv[i], "--rate") == 0 && i + 1 < argc)
            s.rate = (float)atof(argv[++i]);
        else if (strcmp(argv[i], "--crack-fix") == 0 && i + 1 < argc) {
            const char *fix = argv[++i];
            s.crack_fix = strcmp(fix, "none") == 0 ? REYES_CRACK_FIX_NONE : REYES_CRACK_FIX_STITCH;
        } else if (strcmp(argv[i], "--no-grid") == 0)
            s.grid = 0;
        else if (strcmp(argv[i], "--dump") == 0 && i + 1 < argc)
            s.dump = argv[++i];
        else if (strcmp(argv[i], "--cracks") == 0)
            s.cracks_only = 1;
        else if (strcmp(argv[i], "--views") == 0 && i + 1 < argc) {
            if (!parse_views(argv[++i], &s)) {
                fprintf(stderr, "reyes-quality: bad --views '%s'\n", argv[i]);
                return 2;
            }
        } else {
            first_model = i;
            break;
        }
    }
    if (first_model >= argc) {
        fprintf(stderr, "usage: reyes-quality [--size N] [--spp N] [--rate R] [--crack-fix stitch|none] [--no-grid] [--cracks] [--dump DIR] "
                        "[--views a,e,d/...] MODEL...\n");
        return 2;
    }
    reyes_options base;
    reyes_options_init(&base);
    base.width = base.height = s.size;
    base.spp = s.spp;
    base.crack_fix = s.crack_fix;
    reyes_renderer *renderer;
    reyes_error error;
    if (reyes_renderer_create(&base, &renderer, &error) != REYES_OK) {
        fprintf(stderr, "reyes-quality: %s\n", error.message);
        return 1;
    }
    for (int m = first_model; m < argc; ++m) {
        reyes_scene scene;
        if (!load(argv[m], &scene, &error)) {
            fprintf(stderr, "reyes-quality: %s\n", error.message);
            return 1;
        }
        const char *name = strrchr(argv[m], '/') ? strrchr(argv[m], '/') + 1 : argv[m];
        reyes_camera framed;
        if (reyes_camera_frame(&scene, 40.0f, 1.0f, &framed, &error) != REYES_OK) {
            fprintf(stderr, "reyes-quality: %s\n", error.message);
            return 1;
        }
        for (unsigned v = 0; v < s.view_count; ++v) {
            reyes_camera camera = reyes_quality_orbit(&framed, s.views[v]);
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
            for (int config = s.grid ? 0 : 1; config < 2; ++config) {
                reyes_options o = base;
                o.shading_rate = config == 0 ? 0.0f : s.rate;
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
            }
            reyes_quality_reference_free(&reference);
        }
        reyes_scene_free(&scene);
    }
    reyes_renderer_destroy(renderer);
    return 0;
}
