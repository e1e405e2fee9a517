/* The tree workload's registration, shared by the runtime tests. */
#include "tree_procedure.h"

#include "perma_test.h"

perma_proc tree_add_declaring(perma_runtime *rt, unsigned threads_per_item, unsigned declared, uint32_t counts[2],
                              uint64_t sums[1])
{
    ck_assert_perma_ok(rt, perma_add_source(rt, TREE_TYPES, "tree_types.cl"));
    perma_procedure tree = {
        .name = "tree", .item_type = "struct tree_node", .item_size = sizeof(struct tree_node),
        .threads_per_item = threads_per_item, .source = TREE_SOURCE, .source_file = "tree_split.cl",
        .function = "tree_split", .emits = { { "tree", declared } },
    };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &tree, &id));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "counts", "__global uint *", counts, 2 * sizeof *counts,
                                           PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "sums", "__global ulong *", sums, sizeof *sums, PERMA_READ_WRITE));
    return id;
}

perma_proc tree_add(perma_runtime *rt, unsigned threads_per_item, uint32_t counts[2], uint64_t sums[1])
{
    return tree_add_declaring(rt, threads_per_item, 2, counts, sums);
}
