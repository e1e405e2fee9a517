/*
 * OpenCL C of the BFS procedures.  levels[] starts at BFS_UNREACHED except
 * the source (0); the traversal is label-correcting: groups run visits of
 * different levels at once, so a vertex may first get a level that is too
 * high and later a lower one.  Every improvement (atomic_min) emits a new
 * visit, and a visit whose level is no longer the vertex's level is stale
 * and does nothing, so the levels end at the breadth-first distances.
 *
 *   visit:  {vertex, level}: relax its neighbours, or if it has more than
 *           BFS_CHUNK, hand the whole list to expand.
 *   expand: {vertex, level, begin, end}: a slice of a neighbour list; halve
 *           it until it has at most BFS_CHUNK arcs, then relax them.
 * Halving keeps the emits of one item bounded (perma reserves room for
 * the declared maximum) however large a hub's degree is.
 */
#include "bfs.h"

#define TEXT_(x) #x
#define TEXT(x) TEXT_(x)

static const char types_source[] =
    "#define BFS_CHUNK " TEXT(BFS_CHUNK) "u\n"
    "struct bfs_visit { uint vertex, level; };\n"
    "struct bfs_slice { uint vertex, level, begin, end; };\n"
    "/* The vertex's current level; stale visits and slices stop early. */\n"
    "uint bfs_level(__global uint *levels, uint v)\n"
    "{\n"
    "    return *(volatile __global uint *)(levels + v);\n"
    "}\n";

static const char procedures_source[] =
    "void bfs_relax(perma_ctx *ctx, uint level, uint begin, uint end)\n"
    "{\n"
    "    __global const uint *targets = ctx->buf.targets;\n"
    "    for (uint a = begin; a < end; ++a) {\n"
    "        const uint w = targets[a];\n"
    "        if (atomic_min(&ctx->buf.levels[w], level + 1u) > level + 1u) {\n"
    "            struct bfs_visit next = { w, level + 1u };\n"
    "            emit_visit(ctx, &next);\n"
    "        }\n"
    "    }\n"
    "}\n"
    "\n"
    "void bfs_visit(perma_ctx *ctx, __local const struct bfs_visit *v)\n"
    "{\n"
    "    if (bfs_level(ctx->buf.levels, v->vertex) != v->level)\n"
    "        return;\n"
    "    const uint begin = ctx->buf.offsets[v->vertex], end = ctx->buf.offsets[v->vertex + 1u];\n"
    "    if (end - begin <= BFS_CHUNK) {\n"
    "        bfs_relax(ctx, v->level, begin, end);\n"
    "        return;\n"
    "    }\n"
    "    struct bfs_slice all = { v->vertex, v->level, begin, end };\n"
    "    emit_expand(ctx, &all);\n"
    "}\n"
    "\n"
    "void bfs_expand(perma_ctx *ctx, __local const struct bfs_slice *s)\n"
    "{\n"
    "    if (bfs_level(ctx->buf.levels, s->vertex) != s->level)\n"
    "        return;\n"
    "    if (s->end - s->begin <= BFS_CHUNK) {\n"
    "        bfs_relax(ctx, s->level, s->begin, s->end);\n"
    "        return;\n"
    "    }\n"
    "    const uint middle = s->begin + (s->end - s->begin) / 2u;\n"
    "    struct bfs_slice low = { s->vertex, s->level, s->begin, middle };\n"
    "    struct bfs_slice high = { s->vertex, s->level, middle, s->end };\n"
    "    emit_expand(ctx, &low);\n"
    "    emit_expand(ctx, &high);\n"
    "}\n";

const char *bfs_device_types(void)
{
    return types_source;
}

const char *bfs_device_procedures(void)
{
    return procedures_source;
}
