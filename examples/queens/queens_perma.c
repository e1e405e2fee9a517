/* Counting N-queens subtrees with one perma procedure that emits into itself. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "queens.h"

static const char *types =
    "struct queens_node { uint row, n, columns, left, right; };\n";

/* One node: count it; a full board is a solution, otherwise emit a child
 * per free column.  The counts are reductions (perma_declare_reduction):
 * no atomic per node. */
static const char *source =
    "void queens_place(perma_ctx *ctx, __local const struct queens_node *node)\n"
    "{\n"
    "    reduce_nodes(ctx, 1ul);\n"
    "    if (node->row == node->n) {\n"
    "        reduce_solutions(ctx, 1ul);\n"
    "        return;\n"
    "    }\n"
    "    uint all = node->n >= 32u ? 0xffffffffu : (1u << node->n) - 1u;\n"
    "    uint free = ~(node->columns | node->left | node->right) & all;\n"
    "    while (free) {\n"
    "        uint bit = free & (0u - free);\n"
    "        free ^= bit;\n"
    "        struct queens_node next = { node->row + 1u, node->n, node->columns | bit,\n"
    "                                    ((node->left | bit) << 1) & all, (node->right | bit) >> 1 };\n"
    "        emit_place(ctx, &next);\n"
    "    }\n"
    "}\n";

struct queens_counter {
    perma_runtime *rt;
    perma_proc place;
    uint64_t solutions, nodes; /* the reductions of the last run */
};

static perma_status fail(perma_runtime *rt, perma_status status, perma_error *error)
{
    if (error) {
        error->status = status;
        snprintf(error->message, sizeof error->message, "%s", perma_errmsg(rt));
    }
    return status;
}

perma_status queens_counter_create(const perma_device_ref *device, queens_counter **out, perma_error *error)
{
    *out = NULL;
    queens_counter *c = calloc(1, sizeof *c);
    if (!c) {
        if (error) {
            error->status = PERMA_ERR_NO_MEMORY;
            snprintf(error->message, sizeof error->message, "out of memory");
        }
        return PERMA_ERR_NO_MEMORY;
    }
    perma_config config;
    perma_config_init(&config);
    if (device)
        perma_config_set_device(&config, device);
    perma_status st = perma_create(&config, &c->rt, error);
    if (st != PERMA_OK) {
        free(c);
        return st;
    }
    perma_procedure place = {
        .name = "place", .item_type = "struct queens_node", .item_size = sizeof(queens_node),
        .source = source, .source_file = "queens_place.cl", .function = "queens_place",
        .emits = { { "place", QUEENS_MAX_N } },
    };
    st = perma_add_source(c->rt, types, "queens_types.cl");
    if (st == PERMA_OK)
        st = perma_register(c->rt, &place, &c->place);
    if (st == PERMA_OK)
        st = perma_declare_reduction(c->rt, "solutions", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &c->solutions);
    if (st == PERMA_OK)
        st = perma_declare_reduction(c->rt, "nodes", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &c->nodes);
    if (st == PERMA_OK)
        st = perma_build(c->rt);
    if (st != PERMA_OK) {
        fail(c->rt, st, error);
        queens_counter_destroy(c);
        return st;
    }
    *out = c;
    return PERMA_OK;
}

void queens_counter_destroy(queens_counter *counter)
{
    if (!counter)
        return;
    perma_destroy(counter->rt);
    free(counter);
}

const char *queens_counter_device(const queens_counter *counter)
{
    return perma_device_summary(counter->rt);
}

perma_status queens_counter_run(queens_counter *c, const queens_node *units, size_t count,
                                queens_counts *counts, perma_error *error)
{
    if (count == 0)
        return PERMA_OK;
    perma_status st = perma_seed(c->rt, c->place, units, count);
    if (st == PERMA_OK)
        st = perma_run(c->rt);
    if (st != PERMA_OK)
        return fail(c->rt, st, error);
    counts->solutions += c->solutions;
    counts->nodes += c->nodes;
    return PERMA_OK;
}
