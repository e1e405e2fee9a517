/* Test hook around the OpenCL calls: a shim library, linked before the
 * OpenCL loader, that forwards every call perma makes, can make the Nth
 * one fail with CL_OUT_OF_RESOURCES, and counts the bytes that pass
 * between host and device. */
#ifndef CL_FAULT_H
#define CL_FAULT_H

#include <stddef.h>

/* Fail the `n`th wrapped call from now on (1 = the next); 0 disarms. */
void cl_fault_arm(unsigned long n);
/* Calls counted since the last arm (or since start). */
unsigned long cl_fault_calls(void);
/* Name of the call that was made to fail, or NULL. */
const char *cl_fault_failed_call(void);

/* Bytes clEnqueueReadBuffer and clEnqueueWriteBuffer moved since
 * cl_fault_transfers_reset(), counted only from the first
 * clEnqueueNDRangeKernel after the reset on (so a run's upload of its
 * seeds before its first launch does not count). */
typedef struct cl_fault_transfers {
    unsigned long long read;     /* bytes of clEnqueueReadBuffer */
    unsigned long long written;  /* bytes of clEnqueueWriteBuffer */
    unsigned long long largest;  /* bytes of the largest single call */
    unsigned long calls;
    unsigned long launches;      /* clEnqueueNDRangeKernel calls */
} cl_fault_transfers;

void cl_fault_transfers_reset(void);
cl_fault_transfers cl_fault_transfers_since_launch(void);

/* Make the next `n` reads of a finished launch's status (a blocking read of
 * a control block's header, kernels/perma_abi.h, that says DONE with
 * nothing outstanding) say instead that a group stopped the launch for
 * room with no detail (NEEDS_ROOM, PERMA_DETAIL_NONE): what the host sees
 * when a group calls a stall and another group, which it did not see
 * running, then runs the last items.  0 disarms. */
void cl_fault_report_stall(unsigned n);
/* Header reads rewritten so since the last cl_fault_report_stall(). */
unsigned cl_fault_stalls_reported(void);

/* Make the device look like a GPU with `compute_units` compute units and
 * `local_bytes` of __local memory (clGetDeviceInfo) on which a kernel runs
 * work-groups of at most `kernel_group_size` work-items and uses
 * `kernel_local_bytes` of __local memory (clGetKernelWorkGroupInfo; 0:
 * what the kernel really uses), from the next query on; the real device
 * still runs everything.  0 compute units: the real device again. */
void cl_fault_pretend_gpu(unsigned compute_units, unsigned long local_bytes, size_t kernel_group_size,
                          unsigned long kernel_local_bytes);

#endif
