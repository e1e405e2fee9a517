/* Sequential C count of a UTS tree: depth-first with an explicit stack. */
#include "uts.h"

#include <stdlib.h>

int uts_count_sequential(const uts_tree *tree, uts_result *out)
{
    size_t capacity = 1024, top = 0;
    uts_node *stack = malloc(capacity * sizeof *stack);
    if (!stack)
        return -1;
    uts_result r = { 0, 0, 0 };
    stack[top++] = (uts_node){ tree->root_hash, 0 };
    while (top > 0) {
        uts_node n = stack[--top];
        r.nodes++;
        r.hash_sum += n.hash;
        if (n.depth > r.max_depth)
            r.max_depth = n.depth;
        uint k = uts_children(tree, n);
        if (top + k > capacity) {
            while (top + k > capacity)
                capacity *= 2;
            uts_node *grown = realloc(stack, capacity * sizeof *stack);
            if (!grown) {
                free(stack);
                return -1;
            }
            stack = grown;
        }
        uts_child_nodes(n, k, tree->rounds, stack + top);
        top += k;
    }
    free(stack);
    *out = r;
    return 0;
}
