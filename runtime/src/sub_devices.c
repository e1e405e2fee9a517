/*
 * Equal sub-devices (clCreateSubDevices, CL_DEVICE_PARTITION_EQUALLY).
 *
 * A device is split once per process and part count, and the parts are
 * kept until the process exits: every runtime on "0:0/2.1" shares one
 * sub-device, and none is ever released.  PoCL 3.1's worker threads may
 * still touch a sub-device after clFinish and the last release of its
 * queue and context; releasing it then crashed a concurrent runtime
 * (seen with MALLOC_PERTURB_ in the devices test).  The cost is a few
 * handles per split, once.
 */
#include "device.h"
#include "device_list.h"
#include "internal.h"

#include <pthread.h>
#include <stdlib.h>

typedef struct split {
    cl_device_id root;
    unsigned parts;
    cl_device_id *subs;  /* parts of them */
    struct split *next;
} split;

static pthread_mutex_t splits_lock = PTHREAD_MUTEX_INITIALIZER;
static split *splits;

/* The parts of `root` split `parts` ways, made on first use; NULL with
 * *err set on failure. */
static cl_device_id *find_or_split(cl_device_id root, unsigned parts, cl_int *err, cl_uint *created)
{
    for (split *s = splits; s; s = s->next)
        if (s->root == root && s->parts == parts)
            return s->subs;
    cl_uint units = 0;
    *err = clGetDeviceInfo(root, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, NULL);
    if (*err != CL_SUCCESS)
        return NULL;
    const cl_device_partition_property equally[] = { CL_DEVICE_PARTITION_EQUALLY,
                                                     (cl_device_partition_property)(units / parts), 0 };
    cl_device_id all[PERMA_MAX_SUB_DEVICES];
    *err = clCreateSubDevices(root, equally, PERMA_MAX_SUB_DEVICES, all, created);
    if (*err != CL_SUCCESS)
        return NULL;
    /* With units not a multiple of parts there may be more parts than
     * asked: keep the first `parts` (equal) ones. */
    split *s = calloc(1, sizeof *s);
    cl_device_id *subs = calloc(parts, sizeof *subs);
    if (!s || !subs || *created < parts) {
        for (cl_uint k = 0; k < *created; ++k)
            clReleaseDevice(all[k]);
        free(s);
        free(subs);
        *err = !s || !subs ? CL_OUT_OF_HOST_MEMORY : CL_SUCCESS;
        return NULL;
    }
    for (cl_uint k = 0; k < *created; ++k) {
        if (k < parts)
            subs[k] = all[k];
        else
            clReleaseDevice(all[k]);
    }
    *s = (split){ root, parts, subs, splits };
    splits = s;
    return subs;
}

perma_status perma_open_sub_device(perma_runtime *rt, int platform, int device, unsigned parts,
                                   unsigned part)
{
    char why[256];
    if (part >= parts || parts > PERMA_MAX_SUB_DEVICES)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "sub-device %u of %u requested (config "
                               "sub_device must be below sub_devices, at most %u)", part, parts,
                               PERMA_MAX_SUB_DEVICES);
    if (!perma_device_splits_equally(rt->device, parts, why, sizeof why))
        return perma_set_error(rt, PERMA_ERR_NO_DEVICE, "OpenCL device %d:%d %s (PERMA_DEVICE or config)",
                               platform, device, why);
    cl_int err = CL_SUCCESS;
    cl_uint created = 0;
    pthread_mutex_lock(&splits_lock);
    cl_device_id *subs = find_or_split(rt->device, parts, &err, &created);
    if (subs)
        rt->device = subs[part];
    pthread_mutex_unlock(&splits_lock);
    if (subs)
        return PERMA_OK;
    PERMA_CL_CHECK(rt, "clCreateSubDevices(CL_DEVICE_PARTITION_EQUALLY)", err);
    return perma_set_error(rt, PERMA_ERR_NO_DEVICE, "OpenCL device %d:%d made %u equal sub-devices, "
                           "not %u", platform, device, (unsigned)created, parts);
}
