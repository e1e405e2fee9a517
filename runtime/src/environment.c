/* Every PERMA_* environment variable the runtime reads, in one place:
 * perma_create reads them into the runtime's settings (environment.h). */
#include "environment.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A variable's text into out ("" when unset); whether it is set. */
static bool text_of(const char *name, char *out, size_t size)
{
    const char *value = getenv(name);
    snprintf(out, size, "%s", value ? value : "");
    return value != NULL;
}

/* Set, not empty and not "0". */
static bool flag(const char *name)
{
    const char *value = getenv(name);
    return value && *value && strcmp(value, "0") != 0;
}

/* PERMA_LOCAL_MEMORY_LIMIT: a cap on the __local memory one group uses, in
 * bytes with an optional K or M suffix (KiB, MiB): run code under a smaller
 * device's limit (a GPU's 48 KiB, OpenCL's minimum of 32 KiB) on this one.
 * Unset or empty: no cap. */
static void local_memory_limit(perma_settings *out)
{
    out->local_memory_limit = 0;
    out->local_memory_error.status = PERMA_OK;
    out->local_memory_error.message[0] = '\0';
    const char *text = getenv("PERMA_LOCAL_MEMORY_LIMIT");
    if (!text || !*text)
        return;
    char *end;
    errno = 0;
    unsigned long long value = strtoull(text, &end, 10);
    unsigned long long unit = 1;
    if (*end == 'K' || *end == 'k')
        unit = 1024, ++end;
    else if (*end == 'M' || *end == 'm')
        unit = 1024 * 1024, ++end;
    if (end == text || *end || errno || text[0] == '-' || value == 0 || value > (1ull << 40) / unit) {
        out->local_memory_error.status = PERMA_ERR_ARGUMENT;
        snprintf(out->local_memory_error.message, sizeof out->local_memory_error.message,
                 "PERMA_LOCAL_MEMORY_LIMIT '%s' is not a number of bytes in 1..2^40 "
                 "(a K or M suffix counts KiB or MiB)", text);
        return;
    }
    out->local_memory_limit = (size_t)(value * unit);
}

/* PERMA_CACHE_MIN_SECONDS: the CPU seconds a build must take to be stored
 * (program_cache.c); 1 when unset or not a number. */
static double cache_min_seconds(void)
{
    const char *value = getenv("PERMA_CACHE_MIN_SECONDS");
    char *end = NULL;
    double seconds = value && *value ? strtod(value, &end) : 1.0;
    return end && *end ? 1.0 : seconds;
}

/* PERMA_STOP_GRACE: seconds in 0.1..3600, 10 when unset or empty. */
static void stop_grace(perma_settings *out)
{
    out->stop_grace = 10.0;
    out->stop_grace_error.status = PERMA_OK;
    out->stop_grace_error.message[0] = '\0';
    const char *text = getenv("PERMA_STOP_GRACE");
    if (!text || !*text)
        return;
    char *end;
    errno = 0;
    double seconds = strtod(text, &end);
    if (end == text || *end || errno || !(seconds >= 0.1 && seconds <= 3600.0)) {
        out->stop_grace_error.status = PERMA_ERR_ARGUMENT;
        snprintf(out->stop_grace_error.message, sizeof out->stop_grace_error.message,
                 "PERMA_STOP_GRACE '%s' is not a number of seconds in 0.1..3600", text);
        return;
    }
    out->stop_grace = seconds;
}

void perma_settings_read(perma_settings *out)
{
    out->debug = flag("PERMA_DEBUG");
    text_of("PERMA_TRACE", out->trace, sizeof out->trace);
    perma_settings_device(out->device, sizeof out->device);
    local_memory_limit(out);
    out->build_log = flag("PERMA_BUILD_LOG");
    text_of("PERMA_DUMP_PROGRAM", out->dump_program, sizeof out->dump_program);
    out->cache_dir_set = text_of("PERMA_CACHE_DIR", out->cache_dir, sizeof out->cache_dir);
    out->cache_min_seconds = cache_min_seconds();
    stop_grace(out);
    out->check_bounds = flag("PERMA_CHECK_BOUNDS");
}

const char *perma_settings_device(char *out, size_t size)
{
    text_of("PERMA_DEVICE", out, size);
    return out;
}
