/* The recursive split procedure of the tree tests: a node below the target
 * depth emits two children; a leaf counts itself and adds its heap id (root
 * 1, children 2i and 2i+1) to a checksum.  With several threads per item,
 * thread 0 emits the left child and thread 1 the right one. */
#ifndef TREE_PROCEDURE_H
#define TREE_PROCEDURE_H

#include <stdint.h>

#include "perma.h"

struct tree_node {
    uint32_t depth, target, id, pad;
};

#define TREE_TYPES "struct tree_node { uint depth; uint target; uint id; uint pad; };\n"

#define TREE_SOURCE                                                                  \
    "void tree_split(perma_ctx *ctx, __local const struct tree_node *node)\n"       \
    "{\n"                                                                            \
    "    uint t = ctx->thread;\n"                                                    \
    "    if (node->depth < node->target) {\n"                                        \
    "        struct tree_node child = { node->depth + 1, node->target, node->id * 2u, 0 };\n" \
    "        if (ctx->threads == 1) {\n"                                             \
    "            emit_tree(ctx, &child);\n"                                          \
    "            child.id += 1u;\n"                                                  \
    "            emit_tree(ctx, &child);\n"                                          \
    "        } else if (t < 2) {\n"                                                  \
    "            child.id += t;\n"                                                   \
    "            emit_tree(ctx, &child);\n"                                          \
    "        }\n"                                                                    \
    "        if (t == 0)\n"                                                          \
    "            atomic_inc(&ctx->buf.counts[1]);\n"                                 \
    "    } else if (t == 0) {\n"                                                     \
    "        atomic_inc(&ctx->buf.counts[0]);\n"                                     \
    "        atom_add(&ctx->buf.sums[0], (ulong)node->id);\n"                        \
    "    }\n"                                                                        \
    "}\n"

/* Add the tree to rt as procedure "tree" with `threads_per_item` threads
 * per item (0: 1) and bind counts (leaves, inner nodes) and sums (the
 * leaves' ids) as the buffers of those names; fails the test on any
 * error.  Returns the procedure. */
perma_proc tree_add(perma_runtime *rt, unsigned threads_per_item, uint32_t counts[2], uint64_t sums[1]);
/* The same, declaring `declared` emits per item (it makes at most 2). */
perma_proc tree_add_declaring(perma_runtime *rt, unsigned threads_per_item, unsigned declared, uint32_t counts[2],
                              uint64_t sums[1]);

#endif
