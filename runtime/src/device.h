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
/* How many work-groups of a kernel a device holds at once, so that all
 * persistent groups run together (one that never starts while the others
 * wait for it would hang the run): compute_units times what one compute
 * unit holds by the kernel's __local memory (device_local /
 * kernel_local; 0: not known yet) and its registers (kernel_group_size /
 * group_size, CL_KERNEL_WORK_GROUP_SIZE being what one unit's register
 * file allows), and at most PERMA_MAX_GROUPS_PER_UNIT, the fewest blocks a
 * multiprocessor of NVIDIA's GPUs since Turing runs at once.  The
 * figures are conservative: a GPU's multiprocessor has at least
 * CL_DEVICE_LOCAL_MEM_SIZE of it (NVIDIA: 48 KiB of 100 to 228) and at
 * least the registers of a group of CL_KERNEL_WORK_GROUP_SIZE. */
#define PERMA_MAX_GROUPS_PER_UNIT 16u
#define PERMA_REASON_MAX 160
typedef struct perma_residency {
    unsigned per_unit;         /* groups one compute unit holds at once (0: not one) */
    unsigned limit;            /* compute_units * per_unit */
    char why[PERMA_REASON_MAX]; /* "132 compute units x 1, __local memory: 40960 of 49152 bytes each" */
} perma_residency;
void perma_residency_of(unsigned compute_units, size_t device_local, size_t kernel_local,
                        size_t kernel_group_size, unsigned group_size, perma_residency *out);

/* The number of work-groups, chosen at perma_create (device.c) and settled
 * by the build (program.c) on a device that is not a CPU, when the
 * runtime chooses it: perma_work_groups_plan lowers it to what the
 * device holds of a kernel of `local_bytes` of __local memory (the
 * layout's figure) and returns true if it did (the layout depends on the
 * count); perma_work_groups_fit checks the built megakernel (its
 * CL_KERNEL_LOCAL_MEM_SIZE and CL_KERNEL_WORK_GROUP_SIZE): an error for a
 * kernel that cannot run groups of group_size or uses more __local memory
 * than a group may, or for config.work_groups above what the device holds
 * at once under a persistent technique; *rebuild when it lowered the
 * runtime's choice (the program depends on it). */
bool perma_work_groups_plan(perma_runtime *rt, size_t local_bytes);
perma_status perma_work_groups_fit(perma_runtime *rt, bool *rebuild);

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
