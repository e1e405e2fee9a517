/* A reyes-render job: its scene, camera and items (buckets or frames). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "reyes_job.h"

static reyes_status build_scene(const reyes_cli *cli, reyes_job *job, reyes_error *error)
{
    if (cli->model_count == 0)
        return reyes_scene_add_builtin(&job->scene, error);
    job->model_end = malloc(cli->model_count * sizeof *job->model_end);
    if (!job->model_end)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu models", cli->model_count);
    for (size_t m = 0; m < cli->model_count; ++m) {
        reyes_status status = reyes_scene_load_bpt(&job->scene, cli->models[m],
                                                   reyes_model_color((unsigned)m), error);
        if (status != REYES_OK)
            return status;
        job->model_end[m] = job->scene.patch_count;
        job->model_count = m + 1;
    }
    return REYES_OK;
}

/* What automatic framing left out, for the user: "" if nothing. */
static void note_framing(const reyes_scene *scene, char *note, size_t size)
{
    reyes_bulk bulk;
    note[0] = '\0';
    if (!reyes_scene_bulk(scene, &bulk) || bulk.left_out == 0)
        return;
    const float *p = scene->points + bulk.first_left_out * 4;
    snprintf(note, size, "%zu control point%s far from the rest %s not framed (the first: patch %zu, point %zu, "
             "at %g %g %g); --camera can frame %s", bulk.left_out, bulk.left_out == 1 ? "" : "s",
             bulk.left_out == 1 ? "is" : "are", bulk.first_left_out / 16 + 1, bulk.first_left_out % 16 + 1,
             (double)p[0], (double)p[1], (double)p[2], bulk.left_out == 1 ? "it" : "them");
}

static reyes_status choose_camera(const reyes_cli *cli, reyes_job *job, reyes_error *error)
{
    const reyes_scene *scene = &job->scene;
    reyes_camera *camera = &job->camera;
    float aspect = (float)cli->render.width / (float)cli->render.height;
    if (!cli->has_camera) {
        note_framing(scene, job->framing_note, sizeof job->framing_note);
        return reyes_camera_frame(scene, cli->fov_deg, aspect, camera, error);
    }
    for (int k = 0; k < 3; ++k) {
        camera->eye[k] = cli->camera[k];
        camera->at[k] = cli->camera[3 + k];
    }
    camera->fov_deg = cli->fov_deg;
    return REYES_OK;
}

static unsigned bucket_side(unsigned bucket, unsigned image)
{
    return bucket == 0 || bucket > image ? image : bucket;
}

reyes_status reyes_job_init(reyes_job *job, const reyes_cli *cli, reyes_error *error)
{
    memset(job, 0, sizeof *job);
    reyes_scene_init(&job->scene);
    job->options = cli->render;
    job->options.bucket_source = NULL;
    job->options.device = NULL;
    job->output = cli->output;
    job->models = cli->models;
    job->frames = cli->frames;
    job->orbit_deg = cli->orbit_given ? cli->orbit_deg : 0.0f;
    /* A turntable unless the frames follow a motion. */
    const float *m = cli->render.motion;
    int moves = m[0] != 0.0f || m[1] != 0.0f || m[2] != 0.0f || cli->render.motion_angle_deg != 0.0f;
    if (cli->frames && !cli->orbit_given && !moves)
        job->orbit_deg = 360.0f;
    reyes_status status = reyes_options_check(&job->options, error);
    if (status == REYES_OK)
        status = build_scene(cli, job, error);
    if (status == REYES_OK)
        status = choose_camera(cli, job, error);
    if (status != REYES_OK)
        return status;
    unsigned bw = bucket_side(job->options.bucket_width, job->options.width);
    unsigned bh = bucket_side(job->options.bucket_height, job->options.height);
    job->bucket_columns = (job->options.width + bw - 1) / bw;
    job->items = job->frames ? job->frames
                             : job->bucket_columns * ((job->options.height + bh - 1) / bh);
    return REYES_OK;
}

void reyes_job_print_notes(const reyes_job *job, FILE *out)
{
    if (job->framing_note[0])
        fprintf(out, "reyes-render: note: %s\n", job->framing_note);
}

reyes_status reyes_job_check_outputs(const reyes_job *job, const char *stats_path, reyes_error *error)
{
    char path[4200];
    if (job->frames)
        reyes_job_frame_path(job, 0, path, sizeof path);
    else
        snprintf(path, sizeof path, "%s", job->output);
    reyes_status status = reyes_check_output(path, job->frames ? "--frames" : "--output", error);
    if (status == REYES_OK && stats_path)
        status = reyes_check_output(stats_path, "--stats", error);
    if (status == REYES_OK && job->options.trace_path)
        status = reyes_check_output(job->options.trace_path, "--trace", error);
    return status;
}

void reyes_job_free(reyes_job *job)
{
    reyes_scene_free(&job->scene);
    free(job->model_end);
    job->model_end = NULL;
}

void reyes_job_bucket_rect(const reyes_job *job, unsigned item, unsigned rect[4])
{
    const reyes_options *o = &job->options;
    unsigned bw = bucket_side(o->bucket_width, o->width), bh = bucket_side(o->bucket_height, o->height);
    rect[0] = (item % job->bucket_columns) * bw;
    rect[1] = (item / job->bucket_columns) * bh;
    rect[2] = rect[0] + bw < o->width ? rect[0] + bw : o->width;
    rect[3] = rect[1] + bh < o->height ? rect[1] + bh : o->height;
}

void reyes_job_frame_path(const reyes_job *job, unsigned frame, char *path, size_t size)
{
    reyes_cli_frame_path(job->output, frame, path, size);
}

/* Rotation matrix by `deg` degrees about `axis` (any length but 0). */
static void rotation(const float axis[3], double deg, double r[9])
{
    double a[3], length = sqrt((double)axis[0] * axis[0] + (double)axis[1] * axis[1]
                               + (double)axis[2] * axis[2]);
    for (int k = 0; k < 3; ++k)
        a[k] = axis[k] / length;
    double t = deg * (3.14159265358979323846 / 180.0), c = cos(t), s = sin(t);
    const double cross[9] = { 0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0 };
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            r[i * 3 + k] = c * (i == k) + s * cross[i * 3 + k] + (1.0 - c) * a[i] * a[k];
}

/* p <- r (p - center) + center + shift */
static void move_point(double p[3], const double r[9], const float center[3], const double shift[3])
{
    double d[3] = { p[0] - center[0], p[1] - center[1], p[2] - center[2] };
    for (int i = 0; i < 3; ++i)
        p[i] = r[i * 3] * d[0] + r[i * 3 + 1] * d[1] + r[i * 3 + 2] * d[2] + center[i] + shift[i];
}

reyes_status reyes_job_frame(const reyes_job *job, unsigned frame, reyes_scene *scene,
                             reyes_camera *camera, reyes_error *error)
{
    const reyes_options *o = &job->options;
    const reyes_scene *base = &job->scene;
    reyes_scene_init(scene);
    size_t points = base->patch_count * 16;
    scene->points = malloc((points ? points : 1) * 4 * sizeof *scene->points);
    scene->colors = malloc((base->patch_count ? base->patch_count : 1) * sizeof *scene->colors);
    if (!scene->points || !scene->colors) {
        reyes_scene_free(scene);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for frame %u's scene", frame + 1);
    }
    scene->patch_count = scene->capacity = base->patch_count;
    memcpy(scene->colors, base->colors, base->patch_count * sizeof *scene->colors);
    /* One shutter moves a point p to R (p - target) + target + motion
     * (reyes.h); frame f starts after f of them. */
    double r[9], identity[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    if (o->motion_angle_deg != 0.0f)
        rotation(o->motion_axis, o->motion_angle_deg, r);
    else
        memcpy(r, identity, sizeof r);
    const double shift[3] = { o->motion[0], o->motion[1], o->motion[2] };
    for (size_t i = 0; i < points; ++i) {
        const float *from = base->points + i * 4;
        double p[3] = { from[0], from[1], from[2] };
        for (unsigned f = 0; f < frame; ++f)
            move_point(p, r, job->camera.at, shift);
        float *to = scene->points + i * 4;
        for (int k = 0; k < 3; ++k)
            to[k] = (float)p[k];
        to[3] = from[3];
    }
    /* The orbit: about +z (the scenes' up) through the target. */
    *camera = job->camera;
    if (job->frames && job->orbit_deg != 0.0f) {
        const float up[3] = { 0.0f, 0.0f, 1.0f };
        const double none[3] = { 0.0, 0.0, 0.0 };
        double turn[9], eye[3] = { camera->eye[0], camera->eye[1], camera->eye[2] };
        rotation(up, (double)job->orbit_deg * frame / job->frames, turn);
        move_point(eye, turn, camera->at, none);
        for (int k = 0; k < 3; ++k)
            camera->eye[k] = (float)eye[k];
    }
    return REYES_OK;
}

void reyes_image_copy_rect(reyes_image *to, const reyes_image *from, unsigned x0, unsigned y0,
                           unsigned x1, unsigned y1)
{
    for (unsigned y = y0; y < y1; ++y) {
        size_t at = (size_t)y * to->width + x0;
        memcpy(to->rgb + at * 3, from->rgb + at * 3, (size_t)(x1 - x0) * 3);
        memcpy(to->coverage + at, from->coverage + at, x1 - x0);
    }
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void add_counts(reyes_work_report *report, const reyes_stats *stats)
{
    report->grids += stats->grids;
    report->micropolygons += stats->micropolygons;
    report->samples_written += stats->samples_written;
}

/* Count the buckets a render takes from the source. */
typedef struct counting_source {
    const reyes_bucket_source *inner;
    reyes_work_report *report;
    double start;
} counting_source;

static int counting_next(void *user, unsigned *bucket)
{
    counting_source *c = user;
    if (c->report->first_seconds == 0.0)
        c->report->first_seconds = now() - c->start;
    return c->inner->next(c->inner->user, bucket);
}

static reyes_status counting_done(void *user, unsigned bucket, const reyes_image *image, unsigned x0,
                                  unsigned y0, unsigned x1, unsigned y1, reyes_error *error)
{
    counting_source *c = user;
    c->report->items++;
    c->report->seconds = now() - c->start;
    return c->inner->done ? c->inner->done(c->inner->user, bucket, image, x0, y0, x1, y1, error)
                          : REYES_OK;
}

reyes_status reyes_job_work(const reyes_job *job, reyes_renderer *renderer,
                            const reyes_bucket_source *source, reyes_work_report *report,
                            reyes_error *error)
{
    double start = now();
    reyes_options options = job->options;
    reyes_status status = REYES_OK;
    if (!job->frames) {
        counting_source counting = { source, report, start };
        reyes_bucket_source wrapped = { counting_next, counting_done, &counting };
        options.bucket_source = &wrapped;
        reyes_image image;
        reyes_stats stats;
        status = reyes_render(renderer, &job->scene, &job->camera, &options, &image, &stats, error);
        if (status == REYES_OK) {
            add_counts(report, &stats);
            reyes_stats_free(&stats);
            reyes_image_free(&image);
        }
        return status;
    }
    unsigned frame;
    while (status == REYES_OK && source->next(source->user, &frame)) {
        reyes_scene scene;
        reyes_camera camera;
        reyes_image image;
        reyes_stats stats;
        status = reyes_job_frame(job, frame, &scene, &camera, error);
        if (status != REYES_OK)
            break;
        status = reyes_render(renderer, &scene, &camera, &options, &image, &stats, error);
        reyes_scene_free(&scene);
        if (status != REYES_OK)
            break;
        add_counts(report, &stats);
        reyes_stats_free(&stats);
        status = source->done ? source->done(source->user, frame, &image, 0, 0, image.width, image.height,
                                             error)
                              : REYES_OK;
        reyes_image_free(&image);
        report->items++;
        report->seconds = now() - start;
    }
    if (status != REYES_OK && error) {
        char message[REYES_MESSAGE_MAX];
        snprintf(message, sizeof message, "%s", error->message);
        snprintf(error->message, sizeof error->message, "frame %u: %.1000s", frame + 1, message);
    }
    return status;
}
