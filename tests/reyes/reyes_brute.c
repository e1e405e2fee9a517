/*
 * The brute-force reference (reyes_brute.h): uniform tessellation, exact
 * per-sample shading.  Written for clarity, in double precision where
 * geometry is decided, and independent of the pipeline's code except for
 * the camera (reyes_camera_matrix, reyes_near_plane), the sample
 * positions and the look (light and weights), which define the image.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_brute.h"
#include "reyes_look.h"

/* ---- The renderer's sample positions (reyes_sample.cl) ---- */

/* Sample s of pixel (px, py): stratified on a columns x rows lattice with
 * a hashed offset in its cell, computed in float as the device does. */
static void sample_position(unsigned px, unsigned py, unsigned s, unsigned spp, float *x, float *y)
{
    unsigned columns = (unsigned)ceilf(sqrtf((float)spp)), rows = (spp + columns - 1) / columns;
    uint32_t h = reyes_hash32(px * 0x9e3779b9u ^ reyes_hash32(py * 0x85ebca6bu ^ reyes_hash32(s)));
    float jx = (float)(h & 0xffffu) * (1.0f / 65536.0f), jy = (float)(h >> 16) * (1.0f / 65536.0f);
    *x = (float)px + ((float)(s % columns) + jx) / (float)columns;
    *y = (float)py + ((float)(s / columns) + jy) / (float)rows;
}

/* ---- Bicubic patches ---- */

static void bernstein(double t, double b[4], double d[4])
{
    double s = 1.0 - t;
    b[0] = s * s * s;
    b[1] = 3.0 * t * s * s;
    b[2] = 3.0 * t * t * s;
    b[3] = t * t * t;
    d[0] = -3.0 * s * s;
    d[1] = 3.0 * s * s - 6.0 * t * s;
    d[2] = 6.0 * t * s - 3.0 * t * t;
    d[3] = 3.0 * t * t;
}

/* Point and (unnormalised) normal of patch `points` (16 x xyzw) at (u,v). */
static void patch_eval(const float *points, double u, double v, double x[3], double n[3])
{
    double bu[4], du[4], bv[4], dv[4], tu[3] = {0, 0, 0}, tv[3] = {0, 0, 0};
    bernstein(u, bu, du);
    bernstein(v, bv, dv);
    x[0] = x[1] = x[2] = 0.0;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 3; ++k) {
                double p = points[(r * 4 + c) * 4 + k];
                x[k] += bv[r] * bu[c] * p;
                tu[k] += bv[r] * du[c] * p;
                tv[k] += dv[r] * bu[c] * p;
            }
    n[0] = tu[1] * tv[2] - tu[2] * tv[1];
    n[1] = tu[2] * tv[0] - tu[0] * tv[2];
    n[2] = tu[0] * tv[1] - tu[1] * tv[0];
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void normalize3(double a[3])
{
    double length = sqrt(dot3(a, a));
    if (length > 0.0)
        for (int k = 0; k < 3; ++k)
            a[k] /= length;
}

/* The renderer's look at surface point x with normal n seen from eye:
 * Lambert plus a Blinn-Phong highlight, two-sided, packed like
 * reyes_pack_rgba (rounded to nearest). */
static uint32_t shade(const double eye[3], const double x[3], const double n_in[3], uint32_t base)
{
    double view[3] = {eye[0] - x[0], eye[1] - x[1], eye[2] - x[2]}, n[3] = {n_in[0], n_in[1], n_in[2]};
    normalize3(view);
    if (dot3(n, n) > 0.0)
        normalize3(n);
    else
        memcpy(n, view, sizeof n);
    if (dot3(n, view) < 0.0)
        for (int k = 0; k < 3; ++k)
            n[k] = -n[k];
    float towards[3];
    reyes_light_direction(towards);
    double light[3] = {towards[0], towards[1], towards[2]};
    double lambert = fmax(dot3(n, light), 0.0);
    double half[3] = {light[0] + view[0], light[1] + view[1], light[2] + view[2]};
    normalize3(half);
    double cos_h = dot3(n, half);
    double highlight = lambert > 0.0 && cos_h > 0.0 ? pow(cos_h, REYES_SHININESS) : 0.0;
    uint32_t rgba = 255u << 24;
    for (int c = 0; c < 3; ++c) {
        double channel = (double)((base >> (8 * c)) & 255u) / 255.0;
        double value = channel * (REYES_AMBIENT + REYES_DIFFUSE * lambert) + REYES_SPECULAR * highlight;
        rgba |= (uint32_t)lrint(fmin(fmax(value, 0.0), 1.0) * 255.0) << (8 * c);
    }
    return rgba;
}

/* Where a patch edge collapses to a point (a pole) the normal vanishes:
 * take it a little inside, as the renderer does. */
static void safe_eval(const float *points, double u, double v, double x[3], double n[3])
{
    patch_eval(points, u, v, x, n);
    for (int step = 1; step <= 3 && dot3(n, n) < 1e-24; ++step) {
        double nudge = 1e-3 * step, ignored[3];
        patch_eval(points, u + (0.5 - u) * nudge, v + (0.5 - v) * nudge, ignored, n);
    }
}

/* ---- Rasterization ---- */

typedef struct vertex {
    double sx, sy, w;   /* pixels (y down), view depth */
    double u, v;
} vertex;

/* What the nearest surface of each sample is, before shading. */
typedef struct hit {
    float depth;
    uint32_t patch;
    float u, v;
} hit;

typedef struct raster {
    unsigned width, height, spp;
    const float *positions;  /* x, y per sample */
    hit *hits;
} raster;

/* Edge function of a->b at p with the end points in a canonical order,
 * so a sample on an edge two triangles share is inside at least one. */
static double edge_at(const vertex *a, const vertex *b, double px, double py)
{
    int swap = a->sx > b->sx || (a->sx == b->sx && a->sy > b->sy);
    const vertex *lo = swap ? b : a, *hi = swap ? a : b;
    double value = (hi->sx - lo->sx) * (py - lo->sy) - (hi->sy - lo->sy) * (px - lo->sx);
    return swap ? -value : value;
}

static void raster_triangle(raster *r, uint32_t patch, const vertex *a, const vertex *b, const vertex *c)
{
    double area = edge_at(a, b, c->sx, c->sy);
    if (area == 0.0)
        return;
    double lo_x = fmin(a->sx, fmin(b->sx, c->sx)), hi_x = fmax(a->sx, fmax(b->sx, c->sx));
    double lo_y = fmin(a->sy, fmin(b->sy, c->sy)), hi_y = fmax(a->sy, fmax(b->sy, c->sy));
    if (hi_x < 0.0 || hi_y < 0.0 || lo_x >= r->width || lo_y >= r->height)
        return;
    int x0 = (int)floor(fmax(lo_x, 0.0)), y0 = (int)floor(fmax(lo_y, 0.0));
    int x1 = (int)floor(fmin(hi_x, r->width - 1.0)), y1 = (int)floor(fmin(hi_y, r->height - 1.0));
    for (int py = y0; py <= y1; ++py)
        for (int px = x0; px <= x1; ++px)
            for (unsigned s = 0; s < r->spp; ++s) {
                size_t index = ((size_t)py * r->width + (size_t)px) * r->spp + s;
                double x = r->positions[2 * index], y = r->positions[2 * index + 1];
                double wa = edge_at(b, c, x, y), wb = edge_at(c, a, x, y), wc = edge_at(a, b, x, y);
                int inside = area > 0.0 ? (wa >= 0.0 && wb >= 0.0 && wc >= 0.0)
                                        : (wa <= 0.0 && wb <= 0.0 && wc <= 0.0);
                if (!inside)
                    continue;
                /* Perspective-correct: screen weights over depth. */
                double ka = wa / area / a->w, kb = wb / area / b->w, kc = wc / area / c->w;
                double sum = ka + kb + kc;
                float depth = (float)(1.0 / sum);
                hit *h = &r->hits[index];
                if (depth < h->depth || (depth == h->depth && patch < h->patch)) {
                    h->depth = depth;
                    h->patch = patch;
                    h->u = (float)((ka * a->u + kb * b->u + kc * c->u) / sum);
                    h->v = (float)((ka * a->v + kb * b->v + kc * c->v) / sum);
                }
            }
}

static void project(const float m[16], unsigned width, unsigned height, const double x[3], vertex *out)
{
    double clip[4];
    for (int row = 0; row < 4; ++row)
        clip[row] = m[row * 4] * x[0] + m[row * 4 + 1] * x[1] + m[row * 4 + 2] * x[2] + m[row * 4 + 3];
    out->w = clip[3];
    out->sx = (clip[0] / clip[3] * 0.5 + 0.5) * width;
    out->sy = (0.5 - clip[1] / clip[3] * 0.5) * height;
}

/* Quads per side for a patch so that each is at most half a pixel long
 * in space at the patch's nearest depth (the chords then miss the
 * surface, seen from any side, by at most a few thousandths of a pixel
 * where it curves over a pixel or more): the longest row or column of
 * its control net in world units times the pixels per world unit there.
 * The most when the net reaches the near plane. */
static unsigned adaptive_tessellation(const float *points, const float m[16], unsigned width, unsigned height,
                                      float near_w)
{
    double nearest = INFINITY, longest = 0.0;
    for (int k = 0; k < 16; ++k) {
        const float *x = points + 4 * k;
        double w = m[12] * x[0] + m[13] * x[1] + m[14] * x[2] + m[15];
        nearest = fmin(nearest, w);
    }
    if (!(nearest > near_w))
        return REYES_BRUTE_MAX_TESSELLATION;
    for (int line = 0; line < 4; ++line) {
        double row = 0.0, column = 0.0;
        for (int k = 0; k < 3; ++k) {
            const float *a = points + 4 * (line * 4 + k), *b = a + 4;
            const float *c = points + 4 * (k * 4 + line), *d = c + 16;
            row += sqrt((double)(b[0] - a[0]) * (b[0] - a[0]) + (double)(b[1] - a[1]) * (b[1] - a[1])
                        + (double)(b[2] - a[2]) * (b[2] - a[2]));
            column += sqrt((double)(d[0] - c[0]) * (d[0] - c[0]) + (double)(d[1] - c[1]) * (d[1] - c[1])
                           + (double)(d[2] - c[2]) * (d[2] - c[2]));
        }
        longest = fmax(longest, fmax(row, column));
    }
    double scale_x = 0.5 * width * sqrt((double)m[0] * m[0] + (double)m[1] * m[1] + (double)m[2] * m[2]);
    double scale_y = 0.5 * height * sqrt((double)m[4] * m[4] + (double)m[5] * m[5] + (double)m[6] * m[6]);
    double pixels = longest * fmax(scale_x, scale_y) / nearest;
    double quads = ceil(pixels / 0.5);
    return quads < 4.0 ? 4u : quads > REYES_BRUTE_MAX_TESSELLATION ? REYES_BRUTE_MAX_TESSELLATION : (unsigned)quads;
}

void reyes_brute_free(reyes_brute_image *image)
{
    if (!image)
        return;
    free(image->depth);
    free(image->rgba);
    free(image->rgb);
    free(image->coverage);
    free(image->facing);
    free(image->slant);
    free(image->patch);
    memset(image, 0, sizeof *image);
}

/* The converged image's sample positions: a side x side regular lattice
 * per pixel (0: the renderer's). */
static unsigned regular_side;

reyes_status reyes_brute_render_truth(const reyes_scene *scene, const reyes_camera *camera,
                                      const reyes_options *options, unsigned side, reyes_brute_image *out,
                                      reyes_error *error)
{
    if (side < 1 || side > 8)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "brute-force lattice side %u is not in 1..8", side);
    reyes_options o = *options;
    o.spp = side * side;
    regular_side = side;
    reyes_status status = reyes_brute_render(scene, camera, &o, 0, out, error);
    regular_side = 0;
    return status;
}

reyes_status reyes_brute_render(const reyes_scene *scene, const reyes_camera *camera,
                                const reyes_options *options, unsigned tessellation,
                                reyes_brute_image *out, reyes_error *error)
{
    memset(out, 0, sizeof *out);
    if (tessellation > 1024)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "brute-force tessellation %u is not in 0..1024",
                          tessellation);
    unsigned width = options->width, height = options->height, spp = options->spp;
    float m[16], near_w = reyes_near_plane(scene, camera);
    reyes_status status = reyes_camera_matrix(camera, (float)width / (float)height, near_w, m, error);
    if (status != REYES_OK)
        return status;
    int adaptive = tessellation == 0;
    size_t pixels = (size_t)width * height, samples = pixels * spp;
    size_t side = (adaptive ? REYES_BRUTE_MAX_TESSELLATION : tessellation) + 1;
    float *positions = malloc(samples * 2 * sizeof *positions);
    hit *hits = malloc(samples * sizeof *hits);
    vertex *grid = malloc(side * side * sizeof *grid);
    out->depth = malloc(samples * sizeof *out->depth);
    out->rgba = malloc(samples * sizeof *out->rgba);
    out->rgb = malloc(pixels * 3);
    out->coverage = malloc(pixels);
    out->facing = calloc(samples, 1);
    out->slant = calloc(samples, sizeof *out->slant);
    out->patch = malloc(samples * sizeof *out->patch);
    if (!out->facing || !out->slant || !out->patch || !positions || !hits || !grid || !out->depth || !out->rgba || !out->rgb || !out->coverage) {
        free(positions);
        free(hits);
        free(grid);
        reyes_brute_free(out);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a %ux%u brute-force reference",
                          width, height);
    }
    out->width = width;
    out->height = height;
    out->spp = spp;
    for (unsigned py = 0; py < height; ++py)
        for (unsigned px = 0; px < width; ++px)
            for (unsigned s = 0; s < spp; ++s) {
                size_t index = ((size_t)py * width + px) * spp + s;
                if (regular_side) {
                    positions[2 * index] = (float)px + ((float)(s % regular_side) + 0.5f) / (float)regular_side;
                    positions[2 * index + 1] = (float)py + ((float)(s / regular_side) + 0.5f) / (float)regular_side;
                } else {
                    sample_position(px, py, s, spp, &positions[2 * index], &positions[2 * index + 1]);
                }
                hits[index] = (hit){ .depth = INFINITY, .patch = UINT32_MAX };
            }
    raster r = { width, height, spp, positions, hits };
    for (size_t p = 0; p < scene->patch_count; ++p) {
        const float *points = scene->points + p * 64;
        if (adaptive) {
            tessellation = adaptive_tessellation(points, m, width, height, near_w);
            side = tessellation + 1;
        }
        for (size_t j = 0; j < side; ++j)
            for (size_t i = 0; i < side; ++i) {
                vertex *v = &grid[j * side + i];
                v->u = (double)i / tessellation;
                v->v = (double)j / tessellation;
                double x[3], n[3];
                patch_eval(points, v->u, v->v, x, n);
                project(m, width, height, x, v);
            }
        for (size_t j = 0; j < tessellation; ++j)
            for (size_t i = 0; i < tessellation; ++i) {
                const vertex *a = &grid[j * side + i], *b = &grid[j * side + i + 1];
                const vertex *c = &grid[(j + 1) * side + i + 1], *d = &grid[(j + 1) * side + i];
                if (a->w <= near_w || b->w <= near_w || c->w <= near_w || d->w <= near_w)
                    continue;
                raster_triangle(&r, (uint32_t)p, a, b, c);
                raster_triangle(&r, (uint32_t)p, a, c, d);
            }
    }
    double eye[3] = {camera->eye[0], camera->eye[1], camera->eye[2]};
    for (size_t index = 0; index < samples; ++index) {
        const hit *h = &hits[index];
        out->depth[index] = h->depth;
        out->rgba[index] = options->background;
        if (h->patch != UINT32_MAX) {
            double x[3], n[3];
            safe_eval(scene->points + (size_t)h->patch * 64, h->u, h->v, x, n);
            out->rgba[index] = shade(eye, x, n, scene->colors[h->patch]);
            double view[3] = {eye[0] - x[0], eye[1] - x[1], eye[2] - x[2]};
            out->facing[index] = dot3(n, view) >= 0.0 ? 1 : 2;
            normalize3(view);
            if (dot3(n, n) > 0.0)
                normalize3(n);
            out->slant[index] = (float)fabs(dot3(n, view));
            out->patch[index] = h->patch;
        }
    }
    for (size_t px = 0; px < pixels; ++px) {
        unsigned sum[3] = {0, 0, 0}, covered = 0;
        for (unsigned s = 0; s < spp; ++s) {
            size_t index = px * spp + s;
            covered += out->depth[index] < INFINITY;
            for (int c = 0; c < 3; ++c)
                sum[c] += (out->rgba[index] >> (8 * c)) & 255u;
        }
        for (int c = 0; c < 3; ++c)
            out->rgb[px * 3 + c] = (uint8_t)((sum[c] + spp / 2) / spp);
        out->coverage[px] = (uint8_t)covered;
    }
    free(positions);
    free(hits);
    free(grid);
    return REYES_OK;
}

/* ---- Comparison ---- */

/* Whether the reference has an edge within the 3x3 pixels around (x, y):
 * mixed coverage, depths more than 2 % apart, both sides of the surface
 * (a fold or the rim of an open surface, where its front and its back
 * meet at one depth) or two patches (a seam, maybe a crease: a sample
 * within a hair of it may take either side's colour). */
static int near_edge(const reyes_brute_image *ref, unsigned x, unsigned y, float *farthest)
{
    int covered = 0, empty = 0, sides = 0, seam = 0, grazing = 0;
    uint32_t patch = UINT32_MAX;
    float lo = INFINITY, hi = 0.0f;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            long nx = (long)x + dx, ny = (long)y + dy;
            if (nx < 0 || ny < 0 || nx >= (long)ref->width || ny >= (long)ref->height)
                continue;
            const float *depth = ref->depth + ((size_t)ny * ref->width + (size_t)nx) * ref->spp;
            for (unsigned s = 0; s < ref->spp; ++s) {
                if (depth[s] < INFINITY) {
                    covered = 1;
                    size_t index = (size_t)(depth - ref->depth) + s;
                    grazing |= ref->slant[index] < REYES_BRUTE_GRAZING;
                    sides |= ref->facing[index];
                    seam |= patch != UINT32_MAX && ref->patch[index] != patch;
                    patch = ref->patch[index];
                    lo = fminf(lo, depth[s]);
                    hi = fmaxf(hi, depth[s]);
                } else {
                    empty = 1;
                }
            }
        }
    /* Where the front is seen at a grazing angle (a fold, a rim seen
     * edge-on) a tessellation cuts the contour by its chords' error: not
     * a crack.  INFINITY: no crack can be told here. */
    *farthest = empty || grazing ? INFINITY : hi;
    if ((covered && empty) || (covered && hi > lo * 1.02f) || sides == 3)
        return 2;
    return seam;
}

void reyes_brute_edge_map(const reyes_brute_image *ref, uint8_t *map)
{
    for (unsigned y = 0; y < ref->height; ++y)
        for (unsigned x = 0; x < ref->width; ++x) {
            float farthest;
            map[(size_t)y * ref->width + x] = (uint8_t)near_edge(ref, x, y, &farthest);
        }
}

reyes_status reyes_brute_compare(const reyes_image *image, const reyes_brute_image *ref,
                                 reyes_brute_comparison *out, reyes_error *error)
{
    memset(out, 0, sizeof *out);
    if (!image->samples)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "the render kept no samples (reyes_options.keep_samples)");
    if (image->width != ref->width || image->height != ref->height || image->spp != ref->spp)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "render %ux%u at %u spp against a reference %ux%u at %u spp",
                          image->width, image->height, image->spp, ref->width, ref->height, ref->spp);
    unsigned spp = ref->spp;
    double error_sum = 0.0, interior_sum = 0.0;
    for (unsigned y = 0; y < ref->height; ++y)
        for (unsigned x = 0; x < ref->width; ++x) {
            size_t px = (size_t)y * ref->width + x;
            float farthest;
            int edge = near_edge(ref, x, y, &farthest);
            for (unsigned s = 0; s < spp; ++s) {
                size_t index = px * spp + s;
                uint64_t value = image->samples[index];
                int rendered = value != REYES_EMPTY_SAMPLE, reference = ref->depth[index] < INFINITY;
                union { uint32_t u; float f; } depth = { (uint32_t)(value >> 32) };
                out->reference_covered += reference;
                out->edge_samples += edge;
                if (rendered && !reference) {
                    ++out->extra;
                    out->interior_extra += !edge;
                } else if (!rendered && reference) {
                    ++out->missing;
                    out->interior_missing += !edge;
                    out->holes += farthest < INFINITY;
                } else if (rendered && fabsf(depth.f - ref->depth[index]) > 0.01f * ref->depth[index]) {
                    ++out->other_surface;
                    out->interior_other_surface += !edge;
                    out->see_through += depth.f > 1.01f * farthest;
                }
            }
            if (!ref->coverage[px] && !image->coverage[px])
                continue; /* background in both: the same bytes */
            ++out->pixels;
            unsigned largest = 0;
            for (int c = 0; c < 3; ++c) {
                unsigned difference = (unsigned)abs((int)image->rgb[px * 3 + c] - (int)ref->rgb[px * 3 + c]);
                largest = difference > largest ? difference : largest;
                error_sum += difference;
                if (!edge)
                    interior_sum += difference;
            }
            out->max_error = largest > out->max_error ? largest : out->max_error;
            out->pixels_over_8 += largest > 8;
            out->pixels_over_32 += largest > 32;
            if (!edge) {
                ++out->interior_pixels;
                out->interior_max_error = largest > out->interior_max_error ? largest : out->interior_max_error;
                out->interior_pixels_over_8 += largest > 8;
            }
        }
    out->samples = (size_t)ref->width * ref->height * spp;
    out->mean_error = out->pixels ? error_sum / (3.0 * (double)out->pixels) : 0.0;
    out->interior_mean_error = out->interior_pixels ? interior_sum / (3.0 * (double)out->interior_pixels) : 0.0;
    return REYES_OK;
}

void reyes_brute_print(FILE *out, const char *label, const reyes_brute_comparison *c)
{
    fprintf(out,
            "%s: samples %zu covered %zu near edges %zu | coverage extra %zu (interior %zu) missing %zu "
            "(interior %zu) | other surface %zu (interior %zu) | see-through %zu holes %zu | colour mean %.3f "
            "max %u, pixels >8 %zu >32 %zu; interior mean %.3f max %u >8 %zu of %zu\n",
            label, c->samples, c->reference_covered, c->edge_samples, c->extra, c->interior_extra, c->missing,
            c->interior_missing, c->other_surface, c->interior_other_surface, c->see_through, c->holes,
            c->mean_error, c->max_error,
            c->pixels_over_8, c->pixels_over_32, c->interior_mean_error, c->interior_max_error,
            c->interior_pixels_over_8, c->interior_pixels);
}
