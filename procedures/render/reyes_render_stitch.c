/* The crack-stitching passes of a render (--crack-fix stitch): a first
 * pass over the whole image records the sub-patches bound and split chose
 * to dice, reyes_stitch_plan.c plans the stitches between them, and each
 * bucket is then seeded with the leaves and stitches that reach it. */
#include <stdlib.h>
#include <string.h>

#include "reyes_render_internal.h"
#include "reyes_renderer_internal.h"

/* A leaf's place in the front-to-back order: its hull's nearest clip w,
 * then its index (a total order: the same seeds on every run). */
typedef struct near_key {
    float near_w;
    size_t leaf;
} near_key;

static int compare_near(const void *pa, const void *pb)
{
    const near_key *a = pa, *b = pb;
    if (a->near_w != b->near_w)
        return a->near_w < b->near_w ? -1 : 1;
    return a->leaf < b->leaf ? -1 : a->leaf > b->leaf;
}

/* The order dice takes its seeds in: with occlusion culling the leaves
 * front to back, so the near grids are rasterized before the far ones
 * they hide are tested (reyes_occlusion.cl); without it the order changes
 * nothing, and the leaves stay as recorded (no sort). */
static reyes_status order_seeds(render_buffers *b, reyes_error *error)
{
    size_t count = b->leaf_count ? b->leaf_count : 1;
    b->near_order = malloc(count * sizeof *b->near_order);
    if (!b->near_order)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu grids", b->leaf_count);
    if (!b->params.occlusion_cull) {
        for (size_t l = 0; l < b->leaf_count; ++l)
            b->near_order[l] = l;
        return REYES_OK;
    }
    near_key *keys = malloc(count * sizeof *keys);
    if (!keys)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu grids", b->leaf_count);
    for (size_t l = 0; l < b->leaf_count; ++l)
        keys[l] = (near_key){ b->leaves[l].near_w, l };
    qsort(keys, b->leaf_count, sizeof *keys, compare_near);
    for (size_t l = 0; l < b->leaf_count; ++l)
        b->near_order[l] = keys[l].leaf;
    free(keys);
    return REYES_OK;
}

/* First pass of crack stitching, over the whole image: bound and split
 * record the sub-patches to dice (retrying with a larger buffer if they
 * did not fit), then the stitch plan is built from them. */
reyes_status render_subdivide_and_plan(reyes_renderer *r, const reyes_scene *scene, const reyes_options *o,
                                       render_buffers *b, reyes_stats *stats, reyes_error *error)
{
    tile whole = { 0, 0, o->width, o->height };
    render_set_tile(&b->params, o, whole);
    b->params.record_leaves = 1;
    b->leaf_capacity = scene->patch_count * 16 + 1024;
    /* This pass (bound and split only) starts from the initial capacities,
     * not from what an earlier render's last run grew them to (the whole
     * pipeline, perhaps over the whole image): its peak queue memory is its
     * own, so a bucketed render's peak_queue_bytes is its largest bucket's
     * whenever the buckets need more than this pass. */
    perma_forget_capacities(r->rt);
    for (;;) {
        struct reyes_leaf *grown = realloc(b->leaves, b->leaf_capacity * sizeof *grown);
        if (!grown)
            return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu grids",
                              b->leaf_capacity);
        b->leaves = grown;
        b->params.leaf_capacity = (uint32_t)b->leaf_capacity;
        memset(b->counters, 0, sizeof b->counters);
        reyes_stats attempt = *stats;
        const char *call = "";
        size_t peak;
        perma_status ps = render_run_tile(r, scene, b, &attempt, &peak, &call);
        if (ps != PERMA_OK)
            return reyes_runtime_error(r, call, ps, error);
        size_t recorded = b->counters[REYES_COUNT_LEAVES];
        if (recorded <= b->leaf_capacity) {
            *stats = attempt;
            b->leaf_count = recorded;
            break;
        }
        b->leaf_capacity = recorded;
    }
    b->params.record_leaves = 0;
    /* The buckets need much smaller queues than this pass over the whole
     * image: let them grow their own. */
    perma_forget_capacities(r->rt);
    reyes_leaves_sort(b->leaves, b->leaf_count);
    reyes_status ordered = order_seeds(b, error);
    if (ordered != REYES_OK)
        return ordered;
    b->dice_seeds = malloc((b->leaf_count ? b->leaf_count : 1) * sizeof *b->dice_seeds);
    if (!b->dice_seeds)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu grids", b->leaf_count);
    reyes_status status = reyes_stitch_plan_build(scene, b->leaves, b->leaf_count, o->shading_rate > 0.0f, &b->plan,
                                                  error);
    if (status != REYES_OK)
        return status;
    b->stitch_seeds = malloc((b->plan.item_count ? b->plan.item_count : 1) * sizeof *b->stitch_seeds);
    if (!b->stitch_seeds)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu stitches",
                          b->plan.item_count);
    return REYES_OK;
}

/* 1 if screen box (lo_x, lo_y, hi_x, hi_y) reaches tile t widened by the
 * cull margin; always 1 without buckets. */
static int box_meets_tile(const reyes_options *o, tile t, float lo_x, float lo_y, float hi_x,
                          float hi_y)
{
    if (o->bucket_width == 0)
        return 1;
    float mx = o->cull_margin * 0.5f * (float)o->width, my = o->cull_margin * 0.5f * (float)o->height;
    return hi_x >= (float)t.x0 - mx && lo_x <= (float)t.x1 + mx && hi_y >= (float)t.y0 - my
           && lo_y <= (float)t.y1 + my;
}

/* The stitched seeds of tile t: leaves and stitch items whose screen box
 * reaches it; the leaves left out (and those bound found to cover no
 * sample) count as culled. */
void render_select_stitched_seeds(const reyes_options *o, tile t, render_buffers *b)
{
    b->dice_seed_count = b->stitch_seed_count = 0;
    for (size_t l = 0; l < b->leaf_count; ++l) {
        const struct reyes_leaf *leaf = &b->leaves[b->near_order[l]];
        if (!(leaf->sp.dice_size & REYES_DICE_NO_SAMPLE)
            && box_meets_tile(o, t, leaf->lo_x, leaf->lo_y, leaf->hi_x, leaf->hi_y))
            b->dice_seeds[b->dice_seed_count++] = leaf->sp;
        else
            ++b->counters[REYES_COUNT_CULLED];
    }
    for (size_t k = 0; k < b->plan.item_count; ++k) {
        const float *box = b->plan.item_boxes[k];
        if (box_meets_tile(o, t, box[0], box[1], box[2], box[3]))
            b->stitch_seeds[b->stitch_seed_count++] = b->plan.items[k];
    }
}
