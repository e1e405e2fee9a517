/* Command-line names of techniques, strategies and victim policies. */
#include "internal.h"

#include <string.h>

static const char *const technique_names[] = { "megakernel", "kernel-per-procedure", "bounded-batches" };
static const char *const strategy_names[] = { "shared", "stealing", "donation", "stealing-donation" };
static const char *const victim_names[] = { "random", "round-robin" };

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

static const char *name_of(const char *const *names, size_t count, int value)
{
    return value >= 0 && (size_t)value < count ? names[value] : NULL;
}

static int index_of(const char *const *names, size_t count, const char *name)
{
    for (size_t i = 0; name && i < count; ++i)
        if (strcmp(names[i], name) == 0)
            return (int)i;
    return -1;
}

const char *perma_technique_name(perma_technique t) { return name_of(technique_names, COUNT(technique_names), (int)t); }
const char *perma_strategy_name(perma_strategy s) { return name_of(strategy_names, COUNT(strategy_names), (int)s); }
const char *perma_victim_name(perma_victim v) { return name_of(victim_names, COUNT(victim_names), (int)v); }

perma_status perma_technique_parse(const char *name, perma_technique *out)
{
    int i = index_of(technique_names, COUNT(technique_names), name);
    if (i < 0)
        return PERMA_ERR_ARGUMENT;
    *out = (perma_technique)i;
    return PERMA_OK;
}

perma_status perma_strategy_parse(const char *name, perma_strategy *out)
{
    int i = index_of(strategy_names, COUNT(strategy_names), name);
    if (i < 0)
        return PERMA_ERR_ARGUMENT;
    *out = (perma_strategy)i;
    return PERMA_OK;
}

perma_status perma_victim_parse(const char *name, perma_victim *out)
{
    int i = index_of(victim_names, COUNT(victim_names), name);
    if (i < 0)
        return PERMA_ERR_ARGUMENT;
    *out = (perma_victim)i;
    return PERMA_OK;
}
