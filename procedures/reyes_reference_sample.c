/*
 * The C reference's sampling: each visible quad of a diced grid as two
 * triangles over the samples of its pixel box, with reyes_sample.cl's
 * jittered positions, canonical (watertight) edge functions and
 * nearest-wins (depth, colour) values.  Built at -O3 (meson.build).
 */
#include <math.h>

#include "reyes_reference_internal.h"

static uint32_t hash(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

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
        index_hash[k] = hash(k);
    }
    for (unsigned py = 0; py < height; ++py) {
        for (unsigned k = 0; k < spp; ++k) {
            uint32_t row_hash = hash(py * 0x85ebca6bu ^ index_hash[k]);
            float *at = positions + ((size_t)py * width * spp + k) * 2;
            for (unsigned px = 0; px < width; ++px, at += 2 * spp) {
                uint32_t h = hash(px * 0x9e3779b9u ^ row_hash);
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

/* Triangle (a, b, c) of a quad (vertex indices into the grid): its edges
 * (b,c), (c,a), (a,b) and the reciprocal of its signed area. */
typedef struct triangle {
    edge e[3];
    float area, inv_area;
    unsigned v[3];
} triangle;

static triangle triangle_setup(const reference_grid *g, const unsigned corner[4], int a, int b, int c)
{
    triangle t;
    unsigned va = corner[a], vb = corner[b], vc = corner[c];
    t.e[0] = edge_setup(g->sx[vb], g->sy[vb], g->sx[vc], g->sy[vc]);
    t.e[1] = edge_setup(g->sx[vc], g->sy[vc], g->sx[va], g->sy[va]);
    t.e[2] = edge_setup(g->sx[va], g->sy[va], g->sx[vb], g->sy[vb]);
    t.area = edge_at(&t.e[2], g->sx[vc], g->sy[vc]);
    t.inv_area = 1.0f / t.area;
    t.v[0] = va;
    t.v[1] = vb;
    t.v[2] = vc;
    return t;
}

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

/* Keep the nearer of the sample's value and the triangle's at (x, y), if
 * the point is inside (edges inclusive). */
static void sample_triangle(const reference_grid *g, const triangle *t, float x, float y, uint64_t *value)
{
    float wa = edge_at(&t->e[0], x, y), wb = edge_at(&t->e[1], x, y), wc = edge_at(&t->e[2], x, y);
    int inside = t->area > 0.0f ? (wa >= 0.0f && wb >= 0.0f && wc >= 0.0f) : (wa <= 0.0f && wb <= 0.0f && wc <= 0.0f);
    if (!inside || t->area == 0.0f)
        return;
    float ba = wa * t->inv_area, bb = wb * t->inv_area, bc = wc * t->inv_area;
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

/* Sample one quad over its pixel box. */
static void sample_quad(const reference_samples *s, const reference_grid *g, const unsigned corner[4], float lo_x,
                        float lo_y, float hi_x, float hi_y)
{
    int x0 = (int)floorf(max_f(lo_x, 0.0f)), y0 = (int)floorf(max_f(lo_y, 0.0f));
    int x1 = (int)floorf(min_f(hi_x, (float)s->width - 1.0f)), y1 = (int)floorf(min_f(hi_y, (float)s->height - 1.0f));
    triangle t[2] = { triangle_setup(g, corner, 0, 1, 2), triangle_setup(g, corner, 0, 2, 3) };
    for (int py = y0; py <= y1; ++py) {
        size_t first = ((size_t)py * s->width + (size_t)x0) * s->spp, count = (size_t)(x1 - x0 + 1) * s->spp;
        const float *at = s->positions + first * 2;
        uint64_t *values = s->values + first;
        for (size_t k = 0; k < count; ++k) {
            sample_triangle(g, &t[0], at[2 * k], at[2 * k + 1], &values[k]);
            sample_triangle(g, &t[1], at[2 * k], at[2 * k + 1], &values[k]);
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
