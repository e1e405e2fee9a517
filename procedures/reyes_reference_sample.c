/*
 * The C reference's sampling: each visible quad of a diced grid as two
 * triangles over the samples of its pixel box, with reyes_sample.cl's
 * jittered positions, canonical (watertight) edge functions and
 * nearest-wins (depth, colour) values.  Built at -O3 (meson.build).
 */
#include <math.h>

#include "reyes_look.h"
#include "reyes_reference_internal.h"

void reference_samples_init(reference_samples *s, unsigned width, unsigned height, unsigned spp,
                            uint64_t *values, float *positions)
{
    s->values = values;
    s->positions = positions;
    s->width = width;
    s->height = height;
    s->spp = spp;
    unsigned columns = (unsigned)ceilf(sqrtf((float)spp)), rows = (spp + columns - 1) / columns;
    float cell_x[REYES_MAX_SPP], cell_y[REYES_MAX_SPP];
    uint32_t index_hash[REYES_MAX_SPP];
    for (unsigned k = 0; k < spp; ++k) {
        cell_x[k] = (float)(k % columns);
        cell_y[k] = (float)(k / columns);
        index_hash[k] = reyes_hash32(k);
    }
    for (unsigned py = 0; py < height; ++py) {
        for (unsigned k = 0; k < spp; ++k) {
            uint32_t row_hash = reyes_hash32(py * 0x85ebca6bu ^ index_hash[k]);
            float *at = positions + ((size_t)py * width * spp + k) * 2;
            for (unsigned px = 0; px < width; ++px, at += 2 * spp) {
                uint32_t h = reyes_hash32(px * 0x9e3779b9u ^ row_hash);
                float jx = (float)(h & 0xffffu) * (1.0f / 65536.0f), jy = (float)(h >> 16) * (1.0f / 65536.0f);
                at[0] = (float)px + (cell_x[k] + jx) / (float)columns;
                at[1] = (float)py + (cell_y[k] + jy) / (float)rows;
            }
        }
    }
}

/* An edge a->b with its end points in a fixed order (edge(a,b,p) ==
 * -edge(b,a,p) exactly, so a sample on an edge shared by two triangles is
 * inside the same way for both). */
typedef struct edge {
    float lo_x, lo_y, dx, dy, sign;
} edge;

static edge edge_setup(float ax, float ay, float bx, float by)
{
    int swap = ax > bx || (ax == bx && ay > by);
    edge e;
    e.lo_x = swap ? bx : ax;
    e.lo_y = swap ? by : ay;
    e.dx = (swap ? ax : bx) - e.lo_x;
    e.dy = (swap ? ay : by) - e.lo_y;
    e.sign = swap ? -1.0f : 1.0f;
    return e;
}

static float edge_at(const edge *e, float x, float y)
{
    return e->sign * (e->dx * (y - e->lo_y) - e->dy * (x - e->lo_x));
}

/* A triangle of a quad: the grid indices of its vertices a, b, c and its
 * signed area (its edges are the quad's). */
typedef struct triangle {
    float area;
    unsigned v[3];
} triangle;

/* fminf and fmaxf would be library calls (their NaN rules); these are not. */
static float min_f(float a, float b)
{
    return a < b ? a : b;
}

static float max_f(float a, float b)
{
    return a > b ? a : b;
}

static uint32_t channel_byte(float value)
{
    float scaled = min_f(max_f(value, 0.0f), 1.0f) * 255.0f;
    return (uint32_t)(int32_t)((scaled + 8388608.0f) - 8388608.0f);
}

/* The nearer of the sample's value and triangle t's at a covered point
 * with edge values wa, wb, wc. */
static void keep_nearer(const reference_grid *g, const triangle *t, float wa, float wb, float wc, uint64_t *value)
{
    float inv_area = 1.0f / t->area;
    float ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
    unsigned a = t->v[0], b = t->v[1], c = t->v[2];
    float depth = max_f(ba * g->w[a] + bb * g->w[b] + bc * g->w[c], 0.0f);
    uint32_t rgba = 255u << 24;
    for (int ch = 0; ch < 3; ++ch) {
        const float *color = g->color[ch];
        rgba |= channel_byte(ba * color[a] + bb * color[b] + bc * color[c]) << (8 * ch);
    }
    union { float f; uint32_t u; } bits = { depth };
    uint64_t packed = (uint64_t)bits.u << 32 | rgba;
    if (packed < *value)
        *value = packed;
}

static int inside(float area, float wa, float wb, float wc)
{
    return area > 0.0f ? (wa >= 0.0f && wb >= 0.0f && wc >= 0.0f) : (wa <= 0.0f && wb <= 0.0f && wc <= 0.0f);
}

/* Samples further than this outside a quad's screen box are not tested:
 * rounding never puts a covered sample anywhere near that far out, so the
 * result is that of testing every sample of the box's pixels. */
#define BOX_MARGIN (1.0f / 64.0f)

/* Sample one quad (corners 0-3 around it) as its triangles (0,1,2) and
 * (0,2,3) over its pixel box.  Their five edges in canonical order: the
 * diagonal (2,0) serves both triangles, negated for the second's (0,2). */
static void sample_quad(const reference_samples *s, const reference_grid *g, const unsigned corner[4], float lo_x,
                        float lo_y, float hi_x, float hi_y)
{
    int x0 = (int)floorf(max_f(lo_x, 0.0f)), y0 = (int)floorf(max_f(lo_y, 0.0f));
    int x1 = (int)floorf(min_f(hi_x, (float)s->width - 1.0f)), y1 = (int)floorf(min_f(hi_y, (float)s->height - 1.0f));
    float vx[4], vy[4];
    for (int k = 0; k < 4; ++k) {
        vx[k] = g->sx[corner[k]];
        vy[k] = g->sy[corner[k]];
    }
    edge e12 = edge_setup(vx[1], vy[1], vx[2], vy[2]), e20 = edge_setup(vx[2], vy[2], vx[0], vy[0]);
    edge e01 = edge_setup(vx[0], vy[0], vx[1], vy[1]), e23 = edge_setup(vx[2], vy[2], vx[3], vy[3]);
    edge e30 = edge_setup(vx[3], vy[3], vx[0], vy[0]);
    triangle t0 = { edge_at(&e01, vx[2], vy[2]), { corner[0], corner[1], corner[2] } };
    triangle t1 = { -edge_at(&e20, vx[3], vy[3]), { corner[0], corner[2], corner[3] } };
    lo_x -= BOX_MARGIN;
    lo_y -= BOX_MARGIN;
    hi_x += BOX_MARGIN;
    hi_y += BOX_MARGIN;
    for (int py = y0; py <= y1; ++py) {
        size_t first = ((size_t)py * s->width + (size_t)x0) * s->spp, count = (size_t)(x1 - x0 + 1) * s->spp;
        const float *at = s->positions + first * 2;
        uint64_t *values = s->values + first;
        for (size_t k = 0; k < count; ++k) {
            float x = at[2 * k], y = at[2 * k + 1];
            if (!((x >= lo_x) & (x <= hi_x) & (y >= lo_y) & (y <= hi_y)))
                continue;
            float diagonal = edge_at(&e20, x, y);
            float w12 = edge_at(&e12, x, y), w01 = edge_at(&e01, x, y);
            float w23 = edge_at(&e23, x, y), w30 = edge_at(&e30, x, y);
            uint64_t value = values[k];
            if (t0.area != 0.0f && inside(t0.area, w12, diagonal, w01))
                keep_nearer(g, &t0, w12, diagonal, w01, &value);
            if (t1.area != 0.0f && inside(t1.area, w23, w30, -diagonal))
                keep_nearer(g, &t1, w23, w30, -diagonal, &value);
            values[k] = value;
        }
    }
}

uint64_t reference_sample_grid(const reference_context *c, const reference_grid *g)
{
    unsigned n = g->n;
    float width = (float)c->o->width, height = (float)c->o->height;
    uint64_t visible = 0;
    for (unsigned j = 0; j + 1 < n; ++j) {
        for (unsigned i = 0; i + 1 < n; ++i) {
            const unsigned corner[4] = { j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i };
            float lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
            int front = 1;
            for (int k = 0; k < 4; ++k) {
                front &= g->front[corner[k]];
                lo_x = min_f(lo_x, g->sx[corner[k]]);
                hi_x = max_f(hi_x, g->sx[corner[k]]);
                lo_y = min_f(lo_y, g->sy[corner[k]]);
                hi_y = max_f(hi_y, g->sy[corner[k]]);
            }
            if (!front || hi_x < 0.0f || hi_y < 0.0f || lo_x > width || lo_y > height)
                continue;
            ++visible;
            if (c->samples)
                sample_quad(c->samples, g, corner, lo_x, lo_y, hi_x, hi_y);
        }
    }
    return visible;
}
