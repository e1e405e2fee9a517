/*
 * OpenCL C of the Mariani-Silver procedures.
 *
 *   split: a rectangle (inclusive bounds) whose border may already be in the
 *          image.  If its border has one escape count, emit `fill` for the
 *          interior; if the interior is small, emit `block`; else compute the
 *          middle row and column (they become borders of the four quarters)
 *          and emit the quarters to `split`.
 *   fill:  write one count into every pixel of a rectangle.
 *   block: compute every pixel of a rectangle.
 *
 * fill and block split their rectangle's pixels among the item's threads;
 * split runs on one thread per item.
 */
#include "mandel.h"
#include "mandel_escape.h"

/* The pragma must come before the shared functions; it stays in effect for
 * the rest of the generated program, which only matters for float code. */
static const char types_source[] =
    "#pragma OPENCL FP_CONTRACT OFF\n"
    "struct mandel_params { uint width, height, max_iter, min_size; float x0, y0, dx, dy; };\n"
    "struct mandel_rect { uint x0, y0, x1, y1, border_known; };\n"
    "struct mandel_area { uint x0, y0, x1, y1, value; };\n"
    MANDEL_SHARED_SOURCE "\n"
    "uint mandel_pixel(__global const struct mandel_params *p, uint x, uint y)\n"
    "{\n"
    "    return mandel_escape(mandel_coord(p->x0, p->dx, x), mandel_coord(p->y0, p->dy, y), p->max_iter);\n"
    "}\n";

static const char procedures_source[] =
    "void mandel_split(perma_ctx *ctx, __local const struct mandel_rect *r)\n"
    "{\n"
    "    __global const struct mandel_params *p = ctx->buf.params;\n"
    "    __global uint *img = ctx->buf.counts;\n"
    "    const uint w = p->width, x0 = r->x0, y0 = r->y0, x1 = r->x1, y1 = r->y1;\n"
    "    if (!r->border_known) {\n"
    "        for (uint x = x0; x <= x1; ++x) {\n"
    "            img[y0 * w + x] = mandel_pixel(p, x, y0);\n"
    "            img[y1 * w + x] = mandel_pixel(p, x, y1);\n"
    "        }\n"
    "        for (uint y = y0 + 1; y < y1; ++y) {\n"
    "            img[y * w + x0] = mandel_pixel(p, x0, y);\n"
    "            img[y * w + x1] = mandel_pixel(p, x1, y);\n"
    "        }\n"
    "    }\n"
    "    if (x1 - x0 < 2 || y1 - y0 < 2)\n"
    "        return; /* no interior */\n"
    "    const uint first = img[y0 * w + x0];\n"
    "    uint uniform = 1;\n"
    "    for (uint x = x0; x <= x1; ++x)\n"
    "        uniform &= img[y0 * w + x] == first && img[y1 * w + x] == first;\n"
    "    for (uint y = y0 + 1; y < y1; ++y)\n"
    "        uniform &= img[y * w + x0] == first && img[y * w + x1] == first;\n"
    "    struct mandel_area inner = { x0 + 1, y0 + 1, x1 - 1, y1 - 1, first };\n"
    "    if (uniform) {\n"
    "        emit_fill(ctx, &inner);\n"
    "        return;\n"
    "    }\n"
    "    if (x1 - x0 - 1 <= p->min_size || y1 - y0 - 1 <= p->min_size) {\n"
    "        emit_block(ctx, &inner);\n"
    "        return;\n"
    "    }\n"
    "    const uint mx = x0 + (x1 - x0) / 2, my = y0 + (y1 - y0) / 2;\n"
    "    for (uint x = x0 + 1; x < x1; ++x)\n"
    "        img[my * w + x] = mandel_pixel(p, x, my);\n"
    "    for (uint y = y0 + 1; y < y1; ++y)\n"
    "        if (y != my)\n"
    "            img[y * w + mx] = mandel_pixel(p, mx, y);\n"
    "    /* The quarters read these pixels, possibly in another work-group. */\n"
    "    write_mem_fence(CLK_GLOBAL_MEM_FENCE);\n"
    "    struct mandel_rect q0 = { x0, y0, mx, my, 1 }, q1 = { mx, y0, x1, my, 1 };\n"
    "    struct mandel_rect q2 = { x0, my, mx, y1, 1 }, q3 = { mx, my, x1, y1, 1 };\n"
    "    emit_split(ctx, &q0);\n"
    "    emit_split(ctx, &q1);\n"
    "    emit_split(ctx, &q2);\n"
    "    emit_split(ctx, &q3);\n"
    "}\n"
    "\n"
    "void mandel_fill(perma_ctx *ctx, __local const struct mandel_area *a)\n"
    "{\n"
    "    __global uint *img = ctx->buf.counts;\n"
    "    const uint w = ctx->buf.params->width, cols = a->x1 - a->x0 + 1;\n"
    "    const uint n = cols * (a->y1 - a->y0 + 1);\n"
    "    for (uint i = ctx->thread; i < n; i += ctx->threads)\n"
    "        img[(a->y0 + i / cols) * w + a->x0 + i % cols] = a->value;\n"
    "}\n"
    "\n"
    "void mandel_block(perma_ctx *ctx, __local const struct mandel_area *a)\n"
    "{\n"
    "    __global const struct mandel_params *p = ctx->buf.params;\n"
    "    __global uint *img = ctx->buf.counts;\n"
    "    const uint cols = a->x1 - a->x0 + 1, n = cols * (a->y1 - a->y0 + 1);\n"
    "    for (uint i = ctx->thread; i < n; i += ctx->threads) {\n"
    "        const uint x = a->x0 + i % cols, y = a->y0 + i / cols;\n"
    "        img[y * p->width + x] = mandel_pixel(p, x, y);\n"
    "    }\n"
    "}\n";

const char *mandel_device_types(void)
{
    return types_source;
}

const char *mandel_device_procedures(void)
{
    return procedures_source;
}
