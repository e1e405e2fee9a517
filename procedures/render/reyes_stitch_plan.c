/* Crack stitching plan: neighbours across leaf edges (reyes_stitch_plan.h). */
#include <stdlib.h>
#include <string.h>

#include "reyes_stitch_glue.h"
#include "reyes_stitch_plan.h"

/* One edge of a leaf: along u (axis 0) or v (axis 1), on the line v or u =
 * `line`, spanning [s0,s1]; side 1: the leaf lies on the high side. */
typedef struct edge_record {
    uint32_t patch;
    uint32_t axis, side;
    float line, s0, s1;
    uint32_t leaf, edge;
    uint32_t vertices; /* segments along the edge with a shading rate (its byte of edge_levels), else 0 */
} edge_record;

/* A neighbour's edge covering part of an owner's edge. */
typedef struct registration {
    uint32_t owner, owner_edge, piece_leaf;
    struct reyes_stitch_piece piece;
} registration;

static int compare_float(float a, float b)
{
    return a < b ? -1 : a > b ? 1 : 0;
}

static int compare_leaves(const void *pa, const void *pb)
{
    const struct reyes_subpatch *a = &((const struct reyes_leaf *)pa)->sp;
    const struct reyes_subpatch *b = &((const struct reyes_leaf *)pb)->sp;
    if (a->patch != b->patch)
        return a->patch < b->patch ? -1 : 1;
    int c = compare_float(a->u0, b->u0);
    if (!c)
        c = compare_float(a->v0, b->v0);
    if (!c)
        c = compare_float(a->u1, b->u1);
    if (!c)
        c = compare_float(a->v1, b->v1);
    return c;
}

void reyes_leaves_sort(struct reyes_leaf *leaves, size_t count)
{
    qsort(leaves, count, sizeof *leaves, compare_leaves);
}

static int compare_records(const void *pa, const void *pb)
{
    const edge_record *a = pa, *b = pb;
    if (a->patch != b->patch)
        return a->patch < b->patch ? -1 : 1;
    if (a->axis != b->axis)
        return a->axis < b->axis ? -1 : 1;
    int c = compare_float(a->line, b->line);
    if (c)
        return c;
    if (a->side != b->side)
        return a->side < b->side ? -1 : 1;
    return compare_float(a->s0, b->s0);
}

static edge_record leaf_edge(const struct reyes_subpatch *sp, uint32_t leaf, uint32_t edge)
{
    edge_record r = { .patch = sp->patch, .leaf = leaf, .edge = edge };
    int along_u = edge == REYES_EDGE_V0 || edge == REYES_EDGE_V1;
    r.axis = along_u ? 0 : 1;
    r.side = edge == REYES_EDGE_V0 || edge == REYES_EDGE_U0;
    r.line = edge == REYES_EDGE_V0 ? sp->v0 : edge == REYES_EDGE_V1 ? sp->v1
             : edge == REYES_EDGE_U0 ? sp->u0 : sp->u1;
    r.s0 = along_u ? sp->u0 : sp->v0;
    r.s1 = along_u ? sp->u1 : sp->v1;
    /* With a shading rate each edge has its own count (reyes_rate.cl). */
    r.vertices = sp->dice_size ? (sp->edge_levels >> (8 * edge)) & 0xffu : 0u;
    return r;
}

/* The record of (patch, axis, line, side) whose span contains [s0,s1], or -1. */
static long find_record(const edge_record *records, size_t count, edge_record key)
{
    size_t lo = 0, hi = count;
    while (lo < hi) { /* first record > key (key.s0 compared as is) */
        size_t mid = lo + (hi - lo) / 2;
        if (compare_records(&records[mid], &key) <= 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo == 0)
        return -1;
    const edge_record *r = &records[lo - 1];
    if (r->patch != key.patch || r->axis != key.axis || r->line != key.line || r->side != key.side
        || r->s0 > key.s0 || r->s1 < key.s1)
        return -1;
    return (long)(lo - 1);
}

/* The record a leaf edge would meet across a patch boundary, as a search
 * key in the other patch; 0 if the boundary is not glued. */
static int across_boundary(const boundary_link *links, edge_record mine, edge_record *key,
                           uint32_t *reversed)
{
    uint32_t boundary = mine.axis == 0 ? (mine.line == 0.0f ? REYES_EDGE_V0 : REYES_EDGE_V1)
                                       : (mine.line == 0.0f ? REYES_EDGE_U0 : REYES_EDGE_U1);
    boundary_link link = links[mine.patch * 4 + boundary];
    if (link.patch < 0)
        return 0;
    *reversed = link.reversed;
    *key = (edge_record){ .patch = (uint32_t)link.patch };
    key->axis = link.boundary == REYES_EDGE_V0 || link.boundary == REYES_EDGE_V1 ? 0 : 1;
    key->line = link.boundary == REYES_EDGE_V0 || link.boundary == REYES_EDGE_U0 ? 0.0f : 1.0f;
    key->side = key->line == 0.0f;
    key->s0 = link.reversed ? 1.0f - mine.s1 : mine.s0;
    key->s1 = link.reversed ? 1.0f - mine.s0 : mine.s1;
    return 1;
}

/* Find the neighbour record across edge `mine`; if that neighbour owns the
 * shared span (it is longer, or as long in a lower patch, or as long with
 * fewer vertices), fill *out. */
static int register_edge(const edge_record *records, size_t count, const boundary_link *links,
                         edge_record mine, registration *out)
{
    edge_record key = mine;
    uint32_t reversed = 0;
    int on_boundary = mine.line == (mine.side ? 0.0f : 1.0f);
    if (on_boundary) {
        if (!across_boundary(links, mine, &key, &reversed))
            return 0;
    } else {
        key.side = !mine.side;
    }
    long found = find_record(records, count, key);
    if (found < 0)
        return 0;
    const edge_record *owner = &records[found];
    float owner_length = owner->s1 - owner->s0, length = mine.s1 - mine.s0;
    if (owner_length < length)
        return 0;
    if (owner_length == length) {
        /* Inside a base patch equal spans share their vertices, unless a
         * shading rate diced them at different counts: then the side with
         * fewer owns the span.  Across base patches the lower patch does. */
        int lower = owner->patch < mine.patch || (owner->patch == mine.patch && owner->edge < mine.edge);
        if (on_boundary ? !lower : owner->vertices >= mine.vertices)
            return 0;
    }
    out->owner = owner->leaf;
    out->owner_edge = owner->edge;
    out->piece_leaf = mine.leaf;
    out->piece.edge = mine.edge;
    out->piece.reversed = reversed;
    out->piece.t0 = (key.s0 - owner->s0) / owner_length;
    out->piece.t1 = (key.s1 - owner->s0) / owner_length;
    return 1;
}

static int compare_registrations(const void *pa, const void *pb)
{
    const registration *a = pa, *b = pb;
    if (a->owner != b->owner)
        return a->owner < b->owner ? -1 : 1;
    if (a->owner_edge != b->owner_edge)
        return a->owner_edge < b->owner_edge ? -1 : 1;
    return compare_float(a->piece.t0, b->piece.t0);
}

static void grow_box(float box[4], const struct reyes_leaf *leaf)
{
    box[0] = leaf->lo_x < box[0] ? leaf->lo_x : box[0];
    box[1] = leaf->lo_y < box[1] ? leaf->lo_y : box[1];
    box[2] = leaf->hi_x > box[2] ? leaf->hi_x : box[2];
    box[3] = leaf->hi_y > box[3] ? leaf->hi_y : box[3];
}

/* One stitch item per contiguous run of pieces of the same owner edge. */
static void make_items(const struct reyes_leaf *leaves, const registration *regs, size_t count,
                       reyes_stitch_plan *plan)
{
    for (size_t i = 0; i < count; ++i) {
        const registration *r = &regs[i];
        plan->pieces[i] = r->piece;
        plan->pieces[i].sp = leaves[r->piece_leaf].sp;
        int continues = i > 0 && regs[i - 1].owner == r->owner && regs[i - 1].owner_edge == r->owner_edge
                        && regs[i - 1].piece.t1 == r->piece.t0;
        if (!continues) {
            struct reyes_stitch *item = &plan->items[plan->item_count];
            *item = (struct reyes_stitch){ .owner = leaves[r->owner].sp, .edge = r->owner_edge,
                                           .first = (uint32_t)i, .count = 0 };
            float *box = plan->item_boxes[plan->item_count];
            box[0] = box[1] = 1e30f;
            box[2] = box[3] = -1e30f;
            grow_box(box, &leaves[r->owner]);
            ++plan->item_count;
        }
        ++plan->items[plan->item_count - 1].count;
        grow_box(plan->item_boxes[plan->item_count - 1], &leaves[r->piece_leaf]);
    }
    plan->piece_count = count;
}

reyes_status reyes_stitch_plan_build(const reyes_scene *scene, const struct reyes_leaf *leaves,
                                     size_t count, int near_seams, reyes_stitch_plan *plan, reyes_error *error)
{
    memset(plan, 0, sizeof *plan);
    size_t edges = count * 4;
    edge_record *records = malloc((edges ? edges : 1) * sizeof *records);
    registration *regs = malloc((edges ? edges : 1) * sizeof *regs);
    boundary_link *links = malloc((scene->patch_count ? scene->patch_count * 4 : 1) * sizeof *links);
    plan->items = malloc((edges ? edges : 1) * sizeof *plan->items);
    plan->item_boxes = malloc((edges ? edges : 1) * sizeof *plan->item_boxes);
    plan->pieces = malloc((edges ? edges : 1) * sizeof *plan->pieces);
    reyes_status status = REYES_OK;
    if (!records || !regs || !links || !plan->items || !plan->item_boxes || !plan->pieces)
        status = reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory stitching %zu grids", count);
    if (status == REYES_OK)
        status = reyes_glue_boundaries(scene, near_seams, links, error);
    if (status == REYES_OK) {
        for (size_t l = 0; l < count; ++l)
            for (uint32_t e = 0; e < 4; ++e)
                records[l * 4 + e] = leaf_edge(&leaves[l].sp, (uint32_t)l, e);
        qsort(records, edges, sizeof *records, compare_records);
        size_t used = 0;
        for (size_t l = 0; l < count; ++l)
            for (uint32_t e = 0; e < 4; ++e)
                used += (size_t)register_edge(records, edges, links,
                                              leaf_edge(&leaves[l].sp, (uint32_t)l, e), &regs[used]);
        qsort(regs, used, sizeof *regs, compare_registrations);
        make_items(leaves, regs, used, plan);
    }
    free(records);
    free(regs);
    free(links);
    if (status != REYES_OK)
        reyes_stitch_plan_free(plan);
    return status;
}

void reyes_stitch_plan_free(reyes_stitch_plan *plan)
{
    free(plan->items);
    free(plan->item_boxes);
    free(plan->pieces);
    memset(plan, 0, sizeof *plan);
}
