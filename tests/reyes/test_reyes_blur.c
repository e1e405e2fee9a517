/* Motion blur and depth of field under the three sampling algorithms
 * (simple, interleaved and bbox UVT): zero motion and aperture change
 * nothing; a moving square smears by its motion; a lens keeps the focus
 * plane sharp and blurs the rest; each algorithm gives its samples the
 * times it promises (simple: the same N in every pixel; interleaved: per
 * pixel of a K x K tile; bbox: a pattern of period 64); time strata hold;
 * images do not depend on the schedule. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_blur_tuples.h"
#include "reyes_test_util.h"

#define W 128
#define H 96
#define ALGORITHMS 3 /* loop tests run once per REYES_BLUR_* (_i) */

/* Add a flat patch [x0,x1] x [y0,y1] at height z. */
static void add_rectangle(reyes_scene *scene, float x0, float x1, float y0, float y1, float z,
                          uint32_t rgba)
{
    reyes_error error;
    float cp[4][4][3];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            cp[r][c][0] = x0 + (x1 - x0) * (float)c / 3.0f;
            cp[r][c][1] = y0 + (y1 - y0) * (float)r / 3.0f;
            cp[r][c][2] = z;
        }
    ck_assert_int_eq(reyes_scene_add_patch(scene, cp, rgba, &error), REYES_OK);
}

/* A square z = 0 over [-0.6,0.6]^2, seen from straight above at distance 4. */
static void square_scene(reyes_scene *scene)
{
    reyes_scene_init(scene);
    add_rectangle(scene, -0.6f, 0.6f, -0.6f, 0.6f, 0.0f, REYES_RGBA(255, 255, 255));
}

static const reyes_camera top = { .eye = {0.0f, 0.0f, 4.0f}, .at = {0.0f, 0.0f, 0.0f}, .fov_deg = 40 };

/* Pixel column of world point (world_x, 0, 0) in a width x height image. */
static float pixel_x_at(unsigned width, unsigned height, float world_x)
{
    float m[16], px, py, depth;
    reyes_error error;
    ck_assert_int_eq(reyes_camera_matrix(&top, (float)width / (float)height, 1e-3f, m, &error), REYES_OK);
    const float x[3] = {world_x, 0.0f, 0.0f};
    ck_assert(reyes_camera_project(m, width, height, x, &px, &py, &depth));
    return px;
}

static float pixel_x(float world_x)
{
    return pixel_x_at(W, H, world_x);
}

static void options(reyes_options *o, unsigned algo)
{
    reyes_options_init(o);
    o->width = W;
    o->height = H;
    o->spp = 16;
    o->blur_algo = algo;
}

static const char *algo_name(unsigned algo)
{
    return reyes_blur_algo_name(algo);
}

START_TEST(test_zero_motion_and_aperture_identical)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 96, 72);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 96;
    o.height = 72;
    reyes_image plain, zero;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &plain, NULL);
    o.focus = 3.0f;
    o.time_samples = 2;
    o.blur_algo = (unsigned)_i;
    o.blur_tile = 2;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &zero, NULL);
    reyes_test_expect_same_image(&plain, &zero, "zero motion and aperture");
    reyes_image_free(&zero);
    /* A rotation by 0 about some axis, on a renderer made for per-vertex
     * motion (its larger items) and on the plain one. */
    o.motion_axis[0] = 0.3f;
    o.motion_axis[1] = -1.0f;
    for (int moving = 0; moving < 2; ++moving) {
        reyes_renderer *r = moving ? reyes_test_moving_renderer(0) : reyes_test_renderer(0);
        reyes_test_render(r, &scene, &camera, &o, &zero, NULL);
        reyes_test_expect_same_image(&plain, &zero, moving ? "rotation by 0, moving renderer" : "rotation by 0");
        reyes_image_free(&zero);
    }
    reyes_image_free(&plain);
    reyes_scene_free(&scene);
}
END_TEST

/* The square moves by 0.5 along x: along the middle row coverage starts at
 * its left edge at time 0 and ends at its right edge at time 1 (within a
 * pixel or two: the very ends are covered only at the shutter's ends),
 * keeps the square's width with its centroid moved by half the motion,
 * rises linearly over the first motion length (about half covered
 * on average), and is full where it is covered all the time. */
START_TEST(test_moving_square_blur_extent)
{
    reyes_scene scene;
    square_scene(&scene);
    reyes_options o;
    options(&o, (unsigned)_i);
    o.motion[0] = 0.5f;
    reyes_image image;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &image, NULL);
    printf("%s: ", algo_name(o.blur_algo));
    float left = pixel_x(-0.6f), right = pixel_x(0.6f), shift = pixel_x(0.5f) - pixel_x(0.0f);
    const uint8_t *row = image.coverage + (size_t)(H / 2) * W;
    int first = -1, last = -1;
    for (int x = 0; x < W; ++x) {
        if (row[x]) {
            first = first < 0 ? x : first;
            last = x;
        }
    }
    printf("moving square: covered columns %d..%d, expected %.1f..%.1f (motion %.1f px)\n", first,
           last, (double)left, (double)(right + shift), (double)shift);
    ck_assert(fabsf((float)first - left) <= 1.5f);
    ck_assert(fabsf((float)last + 1.0f - (right + shift)) <= 2.0f);
    /* Coverage is conserved and its centroid moves by half the motion. */
    double sum = 0.0, moment = 0.0;
    for (int x = 0; x < W; ++x) {
        sum += row[x];
        moment += row[x] * (x + 0.5);
    }
    double width = sum / o.spp, centroid = moment / sum;
    printf("  coverage width %.2f px (square %.2f), centroid %.2f (expected %.2f)\n", width,
           (double)(right - left), centroid, 0.5 * (double)(left + right + shift));
    ck_assert(fabs(width - (double)(right - left)) < 0.5);
    ck_assert(fabs(centroid - 0.5 * (double)(left + right + shift)) < 0.5);
    double ramp = 0.0;
    int ramp_pixels = 0;
    for (int x = (int)ceilf(left) + 1; x + 1 < (int)(left + shift); ++x, ++ramp_pixels)
        ramp += row[x];
    ramp /= (double)ramp_pixels * o.spp;
    ck_assert_msg(ramp > 0.35 && ramp < 0.65, "mean coverage over the ramp %g", ramp);
    for (int x = (int)ceilf(left + shift) + 1; x + 1 < (int)right; ++x)
        ck_assert_uint_eq(row[x], o.spp);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* Partially covered pixels: few for a sharp square (its outline), many
 * when a lens of radius 0.2 focuses at half its distance; focused on the
 * square itself the outline stays as sharp as without a lens. */
static unsigned partial_pixels(const reyes_image *image, unsigned spp)
{
    unsigned partial = 0;
    for (size_t k = 0; k < (size_t)image->width * image->height; ++k)
        partial += image->coverage[k] > 0 && image->coverage[k] < spp;
    return partial;
}

START_TEST(test_lens_focus)
{
    reyes_scene scene;
    square_scene(&scene);
    reyes_options o;
    options(&o, (unsigned)_i);
    reyes_image sharp, focused, blurred;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &sharp, NULL);
    o.aperture = 0.2f;
    o.focus = 4.0f;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &focused, NULL);
    o.focus = 2.0f;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &blurred, NULL);
    unsigned p_sharp = partial_pixels(&sharp, o.spp), p_focused = partial_pixels(&focused, o.spp);
    unsigned p_blurred = partial_pixels(&blurred, o.spp);
    printf("%s: partially covered pixels: no lens %u, in focus %u, out of focus %u\n",
           algo_name(o.blur_algo), p_sharp, p_focused, p_blurred);
    ck_assert_uint_le(p_focused, p_sharp + p_sharp / 4);
    ck_assert_uint_gt(p_blurred, 3 * p_sharp);
    /* The covered area is about the same: defocus spreads, it does not add. */
    double a_sharp = (double)reyes_test_covered_samples(&sharp);
    double a_blurred = (double)reyes_test_covered_samples(&blurred);
    ck_assert_msg(fabs(a_blurred - a_sharp) < 0.05 * a_sharp, "area %g vs %g", a_blurred, a_sharp);
    reyes_image_free(&sharp);
    reyes_image_free(&focused);
    reyes_image_free(&blurred);
    reyes_scene_free(&scene);
}
END_TEST

/* The tuple pool: tuple i's time lies in stratum (i mod spp) mod strata,
 * lens positions lie on the unit disk and spread over it, and a smaller
 * pool is a prefix of a larger one (what makes interleaved with 1 x 1
 * tiles simple UVT). */
START_TEST(test_tuple_pool)
{
    const unsigned spp = 16, strata = 4;
    ck_assert_uint_eq(reyes_blur_pool_size(REYES_BLUR_SIMPLE, 4, spp), spp);
    ck_assert_uint_eq(reyes_blur_pool_size(REYES_BLUR_INTERLEAVED, 3, spp), 9 * spp);
    ck_assert_uint_eq(reyes_blur_pool_size(REYES_BLUR_BBOX, 4, spp), 64 * 64 * spp);
    size_t count = reyes_blur_pool_size(REYES_BLUR_INTERLEAVED, 4, spp);
    reyes_blur_tuple *pool = malloc(count * sizeof *pool), prefix[16];
    ck_assert_ptr_nonnull(pool);
    reyes_blur_fill_tuples(pool, count, spp, strata);
    reyes_blur_fill_tuples(prefix, spp, spp, strata);
    ck_assert_mem_eq(pool, prefix, sizeof prefix);
    double sum_x = 0.0, sum_y = 0.0, sum_r2 = 0.0;
    for (size_t i = 0; i < count; ++i) {
        float stratum = (float)((i % spp) % strata);
        ck_assert_msg(pool[i].t >= stratum / strata && pool[i].t <= (stratum + 1.0f) / strata,
                      "tuple %zu: t %g outside stratum %g", i, (double)pool[i].t, (double)stratum);
        float r2 = pool[i].lens_x * pool[i].lens_x + pool[i].lens_y * pool[i].lens_y;
        ck_assert_float_le(r2, 1.0f + 1e-6f);
        sum_x += pool[i].lens_x;
        sum_y += pool[i].lens_y;
        sum_r2 += r2;
    }
    /* Uniform on the disk: mean 0, mean squared radius 1/2. */
    ck_assert_msg(fabs(sum_x / count) < 0.1 && fabs(sum_y / count) < 0.1, "lens mean %g, %g",
                  sum_x / count, sum_y / count);
    ck_assert_msg(fabs(sum_r2 / count - 0.5) < 0.05, "mean squared radius %g", sum_r2 / count);
    free(pool);
}
END_TEST

/* A strip 0.2 wide moving by 4 along x, 4 samples per pixel in 4 time
 * strata.  Simple UVT gives sample s of every pixel the same time, so
 * the union of covered columns over all rows is 4 separate copies of the
 * strip; interleaved and bbox give each pixel (of a tile, of the 64 x 64
 * pattern) its own times, so the copies fill the whole smear. */
START_TEST(test_moving_strip_copies)
{
    const unsigned width = 192, height = 96;
    reyes_scene scene;
    reyes_scene_init(&scene);
    add_rectangle(&scene, -2.5f, -2.3f, -0.6f, 0.6f, 0.0f, REYES_RGBA(255, 255, 255));
    reyes_options o;
    options(&o, (unsigned)_i);
    o.width = width;
    o.height = height;
    o.spp = 4;
    o.motion[0] = 4.0f;
    reyes_image image;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &image, NULL);
    uint8_t column[192] = {0};
    for (unsigned y = 0; y < height; ++y)
        for (unsigned x = 0; x < width; ++x)
            column[x] |= image.coverage[y * width + x] > 0;
    unsigned covered = 0, runs = 0;
    for (unsigned x = 0; x < width; ++x) {
        covered += column[x];
        runs += column[x] && (x == 0 || !column[x - 1]);
    }
    float strip = pixel_x_at(width, height, -2.3f) - pixel_x_at(width, height, -2.5f);
    float smear = pixel_x_at(width, height, 1.7f) - pixel_x_at(width, height, -2.5f);
    printf("%s: moving strip (%.1f px, smear %.1f px): %u covered columns in %u runs\n",
           algo_name(o.blur_algo), (double)strip, (double)smear, covered, runs);
    if (o.blur_algo == REYES_BLUR_SIMPLE) {
        ck_assert_uint_eq(runs, o.spp);
        ck_assert_float_le((float)covered, (float)o.spp * (strip + 2.0f));
    } else {
        ck_assert_float_ge((float)covered, 0.8f * smear);
    }
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* The time race: a plane filling the view at depth 4 moves towards the
 * eye and crosses the near plane exactly at t = 0.5, after which its
 * samples see nothing.  One quad (grid 2, no splitting), so the render is
 * cheap even though every quad covers the whole image.  A pixel's
 * coverage is then the number of its samples with t < 0.5, whatever their
 * position in the pixel or on the lens: a direct view of each pixel's
 * sample times. */
#define RACE_W 192
#define RACE_H 128

static void race_render(unsigned algo, unsigned time_samples, unsigned tile, unsigned permutations,
                        reyes_image *image)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    add_rectangle(&scene, -6.0f, 6.0f, -6.0f, 6.0f, 0.0f, REYES_RGBA(255, 255, 255));
    reyes_options o;
    reyes_options_init(&o);
    o.width = RACE_W;
    o.height = RACE_H;
    o.spp = 4;
    o.grid = 2;
    o.bound_px = 1e6f;
    o.aperture = 0.1f;   /* defocus moves samples sideways only: coverage stays */
    o.focus = 3.0f;
    o.motion[2] = 2.0f * (4.0f - reyes_near_plane(&scene, &top));
    o.time_samples = time_samples;
    o.blur_algo = algo;
    o.blur_tile = tile;
    o.blur_permutations = permutations;
    reyes_test_render_once(&scene, &top, &o, image, NULL);
    reyes_scene_free(&scene);
}

static unsigned coverage_at(const reyes_image *image, unsigned x, unsigned y)
{
    return image->coverage[y * image->width + x];
}

/* Pixels whose coverage differs from the pixel (dx, dy) further on. */
static unsigned differ_by(const reyes_image *image, unsigned dx, unsigned dy)
{
    unsigned differ = 0;
    for (unsigned y = 0; y + dy < image->height; ++y)
        for (unsigned x = 0; x + dx < image->width; ++x)
            differ += coverage_at(image, x, y) != coverage_at(image, x + dx, y + dy);
    return differ;
}

/* Coverage histogram of the k x k tile at (tx, ty). */
static void tile_histogram(const reyes_image *image, unsigned tx, unsigned ty, unsigned k,
                           unsigned histogram[5])
{
    for (int c = 0; c < 5; ++c)
        histogram[c] = 0;
    for (unsigned y = ty * k; y < ty * k + k; ++y)
        for (unsigned x = tx * k; x < tx * k + k; ++x)
            ++histogram[coverage_at(image, x, y)];
}

/* Simple: the same four times in every pixel, so one coverage everywhere;
 * interleaved and bbox vary from pixel to pixel. */
START_TEST(test_time_pattern_simple)
{
    reyes_image simple, interleaved, bbox;
    race_render(REYES_BLUR_SIMPLE, 1, 4, 8, &simple);
    race_render(REYES_BLUR_INTERLEAVED, 1, 4, 8, &interleaved);
    race_render(REYES_BLUR_BBOX, 1, 4, 8, &bbox);
    unsigned first = coverage_at(&simple, 0, 0);
    for (unsigned y = 0; y < RACE_H; ++y)
        for (unsigned x = 0; x < RACE_W; ++x)
            ck_assert_uint_eq(coverage_at(&simple, x, y), first);
    printf("time race: simple %u samples before t = 0.5 in every pixel; pixels differing from "
           "their right neighbour: interleaved %u, bbox %u\n", first, differ_by(&interleaved, 1, 0),
           differ_by(&bbox, 1, 0));
    ck_assert_uint_gt(differ_by(&interleaved, 1, 0), RACE_W * RACE_H / 4);
    ck_assert_uint_gt(differ_by(&bbox, 1, 0), RACE_W * RACE_H / 4);
    reyes_image_free(&simple);
    reyes_image_free(&interleaved);
    reyes_image_free(&bbox);
}
END_TEST

/* Interleaved: every K x K tile uses each tuple block exactly once (a
 * permutation), so all tiles hold the same coverages, in an order that
 * differs between pixels of a tile and, with P > 1, between tiles; with
 * P = 1 the image repeats every K pixels. */
START_TEST(test_time_pattern_interleaved)
{
    const unsigned k = 4;
    reyes_image permuted, fixed;
    race_render(REYES_BLUR_INTERLEAVED, 1, k, 8, &permuted);
    race_render(REYES_BLUR_INTERLEAVED, 1, k, 1, &fixed);
    unsigned reference[5], histogram[5], distinct = 0;
    tile_histogram(&permuted, 0, 0, k, reference);
    for (int c = 0; c < 5; ++c)
        distinct += reference[c] > 0;
    ck_assert_uint_gt(distinct, 1);
    for (unsigned ty = 0; ty < RACE_H / k; ++ty) {
        for (unsigned tx = 0; tx < RACE_W / k; ++tx) {
            tile_histogram(&permuted, tx, ty, k, histogram);
            ck_assert_mem_eq(histogram, reference, sizeof histogram);
            tile_histogram(&fixed, tx, ty, k, histogram);
            ck_assert_mem_eq(histogram, reference, sizeof histogram);
        }
    }
    ck_assert_uint_eq(differ_by(&fixed, k, 0), 0);
    ck_assert_uint_eq(differ_by(&fixed, 0, k), 0);
    printf("interleaved: %u coverage values per tile; pixels differing from the next tile's: "
           "P = 8: %u, P = 1: 0\n", distinct, differ_by(&permuted, k, 0));
    ck_assert_uint_gt(differ_by(&permuted, k, 0), RACE_W * RACE_H / 8);
    reyes_image_free(&permuted);
    reyes_image_free(&fixed);
}
END_TEST

/* bbox: the pattern repeats every 64 pixels across and down, not every 32. */
START_TEST(test_time_pattern_bbox_period)
{
    reyes_image image;
    race_render(REYES_BLUR_BBOX, 1, 4, 8, &image);
    ck_assert_uint_eq(differ_by(&image, REYES_BLUR_BBOX_PERIOD, 0), 0);
    ck_assert_uint_eq(differ_by(&image, 0, REYES_BLUR_BBOX_PERIOD), 0);
    printf("bbox: pixels differing from the pixel 32 to the right: %u, 64 to the right or down: 0\n",
           differ_by(&image, 32, 0));
    ck_assert_uint_gt(differ_by(&image, 32, 0), RACE_W * RACE_H / 8);
    reyes_image_free(&image);
}
END_TEST

/* Time strata hold under every algorithm: with 4 (or 2) strata exactly two
 * of a pixel's 4 samples fall before t = 0.5, in every pixel. */
START_TEST(test_time_strata)
{
    const unsigned strata[2] = {4, 2};
    for (int k = 0; k < 2; ++k) {
        reyes_image image;
        race_render((unsigned)_i, strata[k], 4, 8, &image);
        for (size_t p = 0; p < (size_t)RACE_W * RACE_H; ++p)
            ck_assert_msg(image.coverage[p] == 2, "%s, %u strata: pixel %zu has %u samples before "
                          "t = 0.5", algo_name((unsigned)_i), strata[k], p, image.coverage[p]);
        reyes_image_free(&image);
    }
}
END_TEST

/* Moving, defocused square: interleaved with 1 x 1 tiles and one
 * permutation is simple UVT, byte for byte. */
START_TEST(test_interleaved_k1_is_simple)
{
    reyes_scene scene;
    square_scene(&scene);
    reyes_options o;
    options(&o, REYES_BLUR_SIMPLE);
    o.spp = 8;
    o.motion[0] = 0.3f;
    o.motion[1] = 0.1f;
    o.aperture = 0.1f;
    o.focus = 3.0f;
    reyes_image simple, interleaved;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &simple, NULL);
    o.blur_algo = REYES_BLUR_INTERLEAVED;
    o.blur_tile = 1;
    o.blur_permutations = 1;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &interleaved, NULL);
    reyes_test_expect_same_image(&simple, &interleaved, "interleaved with 1x1 tiles and one permutation");
    /* ... and the default tiles do change it. */
    reyes_image_free(&interleaved);
    o.blur_tile = 4;
    o.blur_permutations = 8;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &interleaved, NULL);
    ck_assert(memcmp(simple.coverage, interleaved.coverage, (size_t)W * H) != 0);
    reyes_image_free(&simple);
    reyes_image_free(&interleaved);
    reyes_scene_free(&scene);
}
END_TEST

/* A bar of half-width BAR_H from the target (the origin) along +x to
 * BAR_L, seen from `top` (straight down the rotation axis z: world x right,
 * world y up on screen) and rotated by 90 degrees about z over the
 * shutter.  Each vertex moves linearly from p to R p, so the bar sweeps
 * the hull of its start and end positions: the quarter disk's triangle
 * (0,0), (L,0), (0,L) grown by the half-width, hexagon bar_hull. */
#define BAR_L 1.2f
#define BAR_H 0.09f
static const float bar_hull[6][2] = { {0.0f, -BAR_H}, {BAR_L, -BAR_H}, {BAR_L, BAR_H},
                                      {BAR_H, BAR_L}, {-BAR_H, BAR_L}, {-BAR_H, 0.0f} };

/* Distance from (x, y) to convex polygon poly (counter-clockwise), 0 inside. */
static float polygon_distance(const float poly[][2], int n, float x, float y)
{
    int inside = 1;
    float nearest = INFINITY;
    for (int k = 0; k < n; ++k) {
        const float *a = poly[k], *b = poly[(k + 1) % n];
        float ex = b[0] - a[0], ey = b[1] - a[1], px = x - a[0], py = y - a[1];
        inside &= ex * py - ey * px >= 0.0f;
        float t = fminf(fmaxf((ex * px + ey * py) / (ex * ex + ey * ey), 0.0f), 1.0f);
        nearest = fminf(nearest, hypotf(px - t * ex, py - t * ey));
    }
    return inside ? 0.0f : nearest;
}

/* World (x, y) of pixel (px, py)'s center on z = 0 seen from `top`;
 * *scale: pixels per world unit. */
static void bar_world(unsigned px, unsigned py, unsigned size, float *x, float *y, float *scale)
{
    *scale = pixel_x_at(size, size, 1.0f) - pixel_x_at(size, size, 0.0f);
    *x = ((float)px + 0.5f - 0.5f * (float)size) / *scale;
    *y = (0.5f * (float)size - ((float)py + 0.5f)) / *scale;
}

START_TEST(test_rotating_bar_sweep)
{
    const unsigned size = 96;
    reyes_scene scene;
    reyes_scene_init(&scene);
    add_rectangle(&scene, 0.0f, BAR_L, -BAR_H, BAR_H, 0.0f, REYES_RGBA(255, 255, 255));
    reyes_options o;
    options(&o, (unsigned)_i);
    o.width = o.height = size;
    o.spp = 32;
    o.motion_angle_deg = 90.0f;
    reyes_image image;
    reyes_test_render(reyes_test_moving_renderer(0), &scene, &top, &o, &image, NULL);
    unsigned outside = 0, inner = 0, inner_covered = 0;
    for (unsigned py = 0; py < size; ++py) {
        for (unsigned px = 0; px < size; ++px) {
            float x, y, scale;
            bar_world(px, py, size, &x, &y, &scale);
            int covered = image.coverage[py * size + px] > 0;
            /* Covered: within 1.5 px of the swept hull (a pixel's samples
             * spread over it), so in the 90 degree sector and the radius. */
            if (covered && polygon_distance(bar_hull, 6, x, y) * scale > 1.5f)
                ++outside;
            /* The triangle's pixels a pixel away from its edges. */
            int in_triangle = x > 1.0f / scale && y > 1.0f / scale && x + y < BAR_L - 1.5f / scale;
            inner += (unsigned)in_triangle;
            inner_covered += (unsigned)(in_triangle && covered);
        }
    }
    printf("%s: rotating bar covers %u of %u pixels of its swept triangle, %u pixels outside\n",
           algo_name(o.blur_algo), inner_covered, inner, outside);
    ck_assert_uint_eq(outside, 0);
    ck_assert_uint_gt(inner, 500);
    ck_assert_uint_ge(inner_covered * 10, inner * 8);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* Render the square at 64x48, 4 spp, under two very different schedules
 * (megakernel with stealing on 2 groups, kernel-per-procedure on 1) and
 * expect the same, non-empty image. */
static void expect_schedules_identical(reyes_options o)
{
    reyes_scene scene;
    square_scene(&scene);
    o.width = 64;
    o.height = 48;
    o.spp = 4;
    reyes_image a, b;
    reyes_test_apply_schedule("megakernel/stealing/random", 2, &o);
    ck_assert_int_eq(o.schedule.strategy, PERMA_STRATEGY_STEALING);
    reyes_test_render_once(&scene, &top, &o, &a, NULL);
    reyes_test_apply_schedule("kernel-per-procedure", 1, &o);
    ck_assert_int_eq(o.schedule.technique, PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE);
    reyes_test_render_once(&scene, &top, &o, &b, NULL);
    ck_assert_uint_gt(reyes_test_covered_samples(&a), 0);
    reyes_test_expect_same_image(&a, &b, "kernel-per-procedure against stealing");
    reyes_image_free(&a);
    reyes_image_free(&b);
    reyes_scene_free(&scene);
}

/* The same image under two schedules, per algorithm: moving and
 * defocused. */
START_TEST(test_schedules_identical)
{
    reyes_options o;
    options(&o, (unsigned)_i);
    o.motion[0] = 0.4f;
    o.aperture = 0.1f;
    o.focus = 3.0f;
    expect_schedules_identical(o);
}
END_TEST

/* A renderer made without a rotation (64-byte micropolygons, no motion
 * per vertex) refuses to render one, saying why. */
START_TEST(test_rotation_needs_moving_renderer)
{
    reyes_scene scene;
    square_scene(&scene);
    reyes_options o;
    options(&o, REYES_BLUR_SIMPLE);
    o.motion_angle_deg = 10.0f;
    reyes_image image;
    reyes_error error;
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &scene, &top, &o, &image, NULL, &error),
                     REYES_ERR_ARGUMENT);
    ck_assert_msg(strstr(error.message, "needs a renderer created with one") != NULL, "%s", error.message);
    reyes_scene_free(&scene);
}
END_TEST

/* The same with a rotation (per-vertex motion) and a translation. */
START_TEST(test_rotation_schedules_identical)
{
    reyes_options o;
    options(&o, (unsigned)_i);
    o.motion[0] = 0.2f;
    o.motion_axis[0] = 0.2f;
    o.motion_angle_deg = 40.0f;
    expect_schedules_identical(o);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_blur");
    TCase *tc = tcase_create("blur");
    tcase_set_timeout(tc, 300);
    tcase_add_loop_test(tc, test_zero_motion_and_aperture_identical, 0, ALGORITHMS);
    tcase_add_loop_test(tc, test_moving_square_blur_extent, 0, ALGORITHMS);
    tcase_add_loop_test(tc, test_lens_focus, 0, ALGORITHMS);
    tcase_add_test(tc, test_tuple_pool);
    tcase_add_loop_test(tc, test_moving_strip_copies, 0, ALGORITHMS);
    tcase_add_test(tc, test_time_pattern_simple);
    tcase_add_test(tc, test_time_pattern_interleaved);
    tcase_add_test(tc, test_time_pattern_bbox_period);
    tcase_add_loop_test(tc, test_time_strata, 0, ALGORITHMS);
    tcase_add_test(tc, test_interleaved_k1_is_simple);
    tcase_add_loop_test(tc, test_schedules_identical, 0, ALGORITHMS);
    tcase_add_loop_test(tc, test_rotating_bar_sweep, 0, ALGORITHMS);
    tcase_add_loop_test(tc, test_rotation_schedules_identical, 0, ALGORITHMS);
    tcase_add_test(tc, test_rotation_needs_moving_renderer);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
