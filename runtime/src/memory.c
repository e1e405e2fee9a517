/* Memory limits of the process (ulimit -v, ulimit -d) and of the device,
 * checked before an allocation reaches the OpenCL driver.  PoCL does not
 * survive a failed allocation of its own: under a tight limit it aborts
 * starting its threads, crashes loading a program or asserts when a
 * buffer's memory is first used.  So the runtime refuses, with a message
 * naming what did not fit, what the driver would not survive. */
#include "device.h"
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#define MIB ((size_t)1 << 20)

/* What the driver itself needs beyond the buffers, per limit, measured
 * with PoCL 3.1 on a 2-core CPU (docs/reliability.md, *Faults tried*).
 * Address space: under 410 MiB and below the Reyes teapot at 512x512
 * (about 13 MiB of buffers) failed in PoCL (abort, segfault or assertion)
 * in some tries, frames rendered by a second thread at 449 MiB; about 10
 * MiB are mapped before the driver is loaded.  Data: the teapot failed at
 * 97 MiB and ran at 146 MiB.  With these floors and the margin below every
 * try ended cleanly.  Each further runtime of the process (--devices: a
 * thread and a context per device) needs room of its own. */
static const struct memory_limit {
    int resource;
    const char *key;        /* in /proc/self/status */
    const char *name;
    size_t driver, runtime; /* bytes */
} limits[] = {
    { RLIMIT_AS, "VmSize:", "address-space limit (ulimit -v)", 456 * MIB, 128 * MIB },
    { RLIMIT_DATA, "VmData:", "data limit (ulimit -d)", 160 * MIB, 64 * MIB },
};
#define LIMITS (sizeof limits / sizeof limits[0])
/* Left free beside each buffer: the driver allocates while it runs (a
 * kernel's arguments and local memory, a launch's commands). */
#define RUN_MARGIN_BYTES (32 * MIB)

/* "VmSize:" or "VmData:" of /proc/self/status in bytes; 0 if unknown. */
static size_t status_bytes(const char *key)
{
    FILE *f = fopen("/proc/self/status", "r");
    if (!f)
        return 0;
    char line[256];
    size_t kib = 0, length = strlen(key);
    while (fgets(line, sizeof line, f))
        if (strncmp(line, key, length) == 0) {
            kib = strtoull(line + length, NULL, 10);
            break;
        }
    fclose(f);
    return kib * 1024;
}

/* The headroom under limit `l`; false if it is not set. */
static bool headroom_under(const struct memory_limit *l, perma_headroom *out)
{
    struct rlimit r;
    if (getrlimit(l->resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY)
        return false;
    size_t limit = (size_t)r.rlim_cur, used = status_bytes(l->key);
    *out = (perma_headroom){ .free = used < limit ? limit - used : 0, .limit = limit, .used = used, .name = l->name };
    return true;
}

bool perma_memory_headroom(perma_headroom *out)
{
    bool limited = false;
    for (size_t i = 0; i < LIMITS; ++i) {
        perma_headroom h;
        if (headroom_under(&limits[i], &h) && (!limited || h.free < out->free)) {
            *out = h;
            limited = true;
        }
    }
    return limited;
}

static perma_status refuse(perma_runtime *rt, const perma_headroom *h, size_t bytes, const char *what)
{
    return perma_set_error(rt, PERMA_ERR_NO_MEMORY,
                           "out of memory for %s (%zu bytes, %zu MiB): the process's %s of %zu MiB has %zu MiB "
                           "free (%zu MiB in use), and the OpenCL driver needs about %zu MiB beside it",
                           what, bytes, (bytes + MIB - 1) / MIB, h->name, h->limit / MIB, h->free / MIB,
                           h->used / MIB, RUN_MARGIN_BYTES / MIB);
}

bool perma_memory_driver_fits(char *message, size_t size, bool runtime)
{
    static int started, runtimes;
    bool loaded = __atomic_load_n(&started, __ATOMIC_RELAXED) != 0;
    bool another = runtime && __atomic_load_n(&runtimes, __ATOMIC_RELAXED) > 0;
    for (size_t i = 0; i < LIMITS && (another || !loaded); ++i) {
        size_t need = another ? limits[i].runtime : limits[i].driver;
        perma_headroom h;
        if (headroom_under(&limits[i], &h) && h.free < need) {
            snprintf(message, size, "out of memory: %s needs about %zu MiB (PoCL), but the process's %s of "
                     "%zu MiB leaves %zu MiB (%zu MiB in use); raise the limit",
                     another ? "another OpenCL runtime in the process" : "the OpenCL driver, to start and run,",
                     need / MIB, h.name, h.limit / MIB, h.free / MIB, h.used / MIB);
            return false;
        }
    }
    __atomic_store_n(&started, 1, __ATOMIC_RELAXED);
    if (runtime)
        __atomic_add_fetch(&runtimes, 1, __ATOMIC_RELAXED);
    return true;
}

perma_status perma_memory_check(perma_runtime *rt, size_t bytes, const char *what)
{
    if (!what)
        what = "a buffer";
    if (rt->caps.max_alloc && bytes > rt->caps.max_alloc)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY,
                               "out of memory for %s (%zu bytes, %zu MiB): more than the device's largest "
                               "buffer (CL_DEVICE_MAX_MEM_ALLOC_SIZE, %llu MiB)", what, bytes,
                               (bytes + MIB - 1) / MIB, (unsigned long long)(rt->caps.max_alloc / MIB));
    /* A CPU device's buffers are the process's memory. */
    perma_headroom h;
    if (rt->caps.is_cpu && perma_memory_headroom(&h) && (h.free < RUN_MARGIN_BYTES
                                                           || bytes > h.free - RUN_MARGIN_BYTES))
        return refuse(rt, &h, bytes, what);
    return PERMA_OK;
}

perma_status perma_check_memory(perma_runtime *rt, size_t bytes, const char *what)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_check_memory", perma_memory_check(rt, bytes, what));
}
