/* Command-line names of techniques, strategies and victim policies: the
 * names of the schedule table's rows (schedules.def). */
#include "schedule_table.h"

#include <string.h>

const char *perma_technique_name(perma_technique t)
{
    const perma_technique_info *row = perma_technique_row((int)t);
    return row ? row->name : NULL;
}

const char *perma_strategy_name(perma_strategy s)
{
    const perma_strategy_info *row = perma_strategy_row((int)s);
    return row ? row->name : NULL;
}

const char *perma_victim_name(perma_victim v)
{
    const perma_victim_info *row = perma_victim_row((int)v);
    return row ? row->name : NULL;
}

const char *perma_technique_name_at(int i) { return perma_technique_name((perma_technique)i); }
const char *perma_strategy_name_at(int i) { return perma_strategy_name((perma_strategy)i); }
const char *perma_victim_name_at(int i) { return perma_victim_name((perma_victim)i); }

/* The index whose name name_at gives is `name`; -1 for none. */
static int index_of(const char *(*name_at)(int), const char *name)
{
    for (int i = 0; name && name_at(i); ++i)
        if (strcmp(name_at(i), name) == 0)
            return i;
    return -1;
}

perma_status perma_technique_parse(const char *name, perma_technique *out)
{
    int i = index_of(perma_technique_name_at, name);
    if (i < 0)
        return PERMA_ERR_ARGUMENT;
    *out = (perma_technique)i;
    return PERMA_OK;
}

perma_status perma_strategy_parse(const char *name, perma_strategy *out)
{
    int i = index_of(perma_strategy_name_at, name);
    if (i < 0)
        return PERMA_ERR_ARGUMENT;
    *out = (perma_strategy)i;
    return PERMA_OK;
}

perma_status perma_victim_parse(const char *name, perma_victim *out)
{
    int i = index_of(perma_victim_name_at, name);
    if (i < 0)
        return PERMA_ERR_ARGUMENT;
    *out = (perma_victim)i;
    return PERMA_OK;
}
