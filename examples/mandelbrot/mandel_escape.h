/*
 * The per-pixel arithmetic, written once in the subset of C shared by C11
 * and OpenCL C.  The host expands MANDEL_SHARED_FUNCTIONS(static inline) and the
 * device source embeds the same tokens as text (MANDEL_SHARED_SOURCE), so
 * both evaluate the same float operations in the same order.  What would
 * still make them differ is contraction of a*b+c into one fused multiply-add
 * (the device is an AVX-512 CPU with FMA, and OpenCL C contracts by
 * default): the device source starts with `#pragma OPENCL FP_CONTRACT OFF`
 * and the host is compiled with -ffp-contract=off (meson.build).  With that,
 * every operation is one correctly rounded IEEE single-precision operation
 * on both sides and the escape counts agree bit for bit.
 */
#ifndef MANDEL_ESCAPE_H
#define MANDEL_ESCAPE_H

#define MANDEL_SHARED_FUNCTIONS(storage)                                      \
    storage float mandel_coord(float lo, float step, unsigned int pixel)              \
    {                                                                         \
        return lo + (float)pixel * step;                                      \
    }                                                                         \
    storage unsigned int mandel_escape(float cx, float cy, unsigned int max_iter) \
    {                                                                         \
        float zx = 0.0f, zy = 0.0f;                                           \
        unsigned int i = 0;                                                   \
        while (i < max_iter) {                                                \
            float x2 = zx * zx;                                               \
            float y2 = zy * zy;                                               \
            if (x2 + y2 > 4.0f)                                               \
                break;                                                        \
            float xy = zx * zy;                                               \
            zy = xy + xy + cy;                                                \
            zx = x2 - y2 + cx;                                                \
            ++i;                                                              \
        }                                                                     \
        return i;                                                             \
    }

#define MANDEL_TEXT_(...) #__VA_ARGS__
#define MANDEL_TEXT(...) MANDEL_TEXT_(__VA_ARGS__)
#define MANDEL_SHARED_SOURCE MANDEL_TEXT(MANDEL_SHARED_FUNCTIONS())

#endif
