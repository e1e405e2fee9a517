/*
 * The C reference's dice: a sub-patch's grid x grid vertices evaluated on
 * its base patch at global (u,v) as reyes_dice.cl does, projected, lit and
 * shaded with the renderer's Blinn-Phong model, then counted (and, in a
 * full render, sampled).  Written as loops over the vertices of a grid row
 * or of the whole grid that a C compiler vectorises (structure of arrays,
 * no calls or branches inside); this file is built at -O3 (meson.build).
 */
#include <math.h>
#include <string.h>

#include "reyes_look.h"
#include "reyes_reference_internal.h"

static inline void bernstein(float t, float b[4])
{
    float s = 1.0f - t;
    b[0] = s * s * s;
    b[1] = 3.0f * t * s * s;
    b[2] = 3.0f * t * t * s;
    b[3] = t * t * t;
}

static inline void bernstein_deriv(float t, float d[4])
{
    float s = 1.0f - t;
    d[0] = -3.0f * s * s;
    d[1] = 3.0f * s * s - 6.0f * t * s;
    d[2] = 6.0f * t * s - 3.0f * t * t;
    d[3] = 3.0f * t * t;
}

/* Control points of a base patch, coordinate by coordinate. */
static inline void load_hull(const reyes_scene *scene, uint32_t patch, float hull[3][16])
{
    const float *p = scene->points + (size_t)patch * 64;
    for (int k = 0; k < 16; ++k)
        for (int d = 0; d < 3; ++d)
            hull[d][k] = p[k * 4 + d];
}

/* The base-patch parameter of grid vertex i of [a, b], as reyes_grid_uv. */
static inline float grid_param(float a, float b, unsigned i, unsigned n)
{
    float t = (float)i / (float)(n - 1);
    return a * (1.0f - t) + b * t;
}

/* Point and derivative cross product at one (u, v) (the poles' fix-up). */
static void eval_one_normal(const float hull[3][16], float u, float v, float x[3], float n[3])
{
    float bu[4], bv[4], du[4], dv[4], tu[3] = {0, 0, 0}, tv[3] = {0, 0, 0};
    bernstein(u, bu);
    bernstein(v, bv);
    bernstein_deriv(u, du);
    bernstein_deriv(v, dv);
    x[0] = x[1] = x[2] = 0.0f;
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            for (int d = 0; d < 3; ++d) {
                float p = hull[d][r * 4 + c];
                x[d] += bv[r] * bu[c] * p;
                tu[d] += bv[r] * du[c] * p;
                tv[d] += dv[r] * bu[c] * p;
            }
        }
    }
    n[0] = tu[1] * tv[2] - tu[2] * tv[1];
    n[1] = tu[2] * tv[0] - tu[0] * tv[2];
    n[2] = tu[0] * tv[1] - tu[1] * tv[0];
}

/* Points (and, when `normals`, the cross products of the derivatives) of
 * grid row j: the row's curve in u (and its derivative in v), four control
 * points made once from the hull, then evaluated at each column with the
 * columns' weights bu and derivative weights du. */
REFERENCE_VECTOR_HELPER void eval_row(reference_grid *g, unsigned j, const float hull[3][16], const float (*bu)[REYES_MAX_GRID],
                     const float (*du)[REYES_MAX_GRID], float v, int normals)
{
    unsigned n = g->columns, o = j * n;
    float bv[4], dv[4], q[3][4], qv[3][4];
    bernstein(v, bv);
    bernstein_deriv(v, dv);
    for (int d = 0; d < 3; ++d) {
        for (int c = 0; c < 4; ++c) {
            q[d][c] = bv[0] * hull[d][c] + bv[1] * hull[d][4 + c] + bv[2] * hull[d][8 + c] + bv[3] * hull[d][12 + c];
            qv[d][c] = dv[0] * hull[d][c] + dv[1] * hull[d][4 + c] + dv[2] * hull[d][8 + c] + dv[3] * hull[d][12 + c];
        }
    }
    const float *restrict b0 = bu[0], *restrict b1 = bu[1], *restrict b2 = bu[2], *restrict b3 = bu[3];
    const float *restrict d0 = du[0], *restrict d1 = du[1], *restrict d2 = du[2], *restrict d3 = du[3];
    float *restrict x = g->x[0] + o, *restrict y = g->x[1] + o, *restrict z = g->x[2] + o;
    float *restrict nx = g->normal[0] + o, *restrict ny = g->normal[1] + o, *restrict nz = g->normal[2] + o;
    for (unsigned i = 0; i < n; ++i) {
        x[i] = b0[i] * q[0][0] + b1[i] * q[0][1] + b2[i] * q[0][2] + b3[i] * q[0][3];
        y[i] = b0[i] * q[1][0] + b1[i] * q[1][1] + b2[i] * q[1][2] + b3[i] * q[1][3];
        z[i] = b0[i] * q[2][0] + b1[i] * q[2][1] + b2[i] * q[2][2] + b3[i] * q[2][3];
    }
    if (!normals)
        return;
    for (unsigned i = 0; i < n; ++i) {
        float ux = d0[i] * q[0][0] + d1[i] * q[0][1] + d2[i] * q[0][2] + d3[i] * q[0][3];
        float uy = d0[i] * q[1][0] + d1[i] * q[1][1] + d2[i] * q[1][2] + d3[i] * q[1][3];
        float uz = d0[i] * q[2][0] + d1[i] * q[2][1] + d2[i] * q[2][2] + d3[i] * q[2][3];
        float vx = b0[i] * qv[0][0] + b1[i] * qv[0][1] + b2[i] * qv[0][2] + b3[i] * qv[0][3];
        float vy = b0[i] * qv[1][0] + b1[i] * qv[1][1] + b2[i] * qv[1][2] + b3[i] * qv[1][3];
        float vz = b0[i] * qv[2][0] + b1[i] * qv[2][1] + b2[i] * qv[2][2] + b3[i] * qv[2][3];
        nx[i] = uy * vz - uz * vy;
        ny[i] = uz * vx - ux * vz;
        nz[i] = ux * vy - uy * vx;
    }
}

/* Clip w, screen position and whether in front of the near plane, for
 * vertices [0, count). */
REFERENCE_VECTOR_HELPER void project(const reference_context *c, reference_grid *g, unsigned count)
{
    const float m0 = c->m[0], m1 = c->m[1], m2 = c->m[2], m3 = c->m[3], m4 = c->m[4], m5 = c->m[5];
    const float m6 = c->m[6], m7 = c->m[7], m12 = c->m[12], m13 = c->m[13], m14 = c->m[14], m15 = c->m[15];
    float width = (float)c->o->width, height = (float)c->o->height, near_w = c->near_w;
    const float *restrict x = g->x[0], *restrict y = g->x[1], *restrict z = g->x[2];
    float *restrict sx = g->sx, *restrict sy = g->sy, *restrict w = g->w;
    unsigned char *restrict front = g->front;
    for (unsigned k = 0; k < count; ++k) {
        float cx = m0 * x[k] + m1 * y[k] + m2 * z[k] + m3;
        float cy = m4 * x[k] + m5 * y[k] + m6 * z[k] + m7;
        float cw = m12 * x[k] + m13 * y[k] + m14 * z[k] + m15;
        float inv_w = 1.0f / cw;
        sx[k] = (cx * inv_w * 0.5f + 0.5f) * width;
        sy[k] = (0.5f - cy * inv_w * 0.5f) * height;
        w[k] = cw;
        front[k] = cw > near_w;
    }
}

/* cos^40 (REYES_SHININESS) by squaring. */
static inline float highlight(float cos_h)
{
    float c2 = cos_h * cos_h, c4 = c2 * c2, c8 = c4 * c4, c16 = c8 * c8;
    return c16 * c16 * c8;
}

/* Lambert plus Blinn-Phong, two-sided, as reyes_light_lanes: the diffuse
 * and specular weights of vertices [0, count). */
REFERENCE_VECTOR_HELPER void light(const reference_context *c, reference_grid *g, unsigned count)
{
    float ex = c->eye[0], ey = c->eye[1], ez = c->eye[2];
    float lx = c->light[0], ly = c->light[1], lz = c->light[2];
    const float *restrict x = g->x[0], *restrict y = g->x[1], *restrict z = g->x[2];
    const float *restrict nx = g->normal[0], *restrict ny = g->normal[1], *restrict nz = g->normal[2];
    float *restrict diffuse = g->diffuse, *restrict specular = g->specular;
    for (unsigned k = 0; k < count; ++k) {
        float vx = ex - x[k], vy = ey - y[k], vz = ez - z[k];
        float inv_v = 1.0f / sqrtf(vx * vx + vy * vy + vz * vz);
        vx *= inv_v;
        vy *= inv_v;
        vz *= inv_v;
        float l2 = nx[k] * nx[k] + ny[k] * ny[k] + nz[k] * nz[k];
        float inv_n = 1.0f / sqrtf(l2 > 0.0f ? l2 : 1.0f);
        float mx = l2 > 0.0f ? nx[k] * inv_n : vx;
        float my = l2 > 0.0f ? ny[k] * inv_n : vy;
        float mz = l2 > 0.0f ? nz[k] * inv_n : vz;
        float facing = mx * vx + my * vy + mz * vz < 0.0f ? -1.0f : 1.0f;
        mx *= facing;
        my *= facing;
        mz *= facing;
        float lambert = max_f(mx * lx + my * ly + mz * lz, 0.0f);
        float hx = lx + vx, hy = ly + vy, hz = lz + vz;
        float inv_h = 1.0f / sqrtf(hx * hx + hy * hy + hz * hz);
        float cos_h = (mx * hx + my * hy + mz * hz) * inv_h;
        diffuse[k] = REYES_AMBIENT + REYES_DIFFUSE * lambert;
        float lit = lambert > 0.0f ? REYES_SPECULAR : 0.0f;
        specular[k] = cos_h > 0.0f ? lit * highlight(cos_h) : 0.0f;
    }
}

/* A colour channel in [0,1] as a byte, rounded to nearest (even). */
static inline uint32_t channel_byte(float value)
{
    float scaled = min_f(max_f(value, 0.0f), 1.0f) * 255.0f;
    return (uint32_t)(int32_t)((scaled + 8388608.0f) - 8388608.0f);
}

/* The packed colours of vertices [0, count) for base colour rgba. */
REFERENCE_VECTOR_HELPER void shade(reference_grid *g, unsigned count, uint32_t rgba)
{
    float r = (float)(rgba & 255u) * (1.0f / 255.0f), gr = (float)((rgba >> 8) & 255u) * (1.0f / 255.0f);
    float b = (float)((rgba >> 16) & 255u) * (1.0f / 255.0f);
    const float *restrict diffuse = g->diffuse, *restrict specular = g->specular;
    uint32_t *restrict out = g->rgba;
    float *restrict cr = g->color[0], *restrict cg = g->color[1], *restrict cb = g->color[2];
    for (unsigned k = 0; k < count; ++k) {
        uint32_t red = channel_byte(r * diffuse[k] + specular[k]), green = channel_byte(gr * diffuse[k] + specular[k]);
        uint32_t blue = channel_byte(b * diffuse[k] + specular[k]);
        out[k] = red | green << 8 | blue << 16 | 255u << 24;
        cr[k] = (float)red * (1.0f / 255.0f);
        cg[k] = (float)green * (1.0f / 255.0f);
        cb[k] = (float)blue * (1.0f / 255.0f);
    }
}

/* Where a patch edge collapses to a point (a pole) the derivative cross
 * product vanishes: take the normal slightly inside, as reyes_safe_normal. */
static inline void fix_poles(reference_grid *g, const float hull[3][16], const struct reyes_subpatch *sp)
{
    unsigned n = g->columns;
    for (unsigned k = 0; k < n * g->rows; ++k) {
        float l2 = g->normal[0][k] * g->normal[0][k] + g->normal[1][k] * g->normal[1][k]
                   + g->normal[2][k] * g->normal[2][k];
        if (l2 >= 1e-24f)
            continue;
        float u = grid_param(sp->u0, sp->u1, k % n, n), v = grid_param(sp->v0, sp->v1, k / n, g->rows);
        for (int step = 1; step <= 3 && l2 < 1e-24f; ++step) {
            float nudge = 1e-3f * (float)step, x[3], normal[3];
            eval_one_normal(hull, u + (0.5f - u) * nudge, v + (0.5f - v) * nudge, x, normal);
            for (int d = 0; d < 3; ++d)
                g->normal[d][k] = normal[d];
            l2 = normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2];
        }
    }
}

REFERENCE_MACHINE_CLONES void reference_dice(reference_context *c, const struct reyes_subpatch *sp)
{
    reference_grid *g = c->grid;
    /* grid x grid, or with a shading rate the size bound chose (as
     * reyes_dice_size). */
    unsigned n = sp->dice_size ? sp->dice_size & 0xffu : c->o->grid;
    unsigned rows = sp->dice_size ? (sp->dice_size >> 8) & 0xffu : c->o->grid;
    int full = c->samples != NULL;
    g->columns = n;
    g->rows = rows;
    float hull[3][16], bu[4][REYES_MAX_GRID], du[4][REYES_MAX_GRID];
    load_hull(c->scene, sp->patch, hull);
    for (unsigned i = 0; i < n; ++i) {
        float w[4], d[4];
        bernstein(grid_param(sp->u0, sp->u1, i, n), w);
        bernstein_deriv(grid_param(sp->u0, sp->u1, i, n), d);
        for (int k = 0; k < 4; ++k) {
            bu[k][i] = w[k];
            du[k][i] = d[k];
        }
    }
    for (unsigned j = 0; j < rows; ++j)
        eval_row(g, j, hull, bu, du, grid_param(sp->v0, sp->v1, j, rows), full);
    project(c, g, n * rows);
    if (full) {
        fix_poles(g, hull, sp);
        light(c, g, n * rows);
        shade(g, n * rows, c->scene->colors[sp->patch]);
    }
    c->counts->micropolygons += reference_sample_grid(c, g);
}
