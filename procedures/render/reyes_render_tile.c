/* One perma run over one tile of a render: point the parameters at the
 * tile, bind the buffers, seed, run, add the statistics.  Below both the
 * bucket loop (reyes_render.c) and the crack-stitching passes
 * (reyes_render_stitch.c), which call it. */
#include "reyes_render_internal.h"
#include "reyes_render_stats.h"
#include "reyes_renderer_internal.h"

/* Point the parameters at one tile: its pixel rectangle and its
 * sub-frustum in normalised device coordinates (exactly -1 and 1 at the
 * image borders, so the whole image culls as without buckets). */
void render_set_tile(struct reyes_params *p, const reyes_options *o, tile t)
{
    p->tile_x0 = (float)t.x0;
    p->tile_y0 = (float)t.y0;
    p->tile_x1 = (float)t.x1;
    p->tile_y1 = (float)t.y1;
    p->ndc_left = (float)(2.0 * t.x0 / o->width - 1.0);
    p->ndc_right = (float)(2.0 * t.x1 / o->width - 1.0);
    p->ndc_top = (float)(1.0 - 2.0 * t.y0 / o->height);
    p->ndc_bottom = (float)(1.0 - 2.0 * t.y1 / o->height);
}

/* Bind every buffer for a run (unused ones get a dummy). */
static perma_status bind_buffers(reyes_renderer *r, const reyes_scene *scene, render_buffers *b)
{
    static struct reyes_leaf no_leaf;
    static struct reyes_stitch_piece no_piece;
    perma_runtime *rt = r->rt;
    perma_status s = perma_bind_host(rt, "patches", "__global const float4 *", (void *)b->points,
                                     scene->patch_count * 64 * sizeof(float), PERMA_READ);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "colors", "__global const uint *", scene->colors,
                            scene->patch_count * sizeof(uint32_t), PERMA_READ);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "params", "__global const struct reyes_params *", &b->params,
                            sizeof b->params, PERMA_READ);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "counters", "__global uint *", b->counters, sizeof b->counters,
                            PERMA_READ_WRITE);
    /* The first pass of stitching rasterizes nothing (its tile, the whole
     * image, may be larger than the sample buffer). */
    int recording = b->params.record_leaves != 0;
    if (s == PERMA_OK)
        s = perma_bind_cl(rt, "samples", "__global ulong *", r->samples);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "leaves", "__global struct reyes_leaf *",
                            recording ? (void *)b->leaves : (void *)&no_leaf,
                            recording ? b->leaf_capacity * sizeof *b->leaves : sizeof no_leaf,
                            recording ? PERMA_WRITE : PERMA_READ);
    static uint8_t no_map;
    int has_map = b->map.gray != NULL;
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "displacement_map", "__global const uchar *",
                            has_map ? (void *)b->map.gray : (void *)&no_map,
                            has_map ? (size_t)b->map.width * b->map.height : 1, PERMA_READ);
    static reyes_blur_tuple no_tuple;
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "blur_tuples", "__global const float4 *",
                            b->tuples ? (void *)b->tuples : (void *)&no_tuple,
                            b->tuples ? b->tuple_count * sizeof *b->tuples : sizeof no_tuple, PERMA_READ);
    int pieces = b->plan.piece_count > 0;
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "pieces", "__global const struct reyes_stitch_piece *",
                            pieces ? (void *)b->plan.pieces : (void *)&no_piece,
                            pieces ? b->plan.piece_count * sizeof *b->plan.pieces : sizeof no_piece,
                            PERMA_READ);
    return s;
}

/* Seed the run: bound with every base patch, or (stitched) dice with the
 * bucket's leaves and stitch with its items. */
static perma_status seed(reyes_renderer *r, const reyes_scene *scene, render_buffers *b)
{
    if (!b->stitched || b->params.record_leaves)
        return perma_seed(r->rt, r->procs[REYES_PROC_BOUND], b->seeds, scene->patch_count);
    perma_status s = PERMA_OK;
    if (b->dice_seed_count)
        s = perma_seed(r->rt, r->procs[REYES_PROC_DICE], b->dice_seeds, b->dice_seed_count);
    if (s == PERMA_OK && b->stitch_seed_count)
        s = perma_seed(r->rt, r->procs[REYES_PROC_STITCH], b->stitch_seeds, b->stitch_seed_count);
    return s;
}

/* Add the last run's runtime statistics to *stats; *peak_bytes: its peak
 * queue memory. */
static perma_status add_run_stats(reyes_renderer *r, reyes_stats *stats, size_t *peak_bytes)
{
    perma_stats run;
    perma_procedure_stats procedures[REYES_PROC_COUNT];
    perma_status s = perma_get_stats(r->rt, &run);
    for (int p = 0; p < REYES_PROC_COUNT && s == PERMA_OK; ++p)
        s = perma_get_procedure_stats(r->rt, r->procs[p], &procedures[p]);
    if (s == PERMA_OK) {
        reyes_stats_add_run(stats, &run, procedures);
        *peak_bytes = run.peak_queue_bytes;
    }
    return s;
}

/* One perma run over the tile in b->params with the seeds of the current
 * mode; adds its statistics.  *call names what failed. */
perma_status render_run_tile(reyes_renderer *r, const reyes_scene *scene, render_buffers *b, reyes_stats *stats,
                             size_t *peak_bytes, const char **call)
{
    *call = "binding the scene";
    perma_status ps = bind_buffers(r, scene, b);
    if (ps == PERMA_OK)
        ps = seed(r, scene, b);
    if (ps == PERMA_OK) {
        *call = "perma_run";
        ps = perma_run(r->rt);
    }
    if (ps == PERMA_OK) {
        *call = "reading the statistics";
        ps = add_run_stats(r, stats, peak_bytes);
    }
    return ps;
}
