/* Settings read from the environment that fill in perma_config fields the
 * caller left at 0. */
#include "internal.h"

#include <errno.h>
#include <stdlib.h>

/* PERMA_LOCAL_MEMORY_LIMIT: a cap on the __local memory one group uses, in
 * bytes with an optional K or M suffix (KiB, MiB): run code under a smaller
 * device's limit (a GPU's 48 KiB, OpenCL's minimum of 32 KiB) on this one.
 * Unset or empty: no cap. */
perma_status perma_env_local_memory_limit(perma_runtime *rt, size_t *out)
{
    *out = 0;
    const char *text = getenv("PERMA_LOCAL_MEMORY_LIMIT");
    if (!text || !*text)
        return PERMA_OK;
    char *end;
    errno = 0;
    unsigned long long value = strtoull(text, &end, 10);
    unsigned long long unit = 1;
    if (*end == 'K' || *end == 'k')
        unit = 1024, ++end;
    else if (*end == 'M' || *end == 'm')
        unit = 1024 * 1024, ++end;
    if (end == text || *end || errno || text[0] == '-' || value == 0 || value > (1ull << 40) / unit)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "PERMA_LOCAL_MEMORY_LIMIT '%s' is not a number of bytes in 1..2^40 "
                               "(a K or M suffix counts KiB or MiB)", text);
    *out = (size_t)(value * unit);
    return PERMA_OK;
}
