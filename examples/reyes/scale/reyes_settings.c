/* The settings of a job that decide its image (reyes_settings.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_settings.h"

/* FNV-1a, 64 bits: enough to tell settings apart (nobody forges them). */
static uint64_t digest_bytes(uint64_t digest, const void *data, size_t size)
{
    const unsigned char *p = data;
    for (size_t k = 0; k < size; ++k)
        digest = (digest ^ p[k]) * 0x100000001b3ull;
    return digest;
}

static const uint64_t DIGEST_START = 0xcbf29ce484222325ull;

/* A file's bytes (the displacement map: the renderer reads it); the path
 * alone when it cannot be read, which the renderer reports. */
static uint64_t digest_file(const char *path)
{
    uint64_t digest = digest_bytes(DIGEST_START, path, strlen(path));
    FILE *f = fopen(path, "rb");
    if (!f)
        return digest;
    unsigned char buffer[65536];
    size_t got;
    while ((got = fread(buffer, 1, sizeof buffer, f)) > 0)
        digest = digest_bytes(digest, buffer, got);
    fclose(f);
    return digest;
}

/* Each option's value as text; floats with 9 digits, which tell any two
 * floats apart. */
typedef void (*format_fn)(const reyes_job *job, char *out, size_t size);

#define O (&job->options)

static void size_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%ux%u", O->width, O->height);
}

static void bucket_text(const reyes_job *job, char *out, size_t size)
{
    if (O->bucket_width == 0 && O->bucket_height == 0)
        snprintf(out, size, "none");
    else
        snprintf(out, size, "%ux%u", O->bucket_width, O->bucket_height);
}

static void displace_text(const reyes_job *job, char *out, size_t size)
{
    if (O->displace_mode == REYES_DISPLACE_BUMPS)
        snprintf(out, size, "bumps:%.9g", O->displace_amplitude);
    else if (O->displace_mode == REYES_DISPLACE_MAP)
        snprintf(out, size, "png:%s:%.9g", O->displace_map ? O->displace_map : "", O->displace_amplitude);
    else
        snprintf(out, size, "none");
}

static void motion_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%.9g,%.9g,%.9g", O->motion[0], O->motion[1], O->motion[2]);
}

static void motion_rotate_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%.9g,%.9g,%.9g,%.9g", O->motion_axis[0], O->motion_axis[1], O->motion_axis[2],
             O->motion_angle_deg);
}

static void aperture_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%.9g", O->aperture);
}

static void focus_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%.9g", O->focus);
}

static void time_samples_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%u", O->time_samples);
}

static void blur_tile_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%u", O->blur_tile);
}

static void blur_permutations_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%u", O->blur_permutations);
}

/* With the tiered criterion --bound is also its largest diced sub-patch. */
static void bound_text(const reyes_job *job, char *out, size_t size)
{
    if (O->flat_bound_px != 0.0f)
        snprintf(out, size, "%.9g (tiered: %.9g)", O->bound_px, O->flat_bound_px);
    else
        snprintf(out, size, "%.9g", O->bound_px);
}

static void epsilon_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%.9g", O->flat_epsilon);
}

static void lambda_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%.9g", O->flat_lambda);
}

static void grid_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%u", O->grid);
}

/* The rate in effect: 0 is fixed grids (--grid alone, wedges, --reference). */
static void shading_rate_text(const reyes_job *job, char *out, size_t size)
{
    if (O->shading_rate == 0.0f)
        snprintf(out, size, "none (fixed grids)");
    else
        snprintf(out, size, "%.9g", O->shading_rate);
}

static void spp_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%u", O->spp);
}

static void max_depth_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%u", O->max_depth);
}

/* The camera in effect: given, or framed from the models, size and fov. */
static void camera_text(const reyes_job *job, char *out, size_t size)
{
    const reyes_camera *c = &job->camera;
    snprintf(out, size, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", c->eye[0], c->eye[1], c->eye[2], c->at[0], c->at[1],
             c->at[2]);
}

static void fov_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%.9g", job->camera.fov_deg);
}

static void frames_text(const reyes_job *job, char *out, size_t size)
{
    if (job->frames)
        snprintf(out, size, "%u", job->frames);
    else
        snprintf(out, size, "none");
}

static void orbit_text(const reyes_job *job, char *out, size_t size)
{
    snprintf(out, size, "%.9g", job->orbit_deg);
}

#undef O

/* Every option that changes the image or its items; NULL: a flag or a
 * choice, whose text the option table gives. */
static const struct {
    const char *option;
    format_fn text;
} options[] = {
    { "size", size_text },
    { "bucket", bucket_text },
    { "camera", camera_text },
    { "fov", fov_text },
    { "frames", frames_text },
    { "orbit", orbit_text },
    { "spp", spp_text },
    { "crack-fix", NULL },
    { "subdivision", NULL },
    { "bound", bound_text },
    { "epsilon", epsilon_text },
    { "lambda", lambda_text },
    { "grid", grid_text },
    { "shading-rate", shading_rate_text },
    { "max-depth", max_depth_text },
    { "show-grids", NULL },
    { "backface", NULL },
    { "displace", displace_text },
    { "motion", motion_text },
    { "motion-rotate", motion_rotate_text },
    { "aperture", aperture_text },
    { "focus", focus_text },
    { "blur-algo", NULL },
    { "blur-tile", blur_tile_text },
    { "blur-permutations", blur_permutations_text },
    { "time-samples", time_samples_text },
};

#define OPTION_COUNT (sizeof options / sizeof options[0])

static void set(reyes_setting *s, const char *name, const char *value, uint64_t digest)
{
    snprintf(s->name, sizeof s->name, "%s", name);
    snprintf(s->value, sizeof s->value, "%s", value);
    s->digest = digest;
}

reyes_setting *reyes_job_settings(const reyes_job *job, const reyes_cli *cli, size_t *count)
{
    size_t total = OPTION_COUNT + 1 + job->model_count;
    reyes_setting *out = calloc(total, sizeof *out);
    if (!out)
        return NULL;
    char name[32], value[4200];
    /* The models first (the cause when they differ, and the camera framed
     * from them differs too): how many, then each one's control points
     * and colours. */
    size_t at = 0;
    if (job->model_count == 0)
        snprintf(value, sizeof value, "none (the built-in scene)");
    else
        snprintf(value, sizeof value, "%zu", job->model_count);
    set(&out[at++], "models", value, digest_bytes(DIGEST_START, value, strlen(value)));
    for (size_t m = 0; m < job->model_count; ++m) {
        size_t first = m ? job->model_end[m - 1] : 0, patches = job->model_end[m] - first;
        uint64_t digest = digest_bytes(DIGEST_START, job->scene.points + first * 64,
                                       patches * 64 * sizeof *job->scene.points);
        digest = digest_bytes(digest, job->scene.colors + first, patches * sizeof *job->scene.colors);
        snprintf(name, sizeof name, "model %zu", m + 1);
        snprintf(value, sizeof value, "%s (%zu patches)", job->models[m], patches);
        set(&out[at++], name, value, digest);
    }
    for (size_t k = 0; k < OPTION_COUNT; ++k) {
        snprintf(name, sizeof name, "--%s", options[k].option);
        if (options[k].text)
            options[k].text(job, value, sizeof value);
        else if (!reyes_cli_field_text(cli, options[k].option, value, sizeof value))
            snprintf(value, sizeof value, "?"); /* an option renamed without this table */
        uint64_t digest = digest_bytes(DIGEST_START, value, strlen(value));
        if (strcmp(options[k].option, "displace") == 0 && job->options.displace_mode == REYES_DISPLACE_MAP
            && job->options.displace_map)
            digest ^= digest_file(job->options.displace_map);
        if (strcmp(options[k].option, "camera") == 0 && !cli->has_camera)
            strcat(value, " (framed)");
        set(&out[at++], name, value, digest);
    }
    *count = at;
    return out;
}

const reyes_setting *reyes_settings_find(const reyes_setting *settings, size_t count, const char *name)
{
    for (size_t k = 0; k < count; ++k)
        if (strcmp(settings[k].name, name) == 0)
            return &settings[k];
    return NULL;
}

size_t reyes_settings_compare(const reyes_setting *a, size_t a_count, const reyes_setting *b,
                              size_t b_count, size_t *differing)
{
    size_t first = SIZE_MAX, count = 0, matched = 0;
    for (size_t k = 0; k < a_count; ++k) {
        const reyes_setting *other = reyes_settings_find(b, b_count, a[k].name);
        matched += other != NULL;
        if (other && other->digest == a[k].digest)
            continue;
        if (first == SIZE_MAX)
            first = k;
        ++count;
    }
    /* Settings only b has (models past a's last). */
    if (matched < b_count) {
        count += b_count - matched;
        if (first == SIZE_MAX)
            first = a_count;
    }
    if (differing)
        *differing = count;
    return first;
}
