/*
 * Host versions of the renderer: brute force (every pixel) and the same
 * Mariani-Silver subdivision as the device procedures, run sequentially
 * with an explicit stack.  Both use the shared functions of mandel_escape.h,
 * so their counts are the device's bit for bit.
 */
#include <stdlib.h>

#include "mandel.h"
#include "mandel_escape.h"

MANDEL_SHARED_FUNCTIONS(static inline)

static uint32_t pixel(const mandel_params *p, uint32_t x, uint32_t y)
{
    return mandel_escape(mandel_coord(p->x0, p->dx, x), mandel_coord(p->y0, p->dy, y), p->max_iter);
}

void mandel_params_init(mandel_params *p, unsigned width, unsigned height,
                        double x_min, double x_max, double y_min, double y_max,
                        unsigned max_iter, unsigned min_size)
{
    p->width = width;
    p->height = height;
    p->max_iter = max_iter;
    p->min_size = min_size;
    p->x0 = (float)x_min;
    p->y0 = (float)y_max;
    p->dx = (float)((x_max - x_min) / width);
    p->dy = (float)(-(y_max - y_min) / height);
}

void mandel_brute_force(const mandel_params *p, uint32_t *counts)
{
    for (uint32_t y = 0; y < p->height; ++y)
        for (uint32_t x = 0; x < p->width; ++x)
            counts[(size_t)y * p->width + x] = pixel(p, x, y);
}

typedef struct rect {
    uint32_t x0, y0, x1, y1;
} rect;

static void fill(const mandel_params *p, uint32_t *counts, rect r, uint32_t value)
{
    for (uint32_t y = r.y0; y <= r.y1; ++y)
        for (uint32_t x = r.x0; x <= r.x1; ++x)
            counts[(size_t)y * p->width + x] = value;
}

static void compute(const mandel_params *p, uint32_t *counts, rect r)
{
    for (uint32_t y = r.y0; y <= r.y1; ++y)
        for (uint32_t x = r.x0; x <= r.x1; ++x)
            counts[(size_t)y * p->width + x] = pixel(p, x, y);
}

static int border_uniform(const mandel_params *p, const uint32_t *counts, rect r)
{
    const size_t w = p->width;
    const uint32_t first = counts[r.y0 * w + r.x0];
    for (uint32_t x = r.x0; x <= r.x1; ++x)
        if (counts[r.y0 * w + x] != first || counts[r.y1 * w + x] != first)
            return 0;
    for (uint32_t y = r.y0 + 1; y < r.y1; ++y)
        if (counts[y * w + r.x0] != first || counts[y * w + r.x1] != first)
            return 0;
    return 1;
}

/* One split step on a rectangle whose border is in `counts`; pushes the
 * quarters onto `stack` (which has room for four more). */
static void split(const mandel_params *p, uint32_t *counts, rect r, rect *stack, size_t *top)
{
    if (r.x1 - r.x0 < 2 || r.y1 - r.y0 < 2)
        return;
    const size_t w = p->width;
    rect inner = { r.x0 + 1, r.y0 + 1, r.x1 - 1, r.y1 - 1 };
    if (border_uniform(p, counts, r)) {
        fill(p, counts, inner, counts[r.y0 * w + r.x0]);
        return;
    }
    if (r.x1 - r.x0 - 1 <= p->min_size || r.y1 - r.y0 - 1 <= p->min_size) {
        compute(p, counts, inner);
        return;
    }
    const uint32_t mx = r.x0 + (r.x1 - r.x0) / 2, my = r.y0 + (r.y1 - r.y0) / 2;
    for (uint32_t x = r.x0 + 1; x < r.x1; ++x)
        counts[my * w + x] = pixel(p, x, my);
    for (uint32_t y = r.y0 + 1; y < r.y1; ++y)
        if (y != my)
            counts[y * w + mx] = pixel(p, mx, y);
    stack[(*top)++] = (rect){ r.x0, r.y0, mx, my };
    stack[(*top)++] = (rect){ mx, r.y0, r.x1, my };
    stack[(*top)++] = (rect){ r.x0, my, mx, r.y1 };
    stack[(*top)++] = (rect){ mx, my, r.x1, r.y1 };
}

int mandel_sequential(const mandel_params *p, uint32_t *counts)
{
    const uint32_t x1 = p->width - 1, y1 = p->height - 1;
    rect frame = { 0, 0, x1, y1 };
    compute(p, counts, (rect){ 0, 0, x1, 0 });
    compute(p, counts, (rect){ 0, y1, x1, y1 });
    compute(p, counts, (rect){ 0, 0, 0, y1 });
    compute(p, counts, (rect){ x1, 0, x1, y1 });
    /* Depth-first: each level halves the sides, so the stack holds at most
     * 3 rectangles per level plus 4. */
    size_t capacity = 4 + 3 * 2 * 32;
    rect *stack = malloc(capacity * sizeof *stack);
    if (!stack)
        return -1;
    size_t top = 0;
    stack[top++] = frame;
    while (top > 0) {
        rect r = stack[--top];
        split(p, counts, r, stack, &top);
    }
    free(stack);
    return 0;
}
