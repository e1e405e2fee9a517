/* Status codes, OpenCL error names and the runtime's error message. */
#include "internal.h"

#include <stdio.h>

const char *perma_status_name(perma_status status)
{
    switch (status) {
    case PERMA_OK: return "PERMA_OK";
    case PERMA_ERR_ARGUMENT: return "PERMA_ERR_ARGUMENT";
    case PERMA_ERR_NO_PLATFORM: return "PERMA_ERR_NO_PLATFORM";
    case PERMA_ERR_NO_DEVICE: return "PERMA_ERR_NO_DEVICE";
    case PERMA_ERR_OPENCL: return "PERMA_ERR_OPENCL";
    case PERMA_ERR_BUILD: return "PERMA_ERR_BUILD";
    case PERMA_ERR_NO_MEMORY: return "PERMA_ERR_NO_MEMORY";
    case PERMA_ERR_CAPACITY: return "PERMA_ERR_CAPACITY";
    case PERMA_ERR_EMIT_LIMIT: return "PERMA_ERR_EMIT_LIMIT";
    case PERMA_ERR_TIMEOUT: return "PERMA_ERR_TIMEOUT";
    case PERMA_ERR_STATE: return "PERMA_ERR_STATE";
    case PERMA_ERR_IO: return "PERMA_ERR_IO";
    case PERMA_ERR_DEVICE: return "PERMA_ERR_DEVICE";
    }
    return "PERMA_ERR_UNKNOWN";
}

const char *perma_cl_error_name(cl_int code)
{
    switch (code) {
#define NAME(c) case c: return #c
    NAME(CL_SUCCESS);
    NAME(CL_DEVICE_NOT_FOUND);
    NAME(CL_DEVICE_NOT_AVAILABLE);
    NAME(CL_COMPILER_NOT_AVAILABLE);
    NAME(CL_MEM_OBJECT_ALLOCATION_FAILURE);
    NAME(CL_OUT_OF_RESOURCES);
    NAME(CL_OUT_OF_HOST_MEMORY);
    NAME(CL_BUILD_PROGRAM_FAILURE);
    NAME(CL_INVALID_VALUE);
    NAME(CL_INVALID_DEVICE);
    NAME(CL_INVALID_PLATFORM);
    NAME(CL_INVALID_CONTEXT);
    NAME(CL_INVALID_COMMAND_QUEUE);
    NAME(CL_INVALID_MEM_OBJECT);
    NAME(CL_INVALID_BUFFER_SIZE);
    NAME(CL_INVALID_PROGRAM);
    NAME(CL_INVALID_PROGRAM_EXECUTABLE);
    NAME(CL_INVALID_KERNEL_NAME);
    NAME(CL_INVALID_KERNEL);
    NAME(CL_INVALID_ARG_INDEX);
    NAME(CL_INVALID_ARG_VALUE);
    NAME(CL_INVALID_ARG_SIZE);
    NAME(CL_INVALID_KERNEL_ARGS);
    NAME(CL_INVALID_WORK_DIMENSION);
    NAME(CL_INVALID_WORK_GROUP_SIZE);
    NAME(CL_INVALID_WORK_ITEM_SIZE);
    NAME(CL_INVALID_GLOBAL_OFFSET);
    NAME(CL_INVALID_EVENT);
    NAME(CL_INVALID_OPERATION);
    NAME(CL_INVALID_BUILD_OPTIONS);
    NAME(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST);
    NAME(CL_INVALID_HOST_PTR);
#undef NAME
    case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
    }
    return "unknown OpenCL error";
}

perma_status perma_set_error_va(perma_runtime *rt, perma_status status, const char *fmt, va_list ap)
{
    if (rt)
        vsnprintf(rt->message, sizeof rt->message, fmt, ap);
    return status;
}

perma_status perma_set_error(perma_runtime *rt, perma_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    perma_set_error_va(rt, status, fmt, ap);
    va_end(ap);
    return status;
}

perma_status perma_cl_error(perma_runtime *rt, const char *call, cl_int code)
{
    return perma_set_error(rt, PERMA_ERR_OPENCL, "%s failed: %s (%d)", call, perma_cl_error_name(code), (int)code);
}

perma_status perma_take_error(perma_runtime *rt, const perma_error *error)
{
    return perma_set_error(rt, error->status, "%s", error->message);
}

perma_status perma_call_begin(perma_runtime *rt, const char *call, bool uses_device)
{
    rt->message[0] = '\0';
    if (uses_device && rt->hung)
        return perma_set_error(rt, PERMA_ERR_STATE, "%s: a previous run's kernel did not stop and is still running; "
                               "this runtime cannot be used again (destroy it and create a new one)", call);
    return PERMA_OK;
}

/* A call refused because another held the runtime says so in its own
 * thread: the runtime's message belongs to the call that runs. */
static _Thread_local const perma_runtime *refused_runtime;
static _Thread_local char refused_message[PERMA_MESSAGE_MAX];

perma_status perma_call_claim(perma_runtime *rt, const char *call)
{
    refused_runtime = NULL;
    const char *running = NULL;
    if (__atomic_compare_exchange_n(&rt->current_call, &running, call, false, __ATOMIC_ACQUIRE, __ATOMIC_RELAXED))
        return PERMA_OK;
    snprintf(refused_message, sizeof refused_message,
             "%s: %s is running on this runtime (in another thread, or this call comes from inside it); a "
             "runtime takes one call at a time: use a runtime per thread, or a lock around the calls", call,
             running);
    refused_runtime = rt;
    return PERMA_ERR_STATE;
}

void perma_call_release(perma_runtime *rt)
{
    if (refused_runtime == rt)
        refused_runtime = NULL; /* a call refused from inside this one came before it ended */
    __atomic_store_n(&rt->current_call, NULL, __ATOMIC_RELEASE);
}

const char *perma_errmsg(const perma_runtime *rt)
{
    if (rt && rt == refused_runtime)
        return refused_message;
    return rt ? rt->message : "no runtime (perma_create failed or was not called)";
}
