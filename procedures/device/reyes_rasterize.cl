/*
 * Rasterization of one diced grid (or a sub-patch's wedge strips), struct
 * reyes_grid of reyes_grid.cl, by the work-item that diced it, from its
 * __local scratch (reyes_dice.cl): a grid never goes through a queue.
 * Every sample in a quad's pixel box is tested against both of its
 * triangles; a covered sample stores (depth, color) with a 64-bit atomic
 * min, so the nearest surface wins whatever order work-items and
 * work-groups write in, and equal depths break ties by color.  Edges are
 * inclusive: a sample on an edge shared by two triangles may be written
 * twice, which the min makes harmless, and none is lost.
 *
 * Sharp quads are sampled sixteen at a time in SIMD lanes
 * (reyes_sharp_quads.cl, before this file); blurred quads take the
 * general loops of reyes_blur.cl.  This file holds what rasterizes a
 * grid: the entry reyes_rasterize, the blurred grids, the prefetch of
 * the samples and the micropolygons' area statistics.
 */

/* What rasterization reads and writes: the buffers dice's perma_ctx binds
 * (this file comes before the runtime's definitions). */
struct reyes_raster_target {
    __global const struct reyes_params *params;
    __global ulong *samples;
    __global uint *counters;
    __global const float4 *blur_tuples;
    __global const float4 *patches; /* for sample shading's derivative nets */
};

/* The micropolygons' areas (reyes_params.area_stats): a grid's quads
 * are tallied in private bins, then added to the counters once per bin
 * that got any (REYES_COUNT_AREA_*, reyes_shared.h). */
struct reyes_area_tally {
    uint bins[REYES_AREA_BINS];
    float16 sum;
};

REYES_INLINE void reyes_area_tally_init(struct reyes_area_tally *t)
{
    for (int b = 0; b < REYES_AREA_BINS; ++b)
        t->bins[b] = 0u;
    t->sum = (float16)0.0f;
}

/* The live quads' areas (half the two triangles' doubled areas): bin
 * (bits >> 22) - 233 is 2 e + h + 1 for an area of 2^e (1 + h / 2 ...)
 * with e >= -10, clamped to the first and last bins. */
REYES_INLINE void reyes_area_tally_add(struct reyes_area_tally *t, const struct reyes_quad_lanes *q)
{
    float16 area = select((float16)0.0f, 0.5f * (fabs(q->area[0]) + fabs(q->area[1])), q->live);
    t->sum += area;
    int16 bin = clamp((as_int16(area) >> 22) - 233, 0, REYES_AREA_BINS - 1);
    uint live = reyes_lane_bits16(q->live);
    while (live) {
        int l = 31 - (int)clz(live & (0u - live));
        live &= live - 1u;
        ++t->bins[((int *)&bin)[l]];
    }
}

REYES_INLINE void reyes_area_tally_flush(const struct reyes_area_tally *t, __global uint *counters)
{
    float8 a = t->sum.lo + t->sum.hi;
    float4 b = a.lo + a.hi;
    float2 c = b.lo + b.hi;
    ulong units = convert_ulong_sat_rte((c.x + c.y) * REYES_AREA_UNITS);
    if (units > 0ul)
        atom_add((__global ulong *)(counters + REYES_COUNT_AREA_SUM), units);
    for (int b = 0; b < REYES_AREA_BINS; ++b)
        if (t->bins[b] > 0u)
            atomic_add(&counters[REYES_COUNT_AREA_BINS + b], t->bins[b]);
}


/* Blurred items: each visible quad with the configured algorithm. */
void reyes_rasterize_blurred_grid(const struct reyes_raster_target *t, __local const struct reyes_grid *item)
{
    __global const struct reyes_params *p = t->params;
    int slots = (int)(item->rows - 1u) * (int)item->columns;
    uint visible = 0;
    for (int k = 0; k < slots; ++k) {
        if (!reyes_grid_visible(p, item, k))
            continue;
        ++visible;
        struct reyes_moving_quad m = reyes_grid_moving(p, item, k);
        reyes_rasterize_blurred(p, t->blur_tuples, t->samples, &m, 2);
    }
    if (item->counted && visible > 0u)
        atomic_add(&t->counters[REYES_COUNT_MICROPOLYGONS], visible);
}

/* Ask for the cache lines of the samples under the grid's screen box
 * (its vertices in front of the eye, clipped to the tile) before sampling
 * it: the sample buffer is far larger than the caches (42 MB at
 * 1280x1024, 4 spp), and without this about a third of the small quads'
 * time was spent waiting for its lines.  A hint only (no effect on any
 * result); at most REYES_PREFETCH_LINES lines, none for a box larger than
 * that.  x86 CPU devices only (a GPU hides memory latency by running other
 * work-items), and not under Oclgrind, whose interpreter has no
 * llvm.prefetch. */
#define REYES_PREFETCH_LINES 512
REYES_INLINE void reyes_prefetch_samples(__global const struct reyes_params *p, __global const ulong *samples,
                                         __local const struct reyes_grid *g, uint spp)
{
#if defined(__clang__) && (defined(__x86_64__) || defined(__i386__)) && !defined(PERMA_RACE_CHECK)
    const int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    int count = (int)(g->rows * g->columns);
    float16 lo_x = (float16)INFINITY, lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;
    for (int k = 0; k < count; k += 16) {
        int16 in = (k + lane < count) & (vload16(0, g->z + k) > p->near_w);
        float16 x = vload16(0, g->x + k), y = vload16(0, g->y + k);
        lo_x = select(lo_x, fmin(lo_x, x), in);
        lo_y = select(lo_y, fmin(lo_y, y), in);
        hi_x = select(hi_x, fmax(hi_x, x), in);
        hi_y = select(hi_y, fmax(hi_y, y), in);
    }
    float8 a = fmin(lo_x.lo, lo_x.hi), b = fmin(lo_y.lo, lo_y.hi), c = fmax(hi_x.lo, hi_x.hi), d = fmax(hi_y.lo, hi_y.hi);
    float4 a4 = fmin(a.lo, a.hi), b4 = fmin(b.lo, b.hi), c4 = fmax(c.lo, c.hi), d4 = fmax(d.lo, d.hi);
    float x0 = fmax(fmin(fmin(a4.x, a4.y), fmin(a4.z, a4.w)), p->tile_x0);
    float y0 = fmax(fmin(fmin(b4.x, b4.y), fmin(b4.z, b4.w)), p->tile_y0);
    float x1 = fmin(fmax(fmax(c4.x, c4.y), fmax(c4.z, c4.w)), p->tile_x1 - 1.0f);
    float y1 = fmin(fmax(fmax(d4.x, d4.y), fmax(d4.z, d4.w)), p->tile_y1 - 1.0f);
    if (!(x0 <= x1 && y0 <= y1))
        return;
    uint tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0, tile_width = (uint)p->tile_x1 - tile_x;
    uint px0 = (uint)x0, px1 = (uint)x1, py0 = (uint)y0, py1 = (uint)y1;
    uint row_words = (px1 - px0 + 1u) * spp;
    if ((py1 - py0 + 1u) * (row_words / 8u + 2u) > REYES_PREFETCH_LINES)
        return;
    for (uint py = py0; py <= py1; ++py) {
        __global const ulong *row = samples + ((py - tile_y) * tile_width + (px0 - tile_x)) * spp;
        for (uint w = 0; w < row_words; w += 8u)
            __builtin_prefetch((__global const void *)(row + w), 1);
        __builtin_prefetch((__global const void *)(row + row_words - 1u), 1);
    }
#else
    (void)p;
    (void)samples;
    (void)g;
    (void)spp;
#endif
}

void reyes_rasterize(const struct reyes_raster_target *t, __local const struct reyes_grid *item)
{
    __global const struct reyes_params *p = t->params;
    if (p->blur) {
        reyes_rasterize_blurred_grid(t, item);
        return;
    }
    __global ulong *samples = t->samples;
    struct reyes_sample_chunks chunks;
    reyes_sample_chunks_init(&chunks, p->spp);
    reyes_prefetch_samples(p, samples, item, p->spp);
    struct reyes_derivative_net net;
    if (item->shading == REYES_SHADE_SURFACE)
        reyes_derivative_net_of(t->patches, item->patch, &net);
    int slots = (int)(item->rows - 1u) * (int)item->columns;
    /* Sixteen quads at a time set up in SIMD lanes, then the small ones
     * sampled side by side stratum by stratum and the larger ones one by
     * one. */
    int16 visible = (int16)0;
    struct reyes_area_tally tally;
    int tallied = item->counted && p->area_stats;
    if (tallied)
        reyes_area_tally_init(&tally);
    for (int first = 0; first < slots; first += 16) {
        struct reyes_quad_lanes quads = reyes_quad_setup_lanes(p, item, first, slots);
        visible -= quads.live; /* live lanes are -1 */
        if (!reyes_any16(quads.live))
            continue;
        if (tallied)
            reyes_area_tally_add(&tally, &quads);
        struct reyes_strata_lanes strata = reyes_strata_of(&quads, &chunks);
        int16 small = quads.live & (strata.x1 - strata.x0 < REYES_SMALL_STRATA)
                      & (strata.y1 - strata.y0 < REYES_SMALL_STRATA);
        if (reyes_any16(small))
            reyes_small_quads(p, samples, item, &quads, &strata, small, first, &chunks, &net);
        uint large = reyes_lane_bits16(quads.live & ~small);
        while (large) {
            int l = 31 - (int)clz(large & (0u - large));
            large &= large - 1u;
            reyes_quad_pixels(p, samples, item, &quads, l, first + l, &chunks, &net);
        }
    }
    if (item->counted) {
        /* The micropolygons: the quads set up live, the tests of
         * reyes_dice_count (which counts the grids of other renders). */
        uint count = (uint)reyes_sum16(visible);
        if (count > 0u)
            atomic_add(&t->counters[REYES_COUNT_MICROPOLYGONS], count);
        if (tallied)
            reyes_area_tally_flush(&tally, t->counters);
    }
}
