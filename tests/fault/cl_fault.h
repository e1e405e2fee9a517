/* Test hook around the OpenCL calls: a shim library, linked before the
 * OpenCL loader, that forwards every call perma makes and can make the Nth
 * one fail with CL_OUT_OF_RESOURCES. */
#ifndef CL_FAULT_H
#define CL_FAULT_H

/* Fail the `n`th wrapped call from now on (1 = the next); 0 disarms. */
void cl_fault_arm(unsigned long n);
/* Calls counted since the last arm (or since start). */
unsigned long cl_fault_calls(void);
/* Name of the call that was made to fail, or NULL. */
const char *cl_fault_failed_call(void);

#endif
