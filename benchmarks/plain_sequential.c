/* Sequential C versions of the plain workloads (plain_baselines.h). */
#include "plain_baselines.h"

#include <stdlib.h>

int plain_uts_sequential(const plain_uts_tree *t, plain_uts_result *out)
{
    size_t capacity = 4096, top = 0;
    struct uts_node *stack = malloc(capacity * sizeof *stack);
    if (!stack)
        return -1;
    plain_uts_result r = { 0, 0 };
    stack[top++] = (struct uts_node){ t->root_hash, 0u, 0u };
    while (top > 0) {
        struct uts_node n = stack[--top];
        r.nodes++;
        r.hash_sum += n.hash;
        uint k = plain_uts_children(t, &n);
        if (top + k > capacity) {
            while (top + k > capacity)
                capacity *= 2;
            struct uts_node *grown = realloc(stack, capacity * sizeof *stack);
            if (!grown) {
                free(stack);
                return -1;
            }
            stack = grown;
        }
        for (uint i = 0; i < k; ++i)
            stack[top++] = uts_child(n.hash, n.depth, i);
    }
    free(stack);
    *out = r;
    return 0;
}

void plain_simpson_sequential(const struct simpson_interval *root, uint max_depth, plain_simpson_result *out)
{
    plain_simpson_result r = { 0, 0, 0.0 };
    r.area = plain_simpson_visit(root, max_depth, &r);
    *out = r;
}

uint64_t plain_queens_sequential(uint n)
{
    return queens_solve(n, 0u, 0u, 0u, 0u);
}

void plain_sort_sequential(uint *keys, uint n)
{
    sort_range_sequential(keys, 0u, n);
}

void plain_subset_instance_init(plain_subset_instance *s, uint n)
{
    uint64_t total = 0;
    s->n = n < SUBSET_MAX_WEIGHTS ? n : SUBSET_MAX_WEIGHTS;
    s->suffix[s->n] = 0u;
    for (uint i = s->n; i-- > 0;) {
        s->weights[i] = subset_weight(i);
        s->suffix[i] = s->suffix[i + 1u] + s->weights[i];
    }
    total = s->suffix[0];
    s->target = (uint)(total / 2u);
}

static void subset_visit(const plain_subset_instance *s, uint index, uint need, plain_subset_result *r)
{
    r->nodes++;
    r->solutions += need == 0u;
    if (!subset_branches(s->n, s->suffix, index, need))
        return;
    subset_visit(s, index + 1u, need, r);
    if (s->weights[index] <= need)
        subset_visit(s, index + 1u, need - s->weights[index], r);
}

void plain_subset_sequential(const plain_subset_instance *s, plain_subset_result *out)
{
    plain_subset_result r = { 0, 0 };
    subset_visit(s, 0u, s->target, &r);
    *out = r;
}
