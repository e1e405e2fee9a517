/* User buffers, passed to the megakernel as arguments. */
#include "buffers.h"
#include "files.h"
#include "internal.h"
#include "program.h"

#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* PERMA_CHECK_BOUNDS: the words after every host buffer, set before each
 * run and compared after it. */
#define GUARD_WORDS 1024u
#define GUARD_BYTES (4 * (size_t)GUARD_WORDS)

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
    const char *reserved = perma_reserved_name(name);
    if (reserved)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "buffer name '%s' is %s; choose another name", name, reserved);
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
        b->guarded = false;
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
    char pointee[PERMA_NAME_MAX + 1];
    size_t element = perma_cl_pointee_size(type, pointee, sizeof pointee);
    if (element && bytes % element != 0)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "buffer '%s': %zu bytes is not a whole number of '%s' elements (%zu bytes each), "
                               "which type '%s' points to", name ? name : "(null)", bytes, pointee, element, type);
    perma_buffer_binding *b;
    perma_status st = binding_for(rt, name, type, &b);
    if (st != PERMA_OK)
        return st;
    char what[PERMA_NAME_MAX + 16];
    snprintf(what, sizeof what, "buffer '%s'", b->name);
    bool guarded = rt->settings.check_bounds;
    size_t room = bytes + (guarded ? GUARD_BYTES : 0);
    st = room < bytes ? perma_set_error(rt, PERMA_ERR_ARGUMENT, "%s: %zu bytes is not a size", what, bytes)
                      : perma_memory_check(rt, room, what);
    if (st != PERMA_OK)
        return st;
    cl_int err;
    b->mem = clCreateBuffer(rt->context, CL_MEM_READ_WRITE, room, NULL, &err);
    PERMA_CL_CHECK(rt, "clCreateBuffer (user buffer)", err);
    b->guarded = guarded;
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
    size_t device_size = perma_cl_type_size(element_type);
    if (device_size && device_size != element_size)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "buffer '%s': element type '%s' is %zu bytes on the device, but the host's elements "
                               "are %zu bytes", shown, element_type, device_size, element_size);
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

/* The guard words, the same after every buffer: a pattern no zeroing or
 * small count reproduces. */
static void guard_pattern(uint32_t words[GUARD_WORDS])
{
    for (uint32_t i = 0; i < GUARD_WORDS; ++i)
        words[i] = 0xB0DEC0DEu ^ (i * 0x9E3779B9u);
}

/* A guarded buffer's guard as the run left it: PERMA_ERR_DEVICE naming
 * the buffer and the first word a procedure changed. */
static perma_status check_guard(perma_runtime *rt, const perma_buffer_binding *b, const uint32_t *expected)
{
    uint32_t found[GUARD_WORDS];
    cl_int err = clEnqueueReadBuffer(rt->queue, b->mem, CL_TRUE, b->bytes, GUARD_BYTES, found, 0, NULL, NULL);
    if (err != CL_SUCCESS)
        return perma_set_error(rt, PERMA_ERR_OPENCL, "clEnqueueReadBuffer (the guard of buffer '%s') failed: %s (%d)",
                               b->name, perma_cl_error_name(err), (int)err);
    unsigned changed = 0, first = 0;
    for (unsigned i = 0; i < GUARD_WORDS; ++i)
        if (found[i] != expected[i] && changed++ == 0)
            first = i;
    if (!changed)
        return PERMA_OK;
    return perma_set_error(rt, PERMA_ERR_DEVICE,
                           "buffer '%s' (%zu bytes): a procedure wrote past its end: %u of the %u guard words after "
                           "it changed, the first at byte %zu (element type '%s'; PERMA_CHECK_BOUNDS)",
                           b->name, b->bytes, changed, GUARD_WORDS, b->bytes + 4 * (size_t)first,
                           b->element_type ? b->element_type : b->type);
}

perma_status perma_buffers_copy(perma_runtime *rt, unsigned flag)
{
    uint32_t guard[GUARD_WORDS];
    guard_pattern(guard);
    for (unsigned i = 0; flag == PERMA_WRITE && i < rt->buffer_count; ++i) {
        perma_status st = rt->buffers[i].guarded ? check_guard(rt, &rt->buffers[i], guard) : PERMA_OK;
        if (st != PERMA_OK)
            return st;
    }
    for (unsigned i = 0; i < rt->buffer_count; ++i) {
        perma_buffer_binding *b = &rt->buffers[i];
        cl_int err = CL_SUCCESS;
        if (flag == PERMA_READ && b->guarded)
            err = clEnqueueWriteBuffer(rt->queue, b->mem, CL_TRUE, b->bytes, GUARD_BYTES, guard, 0, NULL, NULL);
        if (err == CL_SUCCESS && b->host && (b->flags & flag))
            err = flag == PERMA_READ
                      ? clEnqueueWriteBuffer(rt->queue, b->mem, CL_TRUE, 0, b->bytes, b->host, 0, NULL, NULL)
                      : clEnqueueReadBuffer(rt->queue, b->mem, CL_TRUE, 0, b->bytes, b->host, 0, NULL, NULL);
        if (err != CL_SUCCESS)
            return perma_set_error(rt, PERMA_ERR_OPENCL, "%s (buffer '%s') failed: %s (%d)",
                                   flag == PERMA_READ ? "clEnqueueWriteBuffer" : "clEnqueueReadBuffer",
                                   b->name, perma_cl_error_name(err), (int)err);
    }
    return PERMA_OK;
}
