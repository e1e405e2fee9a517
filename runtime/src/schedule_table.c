/* The schedule table (schedules.def) as arrays indexed by the enums. */
#include "schedule_table.h"

#include <stddef.h>

static const perma_technique_info techniques[] = {
#define PERMA_TECHNIQUE_ROW(id, name, strategies, local_queue, batch_limit, description) \
    { PERMA_TECHNIQUE_##id, name, strategies, local_queue, batch_limit, description },
#define PERMA_STRATEGY_ROW(...)
#define PERMA_VICTIM_ROW(...)
#include "schedules.def"
#undef PERMA_TECHNIQUE_ROW
#undef PERMA_STRATEGY_ROW
#undef PERMA_VICTIM_ROW
};

static const perma_strategy_info strategies[] = {
#define PERMA_TECHNIQUE_ROW(...)
#define PERMA_STRATEGY_ROW(id, name, steals, donates, per_group, parameters, description) \
    { PERMA_STRATEGY_##id, name, steals, donates, per_group, parameters, description },
#define PERMA_VICTIM_ROW(...)
#include "schedules.def"
#undef PERMA_TECHNIQUE_ROW
#undef PERMA_STRATEGY_ROW
#undef PERMA_VICTIM_ROW
};

static const perma_victim_info victims[] = {
#define PERMA_TECHNIQUE_ROW(...)
#define PERMA_STRATEGY_ROW(...)
#define PERMA_VICTIM_ROW(id, name, description) { PERMA_VICTIM_##id, name, description },
#include "schedules.def"
#undef PERMA_TECHNIQUE_ROW
#undef PERMA_STRATEGY_ROW
#undef PERMA_VICTIM_ROW
};

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* Row i holds enum value i (the rows follow the enums' order); a row out
 * of order is no row, which the schedule test catches. */
const perma_technique_info *perma_technique_row(int index)
{
    return index >= 0 && (size_t)index < COUNT(techniques) && (int)techniques[index].technique == index
               ? &techniques[index] : NULL;
}

const perma_strategy_info *perma_strategy_row(int index)
{
    return index >= 0 && (size_t)index < COUNT(strategies) && (int)strategies[index].strategy == index
               ? &strategies[index] : NULL;
}

const perma_victim_info *perma_victim_row(int index)
{
    return index >= 0 && (size_t)index < COUNT(victims) && (int)victims[index].victim == index
               ? &victims[index] : NULL;
}
