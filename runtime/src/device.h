/* device.h: the device the runtime opened and what it can do (device.c,
 * sub_devices.c), and the process's memory limits (memory.c). */
#ifndef PERMA_DEVICE_H
#define PERMA_DEVICE_H

#include "perma.h"

#include <stdbool.h>
#include <stddef.h>

/* What the device is and how its OpenCL implementation behaves, found
 * once when it is opened (device.c).  Modules ask these instead of
 * testing the implementation where a quirk bites (docs/design-runs.md,
 * Portability: quirk -> capability -> file). */
typedef struct perma_device_caps {
    bool is_cpu;             /* CL_DEVICE_TYPE_CPU: groups at most the physical cores (device.c); its
                                buffers are the process's memory (memory.c) */
    bool watch_visible;      /* the host sees the watch page change while a kernel runs (a CPU or
                                unified memory): the stall limit and live progress (watchdog.c, progress.c) */
    bool caches_programs;    /* the implementation keeps compiled programs in a cache of its own
                                (PoCL): program_cache.c does not store them too, and locks per host */
    cl_uint compute_units;
    size_t local_mem_size;
    cl_ulong max_alloc;
    size_t max_group_size;
    char name[256];          /* CL_DEVICE_NAME, with the sub-device */
} perma_device_caps;

/* device.c: open the device (resolve the choice, find the platform and
 * the device, fill rt->caps, create the context); let go of it. */
perma_status perma_device_open(perma_runtime *rt);
void perma_device_close(perma_runtime *rt);
/* sub_devices.c: point rt->device at part `part` of the device split
 * into `parts` equal sub-devices. */
perma_status perma_open_sub_device(perma_runtime *rt, int platform, int device, unsigned parts, unsigned part);

/* The tighter of the process's memory limits (memory.c): false if none is set. */
typedef struct perma_headroom {
    size_t free, limit, used; /* bytes */
    const char *name;         /* "address-space limit (ulimit -v)" */
} perma_headroom;
bool perma_memory_headroom(perma_headroom *out);
/* False, with the message, if the limits leave less than the OpenCL
 * driver needs to load, start and run at all (checked before the first
 * OpenCL call of the process), or, for a `runtime` after the first, less
 * than another runtime needs. */
bool perma_memory_driver_fits(char *message, size_t size, bool runtime);

#endif
