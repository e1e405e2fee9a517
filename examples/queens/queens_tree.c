/* The N-queens tree on the host: the sequential count and the work units. */
#include <stdlib.h>

#include "queens.h"

static uint32_t all_columns(unsigned n)
{
    return n >= 32 ? 0xffffffffu : (1u << n) - 1u;
}

static queens_node child(const queens_node *node, uint32_t bit)
{
    uint32_t mask = all_columns(node->n);
    return (queens_node){ node->row + 1, node->n, node->columns | bit, ((node->left | bit) << 1) & mask,
                          (node->right | bit) >> 1 };
}

static void count_below(const queens_node *node, queens_counts *counts)
{
    counts->nodes++;
    if (node->row == node->n) {
        counts->solutions++;
        return;
    }
    uint32_t free = ~(node->columns | node->left | node->right) & all_columns(node->n);
    while (free) {
        uint32_t bit = free & (0u - free);
        free ^= bit;
        queens_node next = child(node, bit);
        count_below(&next, counts);
    }
}

queens_counts queens_count_sequential(unsigned n)
{
    queens_counts counts = { 0, 0 };
    queens_node root = { 0, n, 0, 0, 0 };
    count_below(&root, &counts);
    return counts;
}

typedef struct unit_list {
    queens_node *units;
    size_t count, capacity;
    int failed;
} unit_list;

static void collect(const queens_node *node, unsigned depth, unit_list *list, queens_counts *above)
{
    if (node->row == depth) {
        if (list->count == list->capacity) {
            size_t capacity = list->capacity ? list->capacity * 2 : 64;
            queens_node *grown = realloc(list->units, capacity * sizeof *grown);
            if (!grown) {
                list->failed = 1;
                return;
            }
            list->units = grown;
            list->capacity = capacity;
        }
        list->units[list->count++] = *node;
        return;
    }
    above->nodes++;
    if (node->row == node->n) {
        above->solutions++;
        return;
    }
    uint32_t free = ~(node->columns | node->left | node->right) & all_columns(node->n);
    while (free && !list->failed) {
        uint32_t bit = free & (0u - free);
        free ^= bit;
        queens_node next = child(node, bit);
        collect(&next, depth, list, above);
    }
}

int queens_units(unsigned n, unsigned depth, queens_node **units, size_t *count, queens_counts *above)
{
    unit_list list = { NULL, 0, 0, 0 };
    *above = (queens_counts){ 0, 0 };
    queens_node root = { 0, n, 0, 0, 0 };
    collect(&root, depth, &list, above);
    if (list.failed) {
        free(list.units);
        return 0;
    }
    *units = list.units;
    *count = list.count;
    return 1;
}
