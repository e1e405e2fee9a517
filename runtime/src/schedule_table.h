/* The schedule table (schedules.def) as C: what each technique's label
 * takes, what each strategy does, the victim policies.  Everything that
 * depends on a strategy asks here instead of naming strategies. */
#ifndef PERMA_SCHEDULE_TABLE_H
#define PERMA_SCHEDULE_TABLE_H

#include "perma.h"

#include <stdbool.h>

typedef struct perma_technique_info {
    perma_technique technique;
    const char *name;
    bool strategies;  /* label takes /STRATEGY[/VICTIM] */
    bool local_queue; /* label takes +localN and +wfN (per-group __local state: a front queue,
                         work-item stacks) */
    bool batch_limit; /* label takes /p=N */
    const char *description;
} perma_technique_info;

typedef struct perma_strategy_info {
    perma_strategy strategy;
    const char *name;
    bool steals;
    bool donates;
    bool per_group_queue_sets;
    const char *parameters; /* label options it takes ("/d=N ..."), "" for none */
    const char *description;
} perma_strategy_info;

typedef struct perma_victim_info {
    perma_victim victim;
    const char *name;
    const char *description;
} perma_victim_info;

/* Rows by index (0, 1, ...): NULL past the last one; an enum value is its
 * row's index. */
const perma_technique_info *perma_technique_row(int index);
const perma_strategy_info *perma_strategy_row(int index);
const perma_victim_info *perma_victim_row(int index);
/* The name of row i (names.c), NULL past the last row: for loops over
 * every name, such as the list an error message gives. */
const char *perma_technique_name_at(int index);
const char *perma_strategy_name_at(int index);
const char *perma_victim_name_at(int index);

#endif
