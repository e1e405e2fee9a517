/* User buffers, passed to the megakernel as arguments. */
#include "buffers.h"
#include "files.h"
#include "internal.h"
#include "program.h"

#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static perma_buffer_binding *find_buffer(perma_runtime *rt, const char *name)
{
    for (unsigned i = 0; i < rt->buffer_count; ++i)
        if (strcmp(rt->buffers[i].name, name) == 0)
            return &rt->buffers[i];
    return NULL;
}

/* Find or add the binding `name`; a rebinding must keep the type. */
static perma_status binding_for(perma_runtime *rt, const char *name, const char *type,
                                perma_buffer_binding **out)
{
    if (!perma_is_identifier(name))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "buffer name '%s' is not a C identifier",
                               name ? name : "(null)");
    if (!type || !strchr(type, '*') || strpbrk(type, ";{}\n"))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "buffer '%s': type '%s' is not an OpenCL C pointer type such as '__global float *'",
                               name, type ? type : "(null)");
    perma_buffer_binding *b = find_buffer(rt, name);
    if (b) {
        if (strcmp(b->type, type) != 0)
            return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                                   "buffer '%s' was bound as '%s' and cannot be rebound as '%s'",
                                   name, b->type, type);
        if (b->mem)
            clReleaseMemObject(b->mem);
        b->mem = NULL;
        b->host = NULL;
        b->bytes = 0;
        b->flags = 0;
        *out = b;
        return PERMA_OK;
    }
    if (rt->buffer_count == PERMA_MAX_BUFFERS)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "more than %d buffers", PERMA_MAX_BUFFERS);
    b = &rt->buffers[rt->buffer_count];
    memset(b, 0, sizeof *b);
    b->name = strdup(name);
    b->type = strdup(type);
    if (!b->name || !b->type) {
        free(b->name);
        free(b->type);
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory binding '%s'", name);
    }
    rt->buffer_count++;
    /* A new kernel argument: the program must be generated again. */
    perma_release_program(rt);
    rt->built = false;
    *out = b;
    return PERMA_OK;
}

static perma_status bind_cl_call(perma_runtime *rt, const char *name, const char *type, cl_mem buffer)
{
    perma_status begun = perma_call_begin(rt, "perma_bind_cl", true);
    if (begun != PERMA_OK)
        return begun;
    if (!buffer)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "buffer '%s': cl_mem is NULL", name ? name : "(null)");
    perma_buffer_binding *b;
    perma_status st = binding_for(rt, name, type, &b);
    if (st != PERMA_OK)
        return st;
    PERMA_CL_CHECK(rt, "clRetainMemObject", clRetainMemObject(buffer));
    b->mem = buffer;
    return PERMA_OK;
}

perma_status perma_bind_cl(perma_runtime *rt, const char *name, const char *type, cl_mem buffer)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_bind_cl", bind_cl_call(rt, name, type, buffer));
}

/* Bind host memory under `name` for the public call `call`; *out: the
 * binding. */
static perma_status bind_host(perma_runtime *rt, const char *call, const char *name, const char *type, void *host,
                              size_t bytes, unsigned flags, perma_buffer_binding **out)
{
    perma_status begun = perma_call_begin(rt, call, true);
    if (begun != PERMA_OK)
        return begun;
    if (!host || bytes == 0)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "buffer '%s': host memory is NULL or empty",
                               name ? name : "(null)");
    if (flags == 0 || (flags & ~(unsigned)PERMA_READ_WRITE))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "buffer '%s': flags %u must be PERMA_READ, PERMA_WRITE or both",
                               name ? name : "(null)", flags);
    perma_buffer_binding *b;
    perma_status st = binding_for(rt, name, type, &b);
    if (st != PERMA_OK)
        return st;
    char what[PERMA_NAME_MAX + 16];
    snprintf(what, sizeof what, "buffer '%s'", b->name);
    st = perma_memory_check(rt, bytes, what);
    if (st != PERMA_OK)
        return st;
    cl_int err;
    b->mem = clCreateBuffer(rt->context, CL_MEM_READ_WRITE, bytes, NULL, &err);
    PERMA_CL_CHECK(rt, "clCreateBuffer (user buffer)", err);
    b->host = host;
    b->bytes = bytes;
    b->flags = flags;
    *out = b;
    return PERMA_OK;
}

static perma_status bind_host_call(perma_runtime *rt, const char *name, const char *type,
                                   void *host, size_t bytes, unsigned flags)
{
    perma_buffer_binding *b;
    return bind_host(rt, "perma_bind_host", name, type, host, bytes, flags, &b);
}

perma_status perma_bind_host(perma_runtime *rt, const char *name, const char *type,
                             void *host, size_t bytes, unsigned flags)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_bind_host", bind_host_call(rt, name, type, host, bytes, flags));
}

/* The typed binding (PERMA_BIND_HOST_ARRAY): the pointer type is made from
 * the element type, and the build checks the element's size on the device
 * (abi.c). */
static perma_status bind_host_array_call(perma_runtime *rt, const char *name, const char *element_type, void *host,
                                         size_t count, size_t element_size, unsigned flags)
{
    perma_call_begin(rt, "perma_bind_host_array", false);
    const char *shown = name ? name : "(null)";
    if (!element_type || !*element_type || strpbrk(element_type, "*;{}[]()\n"))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "buffer '%s': element type '%s' is not an OpenCL C type name such as 'float' or "
                               "'struct pair'", shown, element_type ? element_type : "(null)");
    if (count == 0 || element_size == 0 || count > SIZE_MAX / element_size)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "buffer '%s': %zu elements of %zu bytes is not a size",
                               shown, count, element_size);
    char type[PERMA_NAME_MAX + 64];
    int length = snprintf(type, sizeof type, "__global %s%s *", flags == PERMA_READ ? "const " : "", element_type);
    if (length < 0 || (size_t)length >= sizeof type)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "buffer '%s': element type '%s' is too long", shown,
                               element_type);
    perma_buffer_binding *b;
    perma_status st = bind_host(rt, "perma_bind_host_array", name, type, host, count * element_size, flags, &b);
    if (st != PERMA_OK)
        return st;
    if (b->element_size && b->element_size != element_size)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "buffer '%s' was bound with elements of %zu bytes and cannot be rebound with %zu",
                               shown, b->element_size, element_size);
    if (!b->element_size) {
        /* Only a new binding's size is compiled into a program's checks. */
        if (rt->built) {
            perma_release_program(rt);
            rt->built = false;
        }
        free(b->element_type);
        b->element_type = strdup(element_type);
        if (!b->element_type)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory binding '%s'", shown);
        b->element_size = element_size;
    }
    return PERMA_OK;
}

perma_status perma_bind_host_array(perma_runtime *rt, const char *name, const char *element_type, void *host,
                                   size_t count, size_t element_size, unsigned flags)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_bind_host_array",
                         bind_host_array_call(rt, name, element_type, host, count, element_size, flags));
}

perma_status perma_buffers_copy(perma_runtime *rt, unsigned flag)
{
    for (unsigned i = 0; i < rt->buffer_count; ++i) {
        perma_buffer_binding *b = &rt->buffers[i];
        if (!b->host || !(b->flags & flag))
            continue;
        cl_int err = flag == PERMA_READ
                         ? clEnqueueWriteBuffer(rt->queue, b->mem, CL_TRUE, 0, b->bytes, b->host, 0, NULL, NULL)
                         : clEnqueueReadBuffer(rt->queue, b->mem, CL_TRUE, 0, b->bytes, b->host, 0, NULL, NULL);
        if (err != CL_SUCCESS)
            return perma_set_error(rt, PERMA_ERR_OPENCL, "%s (buffer '%s') failed: %s (%d)",
                                   flag == PERMA_READ ? "clEnqueueWriteBuffer" : "clEnqueueReadBuffer",
                                   b->name, perma_cl_error_name(err), (int)err);
    }
    return PERMA_OK;
}
