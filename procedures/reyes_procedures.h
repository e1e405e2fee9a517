/*
 * The stage table of the Reyes pipeline: every procedure and every OpenCL
 * source of the renderer, once.  The enum REYES_PROC_* (reyes.h), the
 * registration (render/reyes_renderer.c) and the embedding of the sources
 * into the library (meson.build reads the X( and L( rows of this file)
 * are made from it: a new stage is one row here and its .cl file in
 * device/ (docs/design.md, "Where does a change go").
 *
 * Keep one row per line, starting with X( or L(: meson.build reads them.
 */
#ifndef REYES_PROCEDURES_H
#define REYES_PROCEDURES_H

/* The sources every procedure uses, in the order they enter the program:
 * L(stem, extension) embeds device/reyes_STEM.EXTENSION as the C string
 * reyes_STEM_EXTENSION_source.  The procedures' own sources follow them. */
#define REYES_LIBRARY_SOURCES(L) \
    L(shared, h)                 \
    L(common, cl)                \
    L(flatness, cl)              \
    L(rate, cl)                  \
    L(sample_shading, cl)        \
    L(sample, cl)                \
    L(blur, cl)                  \
    L(displace, cl)              \
    L(surface, cl)               \
    L(grid, cl)                  \
    L(sharp_quads, cl)           \
    L(rasterize, cl)             \
    L(occlusion, cl)             \
    L(dice_vertices, cl)         \
    L(polyline, cl)

/* X(ENUM, name, item type, priority, emits): procedure `name` is the
 * function reyes_NAME in device/reyes_NAME.cl over items of the type,
 * emitting to the procedures of REYES_EMIT(target, maximum per item)
 * (REYES_EMITS_NONE: none).  Bound and split emit into each other: bound is
 * served before split (it culls and dices, split doubles), and consumers
 * before producers keeps the queues short.  Dice takes a whole grid per
 * work-item (its SIMD is in vector types), so a batch shares the runtime's
 * cost among as many grids as the group has work-items, and rasterizes the
 * grid straight from its __local scratch (reyes_rasterize.cl, sized by the
 * renderer): a grid never goes through a queue. */
#define REYES_PROCEDURES(X) \
    X(BOUND, bound, struct reyes_subpatch, 2, REYES_EMIT(split_u, 1) REYES_EMIT(split_v, 1) REYES_EMIT(dice, 1)) \
    X(SPLIT_U, split_u, struct reyes_subpatch, 1, REYES_EMIT(bound, 2)) \
    X(SPLIT_V, split_v, struct reyes_subpatch, 1, REYES_EMIT(bound, 2)) \
    X(DICE, dice, struct reyes_subpatch, 3, REYES_EMITS_NONE) \
    X(STITCH, stitch, struct reyes_stitch, 4, REYES_EMITS_NONE)

/* An entry of a perma_procedure's emits, and the list of none. */
#define REYES_EMIT(target, maximum) { #target, maximum },
#define REYES_EMITS_NONE { NULL, 0 }

#endif
