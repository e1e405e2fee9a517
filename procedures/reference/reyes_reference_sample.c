/*
 * The C reference's sampling: each visible quad of a diced grid as two
 * triangles over the samples it may cover, with reyes_sample.cl's jittered
 * positions, canonical (watertight) edge functions and nearest-wins
 * (depth, colour) values.  Built at -O3 (meson.build).
 *
 * A sample lies in its own stratum of its pixel (a cell of the columns x
 * rows lattice), so only the strata that a quad's screen box reaches can
 * hold samples it covers.  At the default bound and grid a micropolygon is
 * about a stratum (it reaches one or two strata across and down) and most
 * cover no sample at all; with a shading rate of 1 it is about a pixel.
 * So a grid row's quads are handled side by side, in loops over the row
 * that the compiler vectorises (structure of arrays, no branches): their
 * set-up (screen box, visibility, strata, both triangles' edges), then for
 * each of the strata they reach, the sample there (its position made from
 * its pixel and index by the hash, as the device does) tested against
 * both triangles.  Only the samples covered take a branch: their values
 * are made and stored one by one (made for every lane in the vector loop
 * instead, they cost half as much again at the default bound).  The few
 * quads that reach more strata are sampled one by one.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_look.h"
#include "reyes_reference_internal.h"

reyes_status reference_samples_create(reference_samples *s, unsigned width, unsigned height, unsigned spp,
                                      int concurrent, reyes_error *error)
{
    memset(s, 0, sizeof *s);
    s->width = width;
    s->height = height;
    s->spp = spp;
    s->concurrent = concurrent;
    s->columns = 1;
    while (s->columns * s->columns < spp) /* reyes_sample_columns: ceil(sqrt(spp)) */
        ++s->columns;
    s->rows = (spp + s->columns - 1) / s->columns;
    size_t count = (size_t)width * height * spp;
    s->values = malloc(count * sizeof *s->values);
    if (!s->values)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for the samples of a %ux%u image", width,
                          height);
    memset(s->values, 0xff, count * sizeof *s->values);
    return REYES_OK;
}

void reference_samples_free(reference_samples *s)
{
    free(s->values);
    memset(s, 0, sizeof *s);
}

static inline int min_i(int a, int b)
{
    return a < b ? a : b;
}

static inline int max_i(int a, int b)
{
    return a > b ? a : b;
}

static inline uint32_t channel_byte(float value)
{
    float scaled = min_f(max_f(value, 0.0f), 1.0f) * 255.0f;
    return (uint32_t)(int32_t)((scaled + 8388608.0f) - 8388608.0f);
}

/* Quads whose box reaches at most this many strata across and down are
 * sampled side by side (a step through the strata for all of a row's
 * quads at once: as many steps as the row's widest and tallest quad
 * reaches), the others one by one: 4 takes in the micropolygons of the
 * default bound and grid (about a stratum: 2 x 2) and of a shading rate of
 * 1 (about a pixel, up to 4 x 4 with the margin). */
#define SMALL_STRATA 4

/* Samples further than this outside a quad's screen box are not tested:
 * rounding never puts a covered sample anywhere near that far out, so the
 * result is that of testing every sample of the box's pixels. */
#define BOX_MARGIN (1.0f / 64.0f)

/* Lanes of a grid row's quads: 16 for grids of up to 17 vertices a side,
 * else 32 (REFERENCE_ROW_LANES); the lanes past the row's quads are dead
 * (they read the next row's vertices or the grid's padding).  A fixed
 * count lets the compiler vectorise the row loops without remainders. */
#define ROW_QUADS REFERENCE_ROW_LANES

/* The edges of a quad's triangles (0,1,2) and (0,2,3) (corners 0-3 around
 * it), each with its end points in a fixed order (edge(a,b,p) ==
 * -edge(b,a,p) exactly, so a sample on an edge shared by two triangles is
 * inside the same way for both): the lower end point, the difference to the
 * upper one and -1 where they were swapped.  The diagonal (2,0) serves both
 * triangles, negated for the second's (0,2). */
enum { EDGE_12, EDGE_20, EDGE_01, EDGE_23, EDGE_30, EDGES };

/* A grid row's quads, set up side by side, and the samples of one of the
 * strata each reaches. */
typedef struct quad_row {
    float lo_x[ROW_QUADS], lo_y[ROW_QUADS], hi_x[ROW_QUADS], hi_y[ROW_QUADS]; /* box and margin */
    int live[ROW_QUADS];                                                     /* visible */
    int sx0[ROW_QUADS], sy0[ROW_QUADS];   /* first stratum reached */
    int wide[ROW_QUADS], tall[ROW_QUADS]; /* strata reached beyond it, across and down */
    float edge_x[EDGES][ROW_QUADS], edge_y[EDGES][ROW_QUADS];
    float edge_dx[EDGES][ROW_QUADS], edge_dy[EDGES][ROW_QUADS], edge_sign[EDGES][ROW_QUADS];
    float area[2][ROW_QUADS];
    /* A candidate sample per quad: position, pixel and index, and which
     * triangles cover it (bit 0: (0,1,2), bit 1: (0,2,3)). */
    float x[ROW_QUADS], y[ROW_QUADS];
    int px[ROW_QUADS], py[ROW_QUADS], k[ROW_QUADS], hit[ROW_QUADS];
} quad_row;

/* Edge e of quads [0, count) from end points a to b. */
REFERENCE_VECTOR_HELPER void edge_setup(quad_row *q, int e, unsigned count, const float *restrict ax,
                              const float *restrict ay, const float *restrict bx, const float *restrict by)
{
    float *restrict lx = q->edge_x[e], *restrict ly = q->edge_y[e];
    float *restrict dx = q->edge_dx[e], *restrict dy = q->edge_dy[e], *restrict sign = q->edge_sign[e];
    for (unsigned i = 0; i < count; ++i) {
        int swap = (ax[i] > bx[i]) | ((ax[i] == bx[i]) & (ay[i] > by[i]));
        lx[i] = swap ? bx[i] : ax[i];
        ly[i] = swap ? by[i] : ay[i];
        dx[i] = (swap ? ax[i] : bx[i]) - lx[i];
        dy[i] = (swap ? ay[i] : by[i]) - ly[i];
        sign[i] = swap ? -1.0f : 1.0f;
    }
}

static inline float edge_at(const quad_row *q, int e, unsigned i, float x, float y)
{
    return q->edge_sign[e][i] * (q->edge_dx[e][i] * (y - q->edge_y[e][i]) - q->edge_dy[e][i] * (x - q->edge_x[e][i]));
}

/* Set up the count quads between vertex rows top and bottom (corners
 * top[i], top[i + 1], bottom[i + 1], bottom[i]) in `lanes` lanes; returns
 * how many are visible (in front of the near plane and on the image).
 * Without samples (a geometry-only run) only that. */
REFERENCE_VECTOR_HELPER unsigned quad_row_setup(quad_row *q, const reference_samples *s, const reference_grid *g,
                                      unsigned top, unsigned bottom, unsigned count, unsigned lanes, float width,
                                      float height)
{
    const float *x0 = g->sx + top, *x1 = g->sx + top + 1, *x2 = g->sx + bottom + 1, *x3 = g->sx + bottom;
    const float *y0 = g->sy + top, *y1 = g->sy + top + 1, *y2 = g->sy + bottom + 1, *y3 = g->sy + bottom;
    const unsigned char *f0 = g->front + top, *f1 = g->front + top + 1, *f2 = g->front + bottom + 1;
    const unsigned char *f3 = g->front + bottom;
    int ci = s ? (int)s->columns : 1, ri = s ? (int)s->rows : 1;
    float columns = (float)ci, rows = (float)ri;
    unsigned visible = 0;
    for (unsigned i = 0; i < lanes; ++i) {
        float lo_x = min_f(min_f(x0[i], x1[i]), min_f(x2[i], x3[i]));
        float hi_x = max_f(max_f(x0[i], x1[i]), max_f(x2[i], x3[i]));
        float lo_y = min_f(min_f(y0[i], y1[i]), min_f(y2[i], y3[i]));
        float hi_y = max_f(max_f(y0[i], y1[i]), max_f(y2[i], y3[i]));
        int front = f0[i] & f1[i] & f2[i] & f3[i] & (i < count);
        int live = front & !(hi_x < 0.0f) & !(hi_y < 0.0f) & !(lo_x > width) & !(lo_y > height);
        q->live[i] = live;
        visible += (unsigned)live;
        /* The pixel box (clamped to the image; never negative, so the casts
         * are floors), then the strata that the box and margin reach in it. */
        int px0 = (int)max_f(lo_x, 0.0f), py0 = (int)max_f(lo_y, 0.0f);
        int px1 = (int)min_f(max_f(hi_x, 0.0f), width - 1.0f), py1 = (int)min_f(max_f(hi_y, 0.0f), height - 1.0f);
        q->lo_x[i] = lo_x - BOX_MARGIN;
        q->lo_y[i] = lo_y - BOX_MARGIN;
        q->hi_x[i] = hi_x + BOX_MARGIN;
        q->hi_y[i] = hi_y + BOX_MARGIN;
        int sx0 = max_i((int)(max_f(lo_x - BOX_MARGIN, 0.0f) * columns), px0 * ci);
        int sy0 = max_i((int)(max_f(lo_y - BOX_MARGIN, 0.0f) * rows), py0 * ri);
        int sx1 = min_i((int)(min_f(max_f(hi_x + BOX_MARGIN, 0.0f), width) * columns), (px1 + 1) * ci - 1);
        int sy1 = min_i((int)(min_f(max_f(hi_y + BOX_MARGIN, 0.0f), height) * rows), (py1 + 1) * ri - 1);
        q->sx0[i] = sx0;
        q->sy0[i] = sy0;
        q->wide[i] = sx1 - sx0;
        q->tall[i] = sy1 - sy0;
    }
    if (!s || !visible)
        return visible;
    edge_setup(q, EDGE_12, lanes, x1, y1, x2, y2);
    edge_setup(q, EDGE_20, lanes, x2, y2, x0, y0);
    edge_setup(q, EDGE_01, lanes, x0, y0, x1, y1);
    edge_setup(q, EDGE_23, lanes, x2, y2, x3, y3);
    edge_setup(q, EDGE_30, lanes, x3, y3, x0, y0);
    for (unsigned i = 0; i < lanes; ++i) {
        q->area[0][i] = edge_at(q, EDGE_01, i, x2[i], y2[i]);
        q->area[1][i] = -edge_at(q, EDGE_20, i, x3[i], y3[i]);
    }
    return visible;
}

/* Which of quad i's triangles cover (x, y) (bit 0: (0,1,2), bit 1:
 * (0,2,3)); edges inclusive, never a triangle without area. */
static inline int covers(const quad_row *q, unsigned i, float x, float y)
{
    float diagonal = edge_at(q, EDGE_20, i, x, y);
    float w12 = edge_at(q, EDGE_12, i, x, y), w01 = edge_at(q, EDGE_01, i, x, y);
    float w23 = edge_at(q, EDGE_23, i, x, y), w30 = edge_at(q, EDGE_30, i, x, y);
    float area0 = q->area[0][i], area1 = q->area[1][i];
    int in0 = area0 > 0.0f ? (w12 >= 0.0f) & (diagonal >= 0.0f) & (w01 >= 0.0f)
                           : (w12 <= 0.0f) & (diagonal <= 0.0f) & (w01 <= 0.0f);
    int in1 = area1 > 0.0f ? (w23 >= 0.0f) & (w30 >= 0.0f) & (diagonal <= 0.0f)
                           : (w23 <= 0.0f) & (w30 <= 0.0f) & (diagonal >= 0.0f);
    return (in0 & (area0 != 0.0f)) | ((in1 & (area1 != 0.0f)) << 1);
}

/* The samples in stratum (sx0 + dx, sy0 + dy) of the quads in `lanes` of
 * the row that reach at most two strata across and down: q->hit says which
 * triangles cover it. */
REFERENCE_VECTOR_HELPER void row_candidates(quad_row *q, const reference_samples *s, unsigned lanes, int dx, int dy)
{
    int columns = (int)s->columns, rows = (int)s->rows, spp = (int)s->spp;
    for (unsigned i = 0; i < lanes; ++i) {
        float x, y;
        int px, py, k;
        reference_stratum_sample(q->sx0[i] + dx, q->sy0[i] + dy, columns, rows, &x, &y, &px, &py, &k);
        int small = (q->wide[i] < SMALL_STRATA) & (q->tall[i] < SMALL_STRATA);
        int ok = q->live[i] & small & (dx <= q->wide[i]) & (dy <= q->tall[i]) & (k < spp)
                 & (x >= q->lo_x[i]) & (x <= q->hi_x[i]) & (y >= q->lo_y[i]) & (y <= q->hi_y[i]);
        q->hit[i] = ok ? covers(q, i, x, y) : 0;
        q->x[i] = x;
        q->y[i] = y;
        q->px[i] = px;
        q->py[i] = py;
        q->k[i] = k;
    }
}

/* The packed (depth << 32 | rgba) of triangle (a, b, c) with signed area
 * `area` at a covered point with edge values wa, wb, wc. */
static inline uint64_t triangle_value(const reference_grid *g, float area, unsigned a, unsigned b, unsigned c,
                                      float wa, float wb, float wc)
{
    float inv_area = 1.0f / area;
    float ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
    /* Never below the corners' least depth, as the renderer's
     * (reyes_interpolated_depth): occlusion culling relies on it. */
    float nearest = max_f(min_f(min_f(g->w[a], g->w[b]), g->w[c]), 0.0f);
    float depth = max_f(ba * g->w[a] + bb * g->w[b] + bc * g->w[c], nearest);
    uint32_t rgba = 255u << 24;
    for (int ch = 0; ch < 3; ++ch) {
        const float *color = g->color[ch];
        rgba |= channel_byte(ba * color[a] + bb * color[b] + bc * color[c]) << (8 * ch);
    }
    union { float f; uint32_t u; } bits = { depth };
    return (uint64_t)bits.u << 32 | rgba;
}

/* Keep the smaller of a sample's value and `value`; with several threads
 * writing one buffer, by compare-and-swap (values only decrease, so a
 * sample already nearer is left alone without one). */
static inline void store_nearer(const reference_samples *s, uint64_t *slot, uint64_t value)
{
    if (!s->concurrent) {
        if (value < *slot)
            *slot = value;
        return;
    }
    uint64_t old = __atomic_load_n(slot, __ATOMIC_RELAXED);
    while (value < old && !__atomic_compare_exchange_n(slot, &old, value, 1, __ATOMIC_RELAXED, __ATOMIC_RELAXED))
        ;
}

/* Store the nearer of the covering triangles' values at sample k of pixel
 * (px, py), which quad i of the row (corners top + i, top + i + 1,
 * bottom + i + 1, bottom + i) covers as `hit` says. */
static void store_sample(const reference_samples *s, const reference_grid *g, const quad_row *q, unsigned i,
                         unsigned top, unsigned bottom, int hit, float x, float y, int px, int py, int k)
{
    unsigned a = top + i, b = top + i + 1, c = bottom + i + 1, d = bottom + i;
    float diagonal = edge_at(q, EDGE_20, i, x, y);
    uint64_t value = REYES_EMPTY_SAMPLE;
    if (hit & 1)
        value = triangle_value(g, q->area[0][i], a, b, c, edge_at(q, EDGE_12, i, x, y), diagonal,
                               edge_at(q, EDGE_01, i, x, y));
    if (hit & 2) {
        uint64_t second = triangle_value(g, q->area[1][i], a, c, d, edge_at(q, EDGE_23, i, x, y),
                                         edge_at(q, EDGE_30, i, x, y), -diagonal);
        value = second < value ? second : value;
    }
    store_nearer(s, s->values + ((size_t)py * s->width + (size_t)px) * s->spp + (size_t)k, value);
}

/* Quad i of the row over every stratum it reaches, one by one. */
static void sample_large_quad(const reference_samples *s, const reference_grid *g, const quad_row *q, unsigned i,
                              unsigned top, unsigned bottom)
{
    int columns = (int)s->columns, rows = (int)s->rows;
    for (int dy = 0; dy <= q->tall[i]; ++dy) {
        for (int dx = 0; dx <= q->wide[i]; ++dx) {
            float x, y;
            int px, py, k;
            reference_stratum_sample(q->sx0[i] + dx, q->sy0[i] + dy, columns, rows, &x, &y, &px, &py, &k);
            if (k >= (int)s->spp || !((x >= q->lo_x[i]) & (x <= q->hi_x[i]) & (y >= q->lo_y[i]) & (y <= q->hi_y[i])))
                continue;
            int hit = covers(q, i, x, y);
            if (hit)
                store_sample(s, g, q, i, top, bottom, hit, x, y, px, py, k);
        }
    }
}

/* The grid's quads row by row in `lanes` lanes (a constant where inlined). */
REFERENCE_VECTOR_HELPER uint64_t sample_rows(const reference_context *c, const reference_grid *g, unsigned lanes)
{
    const reference_samples *s = c->samples;
    unsigned n = g->columns, count = n - 1;
    float width = (float)c->o->width, height = (float)c->o->height;
    uint64_t visible = 0;
    quad_row q;
    for (unsigned j = 0; j + 1 < g->rows; ++j) {
        unsigned top = j * n, bottom = top + n;
        unsigned row_visible = quad_row_setup(&q, s, g, top, bottom, count, lanes, width, height);
        visible += row_visible;
        if (!s || !row_visible)
            continue;
        int wide = 0, tall = 0, large = 0;
        for (unsigned i = 0; i < lanes; ++i) {
            int small = q.live[i] & (q.wide[i] < SMALL_STRATA) & (q.tall[i] < SMALL_STRATA);
            wide = max_i(wide, small ? q.wide[i] : 0);
            tall = max_i(tall, small ? q.tall[i] : 0);
            large |= q.live[i] & !small;
        }
        for (int dy = 0; dy <= tall; ++dy) {
            for (int dx = 0; dx <= wide; ++dx) {
                row_candidates(&q, s, lanes, dx, dy);
                for (unsigned i = 0; i < count; ++i)
                    if (q.hit[i])
                        store_sample(s, g, &q, i, top, bottom, q.hit[i], q.x[i], q.y[i], q.px[i], q.py[i], q.k[i]);
            }
        }
        if (large)
            for (unsigned i = 0; i < count; ++i)
                if (q.live[i] && (q.wide[i] >= SMALL_STRATA || q.tall[i] >= SMALL_STRATA))
                    sample_large_quad(s, g, &q, i, top, bottom);
    }
    return visible;
}

REFERENCE_MACHINE_CLONES uint64_t reference_sample_grid(const reference_context *c, const reference_grid *g)
{
    return g->columns <= 17 ? sample_rows(c, g, 16) : sample_rows(c, g, REFERENCE_ROW_LANES);
}
