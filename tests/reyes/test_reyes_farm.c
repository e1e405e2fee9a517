/* Spreading buckets and frames over devices (examples/reyes/scale/reyes_farm.h):
 * the pieces make the one-device image byte for byte, a bucket source gets
 * exactly the buckets it hands out, frames follow the orbit and the motion,
 * and a failure names the device and stops the farm. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "reyes_farm.h"
#include "reyes_test_util.h"

/* Two equal sub-devices where device 0:0 splits, else the device itself. */
static const char *two_devices(void)
{
    perma_device_ref refs[2];
    unsigned count;
    return perma_device_list("0:0/2", refs, 2, &count, NULL) == PERMA_OK ? "0:0/2" : "0:0";
}

static void make_job(reyes_job *job, reyes_cli *cli, int argc, char **argv)
{
    char message[512];
    ck_assert_msg(reyes_cli_parse(argc, argv, cli, message, sizeof message) == PERMA_CLI_OK, "%s", message);
    reyes_error error;
    ck_assert_msg(reyes_job_init(job, cli, &error) == REYES_OK, "%s", error.message);
}

/* Run the job on two devices (two_devices()); returns the status and
 * leaves the pool (free it) and the workers' reports. */
static reyes_status run_on_two(const reyes_job *job, reyes_pool *pool, reyes_farm_worker *workers,
                               unsigned *count, reyes_error *error)
{
    perma_device_ref devices[PERMA_MAX_DEVICES];
    ck_assert_int_eq(perma_device_list(two_devices(), devices, PERMA_MAX_DEVICES, count, NULL), PERMA_OK);
    ck_assert_int_eq(reyes_pool_init(pool, job, error), REYES_OK);
    return reyes_farm_run(pool, devices, *count, workers, error);
}

static void expect_same_image(const reyes_image *a, const reyes_image *b)
{
    size_t pixels = (size_t)a->width * a->height;
    ck_assert_uint_eq(a->width, b->width);
    ck_assert_uint_eq(a->height, b->height);
    ck_assert_mem_eq(a->rgb, b->rgb, pixels * 3);
    ck_assert_mem_eq(a->coverage, b->coverage, pixels);
}

/* 12 buckets over two devices: the one-device bytes, and the grids,
 * micropolygons and samples of the buckets add up to its counts.  Without
 * occlusion culling, whose counts depend on which grids happened to be
 * drawn first (docs/reyes-dicing.md): the images are the same either way. */
START_TEST(test_farm_buckets_identical)
{
    char *argv[] = { "reyes-render", "--size", "96x72", "--bucket", "24x24", "--occlusion", "off" };
    reyes_cli cli;
    reyes_job job;
    make_job(&job, &cli, 7, argv);
    ck_assert_uint_eq(job.items, 12);
    reyes_image single;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &job.scene, &job.camera, &job.options, &single, &stats);

    unsigned count;
    reyes_pool pool;
    reyes_farm_worker workers[PERMA_MAX_DEVICES];
    reyes_error error;
    ck_assert_msg(run_on_two(&job, &pool, workers, &count, &error) == REYES_OK, "%s", error.message);
    expect_same_image(&single, &pool.image);
    unsigned items = 0;
    uint64_t grids = 0, micropolygons = 0, samples = 0;
    for (unsigned k = 0; k < count; ++k) {
        printf("device %s: %u buckets\n", workers[k].report.device, workers[k].report.items);
        items += workers[k].report.items;
        grids += workers[k].report.grids;
        micropolygons += workers[k].report.micropolygons;
        samples += workers[k].report.samples_written;
    }
    ck_assert_uint_eq(items, 12);
    /* Each bucket's renderer and times are recorded, and they agree. */
    unsigned per_renderer[PERMA_MAX_DEVICES] = {0};
    for (unsigned b = 0; b < 12; ++b) {
        ck_assert_int_ge(pool.renderer[b], 0);
        ck_assert_int_lt(pool.renderer[b], (int)count);
        per_renderer[pool.renderer[b]]++;
        ck_assert(pool.render_seconds[b] > 0.0 && pool.render_seconds[b] <= pool.turnaround[b]);
    }
    for (unsigned k = 0; k < count; ++k)
        ck_assert_uint_eq(per_renderer[k], workers[k].report.items);
    ck_assert_uint_eq(grids, stats.grids);
    ck_assert_uint_eq(micropolygons, stats.micropolygons);
    ck_assert_uint_eq(samples, stats.samples_written);
    reyes_pool_free(&pool);
    reyes_image_free(&single);
    reyes_stats_free(&stats);
    reyes_job_free(&job);
    reyes_cli_free(&cli);
}
END_TEST

/* A source handing out buckets 5 and 2: done() sees their rectangles in
 * that order, their pixels are the whole render's, the rest stays 0. */
typedef struct list_source {
    const unsigned *buckets;
    unsigned count, next, done_calls;
    unsigned rects[4][4];
    reyes_status fail_with;
} list_source;

static int list_next(void *user, unsigned *bucket)
{
    list_source *s = user;
    if (s->next >= s->count)
        return 0;
    *bucket = s->buckets[s->next++];
    return 1;
}

static reyes_status list_done(void *user, unsigned bucket, const reyes_image *image, unsigned x0,
                              unsigned y0, unsigned x1, unsigned y1, reyes_error *error)
{
    list_source *s = user;
    (void)image;
    ck_assert_uint_eq(bucket, s->buckets[s->done_calls]);
    unsigned *r = s->rects[s->done_calls++];
    r[0] = x0;
    r[1] = y0;
    r[2] = x1;
    r[3] = y1;
    if (s->fail_with != REYES_OK)
        return reyes_fail(error, s->fail_with, "done refused bucket %u", bucket);
    return REYES_OK;
}

START_TEST(test_bucket_source_subset)
{
    char *argv[] = { "reyes-render", "--size", "80x60", "--bucket", "32x32" };
    reyes_cli cli;
    reyes_job job;
    make_job(&job, &cli, 5, argv);
    ck_assert_uint_eq(job.items, 6); /* 3 x 2, the last column 16 wide, the last row 28 high */
    reyes_image whole, part;
    reyes_test_render(reyes_test_renderer(0), &job.scene, &job.camera, &job.options, &whole, NULL);

    const unsigned buckets[2] = { 5, 2 };
    list_source list = { buckets, 2, 0, 0, {{0}}, REYES_OK };
    reyes_bucket_source source = { list_next, list_done, &list };
    reyes_options options = job.options;
    options.bucket_source = &source;
    reyes_test_render(reyes_test_renderer(0), &job.scene, &job.camera, &options, &part, NULL);
    ck_assert_uint_eq(list.done_calls, 2);
    const unsigned expected[2][4] = { { 64, 32, 80, 60 }, { 64, 0, 80, 32 } };
    for (int k = 0; k < 2; ++k) {
        unsigned rect[4];
        reyes_job_bucket_rect(&job, buckets[k], rect);
        for (int c = 0; c < 4; ++c) {
            ck_assert_uint_eq(list.rects[k][c], expected[k][c]);
            ck_assert_uint_eq(rect[c], expected[k][c]);
        }
    }
    size_t lit = 0;
    for (unsigned y = 0; y < 60; ++y) {
        for (unsigned x = 0; x < 80; ++x) {
            size_t p = (size_t)y * 80 + x;
            if (x >= 64) {
                ck_assert_mem_eq(part.rgb + p * 3, whole.rgb + p * 3, 3);
                ck_assert_uint_eq(part.coverage[p], whole.coverage[p]);
                lit += whole.coverage[p] > 0;
            } else {
                ck_assert_uint_eq(part.rgb[p * 3] | part.rgb[p * 3 + 1] | part.rgb[p * 3 + 2], 0);
                ck_assert_uint_eq(part.coverage[p], 0);
            }
        }
    }
    ck_assert_uint_gt(lit, 0); /* the right column shows something */
    reyes_image_free(&part);

    /* A bucket past the last one, and a failing done(), end the render. */
    const unsigned bad[1] = { 6 };
    list_source beyond = { bad, 1, 0, 0, {{0}}, REYES_OK };
    source.user = &beyond;
    reyes_error error;
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &job.scene, &job.camera, &options, &part, NULL,
                                  &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "the bucket source gave bucket 6 of 6");
    ck_assert_ptr_null(part.rgb);
    list_source refusing = { buckets, 2, 0, 0, {{0}}, REYES_ERR_IO };
    source.user = &refusing;
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &job.scene, &job.camera, &options, &part, NULL,
                                  &error), REYES_ERR_IO);
    ck_assert_str_eq(error.message, "done refused bucket 5");
    ck_assert_uint_eq(refusing.next, 1); /* nothing taken after the failure */
    reyes_image_free(&whole);
    reyes_job_free(&job);
    reyes_cli_free(&cli);
}
END_TEST

START_TEST(test_frame_paths)
{
    const struct { const char *output; unsigned frame; const char *path; } cases[] = {
        { "anim.png", 0, "anim-0001.png" },
        { "out/anim.png", 41, "out/anim-0042.png" },
        { "a.b/anim", 9999, "a.b/anim-10000" },
        { "noext", 1, "noext-0002" },
        { ".hidden", 0, ".hidden-0001" },
        { "dir/.hidden", 0, "dir/.hidden-0001" },
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        reyes_job job = { .output = cases[k].output };
        char path[256];
        reyes_job_frame_path(&job, cases[k].frame, path, sizeof path);
        ck_assert_str_eq(path, cases[k].path);
    }
}
END_TEST

static float distance(const float a[3], const float b[3])
{
    return sqrtf((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/* Frame f: the camera turned f * orbit / frames about +z through the
 * target; the scene moved by f shutters of the motion. */
START_TEST(test_frame_orbit_and_motion)
{
    char *turntable[] = { "reyes-render", "--frames", "4", "--size", "64x64" };
    reyes_cli cli;
    reyes_job job;
    make_job(&job, &cli, 5, turntable);
    ck_assert_float_eq(job.orbit_deg, 360.0f); /* the default without motion */
    ck_assert_uint_eq(job.items, 4);
    reyes_scene scene;
    reyes_camera camera;
    reyes_error error;
    ck_assert_int_eq(reyes_job_frame(&job, 0, &scene, &camera, &error), REYES_OK);
    ck_assert_mem_eq(scene.points, job.scene.points, job.scene.patch_count * 64 * sizeof(float));
    ck_assert_mem_eq(&camera, &job.camera, sizeof camera);
    reyes_scene_free(&scene);
    ck_assert_int_eq(reyes_job_frame(&job, 2, &scene, &camera, &error), REYES_OK); /* half a turn */
    ck_assert_mem_eq(scene.points, job.scene.points, job.scene.patch_count * 64 * sizeof(float));
    const float *e = job.camera.eye, *t = job.camera.at;
    ck_assert_float_eq_tol(camera.eye[0], 2.0f * t[0] - e[0], 1e-3f);
    ck_assert_float_eq_tol(camera.eye[1], 2.0f * t[1] - e[1], 1e-3f);
    ck_assert_float_eq_tol(camera.eye[2], e[2], 1e-4f);
    ck_assert_mem_eq(camera.at, job.camera.at, sizeof camera.at);
    ck_assert_float_eq_tol(distance(camera.eye, t), distance(e, t), 1e-3f);
    reyes_scene_free(&scene);
    reyes_job_free(&job);
    reyes_cli_free(&cli);

    /* Motion: no orbit by default; frame 3 starts 3 shutters along. */
    char *moving[] = { "reyes-render", "--frames", "5", "--motion", "0.5,-0.25,0", "--motion-rotate",
                       "0,0,1,90" };
    make_job(&job, &cli, 7, moving);
    ck_assert_float_eq(job.orbit_deg, 0.0f);
    ck_assert_int_eq(reyes_job_frame(&job, 3, &scene, &camera, &error), REYES_OK);
    ck_assert_mem_eq(&camera, &job.camera, sizeof camera);
    for (size_t i = 0; i < job.scene.patch_count * 16; i += 7) {
        /* Three times p <- Rz(90) (p - t) + t + m, by hand. */
        double p[3] = { job.scene.points[i * 4], job.scene.points[i * 4 + 1], job.scene.points[i * 4 + 2] };
        for (int f = 0; f < 3; ++f) {
            double dx = p[0] - t[0], dy = p[1] - t[1];
            p[0] = -dy + t[0] + 0.5;
            p[1] = dx + t[1] - 0.25;
        }
        ck_assert_float_eq_tol(scene.points[i * 4], (float)p[0], 1e-4f);
        ck_assert_float_eq_tol(scene.points[i * 4 + 1], (float)p[1], 1e-4f);
        ck_assert_float_eq(scene.points[i * 4 + 2], job.scene.points[i * 4 + 2]);
    }
    reyes_scene_free(&scene);
    reyes_job_free(&job);
    reyes_cli_free(&cli);
}
END_TEST

static size_t read_file(const char *path, unsigned char **data)
{
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot read %s", path);
    *data = malloc(1 << 20);
    size_t n = fread(*data, 1, 1 << 20, f);
    fclose(f);
    return n;
}

/* Three frames of an orbit over two devices: each file holds the bytes of
 * that frame rendered on its own. */
START_TEST(test_farm_frames_identical)
{
    char dir[] = "/tmp/reyes-farm-XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    char output[64];
    snprintf(output, sizeof output, "%s/orbit.png", dir);
    char *argv[] = { "reyes-render", "--frames", "3", "--orbit", "90", "--size", "64x48", "-o", output };
    reyes_cli cli;
    reyes_job job;
    make_job(&job, &cli, 9, argv);
    unsigned count;
    reyes_pool pool;
    reyes_farm_worker workers[PERMA_MAX_DEVICES];
    reyes_error error;
    ck_assert_msg(run_on_two(&job, &pool, workers, &count, &error) == REYES_OK, "%s", error.message);
    reyes_pool_free(&pool);
    for (unsigned f = 0; f < 3; ++f) {
        reyes_scene scene;
        reyes_camera camera;
        reyes_image image;
        ck_assert_int_eq(reyes_job_frame(&job, f, &scene, &camera, &error), REYES_OK);
        reyes_test_render(reyes_test_renderer(0), &scene, &camera, &job.options, &image, NULL);
        char farm_path[128], alone_path[128];
        reyes_job_frame_path(&job, f, farm_path, sizeof farm_path);
        snprintf(alone_path, sizeof alone_path, "%s/alone.png", dir);
        ck_assert_int_eq(reyes_write_png(alone_path, &image, &error), REYES_OK);
        unsigned char *a, *b;
        size_t na = read_file(farm_path, &a), nb = read_file(alone_path, &b);
        ck_assert_uint_eq(na, nb);
        ck_assert_mem_eq(a, b, na);
        free(a);
        free(b);
        unlink(farm_path);
        unlink(alone_path);
        reyes_image_free(&image);
        reyes_scene_free(&scene);
    }
    rmdir(dir);
    reyes_job_free(&job);
    reyes_cli_free(&cli);
}
END_TEST

/* Frames that cannot be written: the farm stops with the first failure,
 * naming the device, the frame and the file. */
START_TEST(test_farm_failure_names_device)
{
    char *argv[] = { "reyes-render", "--frames", "6", "--size", "32x32", "-o", "/nonexistent/dir/f.png" };
    reyes_cli cli;
    reyes_job job;
    make_job(&job, &cli, 7, argv);
    unsigned count;
    reyes_pool pool;
    reyes_farm_worker workers[PERMA_MAX_DEVICES];
    reyes_error error;
    ck_assert_int_eq(run_on_two(&job, &pool, workers, &count, &error), REYES_ERR_IO);
    ck_assert_msg(strncmp(error.message, "device 0:0", 10) == 0, "%s", error.message);
    ck_assert_msg(strstr(error.message, ": frame ") != NULL, "%s", error.message);
    ck_assert_msg(strstr(error.message, "/nonexistent/dir/f-000") != NULL, "%s", error.message);
    /* Each device renders at most the frame it held when the first failed. */
    ck_assert_uint_le(pool.next, count);
    reyes_pool_free(&pool);
    reyes_job_free(&job);
    reyes_cli_free(&cli);
}
END_TEST

/* A result whose item or rectangle is not the job's (a rank started with
 * another size, before the ranks compared their jobs) is refused with a
 * message, and nothing is copied; rank 0 used to write past its image. */
START_TEST(test_pool_refuses_foreign_tiles)
{
    char *argv[] = { "reyes-render", "--size", "64x48", "--bucket", "32x32" };
    reyes_cli cli;
    reyes_job job;
    make_job(&job, &cli, 5, argv);
    ck_assert_uint_eq(job.items, 4);
    reyes_pool pool;
    reyes_error error;
    ck_assert_int_eq(reyes_pool_init(&pool, &job, &error), REYES_OK);
    size_t big = (size_t)1024 * 1024;
    uint8_t *rgb = malloc(big * 3), *coverage = malloc(big);
    ck_assert(rgb && coverage);
    memset(rgb, 0xff, big * 3);
    memset(coverage, 0xff, big);
    const unsigned huge[4] = { 0, 0, 1024, 1024 }, shifted[4] = { 32, 0, 64, 32 }, own[4] = { 0, 0, 32, 32 },
                   last[4] = { 32, 32, 64, 48 };
    ck_assert_int_eq(reyes_pool_deliver(&pool, 0, huge, rgb, coverage, 1.0, &error), REYES_ERR_RUNTIME);
    ck_assert_str_eq(error.message, "bucket 0 came with pixels [0,1024)x[0,1024), not its [0,32)x[0,32)");
    ck_assert_int_eq(reyes_pool_deliver(&pool, 0, shifted, rgb, coverage, 1.0, &error), REYES_ERR_RUNTIME);
    ck_assert_int_eq(reyes_pool_deliver(&pool, 4, own, rgb, coverage, 1.0, &error), REYES_ERR_RUNTIME);
    ck_assert_str_eq(error.message, "a result for bucket 4, which the job does not have (4 buckets)");
    for (size_t k = 0; k < (size_t)64 * 48; ++k)
        ck_assert_uint_eq(pool.image.coverage[k], 0);
    ck_assert_uint_eq(pool.delivered, 0);
    /* Its own rectangle is taken: the last bucket is cut by the image. */
    ck_assert_int_eq(reyes_pool_deliver(&pool, 3, last, rgb, coverage, 1.0, &error), REYES_OK);
    ck_assert_uint_eq(pool.delivered, 1);
    ck_assert_uint_eq(pool.image.coverage[47 * 64 + 63], 0xff);
    ck_assert_uint_eq(pool.image.coverage[31 * 64 + 63], 0);
    reyes_pool_free(&pool);
    reyes_job_free(&job);
    reyes_cli_free(&cli);
    /* A frame must be the whole frame (no file is written otherwise). */
    char *frames[] = { "reyes-render", "--size", "16x8", "--frames", "2", "-o", "/nonexistent/f.png" };
    make_job(&job, &cli, 7, frames);
    ck_assert_int_eq(reyes_pool_init(&pool, &job, &error), REYES_OK);
    const unsigned wide[4] = { 0, 0, 32, 8 };
    ck_assert_int_eq(reyes_pool_deliver(&pool, 1, wide, rgb, coverage, 1.0, &error), REYES_ERR_RUNTIME);
    ck_assert_str_eq(error.message, "frame 2 came with pixels [0,32)x[0,8), not its [0,16)x[0,8)");
    reyes_pool_free(&pool);
    reyes_job_free(&job);
    reyes_cli_free(&cli);
    free(rgb);
    free(coverage);
}
END_TEST

int main(void)
{
    Suite *suite = suite_create("reyes_farm");
    TCase *tc = tcase_create("farm");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_frame_paths);
    tcase_add_test(tc, test_pool_refuses_foreign_tiles);
    tcase_add_test(tc, test_frame_orbit_and_motion);
    tcase_add_test(tc, test_bucket_source_subset);
    tcase_add_test(tc, test_farm_buckets_identical);
    tcase_add_test(tc, test_farm_frames_identical);
    tcase_add_test(tc, test_farm_failure_names_device);
    suite_add_tcase(suite, tc);
    return reyes_test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
