/*
 * CPU reference of the Reyes pipeline: the same tests as reyes_bound.cl
 * and reyes_dice.cl, written in C and run depth-first on one thread, and
 * for a full render the same shading and sampling (reyes_reference_dice.c,
 * reyes_reference_sample.c).  Float rounding may differ from the device's
 * (contractions, vector code), so a patch right at a threshold can rarely
 * be decided differently, and a sample on an edge covered differently.
 * With a shading rate it dices each sub-patch to the grid size its
 * longest control-polygon rows ask for and shades vertices: the
 * renderer's shading-rate pipeline before issue 25's edge-conforming
 * dicing and sample shading (reyes_rate.cl, reyes_sample_shading.cl),
 * which it does not model; it stays the speed baseline of that workload
 * (perma-bench reyes --workload defaults), not a check of its counts or
 * images.  At a shading rate it also culls hidden grids as the renderer
 * does (reyes_reference_occlusion.c): the leaves are diced front to back
 * and each tested against the samples first.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "reyes_look.h"
#include "reyes_reference_internal.h"

typedef struct vec3 { float x, y, z; } vec3;
typedef struct vec4 { float x, y, z, w; } vec4;

typedef reference_context context;

static vec3 mix3(vec3 a, vec3 b, float t)
{
    return (vec3){ a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t };
}

static vec3 blossom(const vec3 p[4], float t1, float t2, float t3)
{
    vec3 a = mix3(p[0], p[1], t1), b = mix3(p[1], p[2], t1), c = mix3(p[2], p[3], t1);
    return mix3(mix3(a, b, t2), mix3(b, c, t2), t3);
}

static void restrict_curve(vec3 cp[16], int first, int stride, float a, float b)
{
    vec3 p[4] = { cp[first], cp[first + stride], cp[first + 2 * stride], cp[first + 3 * stride] };
    cp[first] = blossom(p, a, a, a);
    cp[first + stride] = blossom(p, a, a, b);
    cp[first + 2 * stride] = blossom(p, a, b, b);
    cp[first + 3 * stride] = blossom(p, b, b, b);
}

static void load_patch(const reyes_scene *scene, uint32_t patch, vec3 cp[16])
{
    const float *p = scene->points + (size_t)patch * 64;
    for (int k = 0; k < 16; ++k)
        cp[k] = (vec3){ p[k * 4], p[k * 4 + 1], p[k * 4 + 2] };
}

static vec4 to_clip(const float m[16], vec3 x)
{
    float c[4];
    for (int r = 0; r < 4; ++r)
        c[r] = m[r * 4] * x.x + m[r * 4 + 1] * x.y + m[r * 4 + 2] * x.z + m[r * 4 + 3];
    return (vec4){ c[0], c[1], c[2], c[3] };
}

static void to_screen(const context *c, vec4 clip, float *sx, float *sy)
{
    float inv_w = 1.0f / clip.w;
    *sx = (clip.x * inv_w * 0.5f + 0.5f) * (float)c->o->width;
    *sy = (0.5f - clip.y * inv_w * 0.5f) * (float)c->o->height;
}

static int outside_frustum(const vec4 clip[16], float margin)
{
    int left = 1, right = 1, bottom = 1, top = 1;
    for (int k = 0; k < 16; ++k) {
        float w = clip[k].w * (1.0f + margin);
        left &= clip[k].x < -w;
        right &= clip[k].x > w;
        bottom &= clip[k].y < -w;
        top &= clip[k].y > w;
    }
    return left | right | bottom | top;
}

static int backfacing(const float sx[16], const float sy[16])
{
    for (int a = 0; a < 12; ++a) {
        int r = a / 3, col = a % 3;
        float dux = sx[r * 4 + col + 1] - sx[r * 4 + col], duy = sy[r * 4 + col + 1] - sy[r * 4 + col];
        for (int b = 0; b < 12; ++b) {
            int cc = b / 3, rr = b % 3;
            float dvx = sx[(rr + 1) * 4 + cc] - sx[rr * 4 + cc];
            float dvy = sy[(rr + 1) * 4 + cc] - sy[rr * 4 + cc];
            if (dux * dvy - duy * dvx <= 0.0f)
                return 0;
        }
    }
    return 1;
}

/* Longest polyline of the hull along u (rows) or v (columns); 2D when z is NULL. */
static float extent(const float *x, const float *y, const float *z, int along_u)
{
    float longest = 0.0f;
    for (int line = 0; line < 4; ++line) {
        float length = 0.0f;
        for (int k = 0; k < 3; ++k) {
            int i0 = along_u ? line * 4 + k : k * 4 + line;
            int i1 = along_u ? i0 + 1 : i0 + 4;
            float dx = x[i1] - x[i0], dy = y[i1] - y[i0], dz = z ? z[i1] - z[i0] : 0.0f;
            length += sqrtf(dx * dx + dy * dy + dz * dz);
        }
        longest = fmaxf(longest, length);
    }
    return longest;
}

/* The tiered criterion of reyes_flatness.cl. */
static float length3(vec3 a)
{
    return sqrtf(a.x * a.x + a.y * a.y + a.z * a.z);
}

static vec3 sub3(vec3 a, vec3 b)
{
    return (vec3){ a.x - b.x, a.y - b.y, a.z - b.z };
}

static vec3 scale3(vec3 a, float s)
{
    return (vec3){ a.x * s, a.y * s, a.z * s };
}

static float dot3(vec3 a, vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/* Distance of curve `line` (a row when along_u) in world units, mixed. */
static float curve_distance(const vec3 cp[16], int line, int along_u, float lambda)
{
    int first = along_u ? line * 4 : line, stride = along_u ? 1 : 4;
    vec3 b0 = cp[first], b1 = cp[first + stride], b2 = cp[first + 2 * stride];
    vec3 b3 = cp[first + 3 * stride];
    if (b0.x > b3.x || (b0.x == b3.x && (b0.y > b3.y || (b0.y == b3.y && b0.z > b3.z)))) {
        vec3 t = b0;
        b0 = b3;
        b3 = t;
        t = b1;
        b1 = b2;
        b2 = t;
    }
    vec3 chord = sub3(b3, b0);
    vec3 e1 = sub3(b1, (vec3){ b0.x + chord.x * (1.0f / 3.0f), b0.y + chord.y * (1.0f / 3.0f),
                               b0.z + chord.z * (1.0f / 3.0f) });
    vec3 e2 = sub3(b2, (vec3){ b0.x + chord.x * (2.0f / 3.0f), b0.y + chord.y * (2.0f / 3.0f),
                               b0.z + chord.z * (2.0f / 3.0f) });
    float full = fmaxf(length3(e1), length3(e2)), geometric = full;
    float chord_length = length3(chord);
    if (chord_length > 0.0f) {
        vec3 t = scale3(chord, 1.0f / chord_length);
        geometric = fmaxf(length3(sub3(e1, scale3(t, dot3(e1, t)))),
                          length3(sub3(e2, scale3(t, dot3(e2, t)))));
    }
    return geometric + (full - geometric) * lambda;
}

static float pixels_per_unit(const context *c, const vec4 clip[16])
{
    const float *m = c->m;
    float r0 = sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    float r1 = sqrtf(m[4] * m[4] + m[5] * m[5] + m[6] * m[6]);
    float r3 = sqrtf(m[12] * m[12] + m[13] * m[13] + m[14] * m[14]);
    float w_min = INFINITY, ndc_x = 0.0f, ndc_y = 0.0f;
    for (int k = 0; k < 16; ++k) {
        w_min = fminf(w_min, clip[k].w);
        ndc_x = fmaxf(ndc_x, fabsf(clip[k].x / clip[k].w));
        ndc_y = fmaxf(ndc_y, fabsf(clip[k].y / clip[k].w));
    }
    return fmaxf(0.5f * (float)c->o->width * (r0 + ndc_x * r3),
                 0.5f * (float)c->o->height * (r1 + ndc_y * r3)) / w_min;
}

/* Shading-rate dicing (reyes_rate_segments): the micropolygons a
 * sub-patch needs along u (need[0]) and v so that each is at most
 * sqrt(rate) pixels long, from the longest row and column of its
 * projected control net. */
static void rate_segments(const context *c, const float sx[16], const float sy[16], float need[2])
{
    float along_u = 0.0f, along_v = 0.0f;
    for (int k = 0; k < 4; ++k) {
        float row = 0.0f, column = 0.0f;
        for (int i = 0; i < 3; ++i) {
            int a = k * 4 + i, b = i * 4 + k;
            row += sqrtf((sx[a + 1] - sx[a]) * (sx[a + 1] - sx[a]) + (sy[a + 1] - sy[a]) * (sy[a + 1] - sy[a]));
            column += sqrtf((sx[b + 4] - sx[b]) * (sx[b + 4] - sx[b]) + (sy[b + 4] - sy[b]) * (sy[b + 4] - sy[b]));
        }
        along_u = fmaxf(along_u, row);
        along_v = fmaxf(along_v, column);
    }
    float side = sqrtf(c->o->shading_rate);
    need[0] = fmaxf(ceilf(along_u / side + 0.5f), 1.0f);
    need[1] = fmaxf(ceilf(along_v / side + 0.5f), 1.0f);
}

/* The flatness tiers of the tiered criterion: 1 to split (then
 * *along_u), 0 to dice, as reyes_split_reason after its size test. */
static int tiered_split(const context *c, const vec3 cp[16], const vec4 clip[16], int *along_u)
{
    float scale = pixels_per_unit(c, clip), along[2] = { 0.0f, 0.0f };
    int failed = 0;
    for (int line = 0; line < 4; ++line) {
        float row = scale * curve_distance(cp, line, 1, c->o->flat_lambda);
        float column = scale * curve_distance(cp, line, 0, c->o->flat_lambda);
        along[0] = fmaxf(along[0], row);
        along[1] = fmaxf(along[1], column);
        failed |= fmaxf(row, column) > c->o->flat_epsilon;
    }
    if (failed)
        *along_u = along[0] >= along[1];
    return failed;
}

static void split(context *c, struct reyes_subpatch sp, int along_u);

static void bound(context *c, struct reyes_subpatch sp)
{
    const reyes_options *o = c->o;
    if (sp.depth > c->counts->max_depth_seen)
        c->counts->max_depth_seen = sp.depth;
    vec3 cp[16];
    vec4 clip[16];
    load_patch(c->scene, sp.patch, cp);
    for (int row = 0; row < 4; ++row)
        restrict_curve(cp, row * 4, 1, sp.u0, sp.u1);
    for (int col = 0; col < 4; ++col)
        restrict_curve(cp, col, 4, sp.v0, sp.v1);
    int all_behind = 1, any_behind = 0;
    for (int k = 0; k < 16; ++k) {
        clip[k] = to_clip(c->m, cp[k]);
        int behind = clip[k].w <= c->near_w;
        all_behind &= behind;
        any_behind |= behind;
    }
    if (all_behind || outside_frustum(clip, o->cull_margin)) {
        ++c->counts->culled;
        return;
    }
    int forced = sp.depth >= o->max_depth;
    if (any_behind) {
        if (forced) {
            ++c->counts->culled;
        } else {
            float x[16], y[16], z[16];
            for (int k = 0; k < 16; ++k) {
                x[k] = cp[k].x;
                y[k] = cp[k].y;
                z[k] = cp[k].z;
            }
            split(c, sp, extent(x, y, z, 1) >= extent(x, y, z, 0));
        }
        return;
    }
    float sx[16], sy[16], lox = INFINITY, loy = INFINITY, hix = -INFINITY, hiy = -INFINITY;
    for (int k = 0; k < 16; ++k) {
        to_screen(c, clip[k], &sx[k], &sy[k]);
        lox = fminf(lox, sx[k]);
        hix = fmaxf(hix, sx[k]);
        loy = fminf(loy, sy[k]);
        hiy = fmaxf(hiy, sy[k]);
    }
    if (o->backface_cull && backfacing(sx, sy)) {
        ++c->counts->culled;
        return;
    }
    /* As reyes_split_reason: too big for one grid (the screen bound, or
     * with a shading rate the micropolygons needed), then the tiers. */
    float size = fmaxf(hix - lox, hiy - loy), need[2] = { 0.0f, 0.0f };
    int along_u, split_it;
    if (o->shading_rate > 0.0f) {
        rate_segments(c, sx, sy, need);
        split_it = fmaxf(need[0], need[1]) > (float)(o->grid - 1);
        along_u = need[0] >= need[1];
    } else {
        float cap = o->subdivision == REYES_SUBDIVISION_TIERED
                        ? (o->flat_bound_px > 0.0f ? o->flat_bound_px : (float)(o->grid - 1))
                        : o->bound_px;
        split_it = size > cap;
        along_u = extent(sx, sy, NULL, 1) >= extent(sx, sy, NULL, 0);
    }
    if (!split_it && o->subdivision == REYES_SUBDIVISION_TIERED)
        split_it = tiered_split(c, cp, clip, &along_u);
    if (forced || !split_it) {
        c->counts->forced_dice += (uint64_t)forced;
        reference_leaf leaf = { .sp = sp };
        if (o->shading_rate > 0.0f) {
            /* As bound: with a shading rate, a grid that covers no sample
             * is not diced. */
            leaf.octagon = reference_hull_octagon(sx, sy, lox, loy, hix, hiy);
            if (!reference_hull_has_sample(o->width, o->height, o->spp, &leaf.octagon)) {
                ++c->counts->culled;
                return;
            }
            unsigned nu = (unsigned)fminf(need[0], (float)(o->grid - 1)), nv = (unsigned)fminf(need[1], (float)(o->grid - 1));
            leaf.sp.dice_size = (nu + 1u) | ((nv + 1u) << 8);
        }
        ++c->counts->grids;
        if (o->stages == REYES_STAGES_SUBDIVIDE)
            return;
        if (!c->leaves) {
            reference_dice(c, &leaf.sp);
            return;
        }
        leaf.order = c->patch_leaves++;
        float largest = 0.0f;
        leaf.near_w = INFINITY;
        for (int k = 0; k < 16; ++k) {
            leaf.near_w = fminf(leaf.near_w, clip[k].w);
            largest = fmaxf(largest, fabsf(cp[k].x) + fabsf(cp[k].y) + fabsf(cp[k].z));
        }
        if (c->occlusion)
            reference_occlusion_setup(c, &leaf, largest);
        reference_leaves_add(c->leaves, &leaf);
    } else {
        split(c, sp, along_u);
    }
}

static void split(context *c, struct reyes_subpatch sp, int along_u)
{
    struct reyes_subpatch a = sp, b = sp;
    if (along_u) {
        float mid = 0.5f * (sp.u0 + sp.u1);
        a.u1 = mid;
        b.u0 = mid;
    } else {
        float mid = 0.5f * (sp.v0 + sp.v1);
        a.v1 = mid;
        b.v0 = mid;
    }
    a.depth = b.depth = sp.depth + 1;
    ++c->counts->splits;
    bound(c, a); /* recursion depth is at most max_depth (<= 40) */
    bound(c, b);
}

double reference_seconds_since(const struct timespec *start)
{
    struct timespec end;
    clock_gettime(CLOCK_MONOTONIC, &end);
    return (double)(end.tv_sec - start->tv_sec) + 1e-9 * (double)(end.tv_nsec - start->tv_nsec);
}

reyes_status reference_begin(reference_context *c, const reyes_scene *scene, const reyes_camera *camera,
                             const reyes_options *options, reyes_reference_counts *out, reyes_error *error)
{
    memset(out, 0, sizeof *out);
    *c = (context){ .scene = scene, .o = options, .counts = out };
    reyes_status status = reyes_options_check(options, error);
    if (status != REYES_OK)
        return status;
    if (options->crack_fix == REYES_CRACK_FIX_WEDGE)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "the C reference does not model the wedge crack fix's subdivision");
    c->near_w = reyes_near_plane(scene, camera);
    for (int k = 0; k < 3; ++k)
        c->eye[k] = camera->eye[k];
    reyes_light_direction(c->light);
    return reyes_camera_matrix(camera, (float)options->width / (float)options->height, c->near_w, c->m, error);
}

reyes_status reference_grid_alloc(reference_context *c, reyes_error *error)
{
    c->grid = calloc(1, sizeof *c->grid); /* the padding read past the vertices is zeros */
    return c->grid ? REYES_OK : reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for the C reference's grid");
}

void reference_subdivide_patch(reference_context *c, uint32_t patch)
{
    c->patch_leaves = 0;
    bound(c, (struct reyes_subpatch){ .patch = patch, .u1 = 1.0f, .v1 = 1.0f });
}

void reference_leaves_add(reference_leaves *leaves, const reference_leaf *leaf)
{
    if (leaves->count == leaves->capacity) {
        size_t capacity = leaves->capacity ? 2 * leaves->capacity : 1024;
        reference_leaf *grown = realloc(leaves->items, capacity * sizeof *grown);
        if (!grown) {
            leaves->failed = 1;
            return;
        }
        leaves->items = grown;
        leaves->capacity = capacity;
    }
    leaves->items[leaves->count++] = *leaf;
}

void reference_leaves_free(reference_leaves *leaves)
{
    free(leaves->items);
    memset(leaves, 0, sizeof *leaves);
}

reyes_status reference_subdivide_all(reference_context *c, const reyes_scene *scene,
                                     reyes_reference_counts *out, reyes_error *error)
{
    reyes_status status = reference_grid_alloc(c, error);
    if (status != REYES_OK)
        return status;
    /* With occlusion culling the grids are diced front to back, after
     * every patch is subdivided, so that the near ones hide the far. */
    reference_leaves leaves = { 0 };
    c->leaves = c->occlusion ? &leaves : NULL;
    struct timespec start;
    clock_gettime(CLOCK_MONOTONIC, &start);
    for (size_t p = 0; p < scene->patch_count; ++p)
        reference_subdivide_patch(c, (uint32_t)p);
    if (!leaves.failed) {
        reference_leaves_sort(leaves.items, leaves.count);
        for (size_t k = 0; k < leaves.count; ++k)
            reference_dice_leaf(c, &leaves.items[k]);
    }
    out->seconds = reference_seconds_since(&start);
    c->leaves = NULL;
    int failed = leaves.failed;
    reference_leaves_free(&leaves);
    return failed ? reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for the sub-patches to dice") : REYES_OK;
}

reyes_status reyes_reference_run(const reyes_scene *scene, const reyes_camera *camera,
                                 const reyes_options *options, reyes_reference_counts *out,
                                 reyes_error *error)
{
    context c;
    reyes_status status = reference_begin(&c, scene, camera, options, out, error);
    if (status == REYES_OK)
        status = reference_subdivide_all(&c, scene, out, error);
    free(c.grid);
    return status;
}

static vec3 normalize3(vec3 a)
{
    float length = length3(a);
    return length > 0.0f ? scale3(a, 1.0f / length) : a;
}

void reyes_reference_shade(const float eye[3], const float x[3], const float n[3], uint32_t rgba,
                           float rgb[3])
{
    vec3 point = { x[0], x[1], x[2] }, normal = { n[0], n[1], n[2] };
    vec3 view = normalize3(sub3((vec3){ eye[0], eye[1], eye[2] }, point));
    normal = dot3(normal, normal) > 0.0f ? normalize3(normal) : view;
    if (dot3(normal, view) < 0.0f)
        normal = scale3(normal, -1.0f);
    vec3 light = normalize3((vec3){ REYES_LIGHT_X, REYES_LIGHT_Y, REYES_LIGHT_Z });
    float lambert = fmaxf(dot3(normal, light), 0.0f);
    vec3 half_vector = normalize3((vec3){ light.x + view.x, light.y + view.y, light.z + view.z });
    float cos_h = dot3(normal, half_vector);
    float highlight = lambert > 0.0f && cos_h > 0.0f ? powf(cos_h, REYES_SHININESS) : 0.0f;
    for (int c = 0; c < 3; ++c) {
        float base = (float)((rgba >> (8 * c)) & 255u) / 255.0f;
        float value = base * (REYES_AMBIENT + REYES_DIFFUSE * lambert) + REYES_SPECULAR * highlight;
        rgb[c] = fminf(fmaxf(value, 0.0f), 1.0f);
    }
}
